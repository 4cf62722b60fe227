"""Reading a container robustly (``read_bytes``: its error as one diagnostic) and the facts
of its stored bytes every view uses: the header (``header_of``), the offset of each entry.
"""
from __future__ import annotations

from itertools import accumulate

from dcf2bin import schema
from dcf2bin.container import BinContainer, ContainerError, read as read_container
from dcf2bin.diagnostics import Diagnostic, Severity


def read_bytes(data: bytes, name: str) -> tuple[BinContainer | None, list[Diagnostic]]:
    """``container.read`` with its error as one diagnostic naming the byte offset."""
    try:
        c, warnings = read_container(data)
    except ContainerError as exc:
        return None, [Diagnostic(Severity.ERROR, str(exc), name, offset=exc.offset,
                                 rule=exc.rule)]
    return c, [Diagnostic(d.severity, d.message, name, d.line, d.column, d.offset, d.rule,
                          d.hint) for d in warnings]


def header_of(c: BinContainer) -> dict[str, int]:
    """The header as stored (odd layouts) or as ``to_bytes`` builds it."""
    return dict(c.header) if c.header is not None else c.canonical_header()


def entry_offsets(c: BinContainer, header: dict[str, int] | None = None) -> list[int]:
    """Byte offset of each index entry (its WORD index) from the container's start."""
    h = header or header_of(c)
    pos = h["index_offset"] + schema.COUNT.size
    if not c.entries:
        return []
    # each entry starts where the one before ends: its head and data after the previous
    sizes = map(schema.ENTRY_HEAD.size.__add__, map(len, [e[2] for e in c.entries[:-1]]))
    return list(accumulate(sizes, initial=pos))
