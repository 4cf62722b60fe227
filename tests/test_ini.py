"""The line-tracking INI reader (SPEC §1)."""
from __future__ import annotations

from dcf2bin import ini


def parse(text: str | bytes):
    data = text.encode("utf-8") if isinstance(text, str) else text
    return ini.parse_bytes(data, "t.dcf")


def test_case_insensitive_names_and_lines():
    f = parse("; comment\n# also a comment\n[1018SUB01]\nPARAMETERNAME = Vendor  \n\n[deviceinfo]\nVendorName=X\n")
    sec = f.section("1018sub1")
    assert (sec.name, sec.line) == ("1018SUB01", 3)
    assert sec.keys["parametername"] == ini.Key("PARAMETERNAME", "Vendor", 4)
    assert f.section("deviceinfo").get("vendorname") == "X"


def test_sub_sections_with_leading_zeros_are_one_section():
    f = parse("[1018sub01]\nA=1\n[1018sub1]\nA=2\n")
    assert [(d.section, d.key, d.first_line, d.line) for d in f.duplicates] == [
        ("1018sub1", None, 1, 3)]
    assert f.section("1018sub1").get("a") == "1"


def test_duplicate_keys_name_both_lines():
    f = parse("[2000]\nDefaultValue=1\ndefaultvalue=2\n")
    assert [(d.section, d.key, d.first_line, d.line) for d in f.duplicates] == [
        ("2000", "defaultvalue", 2, 3)]


def test_crlf_bom_and_empty_values():
    f = parse(b"\xef\xbb\xbf[2000]\r\nDefaultValue=\r\nParameterName=Motor #1\r\n")
    sec = f.section("2000")
    assert sec.get("defaultvalue") is None            # empty counts as absent
    assert sec.get("parametername") == "Motor #1"     # no inline comments
    assert f.encoding == "utf-8"


def test_latin1_fallback():
    f = parse(b"[2000]\nParameterName=Temperatur \xb0C\n")
    assert f.encoding == "latin-1"
    assert f.section("2000").get("parametername") == "Temperatur \u00b0C"


def test_syntax_errors():
    f = parse("orphan=1\n[2000\n[2001] trailing\n[2002] ; comment\nno equals sign\n=value\n")
    assert [d.format() for d in f.diagnostics] == [
        "t.dcf:1: error: key outside any section: 'orphan=1' [DCF001]",
        "t.dcf:2: error: malformed section header '[2000': missing ']' [DCF003]",
        "t.dcf:3: error: text after section header: 'trailing' [DCF003]",
        "t.dcf:4: warning: comment after section header ignored: '; comment' [DCF004]",
        "t.dcf:5: error: line without '=': 'no equals sign' [DCF002]",
        "t.dcf:6: error: key missing before '=': '=value' [DCF002]",
    ]


def test_empty_file():
    # an empty file is an error for compile and validate alike (the reader reports it)
    f = parse(b"")
    assert f.sections == {} and [d.format() for d in f.diagnostics] == [
        "t.dcf: error: the file is empty [DCF056]"]


# -- the fast path and the exact reader agree ------------------------------------------------

import pytest  # noqa: E402
from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from conftest import SAMPLES, corpus_params  # noqa: E402


def _snapshot(f: ini.IniFile):
    return {canon: (sec.name, sec.line, list(sec.values.items()),   # file order too
                    {k: (key.name, key.value, key.line) for k, key in sec.keys.items()})
            for canon, sec in f.sections.items()}


def _agree(text: str):
    fast = ini._parse_fast(text, "t.dcf", "utf-8")
    exact = ini._parse_exact(text, "t.dcf", "utf-8")
    if fast is not None:   # the fast path may decline; when it answers it must be exact
        assert not exact.duplicates and not list(exact.diagnostics)
        assert _snapshot(fast) == _snapshot(exact)
    return fast


@pytest.mark.parametrize("path", corpus_params() + [pytest.param(p, id=p.name)
                                                    for p in sorted(SAMPLES.glob("*.dcf"))])
def test_fast_path_equals_exact_reader_on_real_files(path):
    text, _ = ini.decode_bytes(path.read_bytes())
    _agree(text)


@pytest.mark.parametrize("data", [
    b"[2000]\r\nParameterName=Temp\xe9rature\r\nDataType=0x0007\r\n\r\n[ 2001 ]\r\nA=\xb0C\r\n",
    "[2000]\nParameterName=Temp\u00e9rature\nDataType=0x0007\n".encode("utf-8"),
    b"[2000]\nParameterName=T\nDataType=0x0007\n",
], ids=["latin-1", "utf-8", "ascii"])
def test_sections_read_from_the_bytes_give_the_text(data):
    # an ASCII or Latin-1 file's sections read their names and key lines from the bytes
    # when asked; they must read what the text says (a Latin-1 byte is no ASCII)
    parsed = ini.parse_bytes(data, "t.dcf")
    text, encoding = ini.decode_bytes(data)
    assert _snapshot(parsed) == _snapshot(ini._parse_exact(text, "t.dcf", encoding))


_LINE = st.one_of(
    st.sampled_from(["", " ", "; c=1", "# c", "[2000]", "[2000sub1]", "[2000SUB01]", " [2001]",
                     "[2001] ; x", "[]", "[a]b]", "Key=v", "key=V2", "KEY = v ", "k\t=\tv",
                     "=v", "novalue", "ParameterName=Motor #1", "x=a=b", "\r", "k=v\r"]),
    st.text(alphabet="[]=;# \tkKv01\r", max_size=8))


@settings(max_examples=400, deadline=None)
@given(st.lists(_LINE, max_size=12), st.sampled_from(["\n", "\r\n"]))
def test_fast_path_equals_exact_reader_on_generated_text(lines, eol):
    _agree(eol.join(lines))


def test_fast_path_takes_clean_files():
    assert _agree("[2000]\nA=1\n\n[2000sub1]\nb=2\n") is not None
    assert _agree("[2000]\nA = 1\n") is not None          # blanks: strip mode
    assert _agree("[2000]\nA=1\nA=2\n") is None            # duplicate: exact reader reports it


def test_fast_path_shares_a_template_but_not_the_values():
    """Sections that differ only in the value of ParameterName= share one parsed template
    (Section.rest), wherever that line stands; each keeps its own values in file order."""
    text = ("[A040sub1]\nDataType=0x0005\nParameterName=a\nAccessType=ro\n\n"
            "[A040sub2]\nDataType=0x0005\nParameterName=b\nAccessType=ro\n\n"
            "[A040sub3]\nParameterName=c\nDataType=0x0005\nAccessType=ro\n")
    f = _agree(text)
    s1, s2, s3 = (f.section(f"a040sub{i}") for i in (1, 2, 3))
    assert s1.rest is s2.rest and s1.rest is not s3.rest
    assert (s1.param_name, s2.param_name, s3.param_name) == ("a", "b", "c")
    assert list(s2.values.items()) == [("datatype", "0x0005"), ("parametername", "b"),
                                       ("accesstype", "ro")]
    s1.values["datatype"] = "0x0006"
    assert s2.get("datatype") == "0x0005" and s2.rest["datatype"] == "0x0005"
    assert s3.keys["parametername"] == ini.Key("ParameterName", "c", 12)


def test_fast_path_crlf_keeps_lines():
    f = _agree("; c\r\n[2000]\r\nParameterName=x\r\n\r\n[2000sub1]\r\nA=1\r\n")
    assert f.section("2000sub1").line == 5
    assert f.section("2000sub1").keys["a"] == ini.Key("A", "1", 6)


def test_fast_path_cuts_denotations_out_of_the_template_too():
    text = ("[A040sub1]\nParameterName=a\nDataType=0x0005\nDenotation=Pump 1\n\n"
            "[A040sub2]\nParameterName=b\nDataType=0x0005\nDenotation=Pump 2\n\n"
            "[A040sub3]\nParameterName=c\nDataType=0x0005\nDenotation=\n\n"
            "[A040sub4]\nParameterName=d\nDataType=0x0005\nDenotation=x=Denotation=y\n")
    f = _agree(text)
    secs = [f.section(f"a040sub{i}") for i in (1, 2, 3, 4)]
    assert all(s.rest is secs[0].rest for s in secs)
    assert [s.denotation for s in secs] == ["Pump 1", "Pump 2", "", "x=Denotation=y"]
    assert list(secs[1].values.items()) == [("parametername", "b"), ("datatype", "0x0005"),
                                            ("denotation", "Pump 2")]
    assert secs[2].get("denotation") is None          # empty counts as absent


def test_fast_path_cuts_only_whole_lines():
    """A name key inside another line's value is not the name line."""
    text = ("[2000]\nDescription=see ParameterName=x\nParameterName=real\n"
            "Notes=Denotation=no\n")
    f = _agree(text)
    sec = f.section("2000")
    assert (sec.param_name, sec.denotation) == ("real", None)
    assert sec.get("description") == "see ParameterName=x" and sec.get("notes") == "Denotation=no"


@pytest.mark.parametrize("blank", ["\x0b", "\x0c", "\xa0", "\u3000"])
def test_fast_path_leaves_other_blanks_around_a_header_name_to_the_exact_reader(blank):
    """canonical_section strips every kind of blank; the fast path only space and tab."""
    text = f"[1000{blank}]\nA=1\n[1000]\nB=2\n"
    assert _agree(text) is None
    f = ini.parse_text(text, "t.dcf")
    assert [(d.section, d.first_line, d.line) for d in f.duplicates] == [("1000", 1, 3)]
