"""CNT0xx: binary DCF segment containers (SPEC §3).

The checks read the bytes themselves, so that one run reports every problem (the
container reader stops at the first one); CNT099 reports anything the reader still
rejects, so nothing it refuses goes unreported.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin import layout, schema
from dcf2bin.lint.registry import BIN, ERROR, WARNING, Finding, rule

_NAMES = {"index": "index", "address": "PI address", "extinfo": "extended info",
          "piparam": "PI parameter"}


@rule("CNT001", "header-truncated", ERROR,
      "The file is shorter than the 40-byte container header.",
      hint="not a container, or a truncated one", kind=BIN)
def header_truncated(ctx):
    if ctx.header is None:
        yield Finding(f"{len(ctx.data)} bytes: too short for the {schema.HEADER_SIZE}-byte "
                      "header", offset=0)


@rule("CNT002", "total-size-mismatch", ERROR,
      "The header's total size is larger than the file (truncated) or smaller than the header.",
      hint="the first DWORD is the size of the whole container", kind=BIN)
def total_size(ctx):
    if ctx.header is None:
        return
    if ctx.total > len(ctx.data):
        yield Finding(f"header says {ctx.total} bytes, the file has {len(ctx.data)} (truncated)",
                      offset=0)
    elif ctx.total < schema.HEADER_SIZE:
        yield Finding(f"header says {ctx.total} bytes, less than the header itself", offset=0)


@rule("CNT003", "trailing-bytes", ERROR,
      "Bytes follow the container's total size.",
      hint="cut the file at the header's total size, or fix the total", kind=BIN)
def trailing(ctx):
    if ctx.header is None or ctx.total < schema.HEADER_SIZE:
        return
    extra = len(ctx.data) - ctx.total
    if extra > 0:
        yield Finding(f"{extra} trailing bytes after the container's total size {ctx.total}",
                      offset=ctx.total)


@rule("CNT004", "segment-out-of-bounds", ERROR,
      "A segment starts inside the header or ends past the container's total size.",
      hint="segments lie between byte 40 and the total size", kind=BIN)
def out_of_bounds(ctx):
    if ctx.header is None:
        return
    for i, name in enumerate(schema.SEGMENTS):
        if name in ctx.bad_segments:
            off, size = ctx.header[f"{name}_offset"], ctx.header[f"{name}_size"]
            yield Finding(f"{_NAMES[name]} segment [{off}, {off + size}) lies outside the "
                          f"container [40, {ctx.total})", offset=8 + 8 * i)


@rule("CNT005", "segment-overlap", ERROR,
      "Two segments overlap.",
      hint="every byte belongs to at most one segment", kind=BIN)
def overlap(ctx):
    segs = ctx.segments
    reach = None
    for s in segs:
        if reach is not None and s.offset < reach.end:
            yield Finding(f"{_NAMES[s.name]} segment [{s.offset}, {s.end}) overlaps the "
                          f"{_NAMES[reach.name]} segment [{reach.offset}, {reach.end})",
                          offset=s.offset)
        if reach is None or s.end > reach.end:
            reach = s


@rule("CNT006", "segment-count-mismatch", WARNING,
      "The header's segment count differs from the number of non-empty segments.",
      hint="count the segments whose size is not 0", kind=BIN)
def segment_count(ctx):
    if ctx.header is None:
        return
    present = sum(1 for n in schema.SEGMENTS if ctx.header[f"{n}_size"])
    if ctx.header["segment_count"] != present:
        yield Finding(f"header counts {ctx.header['segment_count']} segments, {present} are "
                      "present", offset=6)


@rule("CNT007", "empty-segment-offset", WARNING,
      "A segment of size 0 has an offset other than 0.",
      hint="absent segments have offset 0 and size 0", kind=BIN)
def empty_offset(ctx):
    if ctx.header is None:
        return
    for i, name in enumerate(schema.SEGMENTS):
        if ctx.header[f"{name}_size"] == 0 and ctx.header[f"{name}_offset"] != 0:
            yield Finding(f"empty {_NAMES[name]} segment has offset "
                          f"{ctx.header[f'{name}_offset']}", offset=8 + 8 * i)


@rule("CNT008", "segment-layout", WARNING,
      "Segments are not back to back in header order after the header: out of order, or "
      "with bytes between them (accepted, but not what dcf2bin writes).",
      hint="dcf2bin writes the segments right after the header, in the header's table "
           "order, without gaps", kind=BIN)
def segment_layout(ctx):
    if ctx.header is None or ctx.bad_segments or ctx.cut_segments:
        return
    segs = ctx.segments
    order = [s.name for s in segs]
    if order != [n for n in schema.SEGMENTS if n in order]:
        yield Finding("segments are not in the header's order: " + ", ".join(order),
                      offset=segs[0].offset)
    pos, gaps, first = schema.HEADER_SIZE, 0, None
    for s in segs:
        if s.offset > pos:
            gaps += s.offset - pos
            first = pos if first is None else first
        pos = max(pos, s.end)
    if ctx.total > pos:
        gaps += ctx.total - pos
        first = pos if first is None else first
    if gaps:
        yield Finding(f"{gaps} bytes between segments belong to no segment", offset=first)


@rule("CNT010", "index-segment-missing", ERROR,
      "The container has no index segment.",
      hint="every container has an index segment, at least its count DWORD", kind=BIN)
def index_missing(ctx):
    if ctx.header is not None and ctx.header["index_size"] == 0:
        yield Finding("the container has no index segment", offset=12)


@rule("CNT011", "index-segment-malformed", ERROR,
      "The index segment's count and entries do not fill it exactly (truncated entry, "
      "data past its end, or bytes after the last entry).",
      hint="DWORD count, then per entry WORD index, BYTE sub, DWORD size, data", kind=BIN)
def index_malformed(ctx):
    if ctx.index_problem:
        msg, off = ctx.index_problem
        yield Finding(msg, offset=off)


@rule("CNT012", "extinfo-length-mismatch", ERROR,
      "The extended info segment does not hold exactly one attribute byte per index entry.",
      hint="one attribute BYTE per index-segment entry, same order", kind=BIN)
def extinfo_length(ctx):
    seg = ctx.segment("extinfo")
    if seg is None or ctx.entries is None or ctx.index_problem:
        return
    if seg.size != len(ctx.entries):
        yield Finding(f"extended info segment has {seg.size} bytes for {len(ctx.entries)} "
                      "index entries", offset=seg.offset)


@rule("CNT013", "undefined-attribute-bits", WARNING,
      "Attribute bytes set the undefined bits 0x02/0x04 (kept as stored).",
      hint="the defined attribute bits are 0x01, 0x08, 0x10, 0x20, 0x40, 0x80", kind=BIN)
def undefined_bits(ctx):
    attrs = ctx.segment_bytes("extinfo")
    if not attrs:
        return
    base = ctx.segment("extinfo").offset
    first: dict[int, int] = {}
    counts: dict[int, int] = {}
    for i, a in enumerate(attrs):
        bits = a & dt.ATTR_UNDEFINED
        if bits:
            first.setdefault(bits, i)
            counts[bits] = counts.get(bits, 0) + 1
    for bits in sorted(first):
        i = first[bits]
        more = f" (and {counts[bits] - 1} more)" if counts[bits] > 1 else ""
        yield Finding(f"attribute 0x{attrs[i]:02X} of entry {i + 1} sets undefined bits "
                      f"0x{bits:02X}{more}", offset=base + i)


@rule("CNT014", "attribute-size-mismatch", WARNING,
      "An attribute's type bits disagree with the entry's data size (BOOLEAN not 1 byte, "
      "NUMERIC not 1..8 bytes, or more than one type bit).",
      hint="BOOLEAN entries have 1 byte, NUMERIC 1-8", kind=BIN)
def attribute_size(ctx):
    attrs = ctx.segment_bytes("extinfo")
    if not attrs or ctx.entries is None or len(attrs) != len(ctx.entries):
        return
    base = ctx.segment("extinfo").offset
    for i, ((index, sub, size, _), a) in enumerate(zip(ctx.entries, attrs)):
        t = a & dt.ATTR_TYPE_MASK
        problem = None
        if t not in (0, dt.ATTR_BOOLEAN, dt.ATTR_VSTRING, dt.ATTR_NUMERIC):
            problem = "sets more than one type bit"
        elif t == dt.ATTR_BOOLEAN and size != 1:
            problem = f"is BOOLEAN but the entry has {size} bytes"
        elif t == dt.ATTR_NUMERIC and not 1 <= size <= 8:
            problem = f"is NUMERIC but the entry has {size} bytes"
        if problem:
            yield Finding(f"attribute 0x{a:02X} of entry {i + 1} (0x{index:04X}sub{sub:X}) "
                          f"{problem}", offset=base + i)


def _variables(ctx):
    """Network variables in index order, first occurrence: (index, sub, size, entry no.)."""
    seen, out = set(), []
    for i, (index, sub, size, _) in enumerate(ctx.entries or ()):
        if 0xA000 <= index <= 0xAFFF and sub >= 1 and (index, sub) not in seen:
            seen.add((index, sub))
            out.append((index, sub, size, i))
    return out


@rule("CNT015", "address-count-mismatch", ERROR,
      "The PI address segment does not hold one WORD per network variable of the index "
      "segment (or has an odd size).",
      hint="one WORD per network variable, in index-segment order", kind=BIN)
def address_count(ctx):
    seg = ctx.segment("address")
    if seg is None or ctx.entries is None or ctx.index_problem:
        return
    if seg.size % 2:
        yield Finding(f"PI address segment has odd size {seg.size}", offset=seg.offset)
        return
    n = len(_variables(ctx))
    if seg.size // 2 != n:
        yield Finding(f"PI address segment holds {seg.size // 2} addresses for {n} network "
                      "variables", offset=seg.offset)


@rule("CNT016", "pi-segments-incomplete", WARNING,
      "Only one of the two PI segments (addresses, parameters) is present, or the PI "
      "parameter segment is not 20 bytes.",
      hint="the PI address and PI parameter segments come together", kind=BIN)
def pi_incomplete(ctx):
    if ctx.header is None:
        return
    a, p = ctx.segment("address"), ctx.segment("piparam")
    broken = ctx.bad_segments | ctx.cut_segments
    if (a is None) != (p is None) and not {"address", "piparam"} & broken:
        have, lack = ("PI address", "PI parameter") if a else ("PI parameter", "PI address")
        yield Finding(f"the {have} segment is present without the {lack} segment",
                      offset=(a or p).offset)
    if p is not None and p.size != schema.PIPARAMS.size:
        yield Finding(f"PI parameter segment has {p.size} bytes, expected 20", offset=p.offset)


def _pi(ctx):
    p = ctx.segment("piparam")
    if p is None or p.size != schema.PIPARAMS.size:
        return None
    return schema.PIPARAMS.unpack_from(ctx.data, p.offset)


@rule("CNT017", "pi-parameters-inconsistent", ERROR,
      "The PI parameters contradict themselves: areas overlap or exceed the complete size.",
      hint="five DWORDs: total size, input offset and size, output offset and size",
      kind=BIN)
def pi_inconsistent(ctx):
    pi = _pi(ctx)
    if pi is None:
        return
    total, in_off, in_size, out_off, out_size = pi
    off = ctx.segment("piparam").offset
    if in_size and in_off + in_size > total:
        yield Finding(f"input area [{in_off}, {in_off + in_size}) exceeds the PI size {total}",
                      offset=off + 4)
    if out_size and out_off + out_size > total:
        yield Finding(f"output area [{out_off}, {out_off + out_size}) exceeds the PI size "
                      f"{total}", offset=off + 12)
    if in_size and out_size and in_off < out_off + out_size and out_off < in_off + in_size:
        yield Finding(f"input area [{in_off}, {in_off + in_size}) overlaps output area "
                      f"[{out_off}, {out_off + out_size})", offset=off + 12)


def _addresses(ctx):
    seg = ctx.segment("address")
    if seg is None or seg.size % 2 or ctx.entries is None or ctx.index_problem:
        return None
    import struct
    words = struct.unpack_from(f"<{seg.size // 2}H", ctx.data, seg.offset)
    nv = _variables(ctx)
    if len(words) != len(nv):
        return None   # CNT015
    return [(w, v, seg.offset + 2 * i) for i, (w, v) in enumerate(zip(words, nv))]


def _direction(index: int) -> str | None:
    ch = layout.table_channel(index)
    return ch.direction if ch else None


@rule("CNT018", "address-outside-pi", ERROR,
      "A network variable's PI address (plus its size) lies outside the process image, or "
      "outside its area.",
      hint="addresses are image offsets (or area offsets with --address-base area)", kind=BIN)
def address_outside(ctx):
    pi, addrs = _pi(ctx), _addresses(ctx)
    if pi is None or addrs is None:
        return
    total, in_off, in_size, out_off, out_size = pi
    for addr, (index, sub, size, _), off in addrs:
        end = addr + size
        direction = _direction(index)
        label = f"0x{index:04X}sub{sub:X}"
        if end > total:
            yield Finding(f"{label}: address {addr} + {size} bytes exceeds the PI size {total}",
                          offset=off)
        elif direction == layout.INPUT and end > in_off + in_size:
            yield Finding(f"{label}: address {addr} lies outside the input area "
                          f"[{in_off}, {in_off + in_size})", offset=off)
        elif direction == layout.OUTPUT and not (
                out_off <= addr and end <= out_off + out_size or end <= out_size):
            yield Finding(f"{label}: address {addr} lies outside the output area "
                          f"[{out_off}, {out_off + out_size})", offset=off)


@rule("CNT019", "address-overlap", ERROR,
      "Two network variables of one direction occupy overlapping PI bytes.",
      hint="every variable has its own bytes in the process image", kind=BIN)
def address_overlap(ctx):
    addrs = _addresses(ctx)
    if not addrs:
        return
    groups: dict = {}
    for addr, (index, sub, size, _), off in addrs:
        groups.setdefault(_direction(index), []).append((addr, addr + max(size, 1), index, sub,
                                                         off))
    for spans in groups.values():
        spans.sort()
        reach = None
        for s in spans:
            if reach is not None and s[0] < reach[1]:
                yield Finding(f"0x{s[2]:04X}sub{s[3]:X} [bytes {s[0]}..{s[1] - 1}] overlaps "
                              f"0x{reach[2]:04X}sub{reach[3]:X} [bytes {reach[0]}.."
                              f"{reach[1] - 1}]", offset=s[4])
            if reach is None or s[1] > reach[1]:
                reach = s


@rule("CNT020", "nv-size-mismatch", ERROR,
      "A network variable's data size differs from its CiA 405 range's type size.",
      hint="the target creates the variable with the data type of its CiA 405 index range",
      kind=BIN)
def nv_size(ctx):
    for index, sub, size, i in _variables(ctx):
        ch = layout.table_channel(index)
        if ch is not None and size != ch.dtype.size:
            yield Finding(f"entry {i + 1} (0x{index:04X}sub{sub:X}) has {size} bytes; "
                          f"{ch.dtype.name} has {ch.dtype.size}", offset=ctx.entry_offsets[i])


@rule("CNT099", "container-rejected", ERROR,
      "The container reader rejects the container for a reason no finer rule names.",
      hint="see the message", kind=BIN)
def rejected(ctx):
    if ctx.header is None:
        return
    from dcf2bin.container import ContainerError, read
    try:
        read(ctx.data)
    except ContainerError as exc:
        if not _known_broken(ctx):
            yield Finding(str(exc), offset=exc.offset)


def _known_broken(ctx) -> bool:
    """True when a finer rule above already explains why the reader refuses it."""
    h = ctx.header
    if h is None or ctx.total != len(ctx.data) or ctx.bad_segments or ctx.index_problem:
        return True
    if h["index_size"] == 0:
        return True
    segs = ctx.segments
    if any(b.offset < a.end for a, b in zip(segs, segs[1:])):
        return True
    a = ctx.segment("address")
    return a is not None and a.size % 2 == 1
