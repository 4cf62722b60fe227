"""construct schemas of the binary DCF segment container (SPEC.md §3).

These declarations are the single source of truth for every byte layout.
The hot loops (tens of thousands of index entries or addresses) and ``compile``
use ``struct.Struct`` packers written beside them (``HEADER``, ``ENTRY_HEAD``,
``PIPARAMS``, ``COUNT``); ``fast_struct`` derives such a packer from a schema, and
the tests check that construct (plain and compiled), ``fast_struct`` and the packers
agree field by field. All fields are little-endian.

The construct schemas are built on first use (``schema.Header``, ``from
dcf2bin.schema import Entry``): importing construct costs about 6 MiB and 15 ms,
and compile needs only the packers.
"""
from __future__ import annotations

import struct

HEADER_SIZE = 40
# The header's segment slots, in the order of its table (SPEC §3.1, D-7).
SEGMENTS = ("index", "address", "extinfo", "piparam")

# The header's fields, in the order of its table, and the packers of the fixed-size
# layouts, as the schemas below declare them (the tests check that they agree).
HEADER_FIELDS = ["total_size", "version", "segment_count",
                 "index_offset", "index_size", "address_offset", "address_size",
                 "extinfo_offset", "extinfo_size", "piparam_offset", "piparam_size"]
PIPARAM_FIELDS = ["total_size", "input_offset", "input_size", "output_offset", "output_size"]
HEADER = struct.Struct("<LHHLLLLLLLL")      # Header: 40 bytes
ENTRY_HEAD = struct.Struct("<HBL")          # EntryHead: 7 bytes
PIPARAMS = struct.Struct("<LLLLL")          # PIParams: 20 bytes
COUNT = struct.Struct("<L")                 # IndexCount
ADDRESS_SIZE = 2                            # Address: Int16ul
assert HEADER.size == HEADER_SIZE


def _declare() -> dict:
    """The construct schemas (built once, on first use)."""
    from construct import (Bytes, GreedyRange, Int8ul, Int16ul, Int32ul,
                           PrefixedArray, Rebuild, Struct, this)

    # -- header (SPEC §3.1) -----------------------------------------------------------------
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

    # -- index segment: CiA 302 concise DCF (SPEC §3.2) -----------------------------------
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

    # -- extended info segment: one attribute byte per index entry (SPEC §3.3) --------------
    ExtInfoSegment = GreedyRange(Int8ul)

    # -- PI address segment: one WORD per network variable (SPEC §3.4) ---------------------
    Address = Int16ul
    AddressSegment = GreedyRange(Address)

    # -- PI parameter segment: 5 DWORDs (SPEC §3.5) ----------------------------------------
    PIParams = Struct(
        "total_size" / Int32ul,
        "input_offset" / Int32ul,
        "input_size" / Int32ul,
        "output_offset" / Int32ul,
        "output_size" / Int32ul,
    )

    # -- Lenze PLC Designer master OD record (SPEC §7) ------------------------------------
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
    return {name: value for name, value in locals().items() if name[0].isupper()}


def fast_struct(schema) -> struct.Struct:
    """A ``struct.Struct`` equivalent to a construct ``Struct`` of fixed-size format
    fields (the tests compare the packers above with those of the schemas)."""
    fmt = "<"
    for sc in schema.subcons:
        sub = sc.subcon
        fmtstr = getattr(sub, "fmtstr", None)
        if fmtstr is None or fmtstr[0] not in "<=":
            raise TypeError(f"field {sc.name!r} is not a little-endian format field")
        fmt += fmtstr[1:]
    return struct.Struct(fmt)


_SCHEMAS = ("Header", "Container", "EntryHead", "Entry", "IndexSegment", "IndexCount",
            "ExtInfoSegment", "Address", "AddressSegment", "PIParams", "LenzeRecord",
            "HeaderC", "PIParamsC")


def __getattr__(name: str):
    if name in _SCHEMAS:
        found = _declare()
        globals().update(found)
        return found[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
