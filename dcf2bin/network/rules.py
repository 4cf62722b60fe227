"""What ``network check`` reports about the network as a whole (SPEC §10.4, D-19).

One small function per rule family reads the configured :class:`~.model.Network` and adds
findings; each rule has its own code NET200…NET299 and the severity D-19 gives it. Every
finding names a line: a PDO its ``where`` (a YAML-listed PDO its PDO-number key line, a PDO
kept from a file its comm sub 1 line, a PLC mirror the line of the slave PDO it mirrors); a
node its key line; a network-wide finding (bus load, SYNC, ``sync_window``) the ``master:``
line.

Nothing here reads files or prints. This module holds the table and what every family
shares (naming, the producer/consumer index) and the node-ID rules; ``rules_pdo`` and
``rules_bus`` the others; :func:`dcf2bin.network.check.run_rules` runs them all.
"""
from __future__ import annotations

from dataclasses import dataclass

from dcf2bin.diagnostics import Diagnostics, Severity, Where, shorten
from dcf2bin.lint.registry import Rule
from dcf2bin.network.model import COB_EXTENDED, TPDO, Network, Node, Pdo

ERROR, WARNING, INFO = Severity.ERROR, Severity.WARNING, Severity.INFO
KIND = "network"


FAMILIES = {"NET05": "network project (.cpj)", "NET0": "network file",
            "NET1": "network configuration", "NET2": "network as a whole"}


@dataclass(frozen=True)
class NetRule(Rule):
    """A rule of ``network check``: validate's Rule, with the network's families."""

    @property
    def family(self) -> str:
        return next((name for prefix, name in FAMILIES.items()
                     if self.id.startswith(prefix)), "network")


def _r(id, name, severity, description, hint=""):
    return NetRule(id, name, severity, description, hint, KIND)


# The rule table of this module, in code order (docs/network.md "What check reports").
RULES: dict[str, Rule] = {r.id: r for r in (
    _r("NET200", "node-id-repeated", ERROR,
       "Two nodes of the network (the master included) have one node-ID.",
       "give every node its own node-ID"),
    _r("NET201", "node-id-range", ERROR,
       "A node-ID is outside 1…127.", "CANopen node-IDs are 1…127"),
    _r("NET210", "cob-id-produced-twice", ERROR,
       "Two TPDOs produce one COB-ID.",
       "give one of them another COB-ID (cob_id: auto picks a free one)"),
    _r("NET211", "rpdo-without-producer", ERROR,
       "An RPDO listens to a COB-ID that no TPDO of the network produces.",
       "set its COB-ID to the producing TPDO's, or disable it"),
    _r("NET212", "tpdo-without-consumer", INFO,
       "A TPDO's COB-ID is consumed by no RPDO of the network.",
       "disable the TPDO if nobody needs it (it only loads the bus)"),
    _r("NET220", "mapping-longer-than-producer", ERROR,
       "An RPDO maps more bits than its producer sends: every PDO would arrive too short "
       "(the consumer signals EMCY 0x8210).",
       "map the same objects, or fewer bits, than the producing TPDO sends"),
    _r("NET221", "mapping-shorter-than-producer", WARNING,
       "An RPDO maps fewer bits than its producer sends; the rest is dropped.",
       "map the whole PDO (a dummy entry skips what is not needed)"),
    _r("NET222", "mapping-field-position", ERROR,
       "A field of an RPDO's mapping does not start and end where one of the producer's "
       "fields does.", "map the same objects in the same order as the producer"),
    _r("NET223", "mapping-field-type", WARNING,
       "An RPDO field has the position of a producer field but another data type.",
       "map objects of the same data type at each position"),
    _r("NET224", "object-written-by-two-rpdos", WARNING,
       "One object is mapped by two RPDOs of one node, its values from different places: "
       "the later frame overwrites the first.",
       "map each object in one RPDO only"),
    _r("NET230", "network-cob-id-restricted", ERROR,
       "A PDO's CAN-ID is one CiA 301 reserves (0x000, 0x001–0x07F, 0x101–0x180, "
       "0x581–0x5FF, 0x601–0x67F, 0x6E0–0x6FF, 0x701–0x77F, 0x780–0x7FF).",
       "choose an ID in 0x181–0x57F or 0x680–0x6DF"),
    _r("NET231", "cob-id-service", ERROR,
       "A PDO's CAN-ID is the ID of another service of a node in the network (NMT, SYNC, "
       "TIME, EMCY, SDO, heartbeat, LSS).",
       "choose an ID that no service of the network uses"),
    _r("NET240", "sync-without-producer", ERROR,
       "A synchronous PDO (transmission type 0–240) on a network without a SYNC producer.",
       "give the master a sync_period, or make the PDO event-driven (254/255)"),
    _r("NET241", "sync-producers", ERROR,
       "More than one node produces SYNC.", "let one node produce SYNC"),
    _r("NET242", "sync-window", ERROR,
       "The synchronous window length is not below the communication cycle period.",
       "make sync_window shorter than sync_period"),
    _r("NET250", "heartbeat-consumer-time", ERROR,
       "A heartbeat consumer time is not above the producer time of the node it monitors.",
       "the consumer time must be longer than the producer time (a multiplier of 1.5–3)"),
    _r("NET251", "heartbeat-producer-zero", ERROR,
       "A node monitors a node that produces no heartbeat (producer time 0).",
       "give the monitored node a heartbeat_producer time"),
    _r("NET252", "heartbeat-unknown-node", WARNING,
       "A heartbeat consumer monitors a node-ID that is not in the network.",
       "remove the consumer entry, or add the node"),
    _r("NET253", "mandatory-not-monitored", WARNING,
       "A mandatory slave is not monitored by the master.",
       "give the slave a heartbeat_producer time, or make it not mandatory"),
    _r("NET260", "bus-load", WARNING,
       "The estimated bus load is above --max-load (default 80 %).",
       "raise the bitrate, lengthen event timers or SYNC periods, or move PDOs"),
)}

# CiA 301: CAN-IDs reserved for NMT, SYNC/EMCY, TIME, SDO, NMT error control, LSS (§8.2)
RESTRICTED = ((0x000, 0x000), (0x001, 0x07F), (0x101, 0x180), (0x581, 0x5FF),
              (0x601, 0x67F), (0x6E0, 0x6FF), (0x701, 0x77F), (0x780, 0x7FF))


# -- naming ----------------------------------------------------------------------------------

def where_of(network: Network, node: Node, pdo: Pdo | None = None) -> Where:
    """The line a finding about ``pdo`` (or ``node``) names (D-19)."""
    if pdo is not None:
        if pdo.where is not None:
            return pdo.where
        if pdo.mirror_of is not None and pdo.mirror_of.where is not None:
            return pdo.mirror_of.where
    return node.where or network_where(network)


def network_where(network: Network) -> Where:
    """Where a network-wide finding goes: the ``master:`` line (a .cpj: its section)."""
    if network.master_where is not None:
        return network.master_where
    master = network.master
    if master is not None and master.where is not None:
        return master.where
    return Where(network.path)


def name(node: Node, pdo: Pdo | None = None) -> str:
    """``drive (node 2) TPDO1``: how findings name a node and its PDO."""
    text = f"{shorten(node.name)} (node {node.node_id})"
    return f"{text} {pdo.label}" if pdo is not None else text


def cob(pdo_or_id) -> str:
    value = pdo_or_id.cob_id if isinstance(pdo_or_id, Pdo) else pdo_or_id
    can_id = value & (0x1FFFFFFF if value & COB_EXTENDED else 0x7FF)
    return f"0x{can_id:08X} (29-bit)" if value & COB_EXTENDED else f"0x{can_id:03X}"


def key(pdo: Pdo) -> tuple[int, bool]:
    """The frame a PDO is: its CAN-ID and frame format (bits 30 and 31 do not count)."""
    return pdo.can_id, bool(pdo.cob_id & COB_EXTENDED)


def existing(network: Network, kind: str | None = None):
    """(node, pdo) for every PDO that exists in the network, nodes in the network's order
    (a PDO whose kept mapping names a zero entry is not counted, D-17)."""
    for node in network.nodes:
        for pdo in node.pdos:
            if pdo.exists and not pdo.broken and (kind is None or pdo.kind == kind):
                yield node, pdo


class Links:
    """Who produces and who consumes each frame: the index every PDO rule reads."""

    def __init__(self, network: Network):
        self.producers: dict[tuple[int, bool], list[tuple[Node, Pdo]]] = {}
        self.consumers: dict[tuple[int, bool], list[tuple[Node, Pdo]]] = {}
        for node, pdo in existing(network):
            table = self.producers if pdo.kind == TPDO else self.consumers
            table.setdefault(key(pdo), []).append((node, pdo))

    def producer_of(self, pdo: Pdo) -> tuple[Node, Pdo] | None:
        """The producer an RPDO is compared with: the slave PDO a PLC mirror mirrors,
        else the first TPDO of its COB-ID."""
        found = self.producers.get(key(pdo)) or []
        if pdo.mirror_of is not None:
            for node, p in found:
                if p is pdo.mirror_of:
                    return node, p
        return found[0] if found else None


# -- the rules -------------------------------------------------------------------------------

def add(out: Diagnostics, code: str, message: str, where: Where) -> None:
    r = RULES[code]
    out.add(r.severity, message, where, rule=code, hint=r.hint)


def node_ids(network: Network, out: Diagnostics) -> None:
    first: dict[int, Node] = {}
    for node in network.nodes:
        where = where_of(network, node)
        if not 1 <= node.node_id <= 127:
            add(out, "NET201", f"{shorten(node.name)}: node-ID {node.node_id} is outside "
                               "1…127", where)
            continue
        other = first.setdefault(node.node_id, node)
        if other is not node:
            add(out, "NET200", f"{shorten(node.name)} has node-ID {node.node_id}, as "
                               f"{shorten(other.name)} at "
                f"{where_of(network, other)} has", where)


__all__ = ["RULES", "Links", "NetRule", "add", "node_ids", "where_of"]
