"""The rules' shared tables (dcf2bin/lint/tables.py) against the plain walks they replace,
and the per-template verdicts: a rule that decides once for the sections of one shared
template still reports every one of them, each at its own line."""
from __future__ import annotations

import re

import pytest

from conftest import ROOT, corpus_files
from dcf2bin import ini, model
from dcf2bin.lint import Options, lint_bytes, tables
from dcf2bin.lint.context import DcfContext
from dcf2bin.lint.vocabulary import classify

_HEAD = """[FileInfo]
FileName=t.dcf
[DeviceInfo]
VendorName=x
[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0
"""


def _array(index: int, subs: int, extra: str = "", names=None) -> str:
    """An ARRAY of ``subs`` UNSIGNED8 sub-objects whose sections differ only in their
    names (one shared template), ``extra`` lines in each."""
    out = [f"[{index:04X}]", "ParameterName=Array", "ObjectType=0x8", f"SubNumber={subs + 1}",
           f"[{index:04X}sub0]", "ParameterName=Count", "ObjectType=0x7", "DataType=0x0005",
           "AccessType=ro", f"DefaultValue={subs}"]
    for sub in range(1, subs + 1):
        name = names[sub - 1] if names else f"Var {sub}"
        out += [f"[{index:04X}sub{sub:X}]", f"ParameterName={name}", "ObjectType=0x7",
                "DataType=0x0005", "AccessType=rw", "DefaultValue=0", *extra.split("\n")]
    return "\n".join(line for line in out if line) + "\n"


_TAIL = "[Comments]\nLines=0\n"   # after an array: its last sub-object ends as the others do


def _context(text: str, name: str = "t.dcf") -> DcfContext:
    data = text.encode()
    dev = model.build(ini.parse_bytes(data, name))
    return DcfContext(name, data, Options(), dev.ini, dev)


def _lines(text: str, prefix: str) -> list[int]:
    return [n for n, line in enumerate(text.split("\n"), 1) if line.startswith(prefix)]


def _found(text: str, rule: str) -> list[tuple[int, str]]:
    res = lint_bytes("t.dcf", text.encode(), Options(active={rule}))
    assert not res.tracebacks
    return [(d.line, d.message) for d in res.diagnostics if d.rule == rule]


# -- per-template verdicts --------------------------------------------------------------------

def test_the_subs_of_an_array_share_one_template():
    """The premise of the tests below: the reader gives the sub-objects one template."""
    ctx = _context(_HEAD + _array(0x2000, 5, "Foo=1") + _TAIL)
    subs = [ctx.ini.sections[f"2000sub{s:x}"] for s in range(1, 6)]
    assert len({id(s.rest) for s in subs}) == 1
    groups = [g for g in ctx.groups if g[2][0] is subs[0]]
    assert len(groups) == 1 and groups[0][2] == subs


@pytest.mark.parametrize("rule, extra, prefix, message", [
    ("DCF050", "Foo=1", "Foo=", "key 'Foo' is not defined by CiA 306 for [2000sub{s:X}]"),
    ("DCF058", "PDOMapping=2", "PDOMapping=",
     "[2000sub{s:X}] PDOMapping=2 is not 0 or 1 (read as not mappable)"),
    ("DCF055", "PDOMapping=yes", "PDOMapping=",
     "[2000sub{s:X}] PDOMapping: invalid integer 'yes'"),
    ("DCF216", "ObjFlags=4", "ObjFlags=", "[2000sub{s:X}] ObjFlags=0x4 sets reserved bits"),
    ("DCF057", "PDOMapping=1 ; mappable", "PDOMapping=",
     "comment '; mappable' after the number '1' is ignored"),
])
def test_a_template_verdict_reports_every_section_at_its_line(rule, extra, prefix, message):
    text = _HEAD + _array(0x2000, 5, extra) + _TAIL
    found = _found(text, rule)
    lines = _lines(text, prefix)
    assert len(lines) == 5
    assert [line for line, _ in found] == lines
    assert [m for _, m in found] == [message.format(s=s) for s in range(1, 6)]


def test_names_are_checked_section_by_section():
    """DCF053/DCF114: the names are cut out of the template; only the offending sections
    of it are reported, each at its own line."""
    names = ["a", "x" * 242, "", "b", "y" * 250]
    text = _HEAD + _array(0x2000, 5, names=names) + _TAIL
    name_lines = _lines(text, "ParameterName=")
    long = _found(text, "DCF053")
    assert [line for line, _ in long] == [name_lines[4], name_lines[7]]   # after [2000], sub0
    assert [m for _, m in long] == [
        "ParameterName of [2000sub2] has 242 characters, more than 241",
        "ParameterName of [2000sub5] has 250 characters, more than 241"]
    missing = _found(text, "DCF114")
    header = _lines(text, "[2000sub3]")
    assert missing == [(header[0], "[2000sub3] has no ParameterName")]


def test_a_line_too_long_first_or_one_after_another():
    text = ";" + "c" * 300 + "\n" + _HEAD + _array(0x2000, 2, "LowLimit=" + "2" * 250)
    text = text.replace("[DeviceInfo]", f"[DeviceInfo]\n;{'d' * 260}\n;{'e' * 270}")
    found = _found(text, "DCF052")
    assert found == [(n, f"line has {len(text.split(chr(10))[n - 1])} characters, more than 255")
                     for n in [1, 5, 6] + _lines(text, "LowLimit=")]


# -- the tables against the plain walks -------------------------------------------------------

_SUB = re.compile(r"([0-9a-f]{4})sub([0-9a-f]+)")
_BLANK_COMMENT = re.compile(r"=[^=\n]*?[ \t][;#]")


def _check_tables(ctx: DcfContext) -> None:
    sections = ctx.ini.sections
    kinds = {c: classify(c) for c in sections}
    assert list(ctx.kinds.items()) == list(kinds.items())
    for kind in set(kinds.values()):
        pairs = [(c, s) for c, s in sections.items() if kinds[c] == kind]
        assert ctx.of_kind(kind) == pairs
        assert list(ctx.each_of_kind(kind)) == pairs
        assert tables.kind_sections(ctx, kind) == [s for _, s in pairs]
    subs: dict = {}
    for canon, sec in sections.items():
        m = _SUB.fullmatch(canon)
        if m and int(m.group(2), 16) <= 0xFF:
            subs.setdefault(int(m.group(1), 16), {})[int(m.group(2), 16)] = sec
    assert ctx.sub_sections == subs
    assert tables.sub_counts(ctx) == {i: len(s) for i, s in subs.items()}
    covered = []
    for kind, rest, secs in ctx.groups:
        assert all(kinds_of == kind for kinds_of in (classify(c) for c, s in sections.items()
                                                      if any(s is x for x in secs)))
        covered += secs
        for key in ("pdomapping", "objflags", "datatype", "accesstype", "lowlimit"):
            assert [tables.group_get(rest, secs, key)] * len(secs) == [s.get(key) for s in secs]
        for key in ("parametername", "denotation"):
            assert tables.name_values(rest, secs, key) == [s.get(key) for s in secs]
        assert all(list(ctx.key_names(s)) == list(ctx.key_names(secs[0])) for s in secs)
        if rest is not None:        # DCF050 reads a group's key names from its template
            assert list(rest) == list(ctx.key_names(secs[0]))
    assert sorted(map(id, covered)) == sorted(map(id, sections.values()))
    nameless = tables.nameless(ctx)
    assert {i for ids in nameless.values() for i in ids} == {
        id(s) for c, s in sections.items()
        if kinds[c] in tables.NAMED_KINDS and s.get("parametername") is None}
    entries = [e for i in sorted(ctx.dev.objects) for e in ctx.dev.objects[i].entries.values()
               if not e.implicit]
    assert tables.entries(ctx) == entries
    for attrs in (("download_file",), ("param",), ("low", "high")):
        assert tables.entries_with(ctx, *attrs) == [
            e for e in entries if any(getattr(e, a) is not None for a in attrs)]
    for kinds_ in (frozenset({"vstring", "ustring"}), frozenset({"ostring", "domain"})):
        assert tables.entries_of_kinds(ctx, kinds_) == [
            e for e in entries if e.dtype is not None and e.dtype.kind in kinds_]
    text = ctx.text            # (the file's bytes when each is one character)
    text = text.decode("latin-1") if isinstance(text, bytes) else text
    assert ctx.blank_comment == (_BLANK_COMMENT.search(text) is not None)


_ODD = {
    "last-section-a-sub": _HEAD + _array(0x2000, 3),
    "no-sections": "; nothing\n",
    "respelled-and-big-subindex": _HEAD + "[1018sub001]\nParameterName=x\n[1018SUB02]\n"
                                  "ParameterName=y\n[1018sub100]\nParameterName=z\n[1018]\n"
                                  "ParameterName=Identity\nObjectType=0x9\n",
    "exact-reader": _HEAD.replace("AccessType=ro", "AccessType=ro\nAccessType=rw")
                    + _array(0x2000, 3, "Foo=1"),
    "crlf": (_HEAD + _array(0x2001, 2, "ObjFlags=8")).replace("\n", "\r\n"),
    "names-out-of-order": _HEAD + "[2000sub1]\nParameterName=a\n[2000]\nParameterName=A\n"
                          "ObjectType=0x8\n[3000]\n[2000sub0]\nParameterName=n\n"
                          "[2000sub2]\nParameterName=\n",
    "denotations": _HEAD + _array(0x2002, 3, "Denotation=d"),
    "comments": _HEAD + "[1001]\nParameterName=e ; r\nObjectType=0x7 # x\nDefaultValue=1\n"
                ";a=b ;c\nx ; no equals\n",
}


@pytest.mark.parametrize("name", sorted(_ODD))
def test_tables_equal_the_plain_walks_on_odd_files(name):
    _check_tables(_context(_ODD[name]))


def _files():
    roots = [ROOT / "samples", ROOT / "tests" / "fixtures"]
    files = sorted(p for r in roots for p in r.rglob("*")
                   if p.suffix.lower() in (".dcf", ".eds") and p.is_file())
    return files + corpus_files()


def test_tables_equal_the_plain_walks_on_every_sample_fixture_and_corpus_file():
    checked = 0
    for path in _files():
        data = path.read_bytes()
        try:
            dev = model.build(ini.parse_bytes(data, str(path)))
        except Exception:   # noqa: BLE001 - files the model refuses have no tables to check
            continue
        _check_tables(DcfContext(str(path), data, Options(), dev.ini, dev))
        checked += 1
    assert checked > 50


def test_long_lines_are_those_a_line_by_line_search_finds():
    """DCF052 looks for long lines a window at a time (rules_syntax._long_lines): the same
    lines as the search at every line start, on lines around the limit, empty lines, CRs,
    a long first or last line, with and without a final line end."""
    import random

    from dcf2bin.lint.rules_syntax import _long_lines
    rnd = random.Random(22)
    for trial in range(300):
        lines = [rnd.choice(["", "k=v", "x" * rnd.randint(240, 270), "y" * rnd.randint(0, 600),
                             "z" * 255 + "\r", "w" * 256]) for _ in range(rnd.randint(0, 12))]
        text = "\n".join(lines) + rnd.choice(["", "\n"])
        for width in (256, 5):
            expected = [m.span() for m in re.finditer(r"^[^\n]{%d,}" % width, text, re.M)]
            assert list(_long_lines(text, width)) == expected, (trial, width)


@pytest.mark.parametrize("key, length, reported", [
    ("Denotation", 242, True), ("Denotation", 241, False),
    ("ParameterName", 242, True), ("ParameterName", 241, False)])
def test_a_name_just_over_the_limit_is_found_on_the_shortest_line_that_holds_it(
        key, length, reported):
    """DCF053 looks at the sections only when some line can hold a name of more than 241
    characters: "Denotation=" and 242 characters, 253 in all, is the shortest."""
    name = "" if key == "ParameterName" else "ParameterName=x\n"
    text = _HEAD + f"[2000]\n{name}ObjectType=0x7\nDataType=0x0005\n" \
                   f"AccessType=rw\nDefaultValue=0\n{key}={'n' * length}\n" + _TAIL
    line = _lines(text, f"{key}=n")[0]
    expected = [(line, f"{key} of [2000] has {length} characters, more than 241")]
    assert _found(text, "DCF053") == (expected if reported else [])


def test_the_blank_comment_check_is_the_search_it_replaces():
    """DCF057/DCF203 skip their walk when no line has an '=' and after it a blank and a
    ';' or '#' (context._blank_comment, from the ';' and '#' of the text)."""
    import random

    from dcf2bin.lint.context import _blank_comment
    rnd = random.Random(7)
    texts = ["a=b ;c", ";a=b", "x ;y\na=b", "a=b\tx #c", "=;", "a ;=b", " ;", "a=\n ;",
             "a==b ;", "a=b;c", "a=b ;c\r\n", ""]
    texts += ["".join(rnd.choice("=; #\t\na") for _ in range(rnd.randint(0, 30)))
              for _ in range(3000)]
    for text in texts:
        assert _blank_comment(text) == (_BLANK_COMMENT.search(text) is not None), repr(text)
        assert _blank_comment(text.encode()) == _blank_comment(text), repr(text)


def test_unknown_keys_is_known_key_for_each():
    from dcf2bin.lint.vocabulary import FIXED, NUMBERED, known_key, unknown_keys
    keys = ["parametername", "subnumber", "compactsubobj", "foo", "filename", "nrofentries",
            "line1", "line", "tool3", "dummy0001", "vendorname", "1", "supportedobjects",
            "type1", "x", "nodeid", "items", "name", "type12", "typex", "range", "range3",
            "ppoffset0", "line\u0663", "tool", "1a", "", "maxcnt", "pioffset7", "dir"]
    for kind in ["object", "sub", "dummyusage", "aux", "nonsense", *FIXED, *NUMBERED]:
        assert unknown_keys(kind, keys) == [k for k in keys if not known_key(kind, k)], kind


# -- values the model encoded already ----------------------------------------------------------

_VALUES = [("0x0007", "0x20000008"), ("0x0007", "$NODEID+0x180"), ("0x0007", "384 ; cob"),
           ("0x0003", "0xFFFF"), ("0x0003", "-2"), ("0x0001", "1"), ("0x0005", "256"),
           ("0x0005", "abc"), ("0x0004", "0x80000000"), ("0x0009", "text ; not a comment"),
           ("0x0007", "$NODEID+0x180 ; with a comment")]


def _values_file(node_id: str) -> str:
    out = [_HEAD.replace("[DeviceInfo]", f"[DeviceComissioning]\n{node_id}\n[DeviceInfo]")]
    for k, (dtype, value) in enumerate(_VALUES):
        out.append(f"[{0x2000 + k:04X}]\nParameterName=v{k}\nObjectType=0x7\nDataType={dtype}\n"
                   f"AccessType=rw\nParameterValue={value}\n")
    return "".join(out)


@pytest.mark.parametrize("node_id", ["NodeID=5", ""])
def test_values_encoded_by_the_model_give_the_same_verdicts(node_id):
    # int_value and DCF200 take a value the model encoded already (Device.encoded, filled
    # by the selection) as it is: the same as encoding it again, $NODEID, signed hex,
    # numeric comments (never in the cache) and values that cannot be encoded included
    from dcf2bin import select
    from dcf2bin.lint import rules_values
    text = _values_file(node_id)
    fresh, warm = _context(text), _context(text)
    select.select(warm.dev)
    assert warm.dev.encoded and not fresh.dev.encoded
    es = tables.entries(fresh)
    warm_es = tables.entries(warm)
    assert [fresh.int_value(e) for e in es] == [warm.int_value(e) for e in warm_es]
    assert list(rules_values.bad_value(fresh)) == list(rules_values.bad_value(warm))
    # (fresh gets no encodings from these: it stays the plain path)
    assert not fresh.dev.encoded


def test_the_text_scans_read_bytes_and_decoded_text_alike():
    """The rules that scan the file's text (DCF052, DCF057/DCF203 and every column) read
    its bytes when each is one character (ASCII, Latin-1) and the decoded text otherwise
    (issue 26: no 60 MB copy): the same findings, columns counted in characters."""
    from conftest import ROOT
    from dcf2bin.lint import Options, lint_bytes
    base = (ROOT / "tests" / "fixtures" / "lint" / "DCF200.fail.dcf").read_text()
    long = "Description=" + "x" * 300
    outs = []
    for accent, encoding in (("e", "ascii"), ("\u00e9", "latin-1"), ("\u00e9", "utf-8")):
        text = base.replace("Description=dcf2bin validate fixture",
                            f"Description={accent}\n{long}{accent}\n  ; {accent}")
        for nl in ("\n", "\r\n"):
            data = text.replace("\n", nl).encode(encoding)
            ctx_kind = type(_text_of(data)).__name__
            outs.append([(d.rule, d.line, d.column, d.message)
                         for d in lint_bytes("t.dcf", data, Options()).diagnostics])
            assert ctx_kind == ("str" if encoding == "utf-8" else "bytes")
    assert all(out == outs[0] for out in outs)
    assert ("DCF052", 7, 256, "line has 313 characters, more than 255") in outs[0]
    assert any(rule == "DCF200" and column for rule, _, column, _ in outs[0])


def _text_of(data: bytes):
    """A DcfContext's ``text`` for ``data``."""
    from dcf2bin import ini, model
    from dcf2bin.lint.context import DcfContext, Options
    parsed = ini.parse_bytes(data, "t.dcf")
    return DcfContext("t.dcf", data, Options(), parsed, model.build(parsed)).text
