"""Every segment schema: parse, build, size, the compiled variant and the derived
struct packers agree (construct's own declarativeunittest style)."""
from __future__ import annotations

import struct

import pytest
from construct import Container as CContainer

from dcf2bin import schema


def common(fmt, data: bytes, obj, size=None, compiled=None, fast=None):
    """parse(data) == obj, build(obj) == data, sizeof, compiled and fast forms agree."""
    parsed = fmt.parse(data)
    assert _plain(parsed) == _plain(obj)
    assert fmt.build(obj) == data
    if size is not None:
        assert fmt.sizeof() == size == len(data)
    if compiled is not None:
        assert _plain(compiled.parse(data)) == _plain(obj)
        assert compiled.build(obj) == data
    if fast is not None:
        assert fast.size == len(data)
        values = [obj[sc.name] for sc in fmt.subcons]
        assert fast.pack(*values) == data
        assert list(fast.unpack(data)) == values


def _plain(x):
    if isinstance(x, (dict, CContainer)):
        return {k: _plain(v) for k, v in x.items() if not k.startswith("_")}
    if isinstance(x, list):
        return [_plain(v) for v in x]
    return x


HEADER_HEX = (
    "7f000000"  # total size 127
    "0100"      # version 1 (D-5)
    "0400"      # 4 segments (D-6)
    "28000000 35000000"  # index segment @40, 53 bytes
    "5d000000 08000000"  # PI address segment @93, 8 bytes
    "65000000 06000000"  # extended info @101, 6 bytes
    "6b000000 14000000"  # PI parameters @107, 20 bytes
)


def test_header():
    data = bytes.fromhex(HEADER_HEX.replace(" ", ""))
    obj = dict(total_size=127, version=1, segment_count=4, index_offset=40, index_size=53,
               address_offset=93, address_size=8, extinfo_offset=101, extinfo_size=6,
               piparam_offset=107, piparam_size=20)
    common(schema.Header, data, obj, size=40, compiled=schema.HeaderC, fast=schema.HEADER)


def test_entry_head_and_entry():
    data = bytes.fromhex("c0a4" "03" "02000000")
    common(schema.EntryHead, data, dict(index=0xA4C0, subindex=3, size=2), size=7,
           fast=schema.ENTRY_HEAD)
    full = data + b"\x34\x12"
    assert schema.Entry.build(dict(index=0xA4C0, subindex=3, data=b"\x34\x12")) == full
    assert _plain(schema.Entry.parse(full)) == dict(index=0xA4C0, subindex=3, size=2,
                                                     data=b"\x34\x12")


def test_index_segment_matches_fast_path():
    from dcf2bin.container import BinContainer, _read_index
    entries = [(0x1017, 0, b"\xe8\x03"), (0x1800, 1, b"\x83\x01\x00\x80"), (0x2000, 0, b"")]
    c = BinContainer(entries=entries)
    built = schema.IndexSegment.build([dict(index=i, subindex=s, data=d) for i, s, d in entries])
    assert c.index_bytes() == built
    assert built == bytes.fromhex("03000000" "171000" "02000000" "e803"
                                  "001801" "04000000" "83010080" "002000" "00000000")
    assert _read_index(built, 40) == entries


def test_pi_params():
    data = struct.pack("<5I", 16, 0, 8, 8, 8)
    obj = dict(total_size=16, input_offset=0, input_size=8, output_offset=8, output_size=8)
    common(schema.PIParams, data, obj, size=20, compiled=schema.PIParamsC, fast=schema.PIPARAMS)


def test_address_and_extinfo_segments():
    assert schema.AddressSegment.build([0, 1, 0xFFFF]) == b"\x00\x00\x01\x00\xff\xff"
    assert schema.AddressSegment.parse(b"\x04\x00\x08\x00") == [4, 8]
    assert schema.ExtInfoSegment.build([0x30, 0xF0, 0x06]) == b"\x30\xf0\x06"


def test_lenze_record():
    data = bytes.fromhex("41011018" "78563412" "0400" "07" "01")
    obj = dict(dwIdxSubIdxF=0x18100141, dwContent=0x12345678, wLen=4, byAttrib=7, byAccess=1)
    common(schema.LenzeRecord, data, obj, size=12, fast=schema.fast_struct(schema.LenzeRecord))


def test_container_rebuilds_header_fields():
    """D-6/D-7: absent segments get offset 0 and are not counted; back to back order."""
    built = schema.Container.build(dict(version=7, index=b"\x00" * 4, address=b"",
                                        extinfo=b"", piparam=b"\x01" * 20))
    h = schema.Header.parse(built)
    assert (h.total_size, h.version, h.segment_count) == (64, 7, 2)
    assert (h.index_offset, h.index_size, h.address_offset, h.address_size) == (40, 4, 0, 0)
    assert (h.extinfo_offset, h.extinfo_size, h.piparam_offset, h.piparam_size) == (0, 0, 44, 20)


def test_fast_struct_rejects_variable_fields():
    with pytest.raises(TypeError):
        schema.fast_struct(schema.Entry)
