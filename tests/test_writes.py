"""Extra writes (ordered write sequences) and the DIS-2 tunnel helper (SPEC §6, seed 004)."""
from __future__ import annotations

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES
from dcf2bin.cli import main
from dcf2bin.diagnostics import DcfError
from dcf2bin.select import Write
from dcf2bin.writes import (ExtraWritesError, load_extra_writes, parse_extra_writes,
                            read_extra_writes, tunnel_writes)

SAMPLE = SAMPLES / "dis2_identification.writes"


def run(*args, input=None):
    return CliRunner().invoke(main, list(args), input=input, catch_exceptions=False)


# -- the sample ----------------------------------------------------------------------------

def test_sample_loads_to_the_exact_write_list():
    # seed 004 §6.1: 0x2200 := 0x1A (select KO 0x001A), 0x2214 := 1 (start the motor
    # identification); §6.2: 0x2200 := 0x84 (select KO 0x0084, read through 0x2204).
    # All three objects are UINT32 (4 bytes); 0x2200 rw -> 0x70, 0x2214 wo -> 0x50 (D-9).
    assert load_extra_writes(str(SAMPLE)) == [
        Write(0x2200, 0, b"\x1a\x00\x00\x00", 0x70),
        Write(0x2214, 0, b"\x01\x00\x00\x00", 0x50),
        Write(0x2200, 0, b"\x84\x00\x00\x00", 0x70),
    ]


def test_sample_lines_and_comments():
    got = [(x.where.line, x.access, x.comment) for x in read_extra_writes(str(SAMPLE))]
    assert got == [(12, "rw", "KO 0x001A: select"),
                   (13, "wo", "KO 0x001A := 0x00000001"),
                   (14, "rw", "KO 0x0084: select for reading through 0x2204 (value)")]


def test_sample_is_what_the_tunnel_command_writes(tmp_path):
    out = tmp_path / "x.writes"
    r = run("tunnel", "0x1A=1", "--read", "0x84", "-o", str(out))
    assert r.exit_code == 0, r.output
    assert r.stderr == "x.writes: 3 writes\n"
    assert out.read_bytes() == SAMPLE.read_bytes()


def test_tunnel_to_stdout_with_read_mode_and_negative_value():
    r = run("tunnel", "26=-1", "0x20=012", "-r", "0x84", "-r", "0x85", "--read-mode", "max")
    assert r.exit_code == 0
    body = [ln for ln in r.stdout.splitlines() if not ln.startswith("#")]
    assert body == [
        "0x2200  0x00  UNSIGNED32  0x0000001A  rw   ; KO 0x001A: select",
        "0x2214  0x00  UNSIGNED32  0xFFFFFFFF  wo   ; KO 0x001A := 0xFFFFFFFF",
        "0x2200  0x00  UNSIGNED32  0x00000020  rw   ; KO 0x0020: select",
        "0x2214  0x00  UNSIGNED32  0x0000000A  wo   ; KO 0x0020 := 0x0000000A",
        "0x2200  0x00  UNSIGNED32  0x00030084  rw   ; KO 0x0084: select for reading through "
        "0x2204 (max)",
        "0x2200  0x00  UNSIGNED32  0x00030085  rw   ; KO 0x0085: select for reading through "
        "0x2204 (max)",
    ]
    assert "# note: 0x2204 reads the KO selected last (0x0085)" in r.stdout
    assert "# made by: dcf2bin tunnel 0x001A=0xFFFFFFFF 0x0020=0x0000000A --read 0x0084 " \
           "--read 0x0085 --read-mode max" in r.stdout
    # and what it prints loads back
    writes, errors = parse_extra_writes(r.stdout, "t.writes")
    assert errors == [] and [w.write.data for w in writes][1] == b"\xff\xff\xff\xff"


@pytest.mark.parametrize("args, message", [
    ((), "give at least one KO=VALUE or --read KO"),
    (("1A=1",), "Invalid value for KO=VALUE: KO number '1A': invalid integer '1A'"),
    (("0x1A",), "Invalid value for KO=VALUE: '0x1A' is not KO=VALUE"),
    (("0x1A=",), "Invalid value for KO=VALUE: '0x1A=' is not KO=VALUE"),
    (("0x10000=1",), "Invalid value for KO=VALUE: KO number 0x10000 is outside 0..0xFFFF"),
    (("1=0x100000000",), "Invalid value for KO=VALUE: value 0x100000000 does not fit 32 bits"),
    (("1=-0x80000001",), "Invalid value for KO=VALUE: value -0x80000001 does not fit 32 bits"),
    (("-r", "08"), "Invalid value for --read: KO number '08': invalid octal literal '08'"),
])
def test_tunnel_usage_errors(args, message):
    r = run("tunnel", *args)
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == f"Error: {message}"


def test_tunnel_writes_refuses_bad_arguments():
    with pytest.raises(ValueError, match="outside 0..0xFFFF"):
        tunnel_writes([(0x10000, 1)], [])
    with pytest.raises(ValueError, match="does not fit 32 bits"):
        tunnel_writes([(1, 1 << 32)], [])
    with pytest.raises(ValueError, match="read mode 1"):
        tunnel_writes([], [1], read_mode=1)


# -- the format ------------------------------------------------------------------------------

def parse(text: str, **kw):
    return parse_extra_writes(text, "f.writes", **kw)


def test_format_fields_comments_quotes_access_and_map():
    text = "\n".join([
        "# a comment line",
        "; another",
        "",
        "0x2000 1 UNSIGNED8 0x10        ; trailing comment",
        "0x2000 0x02 unsigned16 012 wo  # octal 10, write-only",
        "0x2001 0 VISIBLE_STRING \"two words; #3\" ro",
        "0x2002 0 OCTET_STRING \"01 02 03\" rw map",
        "0x2003 0 0x0009 abc#def",
        "0x2004 0 BOOLEAN TRUE const",
        "0x2005 0 INTEGER24 -1 map",
        "0x2006 0 REAL32 0.5",
        "0x2007 0 DOMAIN \"\"",
        "0xA4C0 1 UNSIGNED8 7",
        "0x2008 0 UNSIGNED32 $NODEID+0x180\r",
    ])
    writes, errors = parse(text, node_id=3)
    assert errors == []
    got = [(w.write.index, w.write.sub, w.write.data, w.write.attr, w.where.line)
           for w in writes]
    assert got == [
        (0x2000, 1, b"\x10", 0x70, 4),                 # NUMERIC|R|W (default rw)
        (0x2000, 2, b"\x0a\x00", 0x50, 5),             # wo -> NUMERIC|W
        (0x2001, 0, b"two words; #3", 0x28, 6),        # VISIBLE_STRING|R
        (0x2002, 0, b"\x01\x02\x03", 0xE0, 7),         # DOMAIN-like: R|W|PDO
        (0x2003, 0, b"abc#def", 0x68, 8),              # '#' without a blank is data
        (0x2004, 0, b"\x01", 0x21, 9),                 # BOOLEAN|R (const)
        (0x2005, 0, b"\xff\xff\xff", 0xF0, 10),        # INTEGER24 rw map
        (0x2006, 0, b"\x00\x00\x00\x3f", 0x70, 11),
        (0x2007, 0, b"", 0x60, 12),
        (0xA4C0, 1, b"\x07", 0xF0, 13),                # a network variable: always 0xF0
        (0x2008, 0, (0x183).to_bytes(4, "little"), 0x70, 14),
    ]
    assert writes[0].comment == "trailing comment"
    assert writes[1].comment == "octal 10, write-only"


def test_repeated_writes_are_kept_in_order():
    writes, errors = parse("0x2200 0 UNSIGNED32 1\n0x2200 0 UNSIGNED32 2\n0x2200 0 UNSIGNED32 1\n")
    assert errors == []
    assert [w.write.data[0] for w in writes] == [1, 2, 1]


def test_errors_are_one_line_with_file_and_line():
    text = "\n".join([
        "0x2200 0 UNSIGNED32",                         # 1 too few fields
        "2200 0 UNSIGNED32 1",                         # 2 decimal index
        "0x0FFF 0 UNSIGNED32 1",                       # 3 below 0x1000
        "0x2200 0x100 UNSIGNED32 1",                   # 4 subindex
        "0x2200 0 UINT32 1",                           # 5 type name
        "0x2200 0 UNSIGNED8 300",                      # 6 range
        "0x2200 0 UNSIGNED32 $NODEID+1",               # 7 no node-ID
        "0x2200 0 UNSIGNED32 1 rx",                    # 8 access
        "0x2200 0 VISIBLE_STRING \"open",              # 9 quote
        "0x2200 0 VISIBLE_STRING \"a\"b",              # 10 quote
        "0x2200 0 UNSIGNED32 1 rw rw",                 # 11 two access types
        "0x2200 0 UNSIGNED32 1;c",                     # 12 ';' without a blank is data
    ])
    writes, errors = parse(text)
    assert writes == []
    assert [d.format() for d in errors] == [
        "f.writes:1: error: expected INDEX SUB TYPE VALUE [ACCESS] [map], got 3 field(s) [XW001]",
        "f.writes:2: error: index '2200' must be hexadecimal with 0x (e.g. 0x2200) [XW002]",
        "f.writes:3: error: index 0x0FFF is outside 0x1000..0xFFFF [XW002]",
        "f.writes:4: error: subindex 0x100 is outside 0..255 [XW003]",
        "f.writes:5: error: unknown data type 'UINT32' [XW004]",
        "f.writes:6: error: 0x2200sub0: value 300 out of range for UNSIGNED8 (0..255) [DCF200]",
        "f.writes:7: error: value '$NODEID+1' uses $NODEID but no node-ID is known [DCF201]",
        "f.writes:8: error: unexpected field 'rx' after the value (expected an access type "
        "ro/wo/rw/rwr/rww/const and/or 'map') [XW005]",
        "f.writes:9: error: unterminated double quote [XW001]",
        "f.writes:10: error: a closing double quote must be followed by a blank [XW001]",
        "f.writes:11: error: unexpected field 'rw' after the value (expected an access type "
        "ro/wo/rw/rwr/rww/const and/or 'map') [XW005]",
        "f.writes:12: error: 0x2200sub0: invalid integer '1;c' [DCF200]",
    ]
    assert errors[6].hint == "give --node-id N"


def test_load_raises_one_dcf_error_carrying_all(tmp_path):
    path = tmp_path / "bad.writes"
    path.write_text("0x2200 0 UNSIGNED32 1\n0x2200 0 UNSIGNED8 999\n\nbad\n")
    with pytest.raises(ExtraWritesError) as info:
        load_extra_writes(str(path))
    exc = info.value
    assert isinstance(exc, DcfError)
    assert str(exc) == f"{path}:2: error: 0x2200sub0: value 999 out of range for UNSIGNED8 " \
                       "(0..255) [DCF200]"
    assert [(d.line, d.rule) for d in exc.diagnostics] == [(2, "DCF200"), (4, "XW001")]


def test_load_from_data_and_unreadable_file(tmp_path):
    assert load_extra_writes("mem.writes", b"\xef\xbb\xbf0x2000 0 UNSIGNED8 1\n") == [
        Write(0x2000, 0, b"\x01", 0x70)]
    with pytest.raises(ExtraWritesError) as info:
        load_extra_writes(str(tmp_path / "missing.writes"))
    assert info.value.diagnostic.message == "cannot read: No such file or directory"


def test_latin1_file_keeps_its_string_bytes():
    data = "0x2000 0 VISIBLE_STRING Motor\xb0C\n".encode("latin-1")
    assert load_extra_writes("l.writes", data)[0].data == b"Motor\xb0C"
    utf8 = "0x2000 0 VISIBLE_STRING Motor\xb0C\n".encode("utf-8")
    assert load_extra_writes("u.writes", utf8)[0].data == b"Motor\xc2\xb0C"


def test_node_id_keyword():
    writes = load_extra_writes("n.writes", b"0x1800 1 UNSIGNED32 $NODEID+0x40000180\n",
                               node_id=5)
    assert writes == [Write(0x1800, 1, (0x40000185).to_bytes(4, "little"), 0x70)]


# -- with compile --append (wired by cli/compile.py) -------------------------------------------------

def test_compile_append_adds_the_writes_after_all_groups(tmp_path):
    from dcf2bin.container import BinContainer, read
    out = tmp_path / "dis2_id.bin"
    r = run("compile", str(SAMPLES / "dis2.dcf"), "--profile", "dis2", "--append",
            str(SAMPLE), "-o", str(out))
    assert r.exit_code == 0, r.output
    base, _ = read((SAMPLES / "dis2.bin").read_bytes())
    extra = load_extra_writes(str(SAMPLE))
    want = BinContainer(entries=base.entries + [(w.index, w.sub, w.data) for w in extra],
                        attributes=base.attributes + bytes(w.attr for w in extra))
    assert out.read_bytes() == want.to_bytes()


# -- documentation ---------------------------------------------------------------------------

def test_man_page_has_examples_and_the_format():
    # every option is checked by tests/test_man.py
    page = (ROOT / "man" / "dcf2bin-tunnel.1").read_text()
    assert ".SH EXAMPLES" in page and "The extra\\-writes format" in page


def test_docs_describe_the_format():
    doc = (ROOT / "docs" / "export.md").read_text()
    for needle in ("## Write sequences", "0x2200", "0x2214", "0x2204", "--append",
                   "load_extra_writes"):
        assert needle in doc, needle
