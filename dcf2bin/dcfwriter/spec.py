"""What the DCF will hold: the per-index facts that bin2dcf reads from a container.

``reader`` fills a ``DcfSpec`` (one ``ObjSpec`` per index, one ``SubSpec`` per
subindex with every write the container makes to it), ``text`` renders it and
``roundtrip`` replays compile on it. The warnings of all three collect in one
``Issues``, by rule.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.container import BinContainer
from dcf2bin.diagnostics import Diagnostic, Severity
from dcf2bin.layout import table_channel
from dcf2bin.select import attribute_byte as attribute

MAX_SHOWN = 5            # warnings of one kind shown before "... and N more"

# Warning rules of bin2dcf (what will not compile back to the same bytes).
R_HEADER = "B2D001"      # header, layout, attribute segment length
R_ATTR = "B2D002"        # an attribute byte no DCF entry produces
R_REPEAT = "B2D003"      # repeated writes outside a PDO block
R_SELECT = "B2D004"      # an entry compile would not write (ro, below 0x1000, missing sub 0)
R_PDO = "B2D005"         # a PDO block compile would not regenerate
R_PI = "B2D006"          # process image: addresses, PI parameters, channels
R_VALUE = "B2D007"       # a value that its type cannot express in a DCF
R_EDS = "B2D008"         # the EDS disagrees with the container
R_SUMMARY = "B2D010"     # the overall verdict


def table_type(index: int) -> tuple[dt.DataType, str] | None:
    """The CiA 405 range type and area of a network-variable index (SPEC §2.1)."""
    ch = table_channel(index)
    return (ch.dtype, ch.direction) if ch is not None else None


@dataclass(slots=True)
class Write:
    pos: int               # 0-based entry number
    offset: int            # byte offset of the entry in the container
    data: bytes
    attr: int | None


@dataclass(slots=True)
class SubSpec:
    index: int
    sub: int
    dtype: dt.DataType
    access: str
    pdo: bool
    writes: list[Write]
    name: str = ""
    value: str = ""        # ParameterValue text ("" = none: an implied sub 0)
    default: str = ""      # DefaultValue text (an implied sub 0; a DIS-2 comm sub 1, D-12)
    note: str = ""         # a comment line before its keys (a concise DCF's guessed type)

    @property
    def data(self) -> bytes:
        return self.writes[-1].data

    @property
    def value_bytes(self) -> bytes:
        """What compile encodes for the entry: the last write, or an implied sub 0's
        DefaultValue (UNSIGNED8)."""
        return self.writes[-1].data if self.writes else int(self.default).to_bytes(1, "little")

    @property
    def attr(self) -> int:
        return attribute(self.index, self.sub, self.dtype, self.access, self.pdo)


@dataclass(slots=True)
class ObjSpec:
    index: int
    object_type: int
    name: str = ""
    subs: dict[int, SubSpec] = field(default_factory=dict)


@dataclass(slots=True)
class ChannelSpec:
    """A ``[DynamicChannels]`` segment bin2dcf reconstructs from the PI addresses."""
    dtype: dt.DataType
    direction: str
    first: int
    last: int = 0
    pp: int | None = None


class Issues:
    """Warnings grouped by rule; at most MAX_SHOWN per rule are reported."""

    def __init__(self, name: str):
        self.name = name
        self.items: dict[str, list[tuple[int | None, str]]] = {}
        self.severity: dict[str, Severity] = {}   # a rule's, where not a warning

    def add(self, rule: str, offset: int | None, message: str,
            severity: Severity = Severity.WARNING) -> None:
        self.items.setdefault(rule, []).append((offset, message))
        if severity is not Severity.WARNING:
            self.severity[rule] = severity

    def __bool__(self) -> bool:
        return any(items for rule, items in self.items.items()
                   if self.severity.get(rule, Severity.WARNING) is Severity.WARNING)

    def diagnostics(self) -> list[Diagnostic]:
        out = []
        for rule, items in self.items.items():
            severity = self.severity.get(rule, Severity.WARNING)
            for offset, message in items[:MAX_SHOWN]:
                out.append(Diagnostic(severity, message, self.name, offset=offset, rule=rule))
            if len(items) > MAX_SHOWN:
                out.append(Diagnostic(severity, f"... and {len(items) - MAX_SHOWN} "
                                      "more like this", self.name, rule=rule))
        return out


@dataclass
class DcfSpec:
    """A container read as DCF objects: what ``text`` writes and ``roundtrip`` checks."""
    container: BinContainer
    name: str                               # the container's name in messages
    header: dict[str, int]                  # as stored, or the canonical one
    offsets: list[int]                      # byte offset of each index-segment entry
    issues: Issues
    objects: dict[int, ObjSpec] = field(default_factory=dict)
    channels: list[ChannelSpec] = field(default_factory=list)
    encoding: str = "utf-8"
    what: str = "container"                 # what the bytes are, in messages and comments

    @property
    def concise(self) -> bool:
        """A concise DCF (CiA 302-3): entries without attributes, header or process image,
        whose DCF is not meant to compile back to them."""
        return self.what == "concise DCF"


def value_text(dtype: dt.DataType, data: bytes, encoding: str) -> str | None:
    """ParameterValue text for ``data``; unsigned values padded to the type's width."""
    if dtype.kind in (dt.UINT, dt.TIME) and dtype.size == len(data):
        return f"0x{int.from_bytes(data, 'little'):0{2 * dtype.size}X}"
    return values.decode(dtype, data, encoding=encoding)


def holds(dtype: dt.DataType | None, data: bytes) -> bool:
    """Can a variable of ``dtype`` store exactly ``data`` (a BOOLEAN only 0 or 1)?"""
    return dtype is not None and dtype.size == len(data) and (dtype.kind != dt.BOOL
                                                              or data[0] < 2)


def by_size(size: int) -> dt.DataType:
    return dt.UNSIGNED_BY_SIZE.get(size, dt.DOMAIN_T)


def short(data: bytes) -> str:
    h = data.hex().upper()
    return h if len(h) <= 24 else h[:20] + "..."


__all__ = ["ChannelSpec", "DcfSpec", "Issues", "ObjSpec", "SubSpec", "Write", "by_size", "holds",
           "short", "table_type", "value_text", "MAX_SHOWN", "R_HEADER", "R_ATTR", "R_REPEAT",
           "R_SELECT", "R_PDO", "R_PI", "R_VALUE", "R_EDS", "R_SUMMARY"]
