"""Entry selection and order (SPEC §3.2, D-8) and attribute bytes (§3.3, D-9)."""
from __future__ import annotations

import pytest

from helpers import compile_text as _compile_text
from helpers import messages, nv_objects


def compile_text(text, **opts):
    # These are DCF fragments (a PDO maps 0x2000 that the fragment lacks; --pdo-sequence
    # none writes a mapping while its PDO is valid): compile's DynBuildOd check would refuse
    # them. It has its own tests (test_target*.py, test_simulate.py); here only the order.
    opts.setdefault("target_check", "off")
    return _compile_text(text, **opts)


def writes(res):
    assert res.ok, messages(res)
    return [(i, s, d.hex(), a) for (i, s, d), a in zip(res.container.entries,
                                                        res.container.attributes)]


VAR = "[{i:04X}]\nParameterName=x\nDataType={t}\nAccessType={a}\n{extra}\n"


def var(i, t="0x0007", a="rw", extra=""):
    return VAR.format(i=i, t=t, a=a, extra=extra)


PDO = """
[1800]
ObjectType=0x9
[1800sub0]
DataType=0x0005
AccessType=ro
DefaultValue=5
[1800sub1]
DataType=0x0007
AccessType=rw
DefaultValue=$NODEID+0x180
{cob}
[1800sub2]
DataType=0x0005
AccessType=rw
DefaultValue=255
{tt}
[1800sub3]
DataType=0x0006
AccessType=rw
DefaultValue=0
[1800sub4]
DataType=0x0005
AccessType=rw
ParameterValue=9
[1800sub5]
DataType=0x0006
AccessType=rw
ObjFlags=1
ParameterValue=100
[1A00]
ObjectType=0x9
[1A00sub0]
DataType=0x0005
AccessType=rw
ParameterValue=2
[1A00sub1]
DataType=0x0007
AccessType=rw
ParameterValue=0x20000020
[1A00sub2]
DataType=0x0007
AccessType=rw
DefaultValue=0x20010010
[1A00sub3]
DataType=0x0007
AccessType=rw
ParameterValue=0x20020008
"""


def test_groups_and_order():
    """Creation (NV objects), then configuration (ascending), then PDO blocks."""
    text = (var(0x2001, extra="ParameterValue=2") + var(0x2000, extra="ParameterValue=1")
            + var(0x1017, "0x0006", extra="ParameterValue=0x64")
            + var(0x1000, a="ro", extra="ParameterValue=1")        # ro: not written
            + var(0x2002, a="const", extra="ParameterValue=1")     # const: not written
            + var(0x2003, extra="ObjFlags=1\nParameterValue=1")    # ObjFlags bit 0
            + var(0x2004, extra="DefaultValue=5")                  # not configured
            + PDO.format(cob="ParameterValue=0x181", tt="")
            + nv_objects({0xA040: [1]}))
    assert writes(compile_text(text)) == [
        (0xA040, 0, "01", 0x30), (0xA040, 1, "00", 0xF0),
        (0x1017, 0, "6400", 0x70),
        (0x2000, 0, "01000000", 0x70), (0x2001, 0, "02000000", 0x70),
        # PDO block (CiA 301): disable, configured comm subs 2/3/5/6 (none here: sub4 never,
        # sub5 has ObjFlags), mapping sub0 := 0, subs 1..n, sub0 := n, enable
        (0x1800, 1, "81010080", 0x70),
        (0x1A00, 0, "00", 0x70),
        (0x1A00, 1, "20000020", 0x70), (0x1A00, 2, "10000120", 0x70),
        (0x1A00, 0, "02", 0x70),
        (0x1800, 1, "81010000", 0x70),
    ]


def test_pdo_block_invalid_final_cob_and_transmission_type():
    text = PDO.format(cob="ParameterValue=0x80000181", tt="ParameterValue=254")
    assert writes(compile_text(text)) == [
        (0x1800, 1, "81010080", 0x70),
        (0x1800, 2, "fe", 0x70),
        (0x1A00, 0, "00", 0x70),
        (0x1A00, 1, "20000020", 0x70), (0x1A00, 2, "10000120", 0x70),
        (0x1A00, 0, "02", 0x70),
        # f) skipped: the final COB-ID itself has bit 31 set
    ]


def test_pdo_block_uses_node_id():
    text = PDO.format(cob="ParameterValue=$NODEID+0x180", tt="")
    res = compile_text(text)
    assert messages(res) == [
        "test.dcf:11: error: value '$NODEID+0x180' of 0x1800sub1 uses $NODEID but no node-ID "
        "is known [DCF201]"]
    assert writes(compile_text(text, node_id=5))[0] == (0x1800, 1, "85010080", 0x70)


def test_pdo_sequence_none():
    text = PDO.format(cob="ParameterValue=0x181", tt="")
    assert writes(compile_text(text, pdo_sequence="none")) == [
        (0x1800, 1, "81010000", 0x70), (0x1800, 4, "09", 0x70), (0x1800, 5, "6400", 0x70),
        (0x1A00, 0, "02", 0x70), (0x1A00, 1, "20000020", 0x70), (0x1A00, 3, "08000220", 0x70),
    ]


def test_dis2_profile_masks():
    # node 1: the DefaultValue $NODEID+0x180 is 0x181, the final CAN-ID too (no D-12 write)
    text = PDO.format(cob="ParameterValue=0x40000181", tt="")
    w = writes(compile_text(text, profile="dis2", node_id=1))
    assert w[0] == (0x1800, 1, "810100c0", 0x70)
    assert w[1] == (0x1A00, 0, "00", 0x70)
    assert w[-1] == (0x1800, 1, "81010040", 0x70)


def test_dis2_old_cob_id_first_when_the_can_id_changes():
    # D-12: node 5, DefaultValue $NODEID+0x180 = 0x185 (the COB-ID the drive has), final
    # 0x40000181: the CAN-IDs differ, so the block starts with 0x185 | 0xC0000000
    text = PDO.format(cob="ParameterValue=0x40000181", tt="")
    w = writes(compile_text(text, profile="dis2", node_id=5))
    assert w[:3] == [(0x1800, 1, "850100c0", 0x70), (0x1800, 1, "810100c0", 0x70),
                     (0x1A00, 0, "00", 0x70)]
    assert w[-1] == (0x1800, 1, "81010040", 0x70)
    assert len(w) == 7   # a, c, d (2 entries), e, f: 6 writes (no b here) plus the old one
    # the CiA 301 profile never writes the old COB-ID (final | 0x80000000, then final)
    assert [x for x in writes(compile_text(text, node_id=5)) if x[1] == 1 and x[0] == 0x1800] \
        == [(0x1800, 1, "810100c0", 0x70), (0x1800, 1, "81010040", 0x70)]


@pytest.mark.parametrize("default, first", [
    ("0xC0000181", "810100c0"),      # same CAN-ID, other flags: no old write
    ("0x181", "810100c0"),
    ("0x20000181", "810100c0"),      # bit 29 (frame format) is not part of the CAN-ID
    ("0x20010181", "810101e0"),      # a 29-bit CAN-ID 0x10181 differs from 0x181
    ("0x1234567", "674523c1"),       # old | 0xC0000000, whatever the old bits are
])
def test_dis2_old_cob_id_compares_bits_0_to_28(default, first):
    text = PDO.format(cob="ParameterValue=0x40000181", tt="").replace(
        "DefaultValue=$NODEID+0x180", f"DefaultValue={default}")
    w = writes(compile_text(text, profile="dis2"))
    assert w[0] == (0x1800, 1, first, 0x70)
    assert w[1][:3] == ((0x1800, 1, "810100c0") if first != "810100c0" else (0x1A00, 0, "00"))


def test_dis2_no_default_value_no_old_cob_id():
    text = PDO.format(cob="ParameterValue=0x40000181", tt="").replace(
        "DefaultValue=$NODEID+0x180\n", "")
    w = writes(compile_text(text, profile="dis2"))
    assert w[:2] == [(0x1800, 1, "810100c0", 0x70), (0x1A00, 0, "00", 0x70)]


def test_dis2_old_cob_id_needs_the_node_id_and_a_good_value():
    text = PDO.format(cob="ParameterValue=0x40000181", tt="")
    assert messages(compile_text(text, profile="dis2")) == [
        "test.dcf:10: error: value '$NODEID+0x180' of 0x1800sub1 uses $NODEID but no node-ID "
        "is known [DCF201]"]
    bad = text.replace("DefaultValue=$NODEID+0x180", "DefaultValue=0x1FFFFFFFF")
    res = compile_text(bad, profile="dis2")
    assert messages(res) == [
        "test.dcf:10: error: 0x1800sub1 DefaultValue: value 0x1FFFFFFFF (= 8589934591) out of "
        "range for UNSIGNED32 (0..4294967295) [DCF200]"]
    assert messages(res, "warning") == []   # not also a "not written" warning
    # without the profile the DefaultValue is not written: a warning, and a container
    res = compile_text(bad)
    assert res.ok and messages(res, "warning") == [
        "test.dcf:10: warning: 0x1800sub1 DefaultValue: value 0x1FFFFFFFF (= 8589934591) out of "
        "range for UNSIGNED32 (0..4294967295) (not written by compile) [DCF200]"]


def test_select_all_takes_default_values():
    text = (var(0x1000, a="ro", extra="DefaultValue=0x191") + var(0x2000, extra="DefaultValue=7")
            + var(0x2003, extra="ObjFlags=1\nDefaultValue=1") + var(0x2005))
    assert writes(compile_text(text, select="all")) == [
        (0x1000, 0, "91010000", 0x30), (0x2000, 0, "07000000", 0x70)]


def test_mapping_count_errors():
    text = PDO.format(cob="ParameterValue=0x181", tt="").replace(
        "[1A00sub0]\nDataType=0x0005\nAccessType=rw\nParameterValue=2",
        "[1A00sub0]\nDataType=0x0005\nAccessType=rw\nParameterValue=4")
    assert messages(compile_text(text)) == [
        "test.dcf:35: error: PDO mapping 0x1A00 maps 4 objects but has no sub 4 [DCF417]"]


def test_comm_without_mapping_is_an_error():
    text = "[1400]\nObjectType=0x9\n[1400sub1]\nDataType=0x0007\nAccessType=rw\n"
    assert messages(compile_text(text)) == [
        "test.dcf:1: error: PDO communication object 0x1400 has no mapping object 0x1600 [DCF401]"]


@pytest.mark.parametrize("dtype, access, mapping, attr", [
    ("0x0001", "rw", "0", 0x61),   # BOOLEAN rw (SPEC §3.3 example)
    ("0x0009", "ro", "0", 0x28),   # VISIBLE_STRING ro -> selected only with --entries all
    ("0x000F", "rw", "0", 0x60),   # DOMAIN rw
    ("0x0007", "rw", "1", 0xF0),   # UNSIGNED32 rw mappable
    ("0x0007", "wo", "0", 0x50),
    ("0x000A", "rww", "0", 0x60),  # OCTET_STRING: byte copy, no type bit
    ("0x0008", "rwr", "1", 0xF0),  # REAL32 is NUMERIC
])
def test_attribute_bytes(dtype, access, mapping, attr):
    value = "0" if dtype not in ("0x0009", "0x000F", "0x000A") else '""'
    text = var(0x2000, dtype, access, f"PDOMapping={mapping}\nDefaultValue={value}")
    assert writes(compile_text(text, select="all"))[0][3] == attr


def test_static_od_creates_missing_objects(tmp_path):
    static = tmp_path / "static.eds"
    static.write_text(var(0x2000, extra="DefaultValue=0"))
    text = (var(0x2000, extra="ParameterValue=1")
            + var(0x2100, a="ro", extra="DefaultValue=3"))
    assert writes(compile_text(text, static_od=str(static))) == [
        (0x2100, 0, "03000000", 0x30), (0x2000, 0, "01000000", 0x70)]


def test_error_in_unwritten_entry_is_a_warning():
    text = var(0x2000, extra="DefaultValue=0x1FFFFFFFF") + var(0x2001, extra="ParameterValue=1")
    res = compile_text(text)
    assert writes(res) == [(0x2001, 0, "01000000", 0x70)]
    text = var(0x2000, "0x0005", extra="ParameterValue=256")
    assert messages(compile_text(text)) == [
        "test.dcf:5: error: 0x2000sub0: value 256 out of range for UNSIGNED8 (0..255) [DCF200]"]


def test_negative_mapping_count_is_an_error_not_a_crash():
    text = PDO.format(cob="ParameterValue=0x181", tt="").replace(
        "[1A00sub0]\nDataType=0x0005\nAccessType=rw\nParameterValue=2",
        "[1A00sub0]\nDataType=0x0002\nAccessType=rw\nParameterValue=-1")
    assert messages(compile_text(text)) == [
        "test.dcf:35: error: 0x1A00sub0: -1 mapped objects is negative [DCF417]"]


def test_static_od_that_is_not_an_eds_is_an_error(tmp_path):
    static = tmp_path / "static.eds"
    static.write_bytes(b"\x00\x01binary\n[2000]\nDataType=0x0007\n")
    res = compile_text(var(0x2000, extra="ParameterValue=1"), static_od=str(static))
    assert messages(res) == [
        f"{static}:1: error: static OD: line without '=': '\\x00\\x01binary' [DCF002]"]


# -- group 1 in bulk: the data column of an object equals encoding entry by entry ----------

def test_group_one_data_column_equals_entry_by_entry():
    # runs of variables built from one template share their bytes; a value with a comment
    # warns once per entry (it is never cached) and a bad value is an error per entry,
    # each at its own line, as Device.encode says entry by entry
    from dcf2bin import model, select
    from dcf2bin.diagnostics import DcfError
    subs = []
    values = ["0", "0", "0", "7 ; seven", "7 ; seven", "0", "x1", "x1", "0", "$NODEID+1", "0"]
    for s, v in enumerate(values, 1):
        subs.append(f"[A040sub{s:X}]\nParameterName=v{s}\nObjectType=0x7\nDataType=0x0005\n"
                    f"AccessType=ro\nDefaultValue={v}\nPDOMapping=1\n")
    text = ("[DynamicChannels]\nNrOfSeg=1\nType1=0x0005\nDir1=ro\nRange1=0xA040-0xA07F\n"
            "PPOffset1=0\n[A040]\nParameterName=in\nObjectType=0x8\nSubNumber=12\n"
            + "".join(subs))
    dev = model.load("t.dcf", data=text.encode(), node_id=3)
    sel = select.select(dev)
    expected, errors = [], []
    ref = model.load("t.dcf", data=text.encode(), node_id=3)
    for e in ref.objects[0xA040].entries.values():
        try:
            data = ref.encode(e)
        except DcfError as exc:
            errors.append(exc.diagnostic.format())
            data = b""
        expected.append((0xA040, e.sub, data))
    assert sel.entries == expected
    assert [d.format() for d in sel.errors] == errors and len(errors) == 2
    assert bytes(sel.attrs) == bytes([select.NV_SUB0_ATTR] + [select.NV_ATTR] * 11)
    assert [p.diagnostic.format() for p in dev.problems] == [
        p.diagnostic.format() for p in ref.problems]
    assert sum("DCF203" in p.diagnostic.format() for p in dev.problems) == 2
    # the bytes of equal values are shared, as the cache of encodings gives them
    assert sel.entries[1][2] is sel.entries[2][2]


def test_pdo_blocks_rpdos_then_tpdos_by_index_at_the_range_ends():
    """The PDO blocks come RPDOs (0x1400-0x15FF) then TPDOs (0x1800-0x19FF), each by
    ascending index, whatever the file order; a comm object at either end of its range
    counts, and the mapping objects between the ranges are no PDO of their own."""
    def block(comm):
        return (PDO.replace("1800", f"{comm:04X}").replace("1A00", f"{comm + 0x200:04X}")
                .format(cob="ParameterValue=0x181", tt=""))
    # one CAN-ID for all: the target check is off here, only the order counts
    text = block(0x19FF) + block(0x1800) + block(0x15FF) + block(0x1400)
    blocks = [i for i, s, _, _ in writes(compile_text(text)) if s == 1 and i < 0x1600
              or s == 1 and 0x1800 <= i < 0x1A00]
    # every block writes its COB-ID twice: disable, then enable
    assert blocks == [0x1400, 0x1400, 0x15FF, 0x15FF, 0x1800, 0x1800, 0x19FF, 0x19FF]
