"""Which entries ``diff`` compares: the node's state left out unless ``--all``, and the
entries and ranges of ``--ignore``.

The node's state, not its configuration (docs/diff.md, "What is the node's state"):

* the objects 0x1001 (error register), 0x1002 (manufacturer status register), 0x1003
  (pre-defined error field: the error history), and 0x1010 (store parameters) and 0x1011
  (restore default parameters), which read as what the node can do, not as what was
  written to them;
* every entry with access ``ro`` from index 0x2000 on (manufacturer and device profile
  areas, network variables: status words, measured values, inputs) except the sub 0 of an
  ARRAY or RECORD, which counts its entries.

``const`` entries and every other entry below 0x2000 (the device type 0x1000, the
identity 0x1018, the communication parameters) are configuration. The access is the
description's (either side's; a container's attribute byte where neither is one: read
without write); an entry whose access no side knows is compared.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from dcf2bin.diagnostics import shorten

STATE_OBJECTS = {0x1001: "error register", 0x1002: "manufacturer status register",
                 0x1003: "pre-defined error field", 0x1010: "store parameters",
                 0x1011: "restore default parameters"}
STATE_RO_FROM = 0x2000

_ENTRY = re.compile(r"(?i)\s*(?P<index>[0-9a-fx]+)(?:\s*sub\s*(?P<sub>[0-9a-f]+))?\s*")


class BadIgnore(ValueError):
    """An --ignore value that names no entry or range (the message says why)."""


@dataclass(frozen=True)
class Span:
    """Entries from (first index, first sub) to (last index, last sub), both included."""
    first: tuple[int, int]
    last: tuple[int, int]
    text: str

    def __contains__(self, key: tuple[int, int]) -> bool:
        return self.first <= key <= self.last


@dataclass
class Scope:
    """What is compared: ``state`` True leaves the node's state out (the default);
    ``ignore`` the spans of --ignore; ``values_only`` compares values and nothing else."""
    state: bool = True
    ignore: list[Span] = field(default_factory=list)
    values_only: bool = False

    def ignored(self, key: tuple[int, int]) -> bool:
        return any(key in s for s in self.ignore)


def parse_ignore(text: str) -> list[Span]:
    """``0x1017``, ``0x1018sub4``, ``0x2000-0x2FFF``, ``0x1A00sub1-0x1A00sub8``; several
    separated by commas. Indexes in hex with ``0x`` or decimal, as a DCF writes them;
    sub-indexes in hex, as in ``0x1018sub4`` (the form dcf2bin's messages use)."""
    spans = []
    for part in text.split(","):
        if not part.strip():
            continue
        first, dash, last = part.partition("-")
        a = _bound(first, part, low=True)
        b = _bound(last, part, low=False) if dash else _bound(first, part, low=False)
        if b < a:
            raise BadIgnore(f"'{shorten(part.strip())}': the range ends before it starts")
        spans.append(Span(a, b, part.strip()))
    if not spans:
        raise BadIgnore(f"'{shorten(text)}' names no entry (an index such as 0x1017, an entry such "
                        "as 0x1018sub4, or a range such as 0x2000-0x2FFF)")
    return spans


def _bound(text: str, whole: str, *, low: bool) -> tuple[int, int]:
    from dcf2bin import values
    m = _ENTRY.fullmatch(text)
    if m is None:
        raise BadIgnore(f"'{shorten(whole.strip())}' is not an entry or range (an index such as "
                        "0x1017, an entry such as 0x1018sub4, or a range such as "
                        "0x2000-0x2FFF)")
    try:
        index = values.parse_int(m["index"])
    except values.ValueProblem as exc:
        raise BadIgnore(f"'{shorten(whole.strip())}': {exc}") from None
    if not 0 <= index <= 0xFFFF:
        raise BadIgnore(f"'{shorten(whole.strip())}': index {shorten(m['index'])} is not in "
                        "0x0000-0xFFFF")
    if m["sub"] is None:
        return (index, 0 if low else 0xFF)
    sub = int(m["sub"], 16)
    if sub > 0xFF:
        raise BadIgnore(f"'{shorten(whole.strip())}': sub-index {shorten(m['sub'])} is not in "
                        "0x00-0xFF")
    return (index, sub)


def state_reason(key: tuple[int, int], items, complex_: bool | None) -> str | None:
    """Why the entry ``key`` is the node's state (None: it is configuration). ``items``
    are the sides' ``Item``s of it (None where a side lacks it); ``complex_`` whether
    its object is an ARRAY/RECORD on a side that knows."""
    index, sub = key
    if index in STATE_OBJECTS:
        return STATE_OBJECTS[index]
    if index < STATE_RO_FROM or (sub == 0 and complex_):
        return None
    described = [it for it in items if it is not None and it.access is not None]
    known = described or [it for it in items if it is not None and it.attr is not None]
    if known and known[0].read_only:
        return "read-only"
    return None
