"""The links (SPEC §10.2, D-17): the PLC mirrors the slaves.

For every slave TPDO that exists, one PLC RPDO with the same COB-ID and transmission type
(event timer 0); for every slave RPDO that exists and whose COB-ID no other node produces,
one PLC TPDO with its COB-ID, its transmission type and the inhibit time / event timer of
its YAML entry. PLC PDO numbers: the lowest free ones (free: the PLC's file does not make
that PDO exist), in order slave node-ID, then PDO number.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics, shorten
from dcf2bin.network.model import COB_EXTENDED, RPDO, TPDO, Network, Node, Pdo
from dcf2bin.network.pdos import comm_index, map_index

MIRROR_BITS = 0x7FFFFFFF        # bit 31 cleared, bits 29-30 copied


def _key(pdo: Pdo) -> tuple[int, bool]:
    return pdo.can_id, bool(pdo.cob_id & COB_EXTENDED)


def make_mirrors(net: Network, diags: Diagnostics) -> list[Pdo]:
    """The PLC's mirror PDOs, added to the master's pdos (inputs first, then outputs)."""
    master = net.master
    slaves = net.slaves
    produced: dict[tuple[int, bool], int] = {}     # COB-ID -> node-ID of a producer
    for node in net.nodes:
        for pdo in node.pdos:
            if pdo.kind == TPDO and pdo.exists:
                produced.setdefault(_key(pdo), node.node_id)
    plc_tpdo = {_key(p) for p in master.pdos if p.kind == TPDO and p.exists}
    pools = {RPDO: _free_numbers(master, RPDO), TPDO: _free_numbers(master, TPDO)}
    mirrors: list[Pdo] = []
    wanted = []
    for node in slaves:
        for pdo in sorted(node.pdos, key=lambda p: p.number):
            if pdo.kind == TPDO and pdo.exists and not pdo.broken:
                wanted.append((node, pdo, RPDO))
    for node in slaves:
        for pdo in sorted(node.pdos, key=lambda p: p.number):
            if pdo.kind != RPDO or not pdo.exists or pdo.broken:
                continue
            owner = produced.get(_key(pdo))
            if owner is not None and owner != master.node_id or _key(pdo) in plc_tpdo:
                continue       # slave-to-slave (or the PLC's own TPDO): not mirrored
            wanted.append((node, pdo, TPDO))
    left: dict[str, list[tuple[Node, Pdo]]] = {RPDO: [], TPDO: []}
    for node, pdo, kind in wanted:
        pool = pools[kind]
        if not pool:
            left[kind].append((node, pdo))
            pdo.unlinked = True
            continue
        number = pool.pop(0)
        m = Pdo(master.node_id, kind, number, pdo.cob_id & MIRROR_BITS,
                transmission=pdo.transmission, mirror_of=pdo, where=pdo.where)
        if kind == TPDO and pdo.config is not None:
            m.inhibit_time = pdo.config.inhibit_time or 0
            m.event_timer = pdo.config.event_timer or 0
        if master.device is not None and not _fits(master, m, pdo, diags):
            pdo.unlinked = True
            continue
        pdo.mirrored_by = m
        mirrors.append(m)
    for kind, links in left.items():
        if links:
            _no_free(master, kind, links, diags)
    # a mirror takes the place of the PLC file's PDO of its number (one that did not
    # exist): master.pdos holds each PDO once, the PLC's own ones first
    taken = {(m.kind, m.number): m for m in mirrors}
    for p in master.pdos:
        m = taken.get((p.kind, p.number))
        if m is not None:
            m.file_cob_id = p.file_cob_id
    master.pdos[:] = [p for p in master.pdos if (p.kind, p.number) not in taken] + mirrors
    return mirrors


def _no_free(master: Node, kind: str, links: list[tuple[Node, Pdo]],
             diags: Diagnostics) -> None:
    """One cause, one finding (issue 27): every link of one kind that finds no free PLC PDO,
    named at the first of them."""
    have = _capacity(master, kind)
    shown = [f"{shorten(node.name)} {pdo.label}" for node, pdo in links[:6]]
    more = len(links) - len(shown)
    what = ", ".join(shown) + (f" and {more} more" if more else "")
    k = kind.upper()
    diags.error(f"the PLC has no free {k} for {what} ({have} {k}s in its file, all in use; "
                f"{len(links)} more link{'s' if len(links) != 1 else ''} than it can take)",
                links[0][1].where, rule="NET108")


def _capacity(master: Node, kind: str) -> int:
    if master.device is None:
        return 512
    return sum(1 for n in range(1, 513) if comm_index(kind, n) in master.device.objects)


def _free_numbers(master: Node, kind: str) -> list[int]:
    if master.device is None:      # a lely master: as many as the links need
        taken = {p.number for p in master.pdos if p.kind == kind}
        return [n for n in range(1, 513) if n not in taken]
    return [p.number for p in sorted(master.pdos, key=lambda p: p.number)
            if p.kind == kind and not p.exists]


def _fits(master: Node, m: Pdo, src: Pdo, diags: Diagnostics) -> bool:
    dev = master.device
    comm = dev.objects.get(comm_index(m.kind, m.number))
    ok = True
    for sub, value, what in ((3, m.inhibit_time, "inhibit time"),
                             (5, m.event_timer, "event timer")):
        if value and sub not in comm.entries:
            diags.error(f"the PLC's 0x{comm.index:04X} has no sub {sub} for the {what} "
                        f"{value} of {src.label} of node {src.node_id}",
                        (src.config.wheres.get("inhibit_time" if sub == 3 else "event_timer")
                         if src.config else None) or src.where, rule="NET108")
            ok = False
    mobj = dev.objects.get(map_index(m.kind, m.number))
    subs = max((s for s in (mobj.entries if mobj else {}) if s), default=0)
    if len(src.mapping) > subs:
        diags.error(f"{src.label} of node {src.node_id} maps {len(src.mapping)} objects; "
                    f"the PLC's 0x{map_index(m.kind, m.number):04X} has {subs} subs",
                    src.where, rule="NET108")
        ok = False
    return ok
