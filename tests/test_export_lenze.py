"""Lenze PLC Designer master OD export (seed 001, SPEC §7): packed layout, ST text, model."""
from __future__ import annotations

import re
import struct

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES, corpus_params, corpus_pick_params
from dcf2bin import datatypes as dt
from dcf2bin import model, values
from dcf2bin.cli import main
from dcf2bin.export import FORMATS, run
from dcf2bin.export import lenze
from dcf2bin.schema import LenzeRecord

SMALL = b"""[1000]
ParameterName=Device type
DataType=0x0007
AccessType=ro
DefaultValue=0x00020192

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=3

[1018sub0]
ParameterName=Highest sub-index supported
DataType=0x0005
AccessType=ro
DefaultValue=2

[1018sub1]
ParameterName=Vendor-ID
DataType=0x0007
AccessType=ro
DefaultValue=0x12345678

[1018sub2]
ParameterName=Setting
DataType=0x0006
AccessType=rw
DefaultValue=0xBEEF

[2000]
ParameterName=Offset
DataType=0x0002
AccessType=rw
PDOMapping=1
DefaultValue=-1

[2001]
ParameterName=Tag
DataType=0x0009
AccessType=const
DefaultValue=AB

[2002]
ParameterName=Gain
DataType=0x0008
AccessType=wo
DefaultValue=1.0
"""

# 12 bytes per record: DWORD dwIdxSubIdxF, DWORD dwContent, WORD wLen, BYTE byAttrib,
# BYTE byAccess, all little-endian (seed 001; SPEC §7).
SMALL_BIN = """
41000010 92010200 0400 30 01   # 1000sub0 flags 41; 0x00020192; len 4; NUMERIC|R; read
41001810 02000000 0400 30 01   # 1018sub0 = 2
41011810 78563412 0400 30 01   # 1018sub1 = 0x12345678
41021810 efbe0000 0400 70 03   # 1018sub2 UNSIGNED16 rw = 0xBEEF; NUMERIC|R|W; read|write
41000020 ffffffff 0400 f0 03   # 2000sub0 INTEGER8 -1 sign-extended; NUMERIC|R|W|PDO
41000120 41420000 0400 28 05   # 2001sub0 VISIBLE_STRING "AB" const; VSTRING|R; read|const
01000220 0000803f 0400 50 02   # 2002sub0 REAL32 1.0 wo, the last entry: flags 01; write
"""


def unhex(annotated: str) -> bytes:
    return bytes.fromhex("".join(line.split("#")[0] for line in annotated.strip().splitlines()))


def test_packed_layout_field_by_field():
    res = run("lenze-bin", "small.eds", data=SMALL)
    assert res.ok and res.diagnostics == []
    data = res.output
    assert data == unhex(SMALL_BIN)
    assert LenzeRecord.sizeof() == 12 and len(data) == 7 * 12
    expected = [  # (index, sub, flags, content, attrib, access)
        (0x1000, 0, 0x41, 0x00020192, 0x30, 0x01),
        (0x1018, 0, 0x41, 2, 0x30, 0x01),
        (0x1018, 1, 0x41, 0x12345678, 0x30, 0x01),
        (0x1018, 2, 0x41, 0xBEEF, 0x70, 0x03),
        (0x2000, 0, 0x41, 0xFFFFFFFF, 0xF0, 0x03),
        (0x2001, 0, 0x41, 0x00004241, 0x28, 0x05),
        (0x2002, 0, 0x01, 0x3F800000, 0x50, 0x02),
    ]
    for k, (index, sub, flags, content, attrib, access) in enumerate(expected):
        raw = data[12 * k:12 * (k + 1)]
        rec = LenzeRecord.parse(raw)
        assert rec.dwIdxSubIdxF == index << 16 | sub << 8 | flags
        assert rec.dwContent == content
        assert rec.wLen == 4
        assert rec.byAttrib == attrib
        assert rec.byAccess == access
        # the same bytes read without construct: offsets 0, 4, 8, 10, 11
        assert struct.unpack_from("<I", raw, 0)[0] == rec.dwIdxSubIdxF
        assert raw[0] == flags and raw[1] == sub and struct.unpack_from("<H", raw, 2)[0] == index
        assert struct.unpack_from("<I", raw, 4)[0] == content
        assert struct.unpack_from("<H", raw, 8)[0] == 4
        assert raw[10] == attrib and raw[11] == access
        assert LenzeRecord.build(rec) == raw


SMALL_ST_BODY = """VAR_GLOBAL
    MasterOD : ARRAY [0..6] OF CanOpenODEntry := [
        (dwIdxSubIdxF := 16#10000041, dwContent := 16#00020192, wLen := 4, byAttrib := 16#30, byAccess := 16#01), (* 1000sub0 Device type *)
        (dwIdxSubIdxF := 16#10180041, dwContent := 16#00000002, wLen := 4, byAttrib := 16#30, byAccess := 16#01), (* 1018sub0 Highest sub-index supported *)
        (dwIdxSubIdxF := 16#10180141, dwContent := 16#12345678, wLen := 4, byAttrib := 16#30, byAccess := 16#01), (* 1018sub1 Vendor-ID *)
        (dwIdxSubIdxF := 16#10180241, dwContent := 16#0000BEEF, wLen := 4, byAttrib := 16#70, byAccess := 16#03), (* 1018sub2 Setting *)
        (dwIdxSubIdxF := 16#20000041, dwContent := 16#FFFFFFFF, wLen := 4, byAttrib := 16#F0, byAccess := 16#03), (* 2000sub0 Offset *)
        (dwIdxSubIdxF := 16#20010041, dwContent := 16#00004241, wLen := 4, byAttrib := 16#28, byAccess := 16#05), (* 2001sub0 Tag *)
        (dwIdxSubIdxF := 16#20020001, dwContent := 16#3F800000, wLen := 4, byAttrib := 16#50, byAccess := 16#02)  (* 2002sub0 Gain *)
    ];
END_VAR
"""


def test_structured_text():
    res = run("lenze-st", "dir/small.eds", data=SMALL)
    text = res.output
    assert text.startswith("(* CANopen master object dictionary for Lenze PLC Designer")
    assert "from small.eds;" in text
    assert text.endswith(SMALL_ST_BODY)
    assert "TYPE CanOpenODEntry" not in text
    typed = run("lenze-st", "small.eds", data=SMALL, with_type=True, var_name="g_OD").output
    assert lenze.TYPE_DECLARATION + "\nVAR_GLOBAL\n    g_OD : ARRAY [0..6] OF" in typed


ST_ROW = re.compile(r"\(dwIdxSubIdxF := 16#([0-9A-F]{8}), dwContent := 16#([0-9A-F]{8}), "
                    r"wLen := (\d+), byAttrib := 16#([0-9A-F]{2}), byAccess := 16#([0-9A-F]{2})\)")


def st_rows(text: str) -> list[tuple[int, int, int, int, int]]:
    return [(int(a, 16), int(b, 16), int(c), int(d, 16), int(e, 16))
            for a, b, c, d, e in ST_ROW.findall(text)]


def bin_rows(data: bytes) -> list[tuple[int, int, int, int, int]]:
    out = []
    for k in range(0, len(data), 12):
        r = LenzeRecord.parse(data[k:k + 12])
        out.append((r.dwIdxSubIdxF, r.dwContent, r.wLen, r.byAttrib, r.byAccess))
    return out


def test_comment_text_cannot_close_the_comment():
    eds = b"[2000]\nParameterName=a *) b (* c \xc3\xa9\nDataType=0x0005\nAccessType=rw\n"
    text = run("lenze-st", "c.eds", data=eds).output
    assert "(* 2000sub0 a * ) b ( * c ? *)" in text


# -- content rules -------------------------------------------------------------------------

@pytest.mark.parametrize("type_name, text, content", [
    ("BOOLEAN", "1", 1),
    ("INTEGER8", "-128", 0xFFFFFF80),
    ("INTEGER16", "0x8000", 0xFFFF8000),          # a bit pattern (SPEC §1), sign-extended
    ("INTEGER24", "-2", 0xFFFFFFFE),
    ("INTEGER32", "-2147483648", 0x80000000),
    ("INTEGER64", "-1", 0xFFFFFFFF),               # fits 32 bits signed
    ("INTEGER64", "2147483647", 0x7FFFFFFF),
    ("UNSIGNED24", "0xABCDEF", 0xABCDEF),
    ("UNSIGNED64", "0xFFFFFFFF", 0xFFFFFFFF),
    ("UNSIGNED40", "0", 0),
    ("REAL32", "-2.5", 0xC0200000),
    ("REAL64", "0", 0),
    ("TIME_OF_DAY", "0x1234", 0x1234),
    ("OCTET_STRING", "0102", 0x0201),
    ("VISIBLE_STRING", '""', 0),
    ("UNICODE_STRING", "AB", 0x00420041),
    ("DOMAIN", "DEADBEEF", 0xEFBEADDE),
])
def test_content_fits(type_name, text, content):
    dtype = dt.BY_NAME[type_name]
    assert lenze.content(dtype, values.encode(dtype, text)) == content


@pytest.mark.parametrize("type_name, text, shown", [
    ("INTEGER64", "-2147483649", "value -2147483649"),
    ("UNSIGNED64", "0x100000000", "value 4294967296"),
    ("UNSIGNED48", "0xFFFFFFFFFFFF", "value 281474976710655"),
    ("REAL64", "1.5", "8-byte value"),
    ("VISIBLE_STRING", "ABCDE", "5-byte value"),
])
def test_content_that_does_not_fit_is_zero_with_a_warning(type_name, text, shown):
    eds = (f"[2000]\nDataType=0x{dt.BY_NAME[type_name].code:04X}\nAccessType=rw\n"
           f"DefaultValue={text}\n").encode()
    res = run("lenze-bin", "w.eds", data=eds)
    assert res.ok
    assert bin_rows(res.output)[0][1] == 0
    assert [d.format() for d in res.diagnostics] == [
        f"w.eds:4: warning: 0x2000sub0: {type_name} {shown} does not fit the 32-bit "
        "dwContent; exported as 0 [EXP101]"]


# -- errors ------------------------------------------------------------------------------------

def test_nodeid_needs_node_id_and_is_a_one_line_error():
    eds = b"[1800]\nObjectType=0x9\nSubNumber=2\n[1800sub1]\nDataType=0x0007\n" \
          b"AccessType=rw\nDefaultValue=$NODEID+0x180\n"
    res = run("lenze-st", "n.eds", data=eds)
    assert not res.ok
    assert [d.format() for d in res.errors] == [
        "n.eds:7: error: value '$NODEID+0x180' of 0x1800sub1 uses $NODEID but no node-ID is "
        "known [DCF201]"]
    ok = run("lenze-bin", "n.eds", data=eds, node_id=4)
    assert bin_rows(ok.output)[1][1] == 0x184


def test_bad_value_is_an_error_and_errors_below_0x1000_are_warnings():
    eds = b"[0005]\nDataType=0x0099\nAccessType=ro\n[2000]\nDataType=0x0005\nAccessType=rw\n" \
          b"DefaultValue=256\n"
    res = run("lenze-st", "b.eds", data=eds)
    assert not res.ok
    assert [d.format() for d in res.diagnostics] == [
        "b.eds:2: warning: [0005] unknown or unsupported DataType 0x0099 (not exported) [DCF030]",
        "b.eds:7: error: 0x2000sub0: value 256 out of range for UNSIGNED8 (0..255) [DCF200]"]


def test_nothing_to_export():
    res = run("lenze-st", "e.eds", data=b"[FileInfo]\nFileName=e.eds\n")
    assert [d.format() for d in res.errors] == [
        "e.eds: error: no objects from 0x1000 up: nothing to export [EXP100]"]


# -- against the model: samples and corpus -----------------------------------------------------

def expected_attrib(e) -> int:
    """SPEC §3.3 / D-9, written out again."""
    if 0xA000 <= e.index <= 0xAFFF:
        return 0x30 if e.sub == 0 else 0xF0
    t = e.dtype
    bits = 0x01 if t.kind == dt.BOOL else 0x08 if t.kind == dt.VSTRING else \
        0x10 if t.kind in (dt.SINT, dt.UINT, dt.REAL, dt.TIME) else 0
    bits |= {"ro": 0x20, "const": 0x20, "wo": 0x40}.get(e.access, 0x60)
    return bits | (0x80 if e.pdo_mapping else 0)


def expected_content(t, data: bytes) -> int:
    if t.kind == dt.REAL:
        return int.from_bytes(data, "little") if t.size == 4 else 0
    if t.kind in (dt.SINT, dt.UINT, dt.BOOL, dt.TIME):
        v = int.from_bytes(data, "little", signed=t.kind == dt.SINT)
        return v & 0xFFFFFFFF if -(1 << 31) <= v < (1 << 32) and (
            t.kind != dt.SINT or v < (1 << 31)) else 0
    return int.from_bytes(data, "little") if len(data) <= 4 else 0


def check_against_model(path, node_id=None):
    dev = model.load(str(path), node_id=node_id)
    st = run("lenze-st", str(path), node_id=node_id)
    binary = run("lenze-bin", str(path), node_id=node_id)
    assert st.ok and binary.ok, [d.format() for d in st.errors]
    rows = bin_rows(binary.output)
    assert st_rows(st.output) == rows             # the two forms say the same
    entries = [e for o in dev.sorted_objects() if o.index >= 0x1000
               for e in o.entries.values()]
    assert len(rows) == len(entries) > 0
    for k, (e, (idx_sub_f, content, length, attrib, access)) in enumerate(zip(entries, rows)):
        flags = 0x01 if k == len(rows) - 1 else 0x41
        assert idx_sub_f == e.index << 16 | e.sub << 8 | flags
        assert length == 4
        assert content == expected_content(e.dtype, dev.encode(e)), e.label
        assert attrib == expected_attrib(e), e.label
        assert access == {"ro": 1, "wo": 2, "const": 5}.get(e.access, 3), e.label
    return dev, rows


@pytest.mark.parametrize("name", ["dis2.dcf", "device.dcf", "plc.dcf", "bild8.dcf"])
def test_samples_against_model(name):
    check_against_model(SAMPLES / name)


# Corpus files that load without errors and cover many types (REAL64, 64-bit, strings,
# DOMAIN, UNICODE_STRING, TIME_*); all use $NODEID, so they get a node-ID.
CORPUS_PICKS = [("cia_profiles_kacanopen/401.eds", 1), ("canopennode/demoDevice.eds", 1),
                ("lely_core/co-gw_txt-slave.dcf", 2)]


@pytest.mark.parametrize("path, node_id", corpus_pick_params(CORPUS_PICKS))
def test_corpus_files_against_model(path, node_id):
    dev, rows = check_against_model(path, node_id)
    assert len(rows) > 20


@pytest.mark.parametrize("path", corpus_params())
def test_every_corpus_file_exports_or_fails_cleanly(path):
    res = run("lenze-bin", str(path), node_id=1)
    for d in res.diagnostics:
        assert "\n" not in d.format()
    if res.ok:
        assert len(res.output) % 12 == 0 and res.output[-12] == 0x01
    else:
        assert res.errors and all(d.file == str(path) for d in res.errors)


# -- command line ------------------------------------------------------------------------------

def cli(*args, input=None):
    return CliRunner().invoke(main, list(args), input=input, catch_exceptions=False)


def test_cli_writes_text_to_stdout_and_binary_to_a_file(tmp_path):
    src = tmp_path / "small.eds"
    src.write_bytes(SMALL)
    r = cli("export", "--format", "lenze-st", str(src))
    assert r.exit_code == 0 and r.stdout.endswith(SMALL_ST_BODY)
    out = tmp_path / "od.bin"
    r = cli("export", "-f", "lenze-bin", str(src), "-o", str(out))
    assert r.exit_code == 0 and out.read_bytes() == unhex(SMALL_BIN)
    r = cli("export", "-f", "lenze-bin", "-", "-o", "-", input=SMALL)
    assert r.exit_code == 0 and r.stdout_bytes == unhex(SMALL_BIN)


def test_cli_error_writes_nothing(tmp_path):
    src = tmp_path / "n.eds"
    src.write_bytes(b"[2000]\nDataType=0x0007\nAccessType=rw\nDefaultValue=$NODEID\n")
    out = tmp_path / "od.st"
    r = cli("export", "-f", "lenze-st", str(src), "-o", str(out))
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{src}:4: error: value '$NODEID' of 0x2000sub0 uses $NODEID but no node-ID is known "
        "[DCF201]",
        "    hint: give --node-id N or set NodeID in [DeviceComissioning]",
        f"{src}: 1 error, nothing written"]
    assert not out.exists()
    r = cli("export", "-f", "lenze-st", str(src), "-o", str(out), "--node-id", "9")
    assert r.exit_code == 0 and "dwContent := 16#00000009" in out.read_text()


def test_cli_option_of_another_format_is_a_usage_error():
    r = cli("export", "-f", "lenze-st", str(SAMPLES / "dis2.dcf"), "--symbol", "x")
    assert r.exit_code == 2
    assert "--symbol applies to --format port-c only" in r.stderr
    r = cli("export", "-f", "lenze-st", str(SAMPLES / "dis2.dcf"), "--var-name", "1a")
    assert r.exit_code == 2
    assert "'1a' is not an IEC 61131-3 identifier" in r.stderr


def test_cli_format_list_matches_the_package():
    from dcf2bin.cli import export as cli_export
    assert cli_export.FORMATS == FORMATS


def test_man_page_names_the_formats_and_has_examples():
    # every option is checked by tests/test_man.py
    page = (ROOT / "man" / "dcf2bin-export.1").read_text()
    for fmt in FORMATS:
        assert f".B {fmt}".replace("-", "\\-") in page
    assert ".SH EXAMPLES" in page
