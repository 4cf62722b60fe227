"""The readable text report of a container (``report``): header notes, segments as tables,
values shown by type (from the EDS when given, else guessed from the index range).
"""
from __future__ import annotations

import functools
import json
from typing import NamedTuple, Sequence

from dcf2bin import datatypes as dt, schema, values
from dcf2bin.container import BinContainer
from dcf2bin.dump.binary import entry_offsets, header_of
from dcf2bin.dump.eds import EdsInfo
from dcf2bin.layout import table_channel


_SEGMENT_TITLES = {"index": "index segment", "address": "PI address segment",
                   "extinfo": "extended info segment", "piparam": "PI parameter segment"}
_DATA_SHOWN = 16     # bytes of data shown before "..." unless --full


_FLAGS = [dt.attr_flags(a) for a in range(256)]


def nv_type(index: int, sub: int, size: int, eds: EdsInfo | None = None):
    """The DataType of a network variable: the EDS's, else its CiA 405 range's, if the size fits."""
    if not 0xA000 <= index <= 0xAFFF or sub == 0:
        return None
    if eds is not None:
        t = eds.dtype(index, sub)
        if t is not None and t.size == size:
            return t
    return _range_type(index, size)


@functools.lru_cache(maxsize=4096)
def _range_type(index: int, size: int):
    ch = table_channel(index)
    if ch is not None and ch.dtype.size == size:
        return ch.dtype
    return None


def value_text(index: int, sub: int, data: bytes, attr: int | None,
               eds: EdsInfo | None = None, full: bool = False) -> str:
    """The decoded value where the type (EDS, CiA 405 range) or attribute and size say how."""
    size = len(data)
    t = eds.dtype(index, sub) if eds is not None else None
    if t is not None and t.size is not None and t.size != size:
        t = None
    if t is None:
        t = nv_type(index, sub, size)
    if t is None and attr is not None:
        kinds = attr & dt.ATTR_TYPE_MASK
        if kinds == dt.ATTR_BOOLEAN and size == 1:
            t = dt.BOOLEAN
        elif kinds == dt.ATTR_VSTRING:
            t = dt.VISIBLE_STRING
        elif kinds == dt.ATTR_NUMERIC and size in dt.UNSIGNED_BY_SIZE:
            t = dt.UNSIGNED_BY_SIZE[size]
    return typed_value(t, index, sub, data, full)


def typed_value(t, index: int, sub: int, data: bytes, full: bool = False) -> str:
    """The value of ``data`` as type ``t`` ("" for none, a DOMAIN or OCTET_STRING, or data
    the type cannot hold); a PDO's COB-ID and mapping entries spelled out."""
    size = len(data)
    if t is None:
        return ""
    if t.kind == dt.BOOL:
        return {0: "FALSE", 1: "TRUE"}.get(data[0], f"0x{data[0]:02X}") if size == 1 else ""
    if t.kind in (dt.VSTRING, dt.USTRING):
        text = values.to_python(t, data)
        shown = json.dumps(text, ensure_ascii=False)
        if not full and len(shown) > 34:
            shown = shown[:30] + '..."'
        return shown
    if t.kind in (dt.OSTRING, dt.DOMAIN):
        return ""
    try:
        v = values.to_python(t, data)
    except values.ValueProblem:
        return ""
    if t.kind == dt.REAL:
        return values.decode(t, data) or repr(v)
    if t.kind == dt.SINT or size <= 2:
        return str(v)
    text = f"0x{v:0{2 * size}X}"
    if size == 4 and sub >= 1 and (0x1600 <= index <= 0x17FF or 0x1A00 <= index <= 0x1BFF):
        text += f" = {v >> 16:04X}sub{(v >> 8) & 0xFF:X}, {v & 0xFF} bits"
    elif size == 4 and sub == 1 and (0x1400 <= index <= 0x15FF or 0x1800 <= index <= 0x19FF):
        text += f" = COB-ID 0x{v & 0x1FFFFFFF:X}{', invalid' if v & 0x80000000 else ''}"
    return text


def _short_hex(data: bytes, full: bool) -> str:
    if full or len(data) <= _DATA_SHOWN:
        return data.hex().upper()
    return data[:_DATA_SHOWN - 4].hex().upper() + "..." + data[-2:].hex().upper()


def nv_keys(c: BinContainer) -> list[tuple[int, int]]:
    """Network variables in index-segment order, first occurrence (SPEC §3.4)."""
    indexes, subs, _ = _columns(c)
    return [key for key in dict.fromkeys(zip(indexes, subs))
            if 0xA000 <= key[0] <= 0xAFFF and key[1] >= 1]


def _columns(c: BinContainer) -> tuple[tuple, tuple, tuple]:
    """The index entries as three columns: indexes, subindexes, data."""
    if not c.entries:
        return (), (), ()
    return tuple(zip(*c.entries))


def header_notes(c: BinContainer, h: dict[str, int], nvs: int) -> dict[str, str]:
    """Where the header disagrees with the segments (or with D-5...D-7): field -> note."""
    notes: dict[str, str] = {}
    if h["version"] != 1:
        notes["version"] = "not the default 1"
    present = sum(1 for name in schema.SEGMENTS if h[f"{name}_size"])
    if h["segment_count"] != present:
        notes["segment_count"] = f"{present} segments are present"
    # read() checked that every segment's bytes are what its header slot says
    canon = schema.HEADER_SIZE + sum(h[f"{name}_size"] for name in schema.SEGMENTS)
    if h["total_size"] != canon:
        notes["total_size"] = f"header + segments = {canon}; {h['total_size'] - canon} bytes " \
                              "belong to no segment"
    spans = sorted((h[f"{n}_offset"], n) for n in schema.SEGMENTS if h[f"{n}_size"])
    order = [n for _, n in spans]
    if order != [n for n in schema.SEGMENTS if n in order]:
        notes["order"] = "segments are not in the header's order"
    for name in schema.SEGMENTS:
        if not h[f"{name}_size"] and h[f"{name}_offset"]:
            notes[f"{name}_offset"] = "an empty segment should have offset 0"
    n = len(c.entries)
    if len(c.attributes or b"") != n:
        notes["extinfo_size"] = f"{_count(len(c.attributes or b''), 'attribute byte')} for " \
                                f"{_count(n, 'entry', 'entries')}"
    if c.raw_piparam is not None:
        notes["piparam_size"] = "a PI parameter segment has 20 bytes"
    n_addr = len(c.addresses or [])
    if n_addr != nvs:
        notes["address_size"] = f"{_count(n_addr, 'address', 'addresses')} for " \
                                f"{_count(nvs, 'network variable')}"
    return notes


def _count(n: int, one: str, many: str | None = None) -> str:
    return f"{n} {one if n == 1 else (many or one + 's')}"


def report(c: BinContainer, name: str, *, eds: EdsInfo | None = None,
           full: bool = False) -> str:
    """The readable text report (``dcf2bin dump --format text``)."""
    h = header_of(c)
    size = h["total_size"]
    nvs = nv_keys(c)
    notes = header_notes(c, h, len(nvs))
    out: list[str] = []
    w = out.append
    layout = "canonical layout" if c.header is None else "stored layout (not canonical)"
    w(f"{name}: binary DCF segment container, {size} bytes, {layout}")
    w("")
    w(f"Header ({schema.HEADER_SIZE} bytes)")

    def note(key: str) -> str:
        return f"  ! {notes[key]}" if key in notes else ""

    w(f"  0x00  total size     {h['total_size']:<10}{note('total_size')}".rstrip())
    w(f"  0x04  version        {h['version']:<10}{note('version')}".rstrip())
    w(f"  0x06  segment count  {h['segment_count']:<10}{note('segment_count')}".rstrip())
    for i, seg in enumerate(schema.SEGMENTS):
        off, sz = h[f"{seg}_offset"], h[f"{seg}_size"]
        msg = note(f"{seg}_offset") or note(f"{seg}_size")
        span = f"bytes {off}..{off + sz - 1}" if sz else "absent"
        w(f"  0x{8 + 8 * i:02X}  {_SEGMENT_TITLES[seg]:<22} offset {off:<6} size {sz:<6} "
          f"{span}{msg}".rstrip())
    if "order" in notes:
        w(f"  ! {notes['order']}")

    # -- index segment
    attrs = c.attributes or b""
    n = len(c.entries)
    w("")
    w(f"Index segment: {n} entr{'y' if n == 1 else 'ies'}")
    if n:
        head = ("#", "offset", "index", "sub", "size", "data", "value", "attr", "flags", "write")
        out.extend(_table_columns(head, _index_columns(c, entry_offsets(c, h), eds, full),
                                  right={0, 3, 4}))
    if len(attrs) > n:
        w(f"  ! {_count(len(attrs) - n, 'attribute byte')} without an entry: "
          f"{_short_hex(attrs[n:], full)}")

    # -- process image
    w("")
    addrs = c.addresses
    if addrs is None:
        w(f"PI address segment: absent ({_count(len(nvs), 'network variable')})")
    else:
        w(f"PI address segment: {_count(len(addrs), 'address', 'addresses')}, "
          f"{_count(len(nvs), 'network variable')}"
          + ("  ! they should match" if "address_size" in notes else ""))
        if addrs or nvs:
            head = ("#", "address", "area", "offset", "index", "sub", "size", "type", "name")
            out.extend(_table_columns(head, _address_columns(c, nvs, eds),
                                      right={0, 3, 5, 6}))

    w("")
    if c.raw_piparam is not None:
        w(f"PI parameter segment: {len(c.raw_piparam)} bytes (expected 20): "
          f"{_short_hex(c.raw_piparam, full)}")
    elif c.pi is None:
        w("PI parameter segment: absent")
    else:
        total, in_off, in_size, out_off, out_size = c.pi
        w("PI parameter segment")
        pnotes = _pi_notes(c.pi)
        w(f"  complete size  {total:<8}{pnotes.get('total', '')}".rstrip())
        for label, off, sz, key in (("input area ", in_off, in_size, "input"),
                                    ("output area", out_off, out_size, "output")):
            span = f"bytes {off}..{off + sz - 1}" if sz else "empty"
            w(f"  {label}    offset {off:<6} size {sz:<6} {span}{pnotes.get(key, '')}")

    if c.gaps:
        w("")
        w("Bytes in no segment")
        for off, data in c.gaps:
            w(f"  0x{off:X}  {len(data)} bytes  {_short_hex(data, full)}")
    return "\n".join(out) + "\n"


def _index_columns(c: BinContainer, offsets: list[int], eds: EdsInfo | None,
                   full: bool) -> list:
    """The index segment's table, column by column (one list of cells per column).

    Each column is made by one pass over the entries; a cell's text is computed once per
    distinct value (data, attribute, a network variable's value by type) and looked up for
    the other entries that share it (a PLC container repeats few of them)."""
    n = len(c.entries)
    attrs = c.attributes or b""
    indexes, subs, datas = _columns(c)
    attr_of: list[int | None] = list(attrs[:n])
    if len(attr_of) < n:
        attr_of += [None] * (n - len(attr_of))

    shown = {d: _short_hex(d, full) for d in set(datas)}
    values: list[str] = []
    append = values.append
    # a network variable's value depends on its range's type, its attribute and its data
    # only (value_text looks at the index for PDO records alone): one cache per type,
    # found once per (index, size)
    slots: dict[tuple[int, int], dict] = {}
    by_type: dict = {}
    for index, sub, data, attr in zip(indexes, subs, datas, attr_of):
        if eds is None and 0xA000 <= index <= 0xAFFF and sub:
            texts = slots.get((index, len(data)))
            if texts is None:
                texts = by_type.setdefault(_range_type(index, len(data)), {})
                slots[(index, len(data))] = texts
            text = texts.get((attr, data))
            if text is None:
                text = texts[(attr, data)] = value_text(index, sub, data, attr, None, full)
            append(text)
        else:
            append(value_text(index, sub, data, attr, eds, full))

    writes = write_marks(zip(indexes, subs))
    attr_text = [f"0x{a:02X}" for a in range(256)]
    return [_Num(range(1, n + 1)),
            _Num(offsets, "0x"),
            _Num(indexes, "0x", 4),
            _Num(subs),
            _Num(list(map(len, datas))),
            list(map(shown.__getitem__, datas)),
            values,
            [attr_text[a] if a is not None else "-" for a in attr_of],
            [_FLAGS[a] if a is not None else "-" for a in attr_of],
            writes]


def _address_columns(c: BinContainer, nvs: list[tuple[int, int]],
                     eds: EdsInfo | None) -> list:
    """The PI address table, column by column: one row per address or network variable
    (a "-" where one list is longer than the other)."""
    addrs = c.addresses or []
    n_addr, n_nv = len(addrs), len(nvs)
    rows = max(n_addr, n_nv)
    # the first data of each (index, sub): later writes are assigned first and overwritten
    indexes, subs, datas = _columns(c)
    first = dict(zip(zip(reversed(indexes), reversed(subs)), map(len, reversed(datas))))
    pi = c.pi
    if pi is None:
        areas, offsets = [""] * n_addr, [""] * n_addr
    else:
        _, in_off, in_size, out_off, out_size = pi
        in_end, out_end = in_off + in_size, out_off + out_size
        areas = ["input" if in_off <= a < in_end else "output" if out_off <= a < out_end
                 else "outside" for a in addrs]
        offsets = [a - in_off if in_off <= a < in_end else a - out_off
                   if out_off <= a < out_end else "" for a in addrs]
    sizes = [first[key] for key in nvs]
    types: dict[tuple[int, int, int], str] = {}
    type_names = []
    for (index, sub), size in zip(nvs, sizes):
        key = (index, sub, size) if eds is not None else (index, 0xFF, size)
        name = types.get(key)
        if name is None:
            t = nv_type(index, sub, size, eds)
            name = types[key] = t.name if t is not None else "-"
        type_names.append(name)
    names = [eds.name(*key) for key in nvs] if eds is not None else [""] * n_nv
    cols = [_Num(range(1, rows + 1)), _Num(addrs, "0x", 4), areas, offsets,
            _Num([k[0] for k in nvs], "0x", 4), _Num([k[1] for k in nvs]), _Num(sizes),
            type_names, names]
    if rows == n_addr == n_nv and "" not in offsets:
        cols[3] = _Num(offsets)
        return cols
    # an address without a variable or the other way round, or one outside both areas
    cols = [col.texts() if isinstance(col, _Num) else col for col in cols]
    cols[3] = list(map(str, offsets))
    for col in (1, 2, 3):
        cols[col] += ["-" if col == 1 else ""] * (rows - n_addr)
    for col in (4, 5, 6, 7, 8):
        cols[col] += ["" if col == 8 else "-"] * (rows - n_nv)
    return cols


def _pi_notes(pi) -> dict[str, str]:
    total, in_off, in_size, out_off, out_size = pi
    notes = {}
    end = max(in_off + in_size, out_off + out_size)
    if total < end:
        notes["total"] = f"  ! the areas end at {end}"
    if in_size and out_size and in_off < out_off + out_size and out_off < in_off + in_size:
        notes["output"] = "  ! overlaps the input area"
    elif out_size and out_off % 8 and out_off >= in_off + in_size:
        notes["output"] = "  (not 8-aligned: --pi-align?)"
    return notes


class _Num(NamedTuple):
    """A table column of non-negative integers, written as ``prefix`` and the number in
    decimal, or in upper-case hex when there is a prefix (at least ``digits`` digits)."""
    values: Sequence[int]
    prefix: str = ""
    digits: int = 0

    def conversion(self) -> str:
        """The printf conversion of one cell, without its width."""
        kind = "X" if self.prefix else "d"
        return f".{self.digits}{kind}" if self.digits else kind

    def width(self) -> int:
        """The width of the widest cell (the numbers' largest, written out); 0 for none."""
        if not self.values:
            return 0
        largest = max(self.values)
        return len(self.prefix) + len(f"%{self.conversion()}" % largest)

    def texts(self) -> list[str]:
        return list(map(f"{self.prefix}%{self.conversion()}".__mod__, self.values))


def write_marks(keys) -> list[str]:
    """The write column of a write list: ``k/n`` for the k-th of n writes of one (index,
    sub), else ``""`` (the reports of a container and a concise DCF, textconv's ``write
    k/n``)."""
    keys = list(keys)
    counts: dict[tuple[int, int], int] = {}
    for key in keys:
        counts[key] = counts.get(key, 0) + 1
    marks = [""] * len(keys)
    if len(counts) < len(keys):
        seen: dict[tuple[int, int], int] = {}
        for i, key in enumerate(keys):
            total = counts[key]
            if total > 1:
                seen[key] = k = seen.get(key, 0) + 1
                marks[i] = f"{k}/{total}"
    return marks


def _table_columns(head: tuple, cols: list, right: set[int]) -> list[str]:
    """A table of left- or right-aligned columns under a head, two spaces apart, each line
    without trailing blanks. The cells come column by column, as lists of text or as
    ``_Num`` columns of numbers; the lines are made by one printf-style template (``%-8s``,
    ``0x%-6.4X``: the column's width), the fastest way to pad here, and numbers are
    written by it directly."""
    heads, specs = [], []
    for i, (title, col) in enumerate(zip(head, cols)):
        if isinstance(col, _Num):
            width = max(len(title), col.width())
            if i in right:
                assert not col.prefix, "a right-aligned number column has no prefix"
                specs.append(f"%{width}{col.conversion()}")
            else:
                specs.append(f"{col.prefix}%-{width - len(col.prefix)}{col.conversion()}")
        else:
            width = max(len(title), max(map(len, col), default=0))
            specs.append(f"%{'' if i in right else '-'}{width}s")
        heads.append(title.rjust(width) if i in right else title.ljust(width))
    fmt = "  " + "  ".join(specs)
    values = [col.values if isinstance(col, _Num) else col for col in cols]
    return [("  " + "  ".join(heads)).rstrip()] + list(
        map(str.rstrip, map(fmt.__mod__, zip(*values))))
