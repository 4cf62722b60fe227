"""construct schemas of the binary DCF segment container (SPEC.md §3).

These declarations are the single source of truth for every byte layout.
The hot loops (tens of thousands of index entries or addresses) use a
``struct.Struct`` *derived from* the fixed-size schemas by ``fast_struct``; the
tests check that construct (plain and compiled) and the derived packers agree.
All fields are little-endian.
"""
from __future__ import annotations

import struct

from construct import (Bytes, GreedyRange, Int8ul, Int16ul, Int32ul,
                       PrefixedArray, Rebuild, Struct, this)

HEADER_SIZE = 40
# The header's segment slots, in the order of its table (SPEC §3.1, D-7).
SEGMENTS = ("index", "address", "extinfo", "piparam")

# -- header (SPEC §3.1) ---------------------------------------------------------------------
Header = Struct(
    "total_size" / Int32ul,
    "version" / Int16ul,          # D-5
    "segment_count" / Int16ul,    # D-6
    "index_offset" / Int32ul,
    "index_size" / Int32ul,
    "address_offset" / Int32ul,
    "address_size" / Int32ul,
    "extinfo_offset" / Int32ul,
    "extinfo_size" / Int32ul,
    "piparam_offset" / Int32ul,
    "piparam_size" / Int32ul,
)
HEADER_FIELDS = [sc.name for sc in Header.subcons]


def _present(ctx, name: str) -> bool:
    return len(ctx[name]) > 0


def _offset(name: str):
    """D-7: segments follow the header back to back in table order; absent ones get 0."""
    def offset(ctx):
        if not _present(ctx, name):
            return 0
        pos = HEADER_SIZE
        for seg in SEGMENTS:
            if seg == name:
                return pos
            pos += len(ctx[seg])
        raise AssertionError(name)
    return offset


# The canonical container: a header whose counts, sizes and offsets are rebuilt
# from the segments that follow it. Built from the four segments' bytes.
Container = Struct(
    "total_size" / Rebuild(Int32ul, lambda c: HEADER_SIZE + sum(len(c[s]) for s in SEGMENTS)),
    "version" / Int16ul,
    "segment_count" / Rebuild(Int16ul, lambda c: sum(1 for s in SEGMENTS if _present(c, s))),
    "index_offset" / Rebuild(Int32ul, _offset("index")),
    "index_size" / Rebuild(Int32ul, lambda c: len(c.index)),
    "address_offset" / Rebuild(Int32ul, _offset("address")),
    "address_size" / Rebuild(Int32ul, lambda c: len(c.address)),
    "extinfo_offset" / Rebuild(Int32ul, _offset("extinfo")),
    "extinfo_size" / Rebuild(Int32ul, lambda c: len(c.extinfo)),
    "piparam_offset" / Rebuild(Int32ul, _offset("piparam")),
    "piparam_size" / Rebuild(Int32ul, lambda c: len(c.piparam)),
    "index" / Bytes(this.index_size),
    "address" / Bytes(this.address_size),
    "extinfo" / Bytes(this.extinfo_size),
    "piparam" / Bytes(this.piparam_size),
)

# -- index segment: CiA 302 concise DCF (SPEC §3.2) ---------------------------------------
EntryHead = Struct(
    "index" / Int16ul,
    "subindex" / Int8ul,
    "size" / Int32ul,
)
Entry = Struct(
    "index" / Int16ul,
    "subindex" / Int8ul,
    "size" / Rebuild(Int32ul, lambda c: len(c.data)),
    "data" / Bytes(this.size),
)
IndexSegment = PrefixedArray(Int32ul, Entry)
IndexCount = Int32ul

# -- extended info segment: one attribute byte per index entry (SPEC §3.3) ------------------
ExtInfoSegment = GreedyRange(Int8ul)

# -- PI address segment: one WORD per network variable (SPEC §3.4) -------------------------
Address = Int16ul
AddressSegment = GreedyRange(Address)

# -- PI parameter segment: 5 DWORDs (SPEC §3.5) --------------------------------------------
PIParams = Struct(
    "total_size" / Int32ul,
    "input_offset" / Int32ul,
    "input_size" / Int32ul,
    "output_offset" / Int32ul,
    "output_size" / Int32ul,
)
PIPARAM_FIELDS = [sc.name for sc in PIParams.subcons]

# -- Lenze PLC Designer master OD record (SPEC §7) ---------------------------------------------
LenzeRecord = Struct(
    "dwIdxSubIdxF" / Int32ul,
    "dwContent" / Int32ul,
    "wLen" / Int16ul,
    "byAttrib" / Int8ul,
    "byAccess" / Int8ul,
)

# Compiled forms, for the places where construct itself is on a hot path.
HeaderC = Header.compile()
PIParamsC = PIParams.compile()


def fast_struct(schema: Struct) -> struct.Struct:
    """A ``struct.Struct`` equivalent to a schema of fixed-size format fields.

    Derived from the declaration, so the schema stays the one source of truth.
    """
    fmt = "<"
    for sc in schema.subcons:
        sub = sc.subcon
        fmtstr = getattr(sub, "fmtstr", None)
        if fmtstr is None or fmtstr[0] not in "<=":
            raise TypeError(f"field {sc.name!r} is not a little-endian format field")
        fmt += fmtstr[1:]
    return struct.Struct(fmt)


ENTRY_HEAD = fast_struct(EntryHead)           # '<HBI', 7 bytes
HEADER = fast_struct(Header)                  # 40 bytes
PIPARAMS = fast_struct(PIParams)              # 20 bytes
COUNT = struct.Struct("<" + IndexCount.fmtstr[1:])
ADDRESS_SIZE = Address.sizeof()
assert HEADER.size == HEADER_SIZE
