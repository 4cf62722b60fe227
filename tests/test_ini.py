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
    f = parse(b"")
    assert f.sections == {} and list(f.diagnostics) == []
