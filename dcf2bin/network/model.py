"""The configured network (SPEC §10.1, D-16…D-20): the one neutral model that `network
build`, `check`, `show`, `download` and `scan` share.

A reader (``yamlfile`` for lely/ros2_canopen ``bus.yml``, ``cpj`` for CiA 306-3 nodelist
projects) turns a network file into a :class:`Network` of :class:`Node`s; ``configure``
then applies D-17/D-18 in memory, filling every node's PDOs, the PLC's variables, the
slaves' write lists and the identities the master enforces. Everything after that (the
rules, the load estimate, the outputs, the bus) reads this model only.

Every element carries a :class:`~dcf2bin.diagnostics.Where`, so every finding names a line:
a YAML-listed PDO its PDO-number key line; a PDO kept from a file its comm sub 1 line in
that file; a PLC mirror the line of the slave PDO it mirrors; a node its key line.

This module holds data only: no reading, no rules, no output, no click.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from dcf2bin.diagnostics import Diagnostics, Where

MASTER, SLAVE = "master", "slave"
TPDO, RPDO = "tpdo", "rpdo"

COB_INVALID = 0x80000000      # CiA 301 COB-ID bit 31: the PDO does not exist
COB_NO_RTR = 0x40000000       # bit 30
COB_EXTENDED = 0x20000000     # bit 29: 29-bit CAN-ID


@dataclass
class Mapped:
    """One entry of a PDO mapping: the object, its length in bits (its data type's size;
    BOOLEAN 1) and, for a slave PDO linked to the PLC, the PLC variable it becomes."""
    index: int
    sub: int
    bits: int
    datatype: int | None = None       # CiA 301 data type code; None for an unknown object
    name: str | None = None           # the YAML `name:` (D-17), or None
    where: Where | None = None

    @property
    def is_dummy(self) -> bool:
        return 0x0001 <= self.index <= 0x0007


@dataclass
class Pdo:
    """One PDO of one node after configuration. ``cob_id`` is the effective 32-bit value."""
    node_id: int
    kind: str                          # TPDO or RPDO
    number: int                        # 1…512
    cob_id: int
    transmission: int = 255
    inhibit_time: int = 0              # ×100 µs
    event_timer: int = 0               # ms (RPDO: event deadline)
    sync_start: int = 0
    mapping: list[Mapped] = field(default_factory=list)
    listed: bool = False               # given in the YAML
    mirror_of: "Pdo | None" = None     # for a PLC PDO: the slave PDO it mirrors
    where: Where | None = None
    # added by configure (the names above are shared, never renamed)
    config: "PdoConfig | None" = None  # the YAML entry, when listed
    file_cob_id: int | None = None     # comm sub 1 as the node's file gives it
    broken: bool = False               # a kept mapping naming a zero entry: not linked
    mirrored_by: "Pdo | None" = None   # for a slave PDO: the PLC PDO that mirrors it
    unlinked: bool = False             # a link the PLC cannot take (NET108 says why): the
                                       # rules do not report it again as unconsumed

    @property
    def can_id(self) -> int:
        return self.cob_id & (0x1FFFFFFF if self.cob_id & COB_EXTENDED else 0x7FF)

    @property
    def exists(self) -> bool:
        """In the network: COB-ID bit 31 clear and at least one mapped entry (§10.1)."""
        return not self.cob_id & COB_INVALID and len(self.mapping) >= 1

    @property
    def bits(self) -> int:
        return sum(m.bits for m in self.mapping)

    @property
    def label(self) -> str:
        return f"{self.kind.upper()}{self.number}"


@dataclass
class Write:
    """One SDO write of a node's configuration (D-18 for a slave, the PLC's NMT and PDO
    entries for the master), in the order it is written."""
    index: int
    sub: int
    datatype: int
    value: Any                         # the decoded value (int, float, str, bytes)
    data: bytes                        # as sent by SDO / stored in the concise DCF
    name: str = ""                     # the object's ParameterName
    why: str = ""                      # "TPDO1 COB-ID (invalid while configuring)", ...
    where: Where | None = None


@dataclass
class Variable:
    """A PLC network variable made from a slave object mapped in a linked PDO (D-17)."""
    name: str
    direction: str                     # "input" (from a slave TPDO) or "output"
    datatype: int
    node_id: int                       # the slave
    index: int
    sub: int
    pi_index: int | None = None        # the PLC object (0xA000…) and sub it is placed at
    pi_sub: int | None = None
    pi_offset: int | None = None       # byte offset in its process-image area
    where: Where | None = None


@dataclass
class Heartbeat:
    """A consumer entry: this node monitors ``node_id`` with ``time_ms``."""
    node_id: int
    time_ms: int
    where: Where | None = None


@dataclass
class MapConfig:
    """One `mapping:` item of a YAML PDO: the object and the PLC variable name it becomes."""
    index: int
    sub: int
    name: str | None = None
    where: Where | None = None          # the item's line
    name_where: Where | None = None     # the `name:` line


@dataclass
class PdoConfig:
    """A PDO as the YAML lists it (D-16); a key not given is None."""
    kind: str
    number: int
    where: Where | None = None          # the PDO-number key line
    enabled: bool | None = None
    cob_id: int | str | None = None     # "auto" or an integer
    transmission: int | None = None
    inhibit_time: int | None = None
    event_timer: int | None = None
    event_deadline: int | None = None
    sync_start: int | None = None
    mapping: list[MapConfig] | None = None
    wheres: dict[str, Where] = field(default_factory=dict)   # key -> its line
    empty_mapping: bool = False         # `mapping:` given as null or [] (NET121)


@dataclass
class SdoConfig:
    """One item of a slave's `sdo:` list, in order."""
    index: int
    sub: int
    value: Any
    where: Where | None = None


@dataclass
class Node:
    name: str
    node_id: int
    role: str                          # MASTER or SLAVE
    file: str | None = None            # its EDS/DCF (None: a lely master without `dcf:`)
    device: Any = None                 # dcf2bin.model.Device of ``file``, when read
    where: Where | None = None         # its key line in the network file
    pdos: list[Pdo] = field(default_factory=list)
    heartbeat_producer: int = 0        # ms, 0x1017 after configuration
    heartbeat_consumers: list[Heartbeat] = field(default_factory=list)
    sync_producer: bool = False        # 0x1005 bit 30 and 0x1006 != 0 after configuration
    sync_period: int = 0               # µs (0x1006)
    sync_cob_id: int = 0x80            # 0x1005 CAN-ID
    sync_counter: int = 0              # 0x1019
    emcy_cob_id: int | None = None     # 0x1014 effective (default 0x80 + node-ID)
    time_cob_id: int | None = None     # 0x1012 effective, when the node has it
    mandatory: bool = False
    identity: dict[int, int] = field(default_factory=dict)   # slave: 0x1F84…0x1F88 → value
    writes: list[Write] = field(default_factory=list)         # slave: D-18 list
    config: dict[str, Any] = field(default_factory=dict)      # the YAML keys as read
    # added by the YAML reader and configure (the names above are shared, never renamed)
    config_where: dict[str, Where] = field(default_factory=dict)   # YAML key -> its line
    pdo_config: dict[tuple[str, int], PdoConfig] = field(default_factory=dict)
    sdo_config: list[SdoConfig] = field(default_factory=list)
    names: dict[tuple[int, int], tuple[str, Where]] = field(default_factory=dict)
    # the slave's `names:` (D-17): (index, sub) -> the variable name and its line
    settings: dict[tuple[int, int], Write] = field(default_factory=dict)
    # the configured value of each (index, sub) this node's output DCF states as a
    # ParameterValue (slave: the last write of each entry; master: its PDOs, NMT entries)

    def pdo(self, kind: str, number: int) -> Pdo | None:
        return next((p for p in self.pdos if p.kind == kind and p.number == number), None)


@dataclass
class Network:
    """A network file, read (and, after ``configure``, configured)."""
    path: str
    kind: str = "yaml"                 # "yaml" or "cpj"
    nodes: list[Node] = field(default_factory=list)          # node-ID order after configure
    options: dict[str, Any] = field(default_factory=dict)    # heartbeat_multiplier, …
    options_where: dict[str, Where] = field(default_factory=dict)  # option -> its line
    bitrate: int = 500_000             # bit/s, for the load estimate (D-20)
    variables: list[Variable] = field(default_factory=list)
    diagnostics: Diagnostics = field(default_factory=Diagnostics)
    master_where: Where | None = None  # the `master:` line: network-wide findings go there
    layout: str = "flat"               # "flat" (lely) or "nodes" (ros2_canopen)
    configured: bool = False
    plc_plan: Any = None               # the variables allocate --into adds to the PLC's
                                       # file (dcf2bin.plc.merge.Plan; D-15)
    files: dict[str, bytes] = field(default_factory=dict, repr=False)  # path -> bytes read
    # path -> (CiA 306 text, its INI reading, the sections it was written from) of a node
    # file in another format (CiA 311 XML): what its configured DCF is made of (files.cia306)
    texts: dict[str, tuple] = field(default_factory=dict, repr=False)

    @property
    def master(self) -> Node | None:
        return next((n for n in self.nodes if n.role == MASTER), None)

    @property
    def slaves(self) -> list[Node]:
        return [n for n in self.nodes if n.role == SLAVE]

    def node(self, node_id: int) -> Node | None:
        return next((n for n in self.nodes if n.node_id == node_id), None)
