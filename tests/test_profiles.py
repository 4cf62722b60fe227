"""Device profiles (SPEC §6): the DIS-2 golden sample, and how a profile changes PDO blocks.

samples/dis2.bin was made with ``dcf2bin compile samples/dis2.dcf --profile dis2`` and
checked by hand against SPEC §3.1-3.3 and §6; the annotation below is that check.
"""
from __future__ import annotations

import pytest

from conftest import ROOT, SAMPLES
from dcf2bin.compiler import CompileOptions, compile_file, compile_path
from dcf2bin.profiles import NAMES, get_profile

# samples/dis2.dcf, node 5. D-8: group 2 (configured, writable, not PDO) then group 3
# (PDO blocks, RPDO1 then TPDO1). SPEC §6: disable = final | 0xC0000000, enable =
# final | 0x40000000; the final COB-IDs are 0x40000205 and 0x40000185.
DIS2 = """
f7000000 0100 0200          # total 247 = 40 + 188 + 19; version 1 (D-5); 2 segments (D-6)
28000000 bc000000           # index segment @40, 188 bytes = 4 + 19*7 + 51 data bytes
00000000 00000000           # no PI address segment (no network variables)
e4000000 13000000           # extended info @228 = 40 + 188, 19 bytes (one per entry)
00000000 00000000           # no PI parameter segment
13000000                    # 19 entries
1710 00 02000000 6400       # 1017sub0 producer heartbeat := 100            (group 2)
6060 00 01000000 01         # 6060sub0 modes of operation := 1              (group 2)
0014 01 04000000 050200c0   # RPDO1 a) 1400sub1 := 0x40000205 | 0xC0000000 (disable)
0014 02 01000000 ff         #       b) 1400sub2 transmission type := 255
0016 00 01000000 00         #       c) 1600sub0 := 0
0016 01 04000000 10004060   #       d) 1600sub1 := 0x60400010 controlword, 16 bits
0016 02 04000000 08006060   #          1600sub2 := 0x60600008 modes of operation, 8 bits
0016 03 04000000 20007a60   #          1600sub3 := 0x607A0020 target position, 32 bits
0016 00 01000000 03         #       e) 1600sub0 := 3 (1600sub4 is not written)
0014 01 04000000 05020040   #       f) 1400sub1 := 0x40000205 | 0x40000000 (enable)
0018 01 04000000 850100c0   # TPDO1 a) 1800sub1 := 0x40000185 | 0xC0000000 (disable)
0018 02 01000000 ff         #       b) 1800sub2 transmission type := 255
0018 03 02000000 6400       #          1800sub3 inhibit time := 100 (x 100 us)
001a 00 01000000 00         #       c) 1A00sub0 := 0
001a 01 04000000 10004160   #       d) 1A00sub1 := 0x60410010 statusword
001a 02 04000000 08006160   #          1A00sub2 := 0x60610008 modes of operation display
001a 03 04000000 20006460   #          1A00sub3 := 0x60640020 position actual value
001a 00 01000000 03         #       e) 1A00sub0 := 3
0018 01 04000000 85010040   #       f) 1800sub1 := 0x40000185 | 0x40000000 (enable)
70                          # 1017: UNSIGNED16 rw -> NUMERIC|R|W (D-9)
f0                          # 6060: INTEGER8 rw, PDOMapping=1 -> NUMERIC|R|W|PDO
70 70 70 70 70 70 70 70     # the 8 RPDO1 block writes: UNSIGNED8/32 rw
70 70 70 70 70 70 70 70 70  # the 9 TPDO1 block writes
"""


def unhex(annotated: str) -> bytes:
    return bytes.fromhex("".join(line.split("#")[0] for line in annotated.strip().splitlines()))


def test_dis2_golden_is_the_annotated_bytes():
    assert (SAMPLES / "dis2.bin").read_bytes() == unhex(DIS2)


def test_dis2_sample_recompiles_byte_identically():
    data = compile_file(str(SAMPLES / "dis2.dcf"), CompileOptions(profile="dis2"))
    assert data == (SAMPLES / "dis2.bin").read_bytes()


# samples/dis2_cobid.dcf, node 5, checked by hand against SPEC §3.2 and §6 (D-12): the
# COB-ID the drive has is sub 1's DefaultValue; when its CAN-ID (bits 0-28) differs from
# the final one, the block starts with old | 0xC0000000. No group 2 entries (the only
# configured entries are PDO parameters); every attribute is UNSIGNED8/32 rw = 0x70.
DIS2_COBID = """
e3000000 0100 0200          # total 227 = 40 + 170 + 17; version 1; 2 segments
28000000 aa000000           # index segment @40, 170 bytes = 4 + 17*7 + 47 data bytes
00000000 00000000           # no PI address segment
d2000000 11000000           # extended info @210 = 40 + 170, 17 bytes
00000000 00000000           # no PI parameter segment
11000000                    # 17 entries
0014 01 04000000 050200c0   # RPDO1    1400sub1 := 0xC0000205: DefaultValue $NODEID+0xC0000200
                            #          (CAN-ID 0x205 != 0x301) | 0xC0000000 -- the D-12 write
0014 01 04000000 010300c0   #       a) 1400sub1 := 0x40000301 | 0xC0000000 (disable)
0016 00 01000000 00         #       c) 1600sub0 := 0 (b: no comm sub 2/3/5/6 configured)
0016 01 04000000 10004060   #       d) 1600sub1 := 0x60400010 controlword, 16 bits
0016 00 01000000 01         #       e) 1600sub0 := 1
0014 01 04000000 01030040   #       f) 1400sub1 := 0x40000301 | 0x40000000 (enable)
0018 01 04000000 850100c0   # TPDO1 a) 1800sub1 := 0x40000185 | 0xC0000000; DefaultValue
                            #          0xC0000185 has the same CAN-ID 0x185: no D-12 write
001a 00 01000000 00         #       c) 1A00sub0 := 0
001a 01 04000000 10004160   #       d) 1A00sub1 := 0x60410010 statusword
001a 00 01000000 01         #       e) 1A00sub0 := 1
0018 01 04000000 85010040   #       f) 1800sub1 := 0x40000185
0118 01 04000000 850200c0   # TPDO2 a) 1801sub1 := 0x40000285 | 0xC0000000; no DefaultValue:
                            #          no D-12 write
0118 02 01000000 01         #       b) 1801sub2 transmission type := 1
011a 00 01000000 00         #       c) 1A01sub0 := 0
011a 01 04000000 20006460   #       d) 1A01sub1 := 0x60640020 position actual value, 32 bits
011a 00 01000000 01         #       e) 1A01sub0 := 1
0118 01 04000000 85020040   #       f) 1801sub1 := 0x40000285
70 70 70 70 70 70 70 70 70  # 17 attributes: UNSIGNED8/32 rw -> NUMERIC|R|W (D-9)
70 70 70 70 70 70 70 70
"""


def test_dis2_cobid_golden_is_the_annotated_bytes():
    assert (SAMPLES / "dis2_cobid.bin").read_bytes() == unhex(DIS2_COBID)


def test_dis2_cobid_sample_recompiles_byte_identically():
    data = compile_file(str(SAMPLES / "dis2_cobid.dcf"), CompileOptions(profile="dis2"))
    assert data == (SAMPLES / "dis2_cobid.bin").read_bytes()


def test_dis2_cobid_old_write_is_dis2_only():
    # CiA 301 reconfiguration has no old-COB-ID write: RPDO1 is disable, c-e, enable
    data = compile_file(str(SAMPLES / "dis2_cobid.dcf"), CompileOptions())
    assert _cob_writes(data) == [(0x1400, 0xC0000301), (0x1400, 0x40000301),
                                 (0x1800, 0xC0000185), (0x1800, 0x40000185)]


def test_dis2_cobid_node_id_decides_the_old_write(tmp_path):
    # --node-id 1: RPDO1's DefaultValue is 0xC0000201 (still another CAN-ID than 0x301);
    # TPDO1's DefaultValue and final value both follow the node-ID (0x181): no old write
    data = compile_file(str(SAMPLES / "dis2_cobid.dcf"), CompileOptions(profile="dis2",
                                                                        node_id=1))
    assert _cob_writes(data) == [(0x1400, 0xC0000201), (0x1400, 0xC0000301),
                                 (0x1400, 0x40000301), (0x1800, 0xC0000181),
                                 (0x1800, 0x40000181)]
    # an RPDO1 configured to its default CAN-ID needs no old write
    path = tmp_path / "same.dcf"
    path.write_text((SAMPLES / "dis2_cobid.dcf").read_text().replace(
        "ParameterValue=0x40000301", "ParameterValue=0x40000205"))
    data = compile_file(str(path), CompileOptions(profile="dis2"))
    assert _cob_writes(data)[:2] == [(0x1400, 0xC0000205), (0x1400, 0x40000205)]


def _without_bit30(tmp_path):
    """dis2.dcf with COB-IDs that lack bit 30: there cia301 and dis2 differ."""
    text = (SAMPLES / "dis2.dcf").read_text()
    text = text.replace("ParameterValue=$NODEID+0x40000200", "ParameterValue=$NODEID+0x200")
    text = text.replace("ParameterValue=$NODEID+0x40000180", "ParameterValue=$NODEID+0x180")
    path = tmp_path / "plain.dcf"
    path.write_text(text)
    return str(path)


def _cob_writes(data: bytes) -> list[tuple[int, int]]:
    from dcf2bin.container import read
    c, _ = read(data)
    return [(i, int.from_bytes(d, "little")) for i, s, d in c.entries if s == 1 and i in
            (0x1400, 0x1800)]


def test_profiles_differ_only_in_the_cob_id_masks(tmp_path):
    path = _without_bit30(tmp_path)
    cia = compile_file(path, CompileOptions(profile="cia301"))
    dis = compile_file(path, CompileOptions(profile="dis2"))
    assert _cob_writes(cia) == [(0x1400, 0x80000205), (0x1400, 0x00000205),
                                (0x1800, 0x80000185), (0x1800, 0x00000185)]
    assert _cob_writes(dis) == [(0x1400, 0xC0000205), (0x1400, 0x40000205),
                                (0x1800, 0xC0000185), (0x1800, 0x40000185)]
    # apart from those four DWORDs the containers are the same
    assert len(cia) == len(dis)
    assert sum(a != b for a, b in zip(cia, dis)) == 4   # one byte (the top one) each


def test_dis2_disabled_pdo_gets_no_enable_write(tmp_path):
    text = (SAMPLES / "dis2.dcf").read_text().replace(
        "ParameterValue=$NODEID+0x40000180", "ParameterValue=$NODEID+0xC0000180")
    path = tmp_path / "off.dcf"
    path.write_text(text)
    data = compile_file(str(path), CompileOptions(profile="dis2"))
    assert _cob_writes(data) == [(0x1400, 0xC0000205), (0x1400, 0x40000205),
                                 (0x1800, 0xC0000185)]


def test_dis2_violations_fixture_fails_compile_on_the_mapping_count():
    path = ROOT / "tests" / "fixtures" / "dis2_violations.dcf"
    res = compile_path(str(path), CompileOptions(profile="dis2"))
    assert not res.ok
    errors = [d.format() for d in res.diagnostics if d.severity.value == "error"]
    assert errors == [f"{path}:81: error: 0x1600sub0: 5 mapped objects, more than 4 [DCF450]"]
    # the same file is fine for plain CiA 301 (64 objects allowed; bit 30 is DIS-2 only)
    assert compile_path(str(path), CompileOptions()).ok


def test_violations_fixture_lines_named_in_its_header():
    lines = (ROOT / "tests" / "fixtures" / "dis2_violations.dcf").read_text().splitlines()
    assert lines[81 - 1] == "ParameterValue=5"
    assert lines[141 - 1] == "ParameterValue=$NODEID+0x180"
    assert "(line 81)" in lines[2] and "(line 141)" in lines[4]


@pytest.mark.parametrize("name", NAMES)
def test_registry(name):
    p = get_profile(name)
    assert p.name == name
    rules = p.pdo_rules()
    assert (rules.disable_mask, rules.enable_mask, rules.max_mapped) == (
        p.disable_mask, p.enable_mask, p.max_mapped)


def test_dis2_profile_values():
    p = get_profile("dis2")
    assert (p.disable_mask, p.enable_mask, p.max_mapped, p.max_bits,
            p.cob_bit30_required) == (0xC0000000, 0x40000000, 4, 64, True)
    assert p.old_cob_first and p.pdo_rules().old_cob_first          # D-12
    c = get_profile("cia301")
    assert (c.disable_mask, c.enable_mask, c.max_mapped) == (0x80000000, 0, 64)
    assert not c.old_cob_first and not c.pdo_rules().old_cob_first
    with pytest.raises(ValueError, match="unknown profile 'x'"):
        get_profile("x")
