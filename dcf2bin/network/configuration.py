"""Configure a network in memory (SPEC §10.2 D-17, §10.3 D-18): every command's first step.

In order: each node's file is read; its PDOs are taken from it and changed by the YAML;
COB-IDs are assigned; each slave's write list is made; the PLC mirrors the links, its
variables are named and placed (with a master ``dcf:``); the PLC's PDO and NMT entries
follow, and 0x1F22 takes each slave's concise DCF when the PLC's file has it. Then every
node's heartbeat, SYNC and EMCY facts are filled in for the rules.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics
from dcf2bin.network import cobids, links, nmt, pdos, slaveconfig, variables
from dcf2bin.network.model import TPDO, Heartbeat, Network, Node
from dcf2bin.network.pdos import comm_index, entry_int, map_index


def configure(net: Network) -> Network:
    """Apply D-17/D-18 to ``net`` in place; findings go to ``net.diagnostics``."""
    if net.configured:
        return net
    net.configured = True
    diags = net.diagnostics
    if len(net.nodes) > 127:     # more nodes than node-IDs (NET200 names the repeats); not
        diags.error(f"{len(net.nodes)} nodes, but a CANopen network has 127 node-IDs: not "
                    "configured", net.master_where, rule="NET004")
        return net               # configured: 10,000 fuzzed slaves took half a minute
    _read_files(net, diags)
    nodes = [n for n in net.nodes if n.device is not None]
    shared: dict = {}
    for node in nodes:
        pdos.from_file(node, shared)
    for node in net.slaves:
        if node.device is not None:
            pdos.apply_yaml(node, diags)
    cobids.assign(net, diags)
    for node in net.slaves:
        if node.device is not None:
            pdos.check_kept(node, diags)
    master = net.master
    if master is None:
        return net
    master.heartbeat_producer = master.config.get("heartbeat_producer", 0)
    if "heartbeat_producer" not in master.config and master.device is not None:
        master.heartbeat_producer = entry_int(master.device, 0x1017, 0, 0) or 0
    for node in net.slaves:
        if node.device is not None:
            slaveconfig.configure_slave(net, node, diags)
        _node_facts(node)
    mirrors = links.make_mirrors(net, diags)
    if master.device is None:          # a lely master (D-21): numbered as dcfgen does
        from dcf2bin.network.lely import order
        order.renumber(net, mirrors)
    variables.make_variables(net, mirrors, diags)
    if master.device is not None and not _errors_before_placing(diags):
        variables.place(net, diags)
    plc = nmt.PlcWriter(master, diags)
    _plc_pdos(mirrors, plc)
    nmt.nmt_entries(net, plc, diags)
    if master.device is None:          # the identity a lely master checks (D-21)
        from dcf2bin.network.lely import identity
        identity.apply(net)
    if master.device is not None and 0x1F22 in master.device.objects:
        from dcf2bin.network.concise import concise_dcf
        for s in net.slaves:
            if s.device is not None:
                plc.put(0x1F22, s.node_id, concise_dcf(s), f"{s.name}'s concise DCF", s.where)
    _master_facts(master)
    return net


def _errors_before_placing(diags: Diagnostics) -> bool:
    """Placement is skipped when a variable is wrong (its name or type): allocate would
    report the same objects again."""
    return any(d.rule in ("NET104", "NET106", "NET107") for d in diags.errors)


def _read_files(net: Network, diags: Diagnostics) -> None:
    """Each node's file, read and modelled once per file: the nodes that share a file
    get copies of its Device that differ in the node-ID ($NODEID values) only."""
    import copy

    from dcf2bin import formats
    parsed: dict[str, object] = {}
    built: dict[str, object] = {}
    for node in net.nodes:
        if node.file is None:
            continue
        where = node.config_where.get("dcf", node.where)
        path = node.file
        if path not in parsed:
            parsed[path] = _parse(net, path, where, diags)
        if parsed[path] is None or parsed[path].rejected or not parsed[path].sections:
            continue     # (not a description, no section: its findings say so, and
            #              nothing is configured from it -- the node has no device)
        base = built.get(path)
        if base is None:
            base = built[path] = formats.build(parsed[path], node_id=node.node_id)
            node.device = base
            continue
        dev = copy.copy(base)
        dev.node_id, dev.node_id_from_cli = node.node_id, True
        dev.encoded, dev._warned, dev._verdicts = {}, set(), {}
        dev.problems = list(base.problems)
        node.device = dev


def _parse(net: Network, path: str, where, diags: Diagnostics):
    """A node's file read as every network command reads it (issue 26): through the one
    bounded reader (never a FIFO or /dev/zero), then its kind by content as every command
    tells it (a container or its JSON form is refused: NET011), then the reader of its
    format (issue 28: CiA 306 text or CiA 311 XML, ``dcf2bin.formats``). The syntax and
    model findings are the node file's findings, at its own lines (``check``); None when
    the file cannot be read or is of another kind."""
    from dcf2bin import formats
    from dcf2bin.network.files import read_node_file, wrong_kind
    try:
        data = read_node_file(path)
    except OSError as exc:
        diags.error(f"cannot read {path}: {exc.strerror or exc}", where, rule="NET010")
        return None
    wrong = wrong_kind(path, data)
    if wrong is not None:
        diags.error(wrong, where, rule="NET011")
        return None
    net.files[path] = data
    return formats.read(data, path)


def _plc_pdos(mirrors, plc: nmt.PlcWriter) -> None:
    dev = plc.master.device
    for m in mirrors:
        comm, mi = comm_index(m.kind, m.number), map_index(m.kind, m.number)
        src = m.mirror_of
        what = f"{m.label} mirrors {src.label} of node {src.node_id}"
        plc.put(comm, 1, m.cob_id, f"{what}: COB-ID", m.where)
        plc.put(comm, 2, m.transmission, f"{what}: transmission type", m.where)
        if m.kind == TPDO:
            for sub, value, name in ((3, m.inhibit_time, "inhibit time"),
                                     (5, m.event_timer, "event timer")):
                if value or dev is None or sub in dev.objects[comm].entries:
                    plc.put(comm, sub, value, f"{what}: {name}", m.where)
        elif dev is None or 5 in dev.objects[comm].entries:
            plc.put(comm, 5, 0, f"{what}: event timer", m.where)
        for k, e in enumerate(m.mapping, 1):
            plc.put(mi, k, (e.index << 16) | (e.sub << 8) | e.bits,
                    f"{what}: maps 0x{e.index:04X}sub{e.sub:X}", e.where or m.where)
        plc.put(mi, 0, len(m.mapping), f"{what}: {len(m.mapping)} objects", m.where)


def _value(node: Node, index: int, sub: int, default: int | None = None) -> int | None:
    w = node.settings.get((index, sub))
    if w is not None and isinstance(w.value, int):
        return w.value
    if node.device is None:
        return default
    return entry_int(node.device, index, sub, default)


def _node_facts(node: Node) -> None:
    """Heartbeat, SYNC, EMCY and TIME after configuration (the last write, else the
    file)."""
    if node.device is None:
        return
    node.heartbeat_producer = _value(node, 0x1017, 0, 0) or 0
    obj = node.device.objects.get(0x1016)
    node.heartbeat_consumers = []
    for sub in sorted(s for s in (obj.entries if obj else {}) if s):
        v = _value(node, 0x1016, sub, 0) or 0
        if (v >> 16) & 0xFF and v & 0xFFFF:
            w = node.settings.get((0x1016, sub))
            where = w.where if w is not None else pdos.entry_where(node.device, 0x1016, sub)
            node.heartbeat_consumers.append(Heartbeat((v >> 16) & 0xFF, v & 0xFFFF, where))
    _sync_emcy(node)


def _sync_emcy(node: Node) -> None:
    sync = _value(node, 0x1005, 0, 0x80)
    node.sync_cob_id = (sync if sync is not None else 0x80) & 0x7FF
    node.sync_period = _value(node, 0x1006, 0, 0) or 0
    node.sync_producer = bool((sync or 0) & 0x40000000) and node.sync_period != 0
    node.sync_counter = _value(node, 0x1019, 0, 0) or 0
    emcy = _value(node, 0x1014, 0, None)
    node.emcy_cob_id = emcy if emcy is not None else 0x80 + node.node_id
    node.time_cob_id = _value(node, 0x1012, 0, None)


def _master_facts(master: Node) -> None:
    if master.device is not None:
        master.heartbeat_producer = _value(master, 0x1017, 0, 0) or 0
        _sync_emcy(master)
        return
    cfg = master.config
    master.heartbeat_producer = cfg.get("heartbeat_producer", 0)
    master.sync_period = cfg.get("sync_period", 0)
    master.sync_producer = bool(master.sync_period)
    master.sync_cob_id = 0x80
    master.emcy_cob_id = 0x80 + master.node_id
    master.sync_counter = cfg.get("sync_overflow", 0)       # a lely master's 0x1019 and
    master.time_cob_id = cfg.get("time_cob_id", 0x100)      # 0x1012 (D-21, as dcfgen)


PLC, LELY = "plc", "lely"


def master_kind(net: Network, kind: str | None) -> str:
    """PLC or LELY: ``kind`` when given, else PLC for a master with ``dcf:``. A lely
    master built from a file whose master has ``dcf:`` does not read it (an info)."""
    master = net.master
    if kind is None:
        return PLC if master is not None and master.file is not None else LELY
    if kind == LELY and master is not None and master.file is not None:
        net.diagnostics.info("the master's dcf: is not read: a lely master is built",
                             master.config_where.get("dcf", master.where), rule="NET007")
        master.file = None
    if kind == PLC and master is not None and master.file is None:
        # said here, so that check and show say what build says (one verdict)
        net.diagnostics.error("build needs the PLC's EDS or DCF: give it as 'dcf:' under "
                              "'master:'", master.where, rule="NET119")
    return kind
