"""The DynBuildOd emulation (SPEC §8, D-11): every return code at a known entry, each
next to a passing neighbour that differs in one byte (or one option); the static OD; the
result (descriptor, created, PDOs, OD); compile's check of what it writes."""
from __future__ import annotations

import struct

import pytest
from conftest import SAMPLES

from dcf2bin import model
from dcf2bin.container import BinContainer, read
from dcf2bin.dynod import StaticOD, TargetOptions, emulate, emulate_bytes
from dcf2bin.dynod import codes as C

U32 = struct.Struct("<I")
RW, RW_MAP = 0x70, 0xF0          # NUMERIC|READ|WRITE (+PDO)


def u32(v: int) -> bytes:
    return U32.pack(v)


def run(c: BinContainer, **kw):
    """Emulate the container through its bytes (as a target gets it)."""
    static = kw.pop("static", None)
    data = c.to_bytes()
    if static is None:
        return emulate_bytes(data, TargetOptions(**kw))
    return emulate(read(data)[0], TargetOptions(**kw), static)


def offset_of(c: BinContainer, pos: int) -> int:
    """Byte offset of entry ``pos`` (1-based) in a canonical container."""
    return 40 + 4 + sum(7 + len(d) for _, _, d in c.entries[:pos - 1])


def one_byte_apart(a: BinContainer, b: BinContainer) -> None:
    x, y = a.to_bytes(), b.to_bytes()
    assert len(x) == len(y) and sum(p != q for p, q in zip(x, y)) == 1


def pdo(comm: int, cob: int, mapped: list[int], disable: int | None = None
        ) -> list[tuple[int, int, bytes]]:
    """A CiA 301 PDO block: disable, sub 0 := 0, entries, sub 0 := n, enable."""
    m = comm + 0x200
    out = [(comm, 1, u32((cob if disable is None else disable) | 0x80000000)), (m, 0, b"\x00")]
    out += [(m, k, u32(v)) for k, v in enumerate(mapped, 1)]
    out += [(m, 0, bytes([len(mapped)]))]
    if not cob & 0x80000000:
        out.append((comm, 1, u32(cob)))
    return out


def app(*blocks) -> BinContainer:
    """0x2000 (UNSIGNED8, mappable) and 0x2001 (UNSIGNED32, mappable), then PDO blocks;
    every entry carries an attribute (created on a target without a static OD)."""
    entries = [(0x2000, 0, b"\x00"), (0x2001, 0, u32(0))]
    for b in blocks:
        entries += b
    attrs = bytes(RW_MAP if i in (0x2000, 0x2001) else RW for i, _, _ in entries)
    return BinContainer(entries=entries, attributes=attrs)


def plc(addresses: list[int], pi: tuple) -> BinContainer:
    """Two UNSIGNED8 inputs A040sub1/sub2 at ``addresses``."""
    entries = [(0xA040, 0, b"\x02"), (0xA040, 1, b"\x00"), (0xA040, 2, b"\x00")]
    return BinContainer(entries=entries, attributes=bytes([0x30, RW_MAP, RW_MAP]),
                        addresses=addresses, pi=pi)


def expect(out, code: int, entry: int | None, c: BinContainer | None = None):
    assert (out.code, out.name, out.entry) == (code, C.NAMES[code], entry), out.reason
    if entry is not None and c is not None:
        assert out.offset == offset_of(c, entry)
        assert (out.index, out.subindex) == c.entries[entry - 1][:2]


# -- every code, with a neighbour ------------------------------------------------------------

def test_success_and_what_it_reports():
    c = app(pdo(0x1800, 0x181, [0x20000008, 0x20010020]))
    out = run(c)
    expect(out, C.OK, None)
    assert out.ok and out.reason == "" and out.entries_applied == len(c.entries)
    assert out.created.objects == [0x1800, 0x1A00, 0x2000, 0x2001]
    assert (out.created.entries, out.created.bytes) == (6, 1 + 4 + 4 + 1 + 4 + 4)
    [p] = out.pdos
    assert (p.direction, p.comm_index, p.cob_id, p.can_id, p.bits) == ("tx", 0x1800, 0x181,
                                                                         0x181, 40)
    assert p.mapped == [(0x2000, 0, 8, None), (0x2001, 0, 32, None)]



def test_pdos_are_worked_out_when_first_asked_for():
    # a compile's target check only asks whether the run succeeded: the PDO list (with the
    # PI address of every mapped variable) is made on first use, and is then kept
    c = app(pdo(0x1800, 0x181, [0x20000008]))
    out = run(c)
    assert out._pdos is None
    first = out.pdos
    assert [p.comm_index for p in first] == [0x1800] and out.pdos is first
    c.attributes = c.attributes[:-1]        # a failing run has no PDOs
    assert run(c).pdos == []

def test_0xA1_extended_info_count():
    c = app(pdo(0x1800, 0x181, [0x20000008]))
    c.attributes = c.attributes[:-1]
    out = run(c)
    expect(out, C.INVALID_CONFIG, None)
    assert out.step == "structure"
    assert out.reason == "the extended info segment has 6 attribute bytes for 7 index entries"


def test_0xA1_address_count():
    out = run(plc([0], (2, 0, 2, 0, 0)))
    expect(out, C.INVALID_CONFIG, None)
    assert out.reason == "the PI address segment holds 1 addresses for 2 network variables"


def test_0xA1_areas_outside_the_image_and_neighbour():
    bad, good = plc([0, 1], (2, 0, 3, 0, 0)), plc([0, 1], (3, 0, 3, 0, 0))
    one_byte_apart(bad, good)
    expect(run(bad), C.INVALID_CONFIG, None)
    assert run(bad).reason == "the input area [0, 3) lies beyond the PI size 2"
    expect(run(good), C.OK, None)


def test_0xA1_address_beyond_the_image_names_the_variable():
    bad, good = plc([0, 2], (2, 0, 2, 0, 0)), plc([0, 1], (2, 0, 2, 0, 0))
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.INVALID_CONFIG, 3, bad)
    assert out.reason == "network variable at PI address 2 with 1 bytes ends beyond the PI size 2"
    expect(run(good), C.OK, None)


def test_0xA1_overlap_names_the_later_variable():
    bad, good = plc([1, 1], (2, 0, 2, 0, 0)), plc([1, 0], (2, 0, 2, 0, 0))
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.INVALID_CONFIG, 3, bad)
    assert out.reason == "PI bytes 1..1 overlap those of 0xA040sub1 (1..1)"
    assert run(good).ok


def test_0xA1_overlap_search_finds_the_first_in_address_order():
    entries = [(0xA100, 0, b"\x03")] + [(0xA100, s, b"\x00\x00") for s in (1, 2, 3)]
    c = BinContainer(entries=entries, attributes=bytes([0x30] + [RW_MAP] * 3),
                     addresses=[4, 0, 3], pi=(6, 0, 6, 0, 0))
    out = run(c)
    expect(out, C.INVALID_CONFIG, 4, c)     # sub3 [3, 5) overlaps sub1 [4, 6)
    assert "overlap those of 0xA100sub1 (4..5)" in out.reason


def test_0xA1_entry_size_differs_from_its_object():
    c = BinContainer(entries=[(0x2000, 0, b"\x01\x00"), (0x2000, 0, b"\x01\x00\x00")],
                     attributes=bytes([RW, RW]))
    out = run(c)
    expect(out, C.INVALID_CONFIG, 2, c)
    assert out.reason == "3 data bytes written into a NUMERIC entry of 2 bytes"
    c.entries[1] = (0x2000, 0, b"\x01\x01")
    assert run(c).ok


def test_0xA1_static_entry_of_another_size(tmp_path):
    static = _static(tmp_path, "[2000]\nParameterName=W\nObjectType=0x7\nDataType=0x0006\n"
                               "AccessType=rw\nDefaultValue=0\n")
    bad = BinContainer(entries=[(0x2000, 0, b"\x01")], attributes=b"\x70")
    out = run(bad, static=static)
    expect(out, C.INVALID_CONFIG, 1, bad)
    assert out.reason == "1 data bytes written into a UNSIGNED16 of 2 bytes"
    assert run(BinContainer(entries=[(0x2000, 0, b"\x01\x00")], attributes=b"\x70"),
               static=static).ok


def test_0xA0_pi_memory_and_neighbour():
    bad, good = plc([0, 1], (3, 0, 2, 0, 0)), plc([0, 1], (2, 0, 2, 0, 0))
    one_byte_apart(bad, good)
    out = run(bad, pi_size=2)
    expect(out, C.NO_MEMORY, None)
    assert (out.step, out.reason) == ("memory", "the process image needs 3 bytes, the target "
                                                "gives 2")
    assert out.descriptor.memory == 2 and out.descriptor.out == (3, 0, 2, 0, 0)
    assert run(good, pi_size=2).ok
    assert run(bad).ok                       # unlimited memory by default


def _static(tmp_path, body: str) -> StaticOD:
    p = tmp_path / "static.eds"
    p.write_text(body)
    return StaticOD.from_eds(str(p))


def test_0x31_and_0x32_without_extended_info(tmp_path):
    static = _static(tmp_path, "[2000]\nParameterName=X\nObjectType=0x7\nDataType=0x0005\n"
                               "AccessType=rw\nDefaultValue=0\n")
    absent = BinContainer(entries=[(0x2001, 0, b"\x01")])
    present = BinContainer(entries=[(0x2000, 0, b"\x01")])
    no_sub = BinContainer(entries=[(0x2000, 1, b"\x01")])
    one_byte_apart(absent, present)
    one_byte_apart(no_sub, present)
    expect(run(absent, static=static), C.INDEX_NOT_EXIST, 1, absent)
    expect(run(no_sub, static=static), C.SUBINDEX_NOT_EXIST, 1, no_sub)
    out = run(present, static=static)
    assert out.ok and out.created.entries == 0
    assert out.od[0x2000][0].data == b"\x01" and out.od[0x2000][0].written


def test_unknown_static_od_without_extended_info_assumes_and_warns():
    out = run(BinContainer(entries=[(0x2001, 0, b"\x01"), (0x2002, 0, b"\x01")]))
    assert out.ok
    assert [(w.rule, w.message) for w in out.warnings] == [
        ("TGT101", "2 entries could not be checked: no extended info segment and no static OD, "
                   "so they are assumed to exist")]


def test_0x31_pdo_becomes_valid_without_its_mapping_object(tmp_path):
    static = _static(tmp_path, "[1800]\nParameterName=C\nObjectType=0x9\nSubNumber=2\n\n"
                               "[1800sub0]\nParameterName=n\nObjectType=0x7\nDataType=0x0005\n"
                               "AccessType=ro\nDefaultValue=1\n\n[1800sub1]\nParameterName=COB"
                               "\nObjectType=0x7\nDataType=0x0007\nAccessType=rw\n"
                               "DefaultValue=0x80000181\n")
    bad = BinContainer(entries=[(0x1800, 1, u32(0x181))])
    good = BinContainer(entries=[(0x1800, 1, u32(0x80000181))])
    one_byte_apart(bad, good)
    out = run(bad, static=static)
    expect(out, C.INDEX_NOT_EXIST, 1, bad)
    assert out.reason == "TPDO1 (0x1800) becomes valid but its mapping object 0x1A00 does " \
                         "not exist"
    assert run(good, static=static).ok


def test_0x31_mapped_object_absent(tmp_path):
    static = _static(tmp_path, "[1000]\nParameterName=T\nObjectType=0x7\nDataType=0x0007\n"
                               "AccessType=ro\nDefaultValue=0\n")
    bad = app(pdo(0x1800, 0x181, [0x20030008]))
    good = app(pdo(0x1800, 0x181, [0x20000008]))
    one_byte_apart(bad, good)
    out = run(bad, static=static)
    expect(out, C.INDEX_NOT_EXIST, 5, bad)
    assert out.reason == "the mapped object 0x2003 does not exist"
    assert run(good, static=static).ok
    # without a static OD an object the container never writes cannot be checked
    assert run(bad).ok and run(bad).warnings


def test_0x32_mapped_sub_absent():
    bad, good = app(pdo(0x1800, 0x181, [0x20000108])), app(pdo(0x1800, 0x181, [0x20000008]))
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.SUBINDEX_NOT_EXIST, 5, bad)
    assert out.reason == "the mapped object 0x2000sub1 does not exist (no sub 1 in 0x2000)"
    assert run(good).ok


def test_0x32_sub0_counts_a_missing_mapping_entry():
    entries = [(0x2000, 0, b"\x00"), (0x1A00, 0, b"\x00"), (0x1A00, 1, u32(0x20000008)),
               (0x1A00, 0, b"\x02")]
    bad = BinContainer(entries=entries, attributes=bytes([RW_MAP, RW, RW, RW]))
    good = BinContainer(entries=entries[:3] + [(0x1A00, 0, b"\x01")],
                        attributes=bytes([RW_MAP, RW, RW, RW]))
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.SUBINDEX_NOT_EXIST, 4, bad)
    assert out.reason == "sub 0 = 2, but the mapping has no sub 2"
    assert run(good).ok


@pytest.mark.parametrize("cob, reason", [
    (0x701, "TPDO1 (0x1800): CAN-ID 0x701 is restricted by CiA 301 (0x701-0x77F)"),
    (0x000, "TPDO1 (0x1800): CAN-ID 0x000 is restricted by CiA 301"),
    (0x5FF, "TPDO1 (0x1800): CAN-ID 0x5FF is restricted by CiA 301 (0x581-0x5FF)"),
    (0x00010181, "TPDO1 (0x1800): an 11-bit COB-ID with bits 11-28 set"),
])
def test_0x23_illegal_can_id(cob, reason):
    bad = app(pdo(0x1800, cob, [0x20000008]))
    out = run(bad)
    expect(out, C.ILLEGAL_CAN_ID, 7, bad)
    assert out.reason == reason


def test_0x23_neighbour_and_29_bit_frames():
    bad = app(pdo(0x1800, 0x701, [0x20000008], disable=0x201))
    good = app(pdo(0x1800, 0x201, [0x20000008], disable=0x201))
    one_byte_apart(bad, good)
    assert run(good).ok
    assert run(app(pdo(0x1800, 0x20000701, [0x20000008]))).ok   # 29-bit: any identifier


def test_0x23_valid_pdo_changes_its_can_id():
    block = pdo(0x1800, 0x181, [0x20000008])
    bad = app(block, [(0x1800, 1, u32(0x182))])
    good = app(block, [(0x1800, 1, u32(0x181))])
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.ILLEGAL_CAN_ID, 8, bad)
    assert "a valid PDO may not change its CAN-ID" in out.reason
    assert run(good).ok


def test_0x21_two_valid_pdos_share_a_can_id():
    bad = app(pdo(0x1800, 0x181, [0x20000008]), pdo(0x1801, 0x181, [0x20010020], disable=0x281))
    good = app(pdo(0x1800, 0x181, [0x20000008]), pdo(0x1801, 0x281, [0x20010020], disable=0x281))
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.COB_EXISTS, 12, bad)
    assert out.reason == "CAN-ID 0x181 is already used by valid TPDO1 (0x1800)"
    assert run(good).ok


def test_0x21_only_within_one_direction():
    assert run(app(pdo(0x1800, 0x201, [0x20000008]), pdo(0x1400, 0x201, [0x20010020]))).ok


def test_0x20_cob_table_full():
    bad = app(pdo(0x1800, 0x181, [0x20000008]), pdo(0x1801, 0x281, [0x20010020]))
    # the same block whose last write keeps the PDO invalid (bit 31): one byte
    good = app(pdo(0x1800, 0x181, [0x20000008]),
               pdo(0x1801, 0x281, [0x20010020])[:-1] + [(0x1801, 1, u32(0x80000281))])
    one_byte_apart(bad, good)
    out = run(bad, tx_cobs=1)
    expect(out, C.NO_FREE_COB, 12, bad)
    assert out.reason == "TPDO2 (0x1801) would be valid TX PDO number 2; the target's TX COB " \
                         "table holds 1"
    assert run(good, tx_cobs=1).ok
    assert run(bad, tx_cobs=1, rx_cobs=0).code == C.NO_FREE_COB
    assert run(bad, rx_cobs=0).ok


def test_0x78_length_and_neighbour():
    bad, good = app(pdo(0x1800, 0x181, [0x20000010])), app(pdo(0x1800, 0x181, [0x20000008]))
    one_byte_apart(bad, good)
    out = run(bad)
    expect(out, C.PDO_MAPPING, 5, bad)
    assert out.reason == "0x2000sub0 has 8 bits, the mapping says 16"


def test_0x78_mapping_changed_while_valid():
    block = pdo(0x1800, 0x181, [0x20000008])
    bad = app(block, [(0x1A00, 0, b"\x00")])
    out = run(bad)
    expect(out, C.PDO_MAPPING, 8, bad)
    assert out.reason == "the mapping of TPDO1 (0x1800) is changed while the PDO is valid " \
                         "(set COB-ID bit 31 first)"
    good = app(block[:-1] + [(0x1800, 1, u32(0x80000181))], [(0x1A00, 0, b"\x00")])
    one_byte_apart(bad, good)
    assert run(good).ok


def test_0x78_entry_written_while_sub0_not_zero():
    entries = [(0x2000, 0, b"\x00"), (0x1A00, 0, b"\x01"), (0x1A00, 1, u32(0x20000008))]
    bad = BinContainer(entries=entries, attributes=bytes([RW_MAP, RW, RW]))
    good = BinContainer(entries=[entries[0], (0x1A00, 0, b"\x00"), entries[2]],
                        attributes=bytes([RW_MAP, RW, RW]))
    one_byte_apart(bad, good)
    out = run(bad)
    # sub 0 = 1 checks sub 1 first: it does not exist yet
    expect(out, C.SUBINDEX_NOT_EXIST, 2, bad)
    entries[1:1] = [(0x1A00, 1, u32(0))]
    bad = BinContainer(entries=entries, attributes=bytes([RW_MAP, RW, RW, RW]))
    out = run(bad)
    expect(out, C.PDO_MAPPING, 4, bad)
    assert out.reason == "mapping entry written while sub 0 is 1 (write sub 0 = 0 first)"
    assert run(good).ok


def test_0x78_not_mappable_and_direction():
    entries = [(0x2000, 0, b"\x00")] + pdo(0x1800, 0x181, [0x20000008])
    # 0x2000 without the PDO bit (0x70 instead of 0xF0): one byte
    bad = BinContainer(entries=entries, attributes=bytes([RW] * len(entries)))
    good = BinContainer(entries=entries, attributes=bytes([RW_MAP] + [RW] * (len(entries) - 1)))
    one_byte_apart(bad, good)
    expect(run(bad), C.PDO_MAPPING, 4, bad)
    assert run(bad).reason == "0x2000sub0 is not PDO-mappable"
    assert run(good).ok
    wo = BinContainer(entries=entries, attributes=bytes([0xD0] + [RW] * (len(entries) - 1)))
    assert run(wo).reason == "0x2000sub0 is not readable, so a TPDO cannot map it"
    rx = [(0x2000, 0, b"\x00")] + pdo(0x1400, 0x201, [0x20000008])
    ro = BinContainer(entries=rx, attributes=bytes([0xB0] + [RW] * (len(rx) - 1)))
    assert run(ro).reason == "0x2000sub0 is not writable, so an RPDO cannot map it"


def test_0x78_more_than_64_bits():
    bad = app(pdo(0x1800, 0x181, [0x20010020, 0x20010020, 0x20000008]))
    out = run(bad)
    expect(out, C.PDO_MAPPING, 8, bad)
    assert out.reason == "the 3 mapped objects have 72 bits, more than the 64 of a CAN frame"


def test_boolean_bit_mapping_and_granularity():
    entries = [(0x2000, 0, b"\x00")] + pdo(0x1800, 0x181, [0x20000001, 0x20010020])
    attrs = bytes([0xF1] + [RW] * (len(entries) - 1))       # BOOLEAN|READ|WRITE|PDO
    c = BinContainer(entries=entries, attributes=attrs)
    assert run(c).ok
    out = run(c, bit_mapping=False)
    expect(out, C.PDO_MAPPING, 4, c)
    assert out.reason == "0x2000sub0 is a BOOLEAN mapped with 1 bit, and the target has no " \
                         "bit mapping"
    out = run(c, granularity=8)
    assert (out.code, out.entry) == (C.PDO_MAPPING, 4)
    assert out.reason == "0x2000sub0 is mapped with 1 bits, and the target maps whole bytes " \
                         "only (granularity 8)"
    c4 = BinContainer(entries=[(0x2000, 0, b"\x00")] + pdo(0x1800, 0x181, [0x20000004]),
                      attributes=attrs[:1] + bytes([RW] * 5))
    out = run(c4)
    assert (out.code, out.entry, out.reason) == (
        C.PDO_MAPPING, 4, "0x2000sub0 is a BOOLEAN mapped with 4 bits (1 or 8)")
    assert run(BinContainer(entries=[(0x2000, 0, b"\x00")] + pdo(0x1800, 0x181, [0x20000008]),
                            attributes=attrs[:1] + bytes([RW] * 5)), granularity=8,
               bit_mapping=False).ok


def test_dummy_entries_are_mappable():
    assert run(app(pdo(0x1400, 0x201, [0x00050008, 0x20000008]))).ok
    out = run(app(pdo(0x1400, 0x201, [0x00050010])))
    assert (out.code, out.reason) == (C.PDO_MAPPING, "0x0005sub0 has 8 bits, the mapping says 16")


def test_unknown_static_od_mapped_object_passes_with_a_warning():
    out = run(app(pdo(0x1800, 0x181, [0x60000108, 0x20000008])))
    assert out.ok
    assert [(w.rule, w.message) for w in out.warnings] == [
        ("TGT103", "mapped object 0x6000sub1 is not in the container and the static OD is "
                   "unknown: its existence, access and length were not checked "
                   "(give --static-od)")]
    assert out.pdos[0].bits == 16           # the mapped length still counts


def test_reader_rejection_is_0xA1():
    out = emulate_bytes(b"\x00" * 10)
    assert (out.code, out.entry, out.offset) == (C.INVALID_CONFIG, None, 0)


def test_stops_at_the_first_failure():
    c = app(pdo(0x1800, 0x701, [0x20000010]))    # bad length (entry 5) before bad CAN-ID
    out = run(c)
    assert (out.code, out.entry, out.entries_applied) == (C.PDO_MAPPING, 5, 4)


# -- results ---------------------------------------------------------------------------------

def test_plc_sample_pdos_carry_pi_addresses():
    out = emulate_bytes((SAMPLES / "plc.bin").read_bytes())
    assert out.ok and out.descriptor.out == (16, 0, 8, 8, 8)
    rx, tx = out.pdos
    assert (rx.direction, rx.cob_id, tx.direction, tx.cob_id) == ("rx", 0x210, "tx", 0x190)
    assert rx.mapped == [(0xA040, 1, 8, 0), (0xA040, 2, 8, 1), (0xA040, 3, 8, 2),
                         (0xA040, 4, 8, 3), (0xA0C0, 3, 16, 4), (0xA0C0, 4, 16, 6)]
    assert tx.mapped == [(0xA4C0, 1, 8, 8), (0xA4C0, 2, 8, 9), (0xA680, 2, 32, 12)]
    e = out.od[0xA0C0][3]
    assert (e.dtype.name, e.kind, e.pi_address, e.readable, e.writable, e.mappable,
            e.created) == ("INTEGER16", "numeric", 4, True, True, True, True)


def test_address_base_area_counts_from_the_area():
    entries = [(0xA040, 0, b"\x01"), (0xA040, 1, b"\x00"), (0xA4C0, 0, b"\x01"),
               (0xA4C0, 1, b"\x00")]
    c = BinContainer(entries=entries, attributes=bytes([0x30, RW_MAP] * 2), addresses=[0, 0],
                     pi=(9, 0, 1, 8, 1))
    assert run(c).code == C.INVALID_CONFIG          # image base: both at byte 0
    out = run(c, address_base="area")
    assert out.ok and out.od[0xA4C0][1].pi_address == 8


def test_compile_static_od_is_the_dcf_minus_the_creation_group():
    from dcf2bin import select as select_mod
    dev = model.load(str(SAMPLES / "plc.dcf"))
    sel = select_mod.select(dev)
    static = StaticOD.from_device(dev, sel.created)
    assert static.has(0x1800) and not static.has(0xA040)
    assert 0xA040 in sel.created


def test_emulation_is_fast_enough_for_60000_variables():
    """Not a benchmark (benchmarks/run.py is): a guard against a quadratic step."""
    import time
    n = 60000
    entries = [(0xA040 + i // 254, 1 + i % 254, b"\x00") for i in range(n)]
    c = BinContainer(entries=entries, attributes=bytes([RW_MAP]) * n,
                     addresses=list(range(n)), pi=(n, 0, n, 0, 0))
    t = time.perf_counter()
    out = emulate(c)
    assert out.ok and out.created.entries == n
    assert time.perf_counter() - t < 5


@pytest.mark.parametrize("readable, writable, access", [
    (True, True, "rw"), (False, True, "wo"), (True, False, "ro"),
    (False, False, "ro"),   # an attribute byte with neither READ nor WRITE: never written
])
def test_target_entry_access_is_one_rule_for_emit_od_and_the_node(readable, writable, access):
    from dcf2bin.dynod import TargetEntry
    e = TargetEntry(0x2000, 0, b"\x00", None, "numeric", readable, writable, False)
    assert e.access == access


# -- an unknown static OD: one rule for what the container has not created (SPEC §8.2) -----

def test_unknown_static_od_index_not_created_counts_as_having_all_subs():
    # no extended info segment: 0x1A00 is written, never created, so sub 1 is assumed
    c = BinContainer(entries=[(0x1A00, 0, b"\x00"), (0x1A00, 0x40, u32(0)),
                              (0x1A00, 0, b"\x01")])
    out = run(c)
    assert out.ok, out.reason
    assert [(w.rule, w.message) for w in out.warnings] == [
        ("TGT101", "2 entries could not be checked: no extended info segment and no static OD, "
                   "so they are assumed to exist"),
        ("TGT104", "0x1A00 sub 0 at entry 3 counts sub 1, which the container has not written "
                   "before it: taken to be in the static OD; the target answers 0x32 "
                   "kCopObdSubindexNotExist if it is not (give --static-od)")]
    # sub 0 = 255 with no sub written was, and stays, a pass
    assert run(BinContainer(entries=[(0x1A00, 0, b"\xff")])).ok


def test_unknown_static_od_created_index_has_exactly_its_created_subs():
    # the container creates 0x1A00 (attribute bytes): sub 1 was never created -> 0x32
    c = BinContainer(entries=[(0x1A00, 0, b"\x00"), (0x1A00, 0x40, u32(0)),
                              (0x1A00, 0, b"\x01")], attributes=bytes([RW] * 3))
    out = run(c)
    expect(out, C.SUBINDEX_NOT_EXIST, 3, c)
    assert out.reason == "sub 0 = 1, but the mapping has no sub 1"
    # the creating write itself: sub 0 = 1 creates 0x1A00 with sub 0 only
    c = BinContainer(entries=[(0x1A00, 0, b"\x01")], attributes=bytes([RW]))
    expect(run(c), C.SUBINDEX_NOT_EXIST, 1, c)


def test_mapped_object_written_later_says_so():
    # RPDO1 maps 0xA580sub1 before the entry that creates 0xA580
    entries = pdo(0x1400, 0x201, [0xA5800108]) + [(0xA580, 0, b"\x01"), (0xA580, 1, b"\x00")]
    c = BinContainer(entries=entries, attributes=bytes([RW] * len(entries)))
    out = run(c)
    assert out.ok, out.reason
    assert [(w.rule, w.message) for w in out.warnings] == [
        ("TGT103", "mapped object 0xA580sub1 is mapped at entry 3, but the container writes "
                   "it only at entry 7: it is taken to be in the static OD; the target refuses "
                   "the mapping (0x31 kCopObdIndexNotExist) if it is not")]


def test_mapping_object_written_later_says_so():
    # TPDO1 made valid before its mapping object is written (first entry of the container)
    entries = [(0x1800, 1, u32(0x181)), (0x1A00, 1, u32(0))]
    c = BinContainer(entries=entries, attributes=bytes([RW] * 2))
    out = run(c)
    assert out.ok, out.reason
    assert [(w.rule, w.message) for w in out.warnings] == [
        ("TGT102", "TPDO1 (0x1800) is made valid at entry 1, but the container writes its "
                   "mapping object 0x1A00 only at entry 2: it is taken to be in the static OD; "
                   "the target answers 0x31 kCopObdIndexNotExist if it is not")]


def test_mapped_object_written_without_attribute_is_not_called_absent():
    entries = [(0x2000, 0, b"\x00")] + pdo(0x1800, 0x181, [0x20000008])
    out = run(BinContainer(entries=entries))
    assert out.ok, out.reason
    assert [w.rule for w in out.warnings] == ["TGT101", "TGT103"]
    assert out.warnings[1].message == (
        "mapped object 0x2000sub0 is written by the container without an attribute byte and "
        "the static OD is unknown: its access and length were not checked (give --static-od)")


def test_every_warning_rule_is_registered():
    from dcf2bin.lint.registry import RULES, WARNING
    for rid in (C.UNCHECKED_ENTRY, C.UNCHECKED_MAPPING_OBJECT, C.UNCHECKED_MAPPED_OBJECT,
                C.UNCHECKED_MAPPING_ENTRY):
        assert RULES[rid].severity is WARNING and RULES[rid].name.startswith("target-")
