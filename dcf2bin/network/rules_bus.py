"""D-19's rules about the bus services: PDO CAN-IDs on reserved or service IDs
(NET230/NET231), SYNC (NET240–NET242) and heartbeats (NET250–NET253). See
:mod:`dcf2bin.network.rules` for the table and the naming."""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics, DcfError, Where, shorten
from dcf2bin.network.model import COB_EXTENDED, MASTER, SLAVE, TPDO, Network, Node
from dcf2bin.network.rules import (RESTRICTED, add, cob, existing, key, name, network_where,
                                   where_of)

LSS = ((0x7E4, "LSS (slave to master)"), (0x7E5, "LSS (master to slave)"))


def node_value(node: Node, index: int, sub: int = 0) -> tuple[int | None, Where | None]:
    """A node's value of an integer entry after configuration (its last write, else its
    file's effective value) and the line it comes from; (None, None) when it has none."""
    w = node.settings.get((index, sub))
    if w is not None and isinstance(w.value, int):
        return w.value, w.where
    dev = node.device
    entry = dev.entry(index, sub) if dev is not None else None
    if entry is None or entry.dtype is None or not entry.dtype.is_integer \
            or not entry.has_value or entry.download_file is not None:
        return None, None
    try:
        return dev.effective_int(entry), entry.value_where
    except (DcfError, ValueError, OverflowError):
        return None, None        # the file's own findings say why


def _service_ids(network: Network) -> dict[tuple[int, bool], str]:
    """Every other service's frame in the network -> what it is. A service COB-ID counts
    by its effective value whether its bit 31 is set or not (D-19)."""
    ids: dict[tuple[int, bool], str] = {(0x000, False): "NMT"}
    for value, what in LSS:
        ids[(value, False)] = what

    def put(value: int | None, what: str) -> None:
        if value is not None:
            ext = bool(value & COB_EXTENDED)
            ids.setdefault((value & (0x1FFFFFFF if ext else 0x7FF), ext), what)

    for node in network.nodes:
        n = f"{shorten(node.name)} (node {node.node_id})"
        put(node.sync_cob_id, f"the SYNC of {n}")
        put(node.time_cob_id, f"the TIME of {n}")
        put(node.emcy_cob_id if node.emcy_cob_id is not None else 0x80 + node.node_id,
            f"the EMCY of {n}")
        put(0x580 + node.node_id, f"the SDO response of {n}")
        put(0x600 + node.node_id, f"the SDO request of {n}")
        put(0x700 + node.node_id, f"the heartbeat of {n}")
    return ids


def services(network: Network, out: Diagnostics) -> None:
    """Each frame once: at its first producer, or its first consumer when none produces
    it (a PLC mirror is never the one named: the slave PDO it mirrors is)."""
    ids = _service_ids(network)
    seen: set = set()
    pdos = sorted(existing(network), key=lambda np: (np[1].mirror_of is not None,
                                                      np[1].kind != TPDO))
    for node, pdo in pdos:
        k = key(pdo)
        if k in seen:
            continue
        seen.add(k)
        where = where_of(network, node, pdo)
        if k in ids:
            add(out, "NET231", f"{name(node, pdo)} has COB-ID {cob(pdo)}, the ID of "
                f"{ids[k]}", where)
        elif not k[1] and any(lo <= k[0] <= hi for lo, hi in RESTRICTED):
            add(out, "NET230", f"{name(node, pdo)} has COB-ID {cob(pdo)}, an ID CiA 301 "
                "reserves for other services", where)


def sync(network: Network, out: Diagnostics) -> None:
    producers = [n for n in network.nodes if n.sync_producer]
    if len(producers) > 1:
        add(out, "NET241", "more than one node produces SYNC: " + ", ".join(
            f"{name(n)} every {n.sync_period} µs" for n in producers), network_where(network))
    if not producers:
        for node, pdo in existing(network):
            if pdo.transmission <= 240 and pdo.mirror_of is None:
                add(out, "NET240", f"{name(node, pdo)} is synchronous (transmission type "
                    f"{pdo.transmission}) but no node of the network produces SYNC",
                    where_of(network, node, pdo))
        return
    period = producers[0].sync_period
    for node in network.nodes:
        window, where = _sync_window(network, node)
        if window and period and window >= period:
            add(out, "NET242", f"{name(node)}: the synchronous window of {window} µs is not "
                f"below the SYNC period of {period} µs", where)


def _sync_window(network: Network, node: Node) -> tuple[int | None, Where]:
    if node.role == MASTER and "sync_window" in node.config:
        value = node.config["sync_window"]
        return (value if isinstance(value, int) else None), network_where(network)
    value, where = node_value(node, 0x1007)
    if node.role == MASTER:
        where = network_where(network)
    return value, where or where_of(network, node)


def unread(node: Node) -> bool:
    """A node whose file could not be read: its facts are unknown, and what its file would
    say is not reported again as what it lacks (one cause, one finding)."""
    return node.file is not None and node.device is None


def heartbeats(network: Network, out: Diagnostics) -> None:
    by_id = {n.node_id: n for n in reversed(network.nodes)}
    for node in network.nodes:
        for hb in node.heartbeat_consumers:
            if hb.node_id == 0 or hb.time_ms == 0:
                continue        # CiA 301: an unused entry
            where = hb.where or where_of(network, node)
            them = by_id.get(hb.node_id)
            if them is None:
                add(out, "NET252", f"{name(node)} monitors node {hb.node_id}, which is not in "
                    "the network", where)
            elif unread(them):
                continue
            elif them.heartbeat_producer == 0:
                add(out, "NET251", f"{name(node)} monitors {name(them)}, which produces no "
                    "heartbeat (producer time 0)", where)
            elif hb.time_ms <= them.heartbeat_producer:
                add(out, "NET250", f"{name(node)} expects the heartbeat of {name(them)} within "
                    f"{hb.time_ms} ms, but it is sent every {them.heartbeat_producer} ms",
                    where)
    master = network.master
    if master is None:
        return
    watched = {hb.node_id for hb in master.heartbeat_consumers if hb.time_ms}
    for node in network.nodes:
        if node.role == SLAVE and node.mandatory and node.node_id not in watched \
                and not unread(node):
            add(out, "NET253", f"{name(node)} is mandatory but the master does not monitor "
                "its heartbeat", where_of(network, node))
