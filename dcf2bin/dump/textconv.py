"""A container or a concise DCF as text for git's textconv filter (``dcf2bin dump
--textconv``; docs/diff.md, "git").

git diffs the text two versions of a file turn into, line by line. So this form holds what
the bytes say and nothing that only says where they are: no file name (git names the old
version by a temporary file), no entry numbers and no byte offsets (one entry added or grown
would shift every later one), no table padded to its widest cell (one longer value would
re-pad every row), and no data shortened (a change in the tail of a long DOMAIN would not
show). One line per entry, so that one entry changed is one line changed:

    0x1017sub0: 2 bytes F401 = 500  attr 0x70 NUM|R|W
    0x1800sub1: 4 bytes 83010080 = 0x80000183 = COB-ID 0x183, invalid  attr 0x70 NUM|R|W  write 1/2
    0x1017sub0 Producer heartbeat time: UNSIGNED16  2 bytes 3200 = 50      (concise, --eds)

A container in the canonical layout shows no header fields: every one of them follows from
the segments. A stored layout shows them, and where the bytes between segments lie.

A filter that fails makes git abort the whole diff ("unable to read files to diff"), so
bytes that are no whole container or concise DCF still turn into text (``damaged``): what
can be read of them -- a concise DCF's whole entries before the damage -- and the error as
a line of the text, ``! error at 0x2D: ... [CON002]``:

    concise DCF (CiA 302-3), 50 bytes, damaged: 4 whole entries
    0x1400sub1: UNSIGNED32  4 bytes 02020080 = 0x80000202 = COB-ID 0x202, invalid
    ...
    ! error at 0x2D: entry 5 of 22 (0x1600sub2) claims 4 data bytes, 1 remain [CON002]
"""
from __future__ import annotations

from dcf2bin import concise, schema
from dcf2bin.container import BinContainer
from dcf2bin.dump.concise_text import disagrees
from dcf2bin.dump.concise_types import EDS, GUESS, entry_type
from dcf2bin.dump.eds import EdsInfo
from dcf2bin.dump.text import (_FLAGS, _SEGMENT_TITLES, _address_columns, _Num, _pi_notes,
                               header_notes, nv_keys, typed_value, value_text, write_marks)
from dcf2bin.dump.binary import header_of


def container(c: BinContainer, *, eds: EdsInfo | None = None) -> str:
    """The textconv form of a container."""
    h = header_of(c)
    nvs = nv_keys(c)
    notes = header_notes(c, h, len(nvs))
    layout = "canonical layout" if c.header is None else "stored layout (not canonical)"
    out = [f"binary DCF segment container, {h['total_size']} bytes, {layout}"]
    if c.header is not None:
        out += _header(h, notes)
    attrs = c.attributes or b""
    n = len(c.entries)
    out.append(f"index segment: {_count(n, 'entry', 'entries')}")
    writes = _writes([(i, s) for i, s, _ in c.entries])
    for k, (index, sub, data) in enumerate(c.entries):
        attr = attrs[k] if k < len(attrs) else None
        line = f"{_label(index, sub)}: {_data(data, value_text(index, sub, data, attr, eds, True))}"
        line += f"  attr 0x{attr:02X} {_FLAGS[attr]}" if attr is not None else "  attr -"
        out.append(line + writes[k])
    if len(attrs) > n:
        out.append(f"! {_count(len(attrs) - n, 'attribute byte', 'attribute bytes')} "
                   f"without an entry: {attrs[n:].hex().upper()}")
    out += _addresses(c, nvs, eds, "address_size" in notes)
    out += _pi(c)
    for off, data in c.gaps:
        out.append(f"bytes in no segment at 0x{off:X}: {_count(len(data), 'byte', 'bytes')} "
                   f"{data.hex().upper()}")
    return "\n".join(out) + "\n"


def concise_dcf(entries, *, eds: EdsInfo | None = None, eds_name: str = "") -> str:
    """The textconv form of a concise DCF's entries (``eds_name`` names ``--eds``)."""
    n = len(entries)
    out = [f"concise DCF (CiA 302-3), {concise.size_of(entries)} bytes, "
           f"{_count(n, 'entry', 'entries')}"]
    writes = _writes([(i, s) for i, s, _ in entries])
    notes = []
    for k, (index, sub, data) in enumerate(entries):
        t, source = entry_type(index, sub, len(data), eds)
        typed = "" if t is None else t.name + ("?" if source == GUESS else "") + "  "
        label = _label(index, sub)
        if eds is not None:
            name = eds.name(index, sub)
            label += f" {name}" if name else ""
            if source != EDS:
                note = disagrees(eds, eds_name, index, sub, len(data))
                notes.append(f"! {note}" if note else "")
        line = f"{label}: {typed}{_data(data, typed_value(t, index, sub, data, True))}"
        out.append(line + writes[k])
    return "\n".join(out + list(dict.fromkeys(n for n in notes if n))) + "\n"


def damaged(data: bytes, kind: str, error, *, eds: EdsInfo | None = None,
            eds_name: str = "") -> str:
    """The textconv form of bytes that are no whole container or concise DCF: ``kind`` is
    what they were read as ("bin", "concise"; else None), ``error`` the reader's
    Diagnostic (or the sentence saying what the file is instead). What can be read is
    shown -- a concise DCF's whole entries from its start, the rest of the file's bytes
    counted -- then the error."""
    if kind == "concise":
        entries = _whole_entries(data)
        text = concise_dcf(entries, eds=eds, eds_name=eds_name).splitlines()
        head = (f"concise DCF (CiA 302-3), {_count(len(data), 'byte', 'bytes')}, damaged: "
                f"{_count(len(entries), 'whole entry', 'whole entries')}")
        lines = [head, *text[1:]]
        rest = len(data) - concise.size_of(entries) if len(data) >= concise.COUNT.size \
            else 0
        if rest:
            lines.append(f"! {_count(rest, 'byte', 'bytes')} after them not read")
    elif kind == "bin":
        lines = [f"binary DCF segment container, {_count(len(data), 'byte', 'bytes')}, "
                 "damaged"]
    else:
        lines = []
    if isinstance(error, str):
        lines.append(f"! error: {error}")
    else:
        at = f" at 0x{error.offset:X}" if error.offset is not None else ""
        rule = f" [{error.rule}]" if error.rule else ""
        lines.append(f"! error{at}: {error.message}{rule}")
    return "\n".join(lines) + "\n"


def _whole_entries(data: bytes) -> list:
    """The entries of a concise DCF that lie whole in ``data``, from its start, until one
    does not (whatever its count says)."""
    n, at, out = len(data), concise.COUNT.size, []
    unpack = concise.ENTRY_HEAD.unpack_from
    while at + concise.HEAD <= n:
        index, sub, size = unpack(data, at)
        if at + concise.HEAD + size > n:
            break
        at += concise.HEAD
        out.append((index, sub, data[at:at + size]))
        at += size
    return out


def _label(index: int, sub: int) -> str:
    return f"0x{index:04X}sub{sub:X}"


def _data(data: bytes, value: str) -> str:
    """``2 bytes F401 = 500``: every byte, and the value where one is known."""
    line = _count(len(data), "byte", "bytes")
    line += f" {data.hex().upper()}" if data else ""
    return line + (f" = {value}" if value else "")


def _writes(keys: list[tuple[int, int]]) -> list[str]:
    """``  write k/n`` for the k-th of n writes of one entry, else ``""``."""
    return [f"  write {m}" if m else "" for m in write_marks(keys)]


def _header(h: dict[str, int], notes: dict[str, str]) -> list[str]:
    """A stored layout's header, one field per line, with its notes."""
    def note(*keys: str) -> str:
        return next((f"  ! {notes[k]}" for k in keys if k in notes), "")

    out = [f"header: total size {h['total_size']}{note('total_size')}",
           f"header: version {h['version']}{note('version')}",
           f"header: segment count {h['segment_count']}{note('segment_count')}"]
    for seg in schema.SEGMENTS:
        off, size = h[f"{seg}_offset"], h[f"{seg}_size"]
        out.append(f"header: {_SEGMENT_TITLES[seg]} offset {off} size {size}"
                   f"{note(f'{seg}_offset', f'{seg}_size')}")
    if "order" in notes:
        out.append(f"! {notes['order']}")
    return out


def _addresses(c: BinContainer, nvs, eds, mismatch: bool) -> list[str]:
    addrs = c.addresses
    variables = _count(len(nvs), "network variable", "network variables")
    if addrs is None:
        return [f"PI address segment: absent ({variables})"]
    out = [f"PI address segment: {_count(len(addrs), 'address', 'addresses')}, {variables}"
           + ("  ! they should match" if mismatch else "")]
    if not (addrs or nvs):
        return out
    cols = [col.texts() if isinstance(col, _Num) else list(map(str, col))
            for col in _address_columns(c, nvs, eds)]
    for _, addr, area, off, index, sub, size, dtype, name in zip(*cols):
        where = f"address {addr} {area} {off}".rstrip() if addr != "-" else "no address"
        what = (f"{index}sub{int(sub):X}  {_count(int(size), 'byte', 'bytes')}  {dtype}"
                if index != "-" else "no network variable")
        out.append(f"{where}  {what}  {name}".rstrip())
    return out


def _pi(c: BinContainer) -> list[str]:
    if c.raw_piparam is not None:
        return [f"PI parameter segment: {len(c.raw_piparam)} bytes (expected 20): "
                f"{c.raw_piparam.hex().upper()}"]
    if c.pi is None:
        return ["PI parameter segment: absent"]
    total, in_off, in_size, out_off, out_size = c.pi
    notes = _pi_notes(c.pi)
    return [f"PI parameter segment: complete size {total}{notes.get('total', '')}",
            f"PI parameter segment: input area offset {in_off} size {in_size}"
            f"{notes.get('input', '')}",
            f"PI parameter segment: output area offset {out_off} size {out_size}"
            f"{notes.get('output', '')}"]


def _count(n: int, one: str, many: str) -> str:
    return f"{n} {one if n == 1 else many}"


__all__ = ["concise_dcf", "container", "damaged"]
