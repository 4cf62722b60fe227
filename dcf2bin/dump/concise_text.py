"""The readable text report of a concise DCF (``report``): one row per entry, in the order
they are written, with its byte offset, the data in hex and the value decoded where its type
is known (``concise_types``: the EDS, CiA 301, a CiA 405 range) or guessed from the size
(marked ``?``); where the EDS disagrees with an entry, a ``!`` line says so.
"""
from __future__ import annotations

from dcf2bin import concise
from dcf2bin.dump.concise_types import EDS, GUESS, entry_type
from dcf2bin.dump.eds import EdsInfo
from dcf2bin.dump.text import _Num, _short_hex, _table_columns, typed_value, write_marks

_HEAD = ("#", "offset", "index", "sub", "size", "data", "type", "value", "write")


def report(entries, name: str, *, eds: EdsInfo | None = None, eds_name: str = "",
           full: bool = False) -> str:
    """The report (``dcf2bin dump --format text`` of a concise DCF); ``eds_name`` names
    the ``--eds`` file."""
    n = len(entries)
    size = concise.size_of(entries)
    out = [f"{name}: concise DCF (CiA 302-3), {size} bytes, {_count(n, 'entry', 'entries')}"]
    if eds is not None:
        out.append(f"Types and names from {eds_name}; a type ending in ? is guessed from the "
                   "size alone.")
    else:
        out.append("A type ending in ? is guessed from the size alone (--eds gives the "
                   "device's types).")
    out.append("")
    if not n:
        out.append("No entries: the file configures nothing.")
        return "\n".join(out) + "\n"
    cols, notes = _columns(entries, eds, eds_name, full)
    head = _HEAD + (("name",) if eds is not None else ())
    out.extend(_table_columns(head, cols, right={0, 3, 4}))
    if notes:
        out.append("")
        out.extend(f"  ! {note}" for note in notes)
    return "\n".join(out) + "\n"


def disagrees(eds: EdsInfo, eds_name: str, index: int, sub: int, size: int) -> str:
    """The note where the EDS gives an entry another size, or has no such entry; ""
    where it agrees (the report's and textconv's)."""
    given = eds.dtype(index, sub)
    if given is not None:
        return (f"0x{index:04X}sub{sub:X}: {size} data bytes, {eds_name} gives {given.name} "
                f"({given.size} bytes)")
    if (index, sub) not in eds.entries:
        return f"0x{index:04X}sub{sub:X}: {eds_name} has no such entry"
    return ""


def _columns(entries, eds: EdsInfo | None, eds_name: str, full: bool):
    """The table, column by column, and the notes where the EDS disagrees."""
    types, values, notes = [], [], []
    for index, sub, data in entries:
        t, source = entry_type(index, sub, len(data), eds)
        types.append("-" if t is None else t.name + ("?" if source == GUESS else ""))
        values.append(typed_value(t, index, sub, data, full))
        if eds is not None and source != EDS:
            note = disagrees(eds, eds_name, index, sub, len(data))
            if note:
                notes.append(note)
    writes = write_marks((i, s) for i, s, _ in entries)
    indexes, subs, datas = zip(*entries)
    cols = [_Num(range(1, len(entries) + 1)), _Num(concise.offsets(entries), "0x"),
            _Num(indexes, "0x", 4), _Num(subs), _Num([len(d) for d in datas]),
            [_short_hex(d, full) for d in datas], types, values, writes]
    if eds is not None:
        cols.append([eds.name(i, s) for i, s, _ in entries])
    return cols, _unique(notes)


def _unique(notes: list[str]) -> list[str]:
    return list(dict.fromkeys(notes))


def _count(n: int, one: str, many: str) -> str:
    return f"{n} {one if n == 1 else many}"


__all__ = ["report"]
