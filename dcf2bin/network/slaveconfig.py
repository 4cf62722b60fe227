"""A slave's configuration (SPEC §10.3, D-18): the ordered writes of its concise DCF.

For each configured PDO, RPDOs then TPDOs by number: comm sub 1 = COB-ID | 0x80000000;
the subs the YAML gives; only with ``mapping:``, mapping sub 0 = 0, subs 1..n, sub 0 = n;
last comm sub 1 = COB-ID (left invalid for ``enabled: false``). Then guard_time (0x100C),
life_time_factor (0x100D), heartbeat_producer (0x1017), the heartbeat consumer entry for
the master (0x1016) -- or, for a slave that does not monitor the master, its file's 0x1016
entries that do, cleared as lely's dcfgen clears them --, time_cob_id (0x1012),
error_behavior (0x1029, its subs in the YAML's order), and the ``sdo`` list in order.
"""
from __future__ import annotations

import math

from dcf2bin.diagnostics import Diagnostics, shorten
from dcf2bin.network.entries import sdo_write, write_to
from dcf2bin.network.model import COB_INVALID, RPDO, TPDO, Network, Node
from dcf2bin.network.pdos import comm_index, entry_int, map_index

_TPDO_SUBS = (("transmission", 2, "transmission type"), ("inhibit_time", 3, "inhibit time"),
              ("event_timer", 5, "event timer"), ("sync_start", 6, "SYNC start value"))
_RPDO_SUBS = (("transmission", 2, "transmission type"), ("event_deadline", 5,
                                                         "event deadline"))


def multiplier(net: Network, node: Node) -> float:
    own = node.config.get("heartbeat_multiplier")
    return own if own is not None else net.options.get("heartbeat_multiplier", 3.0)


def times(ms: int, factor: float) -> int:
    """A time multiplied by a heartbeat multiplier, rounded down to whole ms (D-16): the
    product of the decimal the YAML states, not of its binary float (100 x 0.29 = 29)."""
    from decimal import Decimal
    return math.floor(ms * Decimal(repr(float(factor))))


def configure_slave(net: Network, node: Node, diags: Diagnostics) -> None:
    dev = node.device
    out = node.writes

    def put(index, sub, value, why, where):
        w = write_to(dev, index, sub, value, why, where, diags, rule="NET114", slave=True,
                     who=node.name)
        if w is not None:
            out.append(w)

    listed = sorted((p for p in node.pdos if p.listed),
                    key=lambda p: (p.kind != RPDO, p.number))
    for pdo in listed:
        pc = pdo.config
        comm = comm_index(pdo.kind, pdo.number)
        label = pdo.label
        put(comm, 1, pdo.cob_id | COB_INVALID, f"{label} COB-ID (invalid while configuring)",
            pc.wheres.get("cob_id", pc.where))
        if pc.enabled is False and set(pc.wheres) <= {"enabled"}:
            continue
        for key, sub, what in (_TPDO_SUBS if pdo.kind == TPDO else _RPDO_SUBS):
            value = getattr(pc, key)
            if value is not None:
                put(comm, sub, value, f"{label} {what}", pc.wheres.get(key, pc.where))
        if pc.mapping is not None:
            mi = map_index(pdo.kind, pdo.number)
            mwhere = pc.wheres.get("mapping", pc.where)
            put(mi, 0, 0, f"{label} mapping off while configuring", mwhere)
            for k, m in enumerate(pdo.mapping, 1):
                put(mi, k, (m.index << 16) | (m.sub << 8) | m.bits,
                    f"{label} maps 0x{m.index:04X}sub{m.sub:X} ({m.bits} bits)", m.where)
            put(mi, 0, len(pdo.mapping), f"{label} maps {len(pdo.mapping)} objects", mwhere)
        if pc.enabled is not False:
            put(comm, 1, pdo.cob_id, f"{label} COB-ID", pc.wheres.get("cob_id", pc.where))
    cw = node.config_where
    for key, index, what in (("guard_time", 0x100C, "guard time"),
                             ("life_time_factor", 0x100D, "life time factor"),
                             ("heartbeat_producer", 0x1017, "producer heartbeat time")):
        if key in node.config:
            put(index, 0, node.config[key], what, cw.get(key))
    if not (node.config.get("heartbeat_consumer") and _consumer(net, node, put, diags)):
        _stop_watching(net, node, put)
    if "time_cob_id" in node.config:
        put(0x1012, 0, node.config["time_cob_id"], "COB-ID TIME", cw.get("time_cob_id"))
    for sub, (value, where) in node.config.get("error_behavior", {}).items():
        put(0x1029, sub, value, f"error behaviour of class {sub}", where)
    _restore_entry(node, diags)
    for item in node.sdo_config:
        w = sdo_write(dev, item.index, item.sub, item.value, item.where, node.name, diags)
        if w is not None:
            out.append(w)
    for w in out:
        node.settings[(w.index, w.sub)] = w


def _restore_entry(node: Node, diags: Diagnostics) -> None:
    """``restore_configuration: n`` has the master write "load" to the slave's 0x1011
    sub n (CiA 302's restore before configuring): that entry must exist and be
    writable."""
    n = node.config.get("restore_configuration", 0)
    if not n:
        return
    e = node.device.entry(0x1011, n)
    where = node.config_where.get("restore_configuration")
    if e is None:
        diags.error(f"{shorten(node.name)}'s file has no 0x1011sub{n:X}, where the master is to "
                    "restore "
                    "its defaults (restore_configuration)", where, rule="NET114")
    elif e.access in ("ro", "const"):
        diags.error(f"0x1011sub{n:X} of {shorten(node.name)} is {e.access}: the master cannot "
                    "restore "
                    "its defaults there (restore_configuration)", where, rule="NET114")


def _stop_watching(net: Network, node: Node, put) -> None:
    """A slave that does not monitor the master (``heartbeat_consumer`` false, the
    default, or a master without heartbeat) keeps no 0x1016 entry of its file that
    watches the master: a slave monitoring a master that sends no heartbeat, or that the
    network does not mean it to monitor, faults. As lely's dcfgen does it: each sub whose
    value names the master's node-ID with a nonzero time is written as that node-ID with
    time 0 (unused, CiA 301)."""
    master = net.master
    dev = node.device
    obj = dev.objects.get(0x1016) if master is not None else None
    if obj is None:
        return
    why = ("heartbeat_consumer is false" if not node.config.get("heartbeat_consumer")
           else "the master produces no heartbeat")
    where = node.config_where.get("heartbeat_consumer", node.where)
    for s in sorted(x for x in obj.entries if x):
        value = entry_int(dev, 0x1016, s, 0) or 0
        if (value >> 16) & 0xFF == master.node_id and value & 0xFFFF:
            put(0x1016, s, master.node_id << 16,
                f"consumer heartbeat time: stops monitoring the master (node "
                f"{master.node_id}; {why})", where)


def _consumer(net: Network, node: Node, put, diags: Diagnostics) -> bool:
    """The slave's 0x1016 entry that monitors the master; False when the master produces
    no heartbeat (then the slave does not monitor it)."""
    master = net.master
    where = node.config_where.get("heartbeat_consumer")
    if master is None:
        return True
    if not master.heartbeat_producer or not times(master.heartbeat_producer,
                                                 multiplier(net, master)):
        diags.warning(f"{shorten(node.name)} is to monitor the master, but the master produces no "
                      "heartbeat (heartbeat_producer 0): nothing written", where,
                      rule="NET116")
        return False
    dev = node.device
    obj = dev.objects.get(0x1016)
    subs = sorted(s for s in (obj.entries if obj else {}) if s)
    chosen = None
    for s in subs:
        if (entry_int(dev, 0x1016, s, 0) >> 16) & 0xFF == master.node_id:
            chosen = s
            break
    if chosen is None:
        chosen = next((s for s in subs if entry_int(dev, 0x1016, s, 0) == 0), None)
    if chosen is None:
        diags.error(f"{shorten(node.name)} has no free 0x1016 sub for monitoring the master "
                    f"({len(subs)} subs, all in use)" if obj else
                    f"{shorten(node.name)}'s file has no 0x1016 (consumer heartbeat time)", where,
                    rule="NET115")
        return True
    t = times(master.heartbeat_producer, multiplier(net, master))
    if t > 0xFFFF:
        diags.error(f"the master's heartbeat time {master.heartbeat_producer} ms x "
                    f"{multiplier(net, master):g} = {t} ms is over 65535 ms", where,
                    rule="NET112")
        return True
    put(0x1016, chosen, (master.node_id << 16) | t,
        f"consumer heartbeat time: monitors the master (node {master.node_id}, {t} ms)", where)
    return True
