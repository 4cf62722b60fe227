"""The INI fast path's shared sections (``ini._SharedSection``) answer every question as
the exact reader's sections do: name, line, values, keys, get/has/line_of/key_names, the
file's line count and its respelled names -- whether a section's template was found by
the text after a first ParameterName= line, by the section before, or by its whole text,
and whatever the line ends (SPEC §1)."""
from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dcf2bin import ini

_ASKED = ("parametername", "denotation", "datatype", "accesstype", "defaultvalue",
          "objecttype", "k", "nosuchkey")


def _answers(f: ini.IniFile):
    """Everything a caller can ask of the sections, in the order a caller may ask it
    (``name`` first and last: the header index is built on the first question)."""
    out = {}
    for canon, sec in f.sections.items():
        asked = {k: (sec.get(k), sec.has(k), sec.line_of(k)) for k in _ASKED}
        out[canon] = (sec.name, sec.line, list(sec.key_names()), asked,
                      list(sec.values.items()),
                      {k: (key.name, key.value, key.line) for k, key in sec.keys.items()},
                      {k: sec.line_of(k) for k in sec.values}, sec.name)
    return out, f.line_count, sorted(f.respelled)


def _fast_equals_exact(text: str) -> ini.IniFile | None:
    fast = ini._parse_fast(text, "t.dcf", "utf-8")
    exact = ini._parse_exact(text, "t.dcf", "utf-8")
    if fast is not None:
        assert not exact.duplicates and not list(exact.diagnostics)
        assert _answers(fast) == _answers(exact)
        # the bytes read the same (each character one byte: the sections look into them)
        data = text.encode("latin-1")
        via_bytes = ini._parse_fast(text, "t.dcf", "utf-8", data)
        assert _answers(via_bytes) == _answers(exact)
    return fast


# -- generated files of the shapes configurators write -----------------------------------------

_BODY = st.lists(st.sampled_from([
    "ObjectType=0x7", "DataType=0x0005", "DataType=0x0001", "AccessType=ro",
    "AccessType=rw", "DefaultValue=0", "DefaultValue= 7 ", "PDOMapping=1", "K = v",
    "; a comment", "# another", "", "Denotation=", "x=ParameterName=y", "y=Denotation=z"]),
    max_size=5, unique_by=lambda s: s.partition("=")[0].strip().lower() or s)
_SUB = st.sampled_from(["1", "2", "01", "A", "0A", "FE", "001", "10"])
_SECTION = st.tuples(
    st.sampled_from(["A040", "2000", "1018", "A4C0"]), _SUB,
    st.sampled_from(["first", "later", "none"]),          # where ParameterName= stands
    st.sampled_from(["in_u8_00001", "out x", " padded\t", "", "Motor #1", "a=b"]),
    st.sampled_from([None, "Pump 1", "", "Pump 2 "]),       # Denotation=
    _BODY)


def _text(sections, eol: str, head: str, trailing: bool) -> str:
    lines = [head] if head else []
    seen = set()
    for index, sub, where, pname, denotation, body in sections:
        canon = f"{index.lower()}sub{int(sub, 16):x}"
        if canon in seen:
            continue                          # a repeat is the exact reader's case
        seen.add(canon)
        own = [b for b in body if not b.lower().startswith(("denotation", "parametername"))]
        if denotation is not None:
            own.insert(len(own) // 2, f"Denotation={denotation}")
        if where == "first":
            own.insert(0, f"ParameterName={pname}")
        elif where == "later":
            own.insert(len(own), f"ParameterName={pname}")
        lines += [f"[{index}sub{sub}]"] + own
    text = eol.join(lines)
    return text + eol if trailing else text


@settings(max_examples=300, deadline=None)
@given(st.lists(_SECTION, min_size=1, max_size=8), st.sampled_from(["\n", "\r\n"]),
       st.sampled_from(["", "; generated", "\n; after a blank line"]), st.booleans())
def test_shared_sections_answer_like_the_exact_reader(sections, eol, head, trailing):
    text = _text(sections, eol, head.replace("\n", eol), trailing)
    assert _fast_equals_exact(text) is not None     # a clean file: the fast path's case


def test_an_array_shares_one_template_found_by_the_section_before():
    subs = "".join(f"[A040sub{s:X}]\r\nParameterName=in_u8_{s:05}\r\nObjectType=0x7\r\n"
                   f"DataType=0x0005\r\nAccessType=ro\r\nPDOMapping=1\r\n\r\n"
                   for s in range(1, 40))
    text = "[A040]\r\nParameterName=Inputs\r\nObjectType=0x8\r\n\r\n" + subs
    f = _fast_equals_exact(text)
    rests = {id(f.section(f"a040sub{s:x}").rest) for s in range(1, 40)}
    assert len(rests) == 2       # the last one's lines end in a blank line, not a header
    s7 = f.section("a040sub7")
    assert (s7.name, s7.line, s7.get("parametername"), s7.param_name) == (
        "A040sub7", 5 + 7 * 6, "in_u8_00007", "in_u8_00007")
    assert s7.keys["parametername"] == ini.Key("ParameterName", "in_u8_00007", s7.line + 1)
    assert f.line_count == text.count("\n") + 1


def test_the_same_lines_without_a_line_end_at_the_end_of_the_file_are_another_template():
    """A last section whose ParameterName= line ends the file spans one line less."""
    f = _fast_equals_exact("[2000sub1]\nParameterName=a\n\n[2000sub2]\nParameterName=b\n"
                           "\n[2000sub3]\nParameterName=c")
    assert f.line_count == 8
    assert f.section("2000sub3").line == 7


def test_a_header_right_before_the_next_header_spans_one_line():
    f = _fast_equals_exact("[1000]\r\n[1001]\r\nA=1\r\n[1002]\r\n\r\n[1003]")
    assert [s.line for s in f.sections.values()] == [1, 2, 4, 6]
    assert f.line_count == 6


@pytest.mark.parametrize("eol", ["\n", "\r\n"])
def test_respelled_subindexes_are_listed_and_keep_their_spelling(eol):
    text = eol.join(["[1018]", "SubNumber=2", "[1018sub00]", "ParameterName=n",
                     "[1018SUB001]", "ParameterName=v", "[1018sub2]", "ParameterName=w",
                     "[Channel0Info]", "A=1", "[2000sub10]", "ParameterName=x", ""])
    f = _fast_equals_exact(text)
    assert f.respelled == ["1018sub0", "1018sub1"]     # not the names written canonically
    assert f.section("1018sub1").name == "1018SUB001"


# -- a CR or LF that ends no line where the others end in CRLF -----------------------------------

@pytest.mark.parametrize("text", [
    "[2000]\r\nParameterName=a\rb\r\nDataType=0x0005\r\n",          # lone CR in the name value
    # ... of a section whose template is found by the section before
    "[2000]\r\nParameterName=a\r\nA=1\r\n[2001]\r\nParameterName=b\rc\r\nA=1\r\n[2002]\r\n",
    "[2000]\r\nParameterName=a\r\nA=1\r\n[2001]\r\nParameterName=b\nc\r\nA=1\r\n[2002]\r\n",
    "[2000]\r\nParameterName=a\nb\r\nDataType=0x0005\r\n",          # lone LF in it
    "[2000]\r\nDataType=0x0005\r\nParameterName=a\nb\r\n",          # ... not first
    "[2000]\r\nParameterName=a\r\nDenotation=x\ry\r\n",             # in a Denotation=
    "[2000]\r\nParameterName=a\r\nDenotation=x\r\nA=1\r\n[2001]\r\nParameterName=b\r\n"
    "Denotation=y\rz\r\nA=1\r\n[2002]\r\n",                       # ... of a shared template
    "[2000]\r\nParameterName=a\r\nDataType=0x0005\n",               # in the template
    "[2000]\r\nParameterName=a\r\nDataType=0x0005\r\r\n[2001]\r\n",  # a CR before CRLF
    "; head\n\r\n[2000]\r\nParameterName=a\r\n",                    # before the first header
    "[20\r00]\r\nParameterName=a\r\n",                              # in a header
    "[2000]\r\nParameterName=a\r\n\n[2001]\r\nParameterName=b\r\n",  # an LF-only blank line
    "[2000]\r\nParameterName=a\r\n[2001]\nParameterName=b\r\n",     # an LF-only header line
])
def test_a_lone_cr_or_lf_is_never_read_as_part_of_a_crlf_file(text):
    """The CRLF reading declines such a file wherever the character stands; a lone LF
    makes it a file of mixed line ends (read again as LF text), a lone CR the exact
    reader's. Either way the result is the exact reader's."""
    assert ini._read_sections(text, "\r\n", "t.dcf", "utf-8", None) is None
    fast = ini._parse_fast(text, "t.dcf", "utf-8")
    if text.count("\r") != text.count("\r\n"):
        assert fast is None
    else:
        assert fast is None or fast.line_count == text.count("\n") + 1
    if fast is not None:
        assert _answers(fast) == _answers(ini._parse_exact(text, "t.dcf", "utf-8"))


def test_names_are_found_in_any_order_after_the_first_question():
    text = "".join(f"[A{n:03X}]\r\nParameterName=p{n}\r\n\r\n" for n in range(50))
    f = ini.parse_bytes(("; lead\r\n\r\n" + text).encode("ascii"), "t.dcf")
    secs = list(f.sections.values())
    for sec in secs[::-7] + secs:
        assert sec.name == f"A{int(sec.param_name[1:]):03X}"
        assert sec.line == 3 + 3 * int(sec.param_name[1:])


def test_names_are_found_when_only_the_sections_are_kept():
    """The header index takes the sections' lines from their file when it is still
    there, else counts the lines itself."""
    text = "; lead\n" + "".join(f"[A{n:03X}]\nParameterName=p{n}\nA=1\n\n" for n in range(20))
    sections = ini.parse_bytes(text.encode("ascii"), "t.dcf").sections    # the file is gone
    assert [s.name for s in sections.values()] == [f"A{n:03X}" for n in range(20)]
    assert [s.keys["a"].line for s in sections.values()] == [4 + 4 * n for n in range(20)]


def test_a_read_file_is_freed_without_the_cyclic_gc():
    """Sections refer to their file's text through their templates, never in a cycle: a
    compile runs with the cyclic GC off, and a long run of them must not pile files up."""
    import gc
    was = gc.isenabled()
    gc.collect()
    gc.disable()
    try:
        f = ini.parse_bytes(b"[2000]\nParameterName=a\nA=1\n\n[2001]\nParameterName=b\nA=1\n",
                            "t.dcf")
        assert f.section("2001").name == "2001" and f.section("2000").keys["a"].line == 3
        del f
        assert gc.collect() == 0
    finally:
        if was:
            gc.enable()


def test_an_array_with_denotations_shares_one_template():
    """Sections that differ in ParameterName= and Denotation= share their template too;
    each keeps its own values, and one with Denotation= written otherwise has its own."""
    subs = "".join(f"[A040sub{s:X}]\nParameterName=in_{s}\nDataType=0x0005\n"
                   f"Denotation=Pump {s}\nPDOMapping=1\n\n" for s in range(1, 6))
    text = subs + "[A040sub6]\nParameterName=in_6\nDataType=0x0005\nDenotation = x\n" \
        "PDOMapping=1\n\n[A040sub7]\nParameterName=in_7\nDataType=0x0005\nPDOMapping=1\n"
    f = _fast_equals_exact(text)
    secs = [f.section(f"a040sub{s}") for s in range(1, 8)]
    assert len({id(s.rest) for s in secs[:5]}) == 1
    assert [s.denotation for s in secs] == [f"Pump {s}" for s in range(1, 6)] + [None, None]
    assert secs[5].get("denotation") == "x" and secs[6].get("denotation") is None


def test_names_as_written_survive_a_reordered_sections_dict():
    # a caller may sort or reorder IniFile.sections; the names as written are found from
    # the file's text, not from the dict's order
    from pathlib import Path
    sample = Path(__file__).resolve().parent.parent / "samples" / "plc.dcf"
    expected = {k: s.name for k, s in ini.read(str(sample)).sections.items()}
    f = ini.read(str(sample))
    f.sections = dict(sorted(f.sections.items(), reverse=True))
    assert {k: s.name for k, s in f.sections.items()} == expected


# -- sections too long to be templates (issue 26 item 5) -------------------------------------------
# A section of more than ini._BIG characters is read in the file's text, line by line
# (``_Templates.big``), and keeps no text of its own: it answers as the exact reader's.
# Here _BIG is made small, so that the generated files have such sections.

@settings(max_examples=200, deadline=None)
@given(st.lists(_SECTION, min_size=1, max_size=8), st.sampled_from(["\n", "\r\n"]),
       st.sampled_from(["", "; generated", "\n; after a blank line"]), st.booleans(),
       st.sampled_from([0, 1, 24, 60]))
def test_long_sections_answer_like_the_exact_reader(sections, eol, head, trailing, big):
    saved = ini._BIG
    ini._BIG = big
    try:
        text = _text(sections, eol, head.replace("\n", eol), trailing)
        assert _fast_equals_exact(text) is not None
    finally:
        ini._BIG = saved


COMMENTS = "".join(f"; {'x' * 1000} {k}\n" for k in range(100))      # 100 KiB


@pytest.mark.parametrize("where", ["head", "first", "middle", "last"])
@pytest.mark.parametrize("eol", ["\n", "\r\n"])
def test_a_hundred_kib_of_comments_anywhere(where, eol):
    parts = {"head": "", "first": "", "middle": "", "last": ""}
    parts[where] = COMMENTS
    text = (parts["head"] + "[1000]\n" + parts["first"] + "ParameterName=a\nDataType=0x0007\n"
            "[2000]\nParameterName=b\n" + parts["middle"] + "DefaultValue=7\n[3000]\n"
            "ParameterName=c\nDefaultValue=0x10\n" + parts["last"]).replace("\n", eol)
    assert len(COMMENTS) > ini._BIG
    f = _fast_equals_exact(text)
    assert f is not None
    assert f.section("3000").keys["defaultvalue"].line == text.count("\n", 0, text.index(
        "DefaultValue=0x10")) + 1


def test_a_long_value_and_long_keys_are_read_once():
    value = "AB" * 100_000
    text = (f"[1000]\nParameterName=a\n[3000]\nParameterName=Blob\nDataType=0x000F\n"
            f"DefaultValue={value}\n" + "".join(f"Key{k}={'v' * 1000}\n" for k in range(70))
            + "[3001]\nParameterName=c\n")
    f = _fast_equals_exact(text)
    sec = f.section("3000")
    assert sec.rest.text is None                   # no copy of the section is kept
    assert sec.get("defaultvalue") == value and sec.name == "3000"
    assert sec.keys["key69"] == ini.Key("Key69", "v" * 1000, 76)
    assert sec.keys["defaultvalue"].value is sec.get("defaultvalue")   # the same string


@pytest.mark.parametrize("text,why", [
    ("[3000]\nA=1\n" + COMMENTS + "a=2\n", "a repeated key"),
    ("[3000]\nA=1\n" + COMMENTS + "  indented=2\n", "an indented line"),
    ("[3000]\nA=1\n" + COMMENTS + "no equals sign\n", "a line without '='"),
    ("[3000]\r\nA=1\r\n" + COMMENTS.replace("\n", "\r\n") + "b=\r2\r\n", "a lone CR"),
    ("[30\n00]\n" + COMMENTS, "a broken header"),
])
def test_a_long_section_the_exact_reader_has_to_see(text, why):
    assert ini._parse_fast(text, "t.dcf", "utf-8") is None, why


def test_line_of_in_a_long_section_makes_no_key_of_each_line():
    text = "[1000]\nParameterName=a\n[3000]\n" + "".join(f"Key{k}=1\n" for k in range(20_000))
    f = _fast_equals_exact(text)
    f = ini._parse_fast(text, "t.dcf", "utf-8")          # again: nothing asked yet
    sec = f.section("3000")
    assert sec.line_of("key19999") == 20_003 and sec.line_of("nosuchkey") == 3
    assert sec.rest.source.keys == {}                    # no Key made for 20,000 lines
    assert sec.keys["key19999"].line == 20_003
