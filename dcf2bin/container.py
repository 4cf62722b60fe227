"""The binary DCF segment container as data, and its bytes (SPEC.md §3).

``BinContainer`` is the neutral binary model: the index entries as stored
(repeated writes kept), the attribute bytes (undefined bits kept), the address
words and the PI parameters. ``to_bytes`` builds the canonical layout of D-5...D-7
through ``schema.Container``; a container read from another tool keeps its
header as stored and any bytes between segments, so it is rebuilt byte for byte.
"""
from __future__ import annotations

import struct
from dataclasses import dataclass, field

from dcf2bin import concise, schema
from dcf2bin.diagnostics import Diagnostic, Severity


# the segments as messages name them (validate's CNT rules use the same words)
_NAMES = {"index": "index", "address": "PI address", "extinfo": "extended info",
          "piparam": "PI parameter"}

class ContainerError(Exception):
    """A container that cannot be read; names the byte offset."""

    def __init__(self, message: str, offset: int, rule: str = "CNT099"):
        super().__init__(message)
        self.offset = offset
        self.rule = rule      # the validate rule that names this (CNT0xx)


@dataclass
class BinContainer:
    entries: list[tuple[int, int, bytes]] = field(default_factory=list)
    attributes: bytes | None = None         # extended info segment; None = absent
    addresses: list[int] | None = None      # PI address segment; None = absent
    pi: tuple[int, int, int, int, int] | None = None  # PI parameter segment; None = absent
    version: int = 1
    # As stored, for containers whose layout is not the canonical one (SPEC §3.1):
    header: dict[str, int] | None = None
    gaps: list[tuple[int, bytes]] = field(default_factory=list)
    raw_piparam: bytes | None = None        # a PI parameter segment that is not 20 bytes

    # -- segments ---------------------------------------------------------------------------
    def index_bytes(self) -> bytes:
        """The index segment: the entries as a CiA 302 concise DCF (its one writer)."""
        return concise.to_bytes(self.entries)

    def address_bytes(self) -> bytes:
        if not self.addresses:
            return b""
        return struct.pack(f"<{len(self.addresses)}H", *self.addresses)

    def extinfo_bytes(self) -> bytes:
        return bytes(self.attributes or b"")

    def piparam_bytes(self) -> bytes:
        if self.raw_piparam is not None:
            return self.raw_piparam
        return schema.PIPARAMS.pack(*self.pi) if self.pi is not None else b""

    def segments(self) -> dict[str, bytes]:
        return {"index": self.index_bytes(), "address": self.address_bytes(),
                "extinfo": self.extinfo_bytes(), "piparam": self.piparam_bytes()}

    # -- bytes --------------------------------------------------------------------------------
    def segment_sizes(self) -> dict[str, int]:
        """The size of each segment's bytes, without making them (``segments``' lengths)."""
        entries = self.entries
        index = schema.COUNT.size + schema.ENTRY_HEAD.size * len(entries) + sum(
            map(len, [e[2] for e in entries]))
        return {"index": index,
                "address": schema.ADDRESS_SIZE * len(self.addresses or ()),
                "extinfo": len(self.attributes or b""),
                "piparam": len(self.piparam_bytes())}

    def canonical_header(self) -> dict[str, int]:
        # the header depends on the segments' sizes only: the schema builds it from
        # zero bytes of those sizes, so that a dump need not make the index segment
        segs = {name: bytes(size) for name, size in self.segment_sizes().items()}
        built = schema.Container.build(dict(version=self.version, **segs))
        parsed = schema.HeaderC.parse(built[:schema.HEADER_SIZE])
        return {k: parsed[k] for k in schema.HEADER_FIELDS}

    def to_bytes(self, segs: dict[str, bytes] | None = None) -> bytes:
        segs = segs if segs is not None else self.segments()
        if self.header is None:
            return schema.Container.build(dict(version=self.version, **segs))
        return self._build_as_stored(segs)

    def _build_as_stored(self, segs: dict[str, bytes]) -> bytes:
        h = self.header
        out = bytearray(h["total_size"])
        out[:schema.HEADER_SIZE] = schema.HEADER.pack(*(h[k] for k in schema.HEADER_FIELDS))
        for name in schema.SEGMENTS:
            data = segs[name]
            off, size = h[f"{name}_offset"], h[f"{name}_size"]
            if len(data) != size:
                raise ContainerError(f"the {name} segment holds {len(data)} bytes but the "
                                     f"stored header says {size}", 8)
            if size and off + size > len(out):
                raise ContainerError(f"the {name} segment ends past the stored total size", off)
            out[off:off + size] = data
        for off, data in self.gaps:
            out[off:off + len(data)] = data
        return bytes(out)


def read(data: bytes) -> tuple[BinContainer, list[Diagnostic]]:
    """Decode a container (SPEC §3.1 reader rules). Raises ContainerError."""
    warnings: list[Diagnostic] = []

    def warn(msg: str, offset: int, rule: str) -> None:
        warnings.append(Diagnostic(Severity.WARNING, msg, offset=offset, rule=rule))

    n = len(data)
    if n < schema.HEADER_SIZE:
        raise ContainerError(f"{n} bytes: too short for the {schema.HEADER_SIZE}-byte header",
                             0, "CNT001")
    values = schema.HEADER.unpack_from(data, 0)
    h = dict(zip(schema.HEADER_FIELDS, values))
    total = h["total_size"]
    if total > n:
        raise ContainerError(f"header says {total} bytes, the file has {n} (truncated)", 0,
                             "CNT002")
    if total < schema.HEADER_SIZE:
        raise ContainerError(f"header says {total} bytes, less than the header itself", 0,
                             "CNT002")
    if total < n:
        raise ContainerError(f"{n - total} trailing bytes after the container's total size "
                             f"{total}", total, "CNT003")
    spans = []
    for i, name in enumerate(schema.SEGMENTS):
        off, size = h[f"{name}_offset"], h[f"{name}_size"]
        field_off = 8 + 8 * i
        if size == 0:
            if off != 0:
                warn(f"empty {_NAMES[name]} segment has offset {off}", field_off, "CNT007")
            continue
        if off < schema.HEADER_SIZE or off + size > total:
            raise ContainerError(f"{_NAMES[name]} segment [{off}, {off + size}) lies outside the "
                                 f"container [40, {total})", field_off, "CNT004")
        spans.append((off, off + size, name))
    spans.sort()
    for (s1, e1, a), (s2, e2, b) in zip(spans, spans[1:]):
        if s2 < e1:
            raise ContainerError(f"{_NAMES[b]} segment [{s2}, {e2}) overlaps the {_NAMES[a]} "
                                 f"segment [{s1}, {e1})", s2, "CNT005")
    present = len(spans)
    if h["segment_count"] != present:
        warn(f"header counts {h['segment_count']} segments, {present} are present", 6, "CNT006")
    c = BinContainer(version=h["version"])
    if "index" not in {s[2] for s in spans}:
        raise ContainerError("the container has no index segment", 12, "CNT010")
    for off, end, name in spans:
        seg = data[off:end]
        if name == "index":
            c.entries = _read_index(seg, off)
        elif name == "address":
            if len(seg) % schema.ADDRESS_SIZE:
                raise ContainerError(f"PI address segment has odd size {len(seg)}", off, "CNT015")
            c.addresses = list(struct.unpack(f"<{len(seg) // 2}H", seg))
        elif name == "extinfo":
            c.attributes = bytes(seg)
        else:
            if len(seg) == schema.PIPARAMS.size:
                c.pi = schema.PIPARAMS.unpack(seg)
            else:
                warn(f"PI parameter segment has {len(seg)} bytes, expected 20", off, "CNT016")
                c.raw_piparam = bytes(seg)
    # gaps and order: kept as stored
    pos = schema.HEADER_SIZE
    for off, end, name in spans:
        if off > pos:
            c.gaps.append((pos, bytes(data[pos:off])))
        pos = max(pos, end)
    if pos < total:
        c.gaps.append((pos, bytes(data[pos:total])))
    if c.gaps:
        warn(f"{sum(len(g) for _, g in c.gaps)} bytes between segments belong to no segment",
             c.gaps[0][0], "CNT008")
    order = [s[2] for s in spans]
    if order != [s for s in schema.SEGMENTS if s in order]:
        warn("segments are not in the header's order", spans[0][0], "CNT008")
    # Canonical (D-6/D-7) unless the count, the order, a gap or an empty segment's offset
    # says otherwise; then keep the header as stored so the bytes survive (SPEC §3.1).
    canonical = (not c.gaps and h["segment_count"] == present
                 and order == [s for s in schema.SEGMENTS if s in order]
                 and all(h[f"{n}_offset"] == 0 for n in schema.SEGMENTS
                         if h[f"{n}_size"] == 0))
    if not canonical:
        c.header = h
    return c, warnings


def _read_index(seg: bytes, base: int) -> list[tuple[int, int, bytes]]:
    n = len(seg)
    if n < 4:
        raise ContainerError(f"index segment has {n} bytes, too short for its count", base,
                             "CNT011")
    (count,) = schema.COUNT.unpack_from(seg, 0)
    # every entry needs at least 7 bytes: never allocate from an untrusted count
    if count * schema.ENTRY_HEAD.size > n - 4:
        raise ContainerError(f"index segment claims {count} entries, but {n - 4} bytes hold at "
                             f"most {(n - 4) // schema.ENTRY_HEAD.size}", base, "CNT011")
    entries = _read_entries(seg, count)
    if entries is not None:
        return entries
    entries = []        # a segment that does not hold its entries exactly: find where
    pos = 4
    unpack = schema.ENTRY_HEAD.unpack_from
    head = schema.ENTRY_HEAD.size
    for i in range(count):
        if pos + head > n:
            raise ContainerError(f"index entry {i + 1} of {count} is truncated", base + pos,
                                 "CNT011")
        index, sub, size = unpack(seg, pos)
        pos += head
        if pos + size > n:
            raise ContainerError(f"index entry {i + 1} (0x{index:04X}sub{sub:X}) claims "
                                 f"{size} data bytes, only {n - pos} remain", base + pos - 4,
                                 "CNT011")
        entries.append((index, sub, bytes(seg[pos:pos + size])))
        pos += size
    if pos != n:
        raise ContainerError(f"{n - pos} bytes after the last index entry", base + pos, "CNT011")
    return entries


def _read_entries(seg: bytes, count: int) -> list[tuple[int, int, bytes]] | None:
    """The ``count`` entries of an index segment that holds them exactly, read without a
    bounds check each; None when it does not (``_read_index`` then says where not)."""
    unpack = schema.ENTRY_HEAD.unpack_from
    head = schema.ENTRY_HEAD.size
    seg = bytes(seg)
    entries = []
    append = entries.append
    pos = 4
    try:
        for _ in range(count):
            index, sub, size = unpack(seg, pos)
            pos += head
            append((index, sub, seg[pos:pos + size]))
            pos += size
    except struct.error:
        return None
    return entries if pos == len(seg) else None
