"""The data of an emulation (SPEC §8): the options (``TargetOptions``), the result
(``Outcome`` with its ``TargetEntry``s, ``Pdo``s, ``Created`` and ``Descriptor``), the failure
``_Fail`` carrying a DynBuildOd code, and small helpers the steps share.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.dynod import codes as C


RX, TX = "rx", "tx"
_NUMERIC_OR_BOOL = dt.ATTR_NUMERIC | dt.ATTR_BOOLEAN
_OUTPUT_FIRST = 0xA480      # CiA 405: A000-A47F inputs, A480-A8FF outputs


@dataclass
class TargetOptions:
    """What the firmware was built with (seed 000 §4) and what it gives (SPEC §8.1)."""
    pi_size: int | None = None        # m_dwProcessImageSize; None = unlimited
    tx_cobs: int | None = None        # PDO entries of the TX COB table; None = unlimited
    rx_cobs: int | None = None
    granularity: int = 64             # PDO_GRANULARITY (8 or 64)
    bit_mapping: bool = True          # PDO_USE_BIT_MAPPING
    address_base: str = "image"       # D-10: "image" or "area"


@dataclass(slots=True)
class TargetEntry:
    """One entry of the emulated object dictionary after the run: its data, type and access."""
    index: int
    sub: int
    data: bytes
    dtype: dt.DataType | None
    kind: str                 # "bool", "numeric", "vstring" or "domain"
    readable: bool
    writable: bool
    mappable: bool
    pi_address: int | None = None     # image address of a placed network variable
    created: bool = False             # created by the container (not in the static OD)
    written: bool = False             # written by the container

    @property
    def access(self) -> str:
        """The AccessType this entry has after DynBuildOd: rw, wo, or ro (also for an
        attribute byte with neither READ nor WRITE: such an entry is never written)."""
        if self.readable and self.writable:
            return "rw"
        return "wo" if self.writable else "ro"


@dataclass
class Pdo:
    """A PDO as the target would run it: its direction, comm object, COB-ID and mapping."""
    direction: str            # "rx" or "tx"
    comm_index: int
    cob_id: int               # the COB-ID as last written (bit 31 clear)
    mapped: list[tuple[int, int, int, int | None]]   # (index, sub, bits, PI address)

    @property
    def can_id(self) -> int:
        return self.cob_id & 0x3FFFFFFF

    @property
    def bits(self) -> int:
        return sum(m[2] for m in self.mapped)


@dataclass(frozen=True)
class TargetWarning:
    """What the emulation could not check (an unknown static OD): a TGT1xx rule id and one
    line saying what was assumed and what the target answers if the assumption is wrong."""
    rule: str
    message: str

    def __str__(self) -> str:
        return self.message


@dataclass
class Descriptor:
    """tProcessImageDscrpt: IN the PI memory the caller gives, OUT the five numbers."""
    memory: int | None                                  # IN m_dwProcessImageSize (None: unlimited)
    out: tuple[int, int, int, int, int] | None = None   # size, in off, in size, out off, out size


@dataclass
class Created:
    """What the container created: the objects, their entries and their data bytes."""
    objects: list[int] = field(default_factory=list)   # indexes the container created
    entries: int = 0
    bytes: int = 0


@dataclass
class Outcome:
    """The verdict of an emulated DynBuildOd() run: its code, and where and why it failed."""
    code: int
    reason: str = ""
    entry: int | None = None          # 1-based position in the index segment
    index: int | None = None
    subindex: int | None = None
    offset: int | None = None         # byte offset of the entry in the container
    where: str | None = None          # DCF file:line that produced the entry
    value: bytes | None = None        # the failing entry's data
    step: str = ""                    # "structure", "memory", "entries" or "" (success)
    warnings: list[TargetWarning] = field(default_factory=list)
    descriptor: Descriptor | None = None
    created: Created = field(default_factory=Created)
    entries_applied: int = 0
    _engine: object = field(default=None, repr=False)   # the emulate._Engine that ran
    _od: dict | None = field(default=None, repr=False)
    _pdos: list[Pdo] | None = field(default=None, repr=False)

    @property
    def name(self) -> str:
        return C.name(self.code)

    @property
    def ok(self) -> bool:
        return self.code == C.OK

    @property
    def rule(self) -> str:
        return C.rule_id(self.code)

    @property
    def label(self) -> str | None:
        if self.index is None:
            return None
        return f"0x{self.index:04X}sub{self.subindex:X}"

    @property
    def pdos(self) -> list[Pdo]:
        """The valid PDOs after a successful run (none after a failure), each with its
        mapped objects and their PI addresses: worked out on first use (a compile's target
        check only asks whether the run succeeded)."""
        if self._pdos is None:
            self._pdos = self._engine.pdos() if self._engine is not None and self.ok else []
        return self._pdos

    @pdos.setter
    def pdos(self, value: list[Pdo]) -> None:
        self._pdos = value

    @property
    def od(self) -> dict[int, dict[int, TargetEntry]]:
        """The object dictionary after DynBuildOd (up to the failing entry): static,
        created and written entries (built on first use)."""
        if self._od is None:
            self._od = self._engine.build_od() if self._engine is not None else {}
        return self._od


class _Fail(Exception):
    def __init__(self, code: int, reason: str, pos: int | None = None):
        super().__init__(reason)
        self.code, self.reason, self.pos = code, reason, pos


def can_id_problem(cob: int) -> str | None:
    """Why a COB-ID's CAN-ID is not legal for a PDO (CiA 301), or None."""
    if cob & 0x20000000:
        return None                                 # 29-bit frame: any identifier
    if cob & 0x1FFFF800:
        return "an 11-bit COB-ID with bits 11-28 set"
    cid = cob & 0x7FF
    for lo, hi in _RESTRICTED:
        if lo <= cid <= hi:
            return f"CAN-ID 0x{cid:03X} is restricted by CiA 301 (0x{lo:03X}-0x{hi:03X})" \
                if lo != hi else f"CAN-ID 0x{cid:03X} is restricted by CiA 301"
    return None


_RESTRICTED = ((0x000, 0x000), (0x001, 0x07F), (0x101, 0x180), (0x581, 0x5FF), (0x601, 0x67F),
               (0x6E0, 0x6FF), (0x701, 0x77F), (0x780, 0x7FF))


def _le(data: bytes) -> int:
    return int.from_bytes(data, "little")


def _dir(comm: int) -> str:
    return RX if comm < 0x1800 else TX


def _pdo_name(comm: int) -> str:
    base = 0x1400 if comm < 0x1800 else 0x1800
    return f"{'RPDO' if comm < 0x1800 else 'TPDO'}{comm - base + 1} (0x{comm:04X})"
