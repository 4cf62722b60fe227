"""port CANopen Library OD export (seed 002, SPEC §7).

The generated C is compiled with the system C compiler against tests/port/co_acces.h (a
small header written from the seed's type definitions) and linked with tests/port/walk.c,
which walks LIST_ELEMENT_T / VALUE_DESC_T as the library does and prints index, subindex,
type, attribute, default and data. That output is compared with the model: types,
attributes and values are derived here again from the model's entries, independently of
dcf2bin.export.port; only the placement of split objects is taken from the plan.
"""
from __future__ import annotations

import re
import shutil
import struct
import subprocess

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES, corpus_params, corpus_pick_params
from dcf2bin import datatypes as dt
from dcf2bin import model
from dcf2bin.cli import main
from dcf2bin.export import port, run

PORT_DIR = ROOT / "tests" / "port"
CC = shutil.which("cc") or shutil.which("gcc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc or gcc) found on PATH")


def header_values() -> dict[str, int]:
    """The CO_* numbers of the test header."""
    text = (PORT_DIR / "co_acces.h").read_text()
    out = {}
    pattern = r"#define\s+(CO_\w+)\s+\(?(?:\(UNSIGNED16\))?(0x[0-9A-Fa-f]+|\d+)u"
    for name, value in re.findall(pattern, text):
        out[name] = int(value, 0)
    return out


H = header_values()

# The seed's Table 21, by CANopen type name (written out again, not taken from port.py).
TYPEDESC = {"BOOLEAN": "CO_TYPEDESC_BOOL", "UNSIGNED8": "CO_TYPEDESC_UNSIGNED8",
            "UNSIGNED16": "CO_TYPEDESC_UNSIGNED16", "UNSIGNED32": "CO_TYPEDESC_UNSIGNED32",
            "UNSIGNED64": "CO_TYPEDESC_UNSIGNED64", "INTEGER8": "CO_TYPEDESC_INTEGER8",
            "INTEGER16": "CO_TYPEDESC_INTEGER16", "INTEGER32": "CO_TYPEDESC_INTEGER32",
            "INTEGER64": "CO_TYPEDESC_INTEGER64", "VISIBLE_STRING": "CO_TYPEDESC_VISSTRING",
            "OCTET_STRING": "CO_TYPEDESC_OCTETSTRING", "DOMAIN": "CO_TYPEDESC_DOMAIN",
            "REAL32": "CO_TYPEDESC_REAL32"}
BYTE_TYPES = ("CO_TYPEDESC_VISSTRING", "CO_TYPEDESC_OCTETSTRING")


def test_header_has_the_seed_names():
    for name in list(TYPEDESC.values()) + ["CO_MAP_PERM", "CO_WRITE_PERM", "CO_READ_PERM",
                                           "CO_CONST_PERM", "CO_SHORT_ARRAY_DESC",
                                           "CO_OBJ_ATTR_SAVE", "CO_NUM_VAL",
                                           "CO_UP_DN_LD_DOMAIN"]:
        assert name in H, name
    for name, value in port.ATTR.items():
        assert H[name] == value, name


# -- C build ---------------------------------------------------------------------------------

def build_and_walk(source: str, tmp_path, *defines: str) -> list[str]:
    c_file = tmp_path / "od.c"
    c_file.write_text(source)
    exe = tmp_path / "walk"
    cmd = [CC, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-I", str(PORT_DIR),
           *defines, "-o", str(exe), str(PORT_DIR / "walk.c"), str(c_file)]
    done = subprocess.run(cmd, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[:3000]
    walked = subprocess.run([str(exe)], capture_output=True, text=True)
    assert walked.returncode == 0
    return walked.stdout.splitlines()


# -- expectations from the model ---------------------------------------------------------------

def expected_attr(e, typedesc: str) -> int:
    acc = e.access or ""
    a = 0
    if typedesc not in BYTE_TYPES and typedesc != "CO_TYPEDESC_DOMAIN":
        a |= H["CO_NUM_VAL"]
    if acc in ("ro", "rw", "rwr", "rww", "const"):
        a |= H["CO_READ_PERM"]
    if acc in ("wo", "rw", "rwr", "rww"):
        a |= H["CO_WRITE_PERM"]
    if acc == "const":
        a |= H["CO_CONST_PERM"]
    if e.pdo_mapping:
        a |= H["CO_MAP_PERM"]
    if typedesc == "CO_TYPEDESC_DOMAIN":
        a |= H["CO_UP_DN_LD_DOMAIN"]
    return a


def number_text(dtype, data: bytes) -> str:
    if dtype.kind == dt.REAL:
        return f"0x{int.from_bytes(data, 'little'):08X}"
    return str(int.from_bytes(data, "little", signed=dtype.kind == dt.SINT))


def expected_lines(dev, objs) -> list[str]:
    """What walk.c must print, derived from the model (the plan only places the subs)."""
    lines = []
    seen = set()
    for o in objs:
        lines.append(f"{o.index:04X} n={len(o.subs)}")
        rows = []
        for p in o.subs:
            if p.role == port.GAP:
                assert dev.entry(o.origin, p.sub) is None
                rows.append((p.sub, H["CO_TYPEDESC_UNSIGNED8"], 0, "0", "0", None))
                continue
            e = dev.entry(*p.source)
            assert e is not None
            if p.role == port.COUNT:           # sub 0 of a part of a split object
                typedesc = "CO_TYPEDESC_UNSIGNED8"
                count = str(len(o.subs) - 1)
                rows.append((0, H[typedesc], expected_attr(e, typedesc), count, count, None))
                seen.add(p.source)
                continue
            if o.index == o.origin:            # not split: the model's own numbering
                assert p.source == (o.index, p.sub)
            seen.add(p.source)
            typedesc = TYPEDESC.get(e.dtype.name, "CO_TYPEDESC_OCTETSTRING")
            data = dev.encode(e)
            if typedesc in BYTE_TYPES:
                d, v = f"len={len(data)}/{len(data)}", data.hex() or "-"
            elif typedesc == "CO_TYPEDESC_DOMAIN":
                d, v = f"len={len(data)}", data.hex() or "-"
            else:
                d = v = number_text(e.dtype, data)
            rows.append((p.sub, H[typedesc], expected_attr(e, typedesc), d, v, data))
        # short array description: subs 1..n (n >= 2) all alike
        body = rows[1:]
        short = (len(o.subs) > 1 and not o.is_var and len(body) >= 2
                 and all(r[5] is not None for r in body)
                 and all(r[1:] == body[0][1:] for r in body))
        for sub, t, a, d, v, _ in rows:
            if sub == 0 and short:
                a |= H["CO_SHORT_ARRAY_DESC"]
            lines.append(f"{o.index:04X} {sub:02X} t={t} a={a:04X} d={d} v={v}")
    # every entry of the model from 0x1000 up appears exactly once
    want = {(o.index, s) for o in dev.sorted_objects() if o.index >= 0x1000 for s in o.entries}
    assert seen == want
    return lines


def export_and_walk(path, tmp_path, node_id=None, data=None, **opts):
    dev = model.load(str(path), node_id=node_id, data=data)
    res = run("port-c", str(path), node_id=node_id, data=data, **opts)
    assert res.ok, [d.format() for d in res.errors]
    objs, _ = port.plan(dev, max_object_size=opts.get("max_object_size"))
    got = build_and_walk(res.output, tmp_path)
    assert got == expected_lines(dev, objs)
    indexes = [int(line[:4], 16) for line in got if " n=" in line]
    assert indexes == sorted(indexes) and len(set(indexes)) == len(indexes)
    return got, res


@needs_cc
@pytest.mark.parametrize("name", ["dis2.dcf", "device.dcf", "plc.dcf", "bild8.dcf"])
def test_samples_compile_and_walk_like_the_model(name, tmp_path):
    export_and_walk(SAMPLES / name, tmp_path)


# Corpus files that load without errors: strings, REAL32, BOOLEAN (401), DOMAIN, REAL64,
# 64-bit integers (demoDevice), UNICODE_STRING/TIME types (lely slave), subindex 255.
CORPUS_PICKS = [("cia_profiles_kacanopen/401.eds", 1), ("canopennode/demoDevice.eds", 1),
                ("lely_core/co-gw_txt-slave.dcf", 2), ("eds_dcf_net/max_subnumber.eds", None)]


@needs_cc
@pytest.mark.parametrize("path, node_id", corpus_pick_params(CORPUS_PICKS))
def test_corpus_files_compile_and_walk_like_the_model(path, node_id, tmp_path):
    got, _ = export_and_walk(path, tmp_path, node_id=node_id)
    assert len(got) > 2


# -- a file made to hit every rule -------------------------------------------------------------

def feature_dcf() -> bytes:
    out = ["[DeviceComissioning]", "NodeID=7", ""]

    def var(idx, dtype, access, value, name=""):
        out.extend([f"[{idx:04X}]", f"ParameterName={name or f'V{idx:04X}'}",
                    f"DataType=0x{dtype:04X}", f"AccessType={access}", f"DefaultValue={value}",
                    ""])

    var(0x1000, 0x07, "ro", "0x00020192")
    # 0x1016: identical subindexes 1..3 -> short array description
    out += ["[1016]", "ParameterName=Consumer heartbeat time", "ObjectType=0x8",
            "DataType=0x0007", "AccessType=rw", "DefaultValue=0x00050064", "CompactSubObj=3", ""]
    # 0x1800: subindexes 0,1,2,3,5 -> sub 4 is a placeholder
    out += ["[1800]", "ParameterName=TPDO1", "ObjectType=0x9", "SubNumber=5", ""]
    for s, t, v in ((0, 5, "5"), (1, 7, "$NODEID+0x180"), (2, 5, "255"), (3, 6, "0"),
                    (5, 6, "100")):
        out += [f"[1800sub{s}]", f"DataType=0x{t:04X}", f"AccessType={'ro' if s == 0 else 'rw'}",
                f"DefaultValue={v}", ""]
    out += ["[1A00]", "ObjectType=0x9", "SubNumber=1", "", "[1A00sub0]", "DataType=0x0005",
            "AccessType=rw", "DefaultValue=0", ""]
    # 0x2100: a record of every kind of member
    members = [(0x05, "ro", "9"), (0x09, "rw", "Hello"), (0x0A, "rww", "DEADBEEF"),
               (0x0F, "rw", "0102030405"), (0x08, "rw", "-2.5"), (0x01, "const", "1"),
               (0x15, "rw", "-9223372036854775808"), (0x1B, "ro", "0xFFFFFFFFFFFFFFFF"),
               (0x10, "rwr", "-2"), (0x09, "rw", '""'), (0x04, "wo", "-2147483648"),
               (0x02, "rw", "-128"), (0x03, "rw", "0x8000"), (0x11, "rw", "1.5"),
               (0x0C, "ro", "0x123456789ABC")]
    out += ["[2100]", "ParameterName=Mixed record", "ObjectType=0x9",
            f"SubNumber={len(members) + 1}", ""]
    out += ["[2100sub0]", "DataType=0x0005", "AccessType=ro", f"DefaultValue={len(members)}", ""]
    for s, (t, acc, v) in enumerate(members, 1):
        out += [f"[2100sub{s:X}]", f"ParameterName=M{s}", f"DataType=0x{t:04X}",
                f"AccessType={acc}", f"DefaultValue={v}", "PDOMapping=1" if t == 0x05 else "",
                ""]
    var(0x2200, 0x0F, "rw", "A0A1A2")
    var(0x2201, 0x09, "ro", "text", name="a */ comment")
    var(0x2202, 0x08, "rw", "0.1")
    var(0x2203, 0x04, "const", "-2147483648")
    var(0x2204, 0x09, "rw", '""')
    var(0x2205, 0x0F, "rw", '""')
    # 0x2300: 100 UNSIGNED32 = 401 bytes, split with --max-object-size 255
    out += ["[2300]", "ParameterName=Big array", "ObjectType=0x8", "DataType=0x0007",
            "AccessType=rw", "PDOMapping=1", "CompactSubObj=100", "", "[2300Value]",
            "NrOfEntries=100"]
    out += [f"{k}={k * 1000}" for k in range(1, 101)]
    out.append("")
    # 0x2400: subindex 255 -> split over 0x2400 (254 elements) and 0x2401 (1 element)
    out += ["[2400]", "ParameterName=Full array", "ObjectType=0x8", "DataType=0x0005",
            "AccessType=ro", "DefaultValue=7", "SubNumber=256", ""]
    for s in range(1, 256):
        out += [f"[2400sub{s:X}]", "DataType=0x0005", "AccessType=ro", f"DefaultValue={s}", ""]
    return "\n".join(out).encode()


FEATURES = feature_dcf()


def line_of(section: str, text: bytes = FEATURES) -> int:
    return text.decode().splitlines().index(section) + 1


def test_feature_plan():
    dev = model.load("f.dcf", data=FEATURES)
    objs, diags = port.plan(dev, max_object_size=255)
    by_index = {o.index: o for o in objs}
    assert [hex(i) for i in sorted(by_index)] == [
        "0x1000", "0x1016", "0x1800", "0x1a00", "0x2100", "0x2200", "0x2201", "0x2202",
        "0x2203", "0x2204", "0x2205", "0x2300", "0x2301", "0x2400", "0x2401"]
    assert by_index[0x1016].short and not by_index[0x1018 - 2].is_var
    assert [p.role for p in by_index[0x1800].subs] == ["entry"] * 4 + ["gap", "entry"]
    big, rest = by_index[0x2300], by_index[0x2301]
    assert (len(big.subs), len(rest.subs)) == (64, 38)       # 1 + 63*4 <= 255 bytes
    assert big.subs[0].data == bytes([63]) and rest.subs[0].data == bytes([37])
    assert rest.subs[1].source == (0x2300, 64) and rest.origin == 0x2300
    assert big.short is False                                  # the values differ
    full, last = by_index[0x2400], by_index[0x2401]
    assert (len(full.subs), len(last.subs)) == (255, 2)
    assert last.subs[1].source == (0x2400, 255) and last.subs[1].data == b"\xff"
    assert [d.format() for d in diags] == [
        f"f.dcf:{line_of('[2100]')}: warning: 0x2100: the port library has no CO_TYPEDESC "
        "for INTEGER24, REAL64, TIME_OF_DAY; exported as CO_TYPEDESC_OCTETSTRING with the "
        "little-endian bytes [EXP201]",
        f"f.dcf:{line_of('[2300]')}: warning: 0x2300 has 401 bytes of data (more than 255): "
        "split over indices 0x2300, 0x2301 for the port library [EXP202]",
        f"f.dcf:{line_of('[2400]')}: warning: 0x2400 has 255 elements (more than 254 per "
        "index): split over indices 0x2400, 0x2401 for the port library [EXP202]",
    ]
    # without the byte limit only the subindex count splits
    objs, _ = port.plan(dev)
    assert 0x2301 not in {o.index for o in objs} and 0x2401 in {o.index for o in objs}


@needs_cc
@pytest.mark.parametrize("limit", [None, 255])
def test_feature_file_compiles_and_walks_like_the_model(limit, tmp_path):
    got, res = export_and_walk("f.dcf", tmp_path, data=FEATURES, max_object_size=limit)
    assert "1016 00 t=2 a=0032 d=3 v=3" in got               # NUM|R|SHORT_ARRAY_DESC
    assert "1800 04 t=2 a=0000 d=0 v=0" in got               # the placeholder
    assert "2200 00 t=16 a=0061 d=len=3 v=a0a1a2" in got     # DOMAIN rw
    assert "2100 06 t=1 a=0038 d=1 v=1" in got               # BOOLEAN const
    assert "2100 07 t=13 a=0070 d=-9223372036854775808 v=-9223372036854775808" in got
    assert "2203 00 t=12 a=0038 d=-2147483648 v=-2147483648" in got
    assert "2202 00 t=17 a=0070 d=0x3DCCCCCD v=0x3DCCCCCD" in got
    assert "2204 00 t=14 a=0060 d=len=0/0 v=-" in got
    assert "/ comment" in res.output and "a */ comment" not in res.output


@needs_cc
@pytest.mark.parametrize("defines", [("-DCONFIG_LIMITS_CHECK",),
                                     ("-DCO_CONFIG_ENABLE_OBJ_CALLBACK",),
                                     ("-DCONFIG_LIMITS_CHECK", "-DCO_CONFIG_ENABLE_OBJ_CALLBACK")])
def test_generated_source_fits_the_optional_struct_members(defines, tmp_path):
    res = run("port-c", "f.dcf", data=FEATURES)
    (tmp_path / "plain").mkdir()
    (tmp_path / "variant").mkdir()
    base = build_and_walk(res.output, tmp_path / "plain")
    assert build_and_walk(res.output, tmp_path / "variant", *defines) == base


@needs_cc
def test_symbol_prefix_and_includes(tmp_path):
    (tmp_path / "extra.h").write_text("#define EXTRA_INCLUDED 1\n")
    res = run("port-c", str(SAMPLES / "dis2.dcf"), symbol="myOd", prefix="dis2_",
              includes=["co_acces.h", "extra.h"])
    assert '#include "co_acces.h"\n#include "extra.h"\n' in res.output
    assert "LIST_ELEMENT_T myOd[] = {" in res.output
    assert "const UNSIGNED16 myOdElements = 17u;" in res.output
    assert "dis2_1018_t dis2_1018 = {" in res.output
    c_file = tmp_path / "od.c"
    c_file.write_text(res.output)
    done = subprocess.run([CC, "-std=c99", "-Wall", "-Werror", "-I", str(PORT_DIR), "-I",
                           str(tmp_path), "-DOD_SYMBOL=myOd", "-o", str(tmp_path / "w"),
                           str(PORT_DIR / "walk.c"), str(c_file)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr


# -- errors ------------------------------------------------------------------------------------

def errors_of(text: bytes, **kw) -> list[str]:
    res = run("port-c", "e.eds", data=text, **kw)
    assert not res.ok
    return [d.format() for d in res.errors]


def test_nodeid_without_node_id_is_a_one_line_error():
    eds = b"[1014]\nDataType=0x0007\nAccessType=ro\nDefaultValue=$NODEID+0x80\n"
    assert errors_of(eds) == [
        "e.eds:4: error: value '$NODEID+0x80' of 0x1014sub0 uses $NODEID but no node-ID is "
        "known [DCF201]"]
    assert run("port-c", "e.eds", data=eds, node_id=3).ok


def test_split_needs_free_indices():
    eds = feature_dcf() + b"\n[2301]\nDataType=0x0005\nAccessType=rw\n"
    assert errors_of(eds, max_object_size=255) == [
        f"e.eds:{line_of('[2300]')}: error: 0x2300 has 401 bytes of data (more than 255) and "
        "must be split over indices 0x2300..0x2301, but 0x2301 is already used [EXP203]"]


def test_sub0_must_be_unsigned8_and_elements_must_fit():
    eds = (b"[2000]\nObjectType=0x8\nSubNumber=2\n[2000sub0]\nDataType=0x0006\n"
           b"AccessType=ro\nDefaultValue=1\n[2000sub1]\nDataType=0x0005\nAccessType=rw\n")
    assert errors_of(eds) == [
        "e.eds:5: error: 0x2000sub0 is UNSIGNED16: the port library reads sub 0 of an "
        "ARRAY/RECORD as one UNSIGNED8 [EXP206]"]
    eds = (b"[2000]\nObjectType=0x9\nSubNumber=2\n[2000sub1]\nDataType=0x0009\n"
           b"AccessType=rw\nDefaultValue=" + b"x" * 256 + b"\n")
    assert errors_of(eds) == [
        "e.eds:7: error: 0x2000sub1 takes 256 bytes: an element of an ARRAY/RECORD must fit "
        "255 bytes for the port library [EXP205]"]


def test_real32_without_a_c_literal():
    eds = b"[2000]\nDataType=0x0008\nAccessType=rw\nDefaultValue=0x7FC00000\n"
    assert errors_of(eds) == [
        "e.eds:4: error: 0x2000sub0: REAL32 bit pattern 0x7FC00000 is not finite and has no "
        "C initializer [EXP207]"]


def test_literals():
    def lit(ctype, data):
        return port.literal(port.PortSub(0, port.ENTRY, "", ctype, (), data))
    assert lit("UNSIGNED8", b"\xff") == "0xFFu"
    assert lit("UNSIGNED32", b"\x01\x00\x00\x80") == "0x80000001UL"
    # 64-bit: most significant byte first, as the port manual's SET_U64 takes them
    assert lit("UNSIGNED64", bytes(range(1, 9))) == (
        "DCF2BIN_U64(0x08ull, 0x07ull, 0x06ull, 0x05ull, 0x04ull, 0x03ull, 0x02ull, 0x01ull)")
    p = port.PortSub(0, port.ENTRY, "", "UNSIGNED64", (), b"\xff" + b"\x00" * 7)
    assert port.literal(p, u64="SET_U64") == (
        "SET_U64(0x00ull, 0x00ull, 0x00ull, 0x00ull, 0x00ull, 0x00ull, 0x00ull, 0xFFull)")
    assert lit("INTEGER8", b"\x80") == "(-127 - 1)"
    assert lit("INTEGER16", b"\xfe\xff") == "-2"
    assert lit("INTEGER32", b"\x00\x00\x00\x80") == "(-2147483647L - 1L)"
    assert lit("INTEGER64", b"\x05" + b"\x00" * 7) == "5LL"
    assert lit("REAL32", struct.pack("<f", -2.5)) == "-0x1.4000000000000p+1f"


@pytest.mark.parametrize("path", corpus_params())
def test_every_corpus_file_exports_or_fails_cleanly(path):
    res = run("port-c", str(path), node_id=1)
    for d in res.diagnostics:
        assert "\n" not in d.format()
    if res.ok:
        assert "LIST_ELEMENT_T objDir[] = {" in res.output
    else:
        assert res.errors and all(d.file == str(path) for d in res.errors)


# -- command line ------------------------------------------------------------------------------

def test_cli_port_c_to_file(tmp_path):
    out = tmp_path / "od.c"
    r = CliRunner().invoke(main, ["export", "-f", "port-c", str(SAMPLES / "dis2.dcf"),
                                  "-o", str(out), "--symbol", "od", "--include", "my.h"],
                           catch_exceptions=False)
    assert r.exit_code == 0, r.output
    text = out.read_text()
    assert text.startswith("/*\n * port CANopen Library object dictionary, generated by dcf2bin")
    assert '#include "my.h"' in text and "LIST_ELEMENT_T od[] = {" in text
    r = CliRunner().invoke(main, ["export", "-f", "port-c", str(SAMPLES / "dis2.dcf"),
                                  "--max-object-size", "1"])
    assert r.exit_code == 2


# -- pLimits (CONFIG_LIMITS_CHECK), SET_U64, const data ------------------------------------------

LIMITS_DCF = b"""[DeviceComissioning]
NodeID=7

[2000]
DataType=0x0005
AccessType=rw
LowLimit=1
HighLimit=0x64
DefaultValue=5

[2001]
DataType=0x0003
AccessType=rw
LowLimit=-100
DefaultValue=0

[2002]
DataType=0x0007
AccessType=rw
HighLimit=$NODEID+0x180
DefaultValue=0x181

[2003]
DataType=0x001B
AccessType=rw
LowLimit=0x100
HighLimit=0xFFFFFFFFFFFFFFFF
DefaultValue=0x0102030405060708

[2004]
DataType=0x0015
AccessType=rw
LowLimit=-5
HighLimit=5
DefaultValue=-1

[2005]
DataType=0x0008
AccessType=rw
LowLimit=-1.5
HighLimit=2.5
DefaultValue=0.5

[2006]
DataType=0x0001
AccessType=rw
HighLimit=1
DefaultValue=1

[2007]
DataType=0x0007
AccessType=const
DefaultValue=0x12345678

[2008]
DataType=0x0005
AccessType=rw
LowLimit=zz
DefaultValue=5

[2100]
ObjectType=0x9
SubNumber=3

[2100sub0]
DataType=0x0005
AccessType=ro
DefaultValue=2

[2100sub1]
DataType=0x0006
AccessType=rw
LowLimit=1
HighLimit=10
DefaultValue=3

[2100sub2]
DataType=0x001B
AccessType=rw
DefaultValue=0xFFFFFFFFFFFFFFFF

[2200]
ObjectType=0x8
CompactSubObj=3
DataType=0x0005
AccessType=rw
LowLimit=2
HighLimit=9
DefaultValue=4
"""

U64 = 0x0102030405060708
LIMITED_WALK = [
    "2000 n=1", "2000 00 t=2 a=0070 d=5 v=5 l=1..100",
    "2001 n=1", "2001 00 t=11 a=0070 d=0 v=0 l=-100..32767",
    "2002 n=1", "2002 00 t=5 a=0070 d=385 v=385 l=0..391",
    "2003 n=1", f"2003 00 t=9 a=0070 d={U64} v={U64} l=256..18446744073709551615",
    "2004 n=1", "2004 00 t=13 a=0070 d=-1 v=-1 l=-5..5",
    "2005 n=1", "2005 00 t=17 a=0070 d=0x3F000000 v=0x3F000000 l=0xBFC00000..0x40200000",
    "2006 n=1", "2006 00 t=1 a=0070 d=1 v=1 l=0..1",
    "2007 n=1", "2007 00 t=5 a=0038 d=305419896 v=305419896",
    "2008 n=1", "2008 00 t=2 a=0070 d=5 v=5",
    "2100 n=3", "2100 00 t=2 a=0030 d=2 v=2", "2100 01 t=3 a=0070 d=3 v=3 l=1..10",
    "2100 02 t=9 a=0070 d=18446744073709551615 v=18446744073709551615",
    "2200 n=4", "2200 00 t=2 a=0032 d=3 v=3", "2200 01 t=2 a=0070 d=4 v=4 l=2..9",
    "2200 02 t=2 a=0070 d=4 v=4 l=2..9", "2200 03 t=2 a=0070 d=4 v=4 l=2..9"]


def test_limits_set_u64_and_const_in_the_source():
    res = run("port-c", "lim.dcf", data=LIMITS_DCF)
    assert [d.format() for d in res.diagnostics] == [
        "lim.dcf:58: warning: 0x2008sub0 LowLimit: invalid integer 'zz'; no limits exported "
        "for it [EXP208]"]
    c = res.output
    assert ("#ifdef CONFIG_LIMITS_CHECK\nstatic const LIMIT_U8_T od_2000_m0 = { 0x1u, 0x64u };"
            "\n#endif\n") in c
    assert "static const LIMIT_I16_T od_2001_m0 = { -100, 32767 };" in c
    assert ("static const UNSIGNED64 od_2003_d0 = SET_U64(0x01ull, 0x02ull, 0x03ull, 0x04ull, "
            "0x05ull, 0x06ull, 0x07ull, 0x08ull)\n") in c
    assert ("static const LIMIT_U64_T od_2003_m0 = { DCF2BIN_U64(0x00ull, 0x00ull, 0x00ull, "
            "0x00ull, 0x00ull, 0x00ull, 0x01ull, 0x00ull), DCF2BIN_U64(0xFFull, 0xFFull, "
            "0xFFull, 0xFFull, 0xFFull, 0xFFull, 0xFFull, 0xFFull) };") in c
    assert "const UNSIGNED32 od_2007 = 0x12345678UL;\n" in c            # CO_CONST_PERM: ROM
    assert "DCF2BIN_DESC(&od_2007_d0, 0, CO_TYPEDESC_UNSIGNED32, CO_NUM_VAL | CO_READ_PERM " \
           "| CO_CONST_PERM)" in c
    assert "DCF2BIN_DESC(&od_2100_d1, &od_2100_m1, CO_TYPEDESC_UNSIGNED16," in c
    assert "od_2200_m2" not in c   # short array: sub 1 describes (and limits) subs 1..3


@needs_cc
def test_limits_walk_like_the_model(tmp_path):
    res = run("port-c", "lim.dcf", data=LIMITS_DCF)
    (tmp_path / "limits").mkdir()
    (tmp_path / "plain").mkdir()
    got = build_and_walk(res.output, tmp_path / "limits", "-DCONFIG_LIMITS_CHECK",
                         "-DWALK_LIMITS")
    assert got == LIMITED_WALK
    plain = build_and_walk(res.output, tmp_path / "plain")
    assert plain == [re.sub(r" l=\S+$", "", line) for line in LIMITED_WALK]
