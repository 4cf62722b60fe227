"""The bus-load estimate of a configured network (SPEC §10.4, D-20).

``estimate(network)`` gives one :class:`Row` per frame on the bus — each PDO COB-ID, the
SYNC, each heartbeat — counted once, at its producer, and the total in percent of the
bitrate. A frame of n data bytes has 47 + 8n bits with an 11-bit ID (67 + 8n with a 29-bit
one) plus the worst-case stuff bits ⌊(34 + 8n − 1) / 4⌋ (⌊(54 + 8n − 1) / 4⌋). A rate that
cannot be known from the configuration (an event-driven PDO without event timer or inhibit
time, types 241–253) is None: the row is listed in ``unknown`` and counts as 0.

Data only: ``network show`` renders the rows, ``network check`` compares the total with
``--max-load``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin.network.model import COB_EXTENDED, TPDO, Network, Node, Pdo


def frame_bits(n: int, extended: bool = False) -> int:
    """Bits on the bus of one data frame of ``n`` bytes, worst-case stuffing included."""
    if extended:
        return 67 + 8 * n + (54 + 8 * n - 1) // 4
    return 47 + 8 * n + (34 + 8 * n - 1) // 4


@dataclass
class Row:
    """One frame of the network: who sends it, who receives it, how often."""
    can_id: int
    extended: bool
    what: str                          # "TPDO1", "SYNC", "heartbeat"
    producer: Node
    pdo: Pdo | None = None             # the producing TPDO, for a PDO row
    consumers: list[tuple[Node, Pdo | None]] = field(default_factory=list)
    bytes: int = 0                     # data bytes
    rate: float | None = None          # frames per second; None: unknown
    bits: int = 0                      # bits of one frame (frame_bits)
    share: float = 0.0                 # percent of the bus (0 for an unknown rate)

    @property
    def cob_id(self) -> int:
        return self.can_id | (COB_EXTENDED if self.extended else 0)


@dataclass
class Load:
    bitrate: int
    rows: list[Row] = field(default_factory=list)
    sync_rate: float = 0.0             # SYNC frames per second (0: no SYNC producer)

    @property
    def total(self) -> float:
        """The estimated bus load in percent."""
        return sum(r.share for r in self.rows)

    @property
    def unknown(self) -> list[Row]:
        """The rows whose rate is not known (counted as 0 in ``total``)."""
        return [r for r in self.rows if r.rate is None]


def pdo_rate(pdo: Pdo, sync_rate: float) -> float | None:
    """Frames per second a TPDO sends, or None when its configuration does not say."""
    t = pdo.transmission
    if t == 0:
        return sync_rate
    if 1 <= t <= 240:
        return sync_rate / t
    if t in (254, 255):
        if pdo.event_timer:
            return 1000 / pdo.event_timer
        if pdo.inhibit_time:
            return 10000 / pdo.inhibit_time      # the upper bound: ×100 µs
    return None                                  # 241–253, or event-driven without timers


def estimate(network: Network) -> Load:
    """The load of every frame of ``network`` (configured) at ``network.bitrate``."""
    load = Load(network.bitrate)
    seen: set[tuple[int, bool]] = set()
    producers = [n for n in network.nodes if n.sync_producer]
    if producers and producers[0].sync_period:
        load.sync_rate = 1e6 / producers[0].sync_period

    def row(r: Row) -> None:
        k = (r.can_id, r.extended)
        if k in seen:
            return                               # counted once, at its first producer
        seen.add(k)
        r.bits = frame_bits(r.bytes, r.extended)
        if r.rate is not None and network.bitrate > 0:
            r.share = 100.0 * r.rate * r.bits / network.bitrate
        load.rows.append(r)

    for node in producers:
        ext = bool(node.sync_cob_id & COB_EXTENDED)
        can_id = node.sync_cob_id & (0x1FFFFFFF if ext else 0x7FF)
        consumers = [(n, p) for n in network.nodes if n is not node
                     for p in n.pdos if p.exists and not p.broken and p.transmission <= 240]
        row(Row(can_id, ext, "SYNC", node, None, consumers, 1 if node.sync_counter else 0,
                1e6 / node.sync_period if node.sync_period else 0.0))
    consumers: dict[tuple[int, bool], list] = {}
    for node in network.nodes:
        for p in node.pdos:
            if p.exists and not p.broken and p.kind != TPDO:
                consumers.setdefault((p.can_id, bool(p.cob_id & COB_EXTENDED)), []).append(
                    (node, p))
    for node in network.nodes:
        for p in node.pdos:
            if p.exists and not p.broken and p.kind == TPDO:
                k = (p.can_id, bool(p.cob_id & COB_EXTENDED))
                row(Row(k[0], k[1], p.label, node, p, consumers.get(k, []),
                        (p.bits + 7) // 8, pdo_rate(p, load.sync_rate)))
    for node in network.nodes:
        if node.heartbeat_producer > 0:
            watchers = [(n, None) for n in network.nodes
                        if any(h.node_id == node.node_id and h.time_ms
                               for h in n.heartbeat_consumers)]
            row(Row(0x700 + node.node_id, False, "heartbeat", node, None, watchers, 1,
                    1000 / node.heartbeat_producer))
    load.rows.sort(key=lambda r: (r.extended, r.can_id))
    return load
