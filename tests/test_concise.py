"""The concise DCF's one reader and writer (dcf2bin.concise, SPEC §3.2): exact bytes, the
schema's layout, every way the bytes can be wrong, and the content tests filekind uses."""
from __future__ import annotations

import pytest

from dcf2bin import concise, schema
from dcf2bin.diagnostics import Diagnostic, Severity

# drive.bin of tests/golden/network/flat, its first three entries, one field per line
THREE = bytes.fromhex(
    "03000000"              # count 3
    "0014" "01" "04000000"  # 0x1400 sub 1, 4 bytes
    "02020080"              #   0x80000202: RPDO1 invalid, CAN-ID 0x202
    "0014" "02" "01000000"  # 0x1400 sub 2, 1 byte
    "01"                    #   transmission type 1
    "0016" "00" "01000000"  # 0x1600 sub 0, 1 byte
    "00"                    #   no objects mapped
)
ENTRIES = [(0x1400, 1, bytes.fromhex("02020080")), (0x1400, 2, b"\x01"),
           (0x1600, 0, b"\x00")]


def test_written_as_the_spec_lays_it_out():
    assert concise.to_bytes(ENTRIES) == THREE
    assert concise.size_of(ENTRIES) == len(THREE) == 4 + 3 * 7 + 6
    assert concise.to_bytes([]) == b"\0\0\0\0"


def test_read_back_in_order():
    assert concise.parse(THREE) == ENTRIES
    assert concise.read_concise(THREE, "drive.bin") == (ENTRIES, [])
    assert concise.offsets(ENTRIES) == [4, 15, 23]
    assert concise.offsets(ENTRIES, base=40) == [44, 55, 63]
    assert concise.offsets([]) == []


def test_the_structs_are_the_schemas():
    """Declared again so that network build needs no construct: the same bytes as the
    schema's index segment, both ways (its Rebuild of the size has no compiled form)."""
    assert concise.COUNT.format == schema.COUNT.format
    assert concise.ENTRY_HEAD.format == schema.ENTRY_HEAD.format
    doc = [dict(index=i, subindex=s, data=d) for i, s, d in ENTRIES]
    assert schema.IndexSegment.build(doc) == THREE
    parsed = schema.IndexSegment.parse(THREE)
    assert [(e.index, e.subindex, e.data) for e in parsed] == ENTRIES


def test_repeated_entries_and_empty_data_survive():
    entries = [(0x1A00, 0, b"\0"), (0x2000, 7, b""), (0x1A00, 0, b"\x02")]
    data = concise.to_bytes(entries)
    assert data == bytes.fromhex("03000000" "001A0001000000" "00" "00200700000000"
                                 "001A0001000000" "02")
    assert concise.parse(data) == entries


def _error(data: bytes) -> tuple[str, int, str]:
    entries, diags = concise.read_concise(data, "s.bin")
    assert entries is None and len(diags) == 1
    d = diags[0]
    assert (d.severity, d.file, d.line) == (Severity.ERROR, "s.bin", None)
    return d.message, d.offset, d.rule


@pytest.mark.parametrize("data,expected", [
    (b"", ("0 bytes: too short for the entry count (a DWORD)", 0, "CON001")),
    (b"\x01", ("1 byte: too short for the entry count (a DWORD)", 0, "CON001")),
    (b"\x01\0\0", ("3 bytes: too short for the entry count (a DWORD)", 0, "CON001")),
    # the third entry's data runs past the end
    (THREE[:-1], ("entry 3 of 3 (0x1600sub0) claims 1 data byte, 0 remain", 26, "CON002")),
    # the second entry's data, then its head, is cut
    (THREE[:22], ("entry 2 of 3 (0x1400sub2) claims 1 data byte, 0 remain", 18, "CON002")),
    (THREE[:7] + b"\x40\0\0\0" + THREE[11:], ("entry 1 of 3 (0x1400sub1) claims 64 data "
                                            "bytes, 20 remain", 7, "CON002")),
    (THREE[:18], ("entry 2 of 3 is cut short: its head needs 7 bytes, 3 remain", 15,
                  "CON002")),
    (THREE + b"\xAA", ("1 byte after the last of 3 entries", 31, "CON003")),
    (THREE + b"\xAA\xBB", ("2 bytes after the last of 3 entries", 31, "CON003")),
    (b"\0\0\0\0\xFF", ("1 byte after the last of 0 entries", 4, "CON003")),
    # whole entries fill the file, the count says otherwise
    (b"\x05" + THREE[1:], ("the count says 5 entries, but 3 entries fill the file exactly", 0,
                           "CON004")),
    (b"\x02" + THREE[1:], ("the count says 2 entries, but 3 entries fill the file exactly", 0,
                           "CON004")),
    (b"\0" + THREE[1:15], ("the count says 0 entries, but 1 entry fills the file exactly", 0,
                           "CON004")),
    (b"\xFF\xFF\xFF\xFF" + THREE[4:], ("the count says 4294967295 entries, but 3 entries fill "
                                       "the file exactly", 0, "CON004")),
])
def test_every_way_to_be_wrong_is_one_error_at_its_byte(data, expected):
    assert _error(data) == expected
    with pytest.raises(concise.ConciseError) as exc:
        concise.parse(data)
    assert (str(exc.value), exc.value.offset, exc.value.rule) == expected


def test_a_huge_count_allocates_nothing():
    data = b"\xFF\xFF\xFF\x7F" + bytes(7)          # 2**31-1 entries claimed, 11 bytes
    assert _error(data) == ("the count says 2147483647 entries, but 1 entry fills the file "
                            "exactly", 0, "CON004")


def test_the_diagnostic_prints_the_offset():
    _, diags = concise.read_concise(THREE + b"\xAA", "out/drive.bin")
    assert diags == [Diagnostic(Severity.ERROR, "1 byte after the last of 3 entries",
                                "out/drive.bin", offset=31, rule="CON003")]
    assert diags[0].format() == ("out/drive.bin:0x1F: error: 1 byte after the last of 3 "
                                 "entries [CON003]")


# -- the content tests ----------------------------------------------------------------------

def _container(n_entries: int) -> bytes:
    from dcf2bin.container import BinContainer
    return BinContainer(entries=ENTRIES[:n_entries]).to_bytes()


@pytest.mark.parametrize("data,fills,damaged", [
    (THREE, True, False),
    (b"\0\0\0\0", True, False),                     # an empty concise DCF
    (b"\x01\0\0\0" + bytes(7), True, False),        # one entry 0x0000sub0 without data
    (b"", False, False),
    (b"\0\0\0", False, False),
    (THREE[:-1], False, True),                      # cut in the last entry
    (THREE + b"\0", False, True),                   # a trailing byte
    (b"\x05" + THREE[1:], False, True),             # a count that disagrees
    (b"\x01\0\0\0" + bytes(8), False, False),       # index 0: no object a DCF writes
    (_container(0), False, False),                  # containers: first DWORD = their size
    (_container(3), False, False),
    (_container(3)[:-1], False, False),             # a truncated one: the DWORD > the size
    (_container(3) + b"\0", False, False),          # trailing: bytes 4-5 = version 1
    (bytes.fromhex("0C000000" "0100" "0100" "28000000"), False, False),   # a tiny "container"
    (b"[FileInfo]\nFileName=x.dcf\n", False, False),
    (b'{"format": "dcf2bin-concise"}', False, False),
])
def test_content_tests(data, fills, damaged):
    assert (concise.fills(data), concise.damaged(data)) == (fills, damaged)
