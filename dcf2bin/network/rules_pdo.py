"""D-19's PDO rules: who produces and consumes each COB-ID (NET210–NET212), whether a
consumer's mapping fits its producer's (NET220–NET223), and objects written by two RPDOs of
one node (NET224). See :mod:`dcf2bin.network.rules` for the table and the naming."""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import Diagnostics
from dcf2bin.network.model import MASTER, RPDO, TPDO, Network, Pdo
from dcf2bin.network.rules import Links, add, cob, existing, key, name, where_of


def cob_ids(network: Network, links: Links, out: Diagnostics) -> None:
    for producers in links.producers.values():
        (n0, p0), rest = producers[0], producers[1:]
        for node, pdo in rest:
            add(out, "NET210", f"{name(node, pdo)} produces COB-ID {cob(pdo)}, as "
                f"{name(n0, p0)} at {where_of(network, n0, p0)} does",
                where_of(network, node, pdo))
    # (a link the PLC cannot take is NET108's: one cause, one finding)
    for node, pdo in existing(network, RPDO):
        if key(pdo) not in links.producers and not pdo.unlinked:
            add(out, "NET211", f"{name(node, pdo)} listens to COB-ID {cob(pdo)}, which no "
                "TPDO of the network produces", where_of(network, node, pdo))
    for node, pdo in existing(network, TPDO):
        if key(pdo) not in links.consumers and not pdo.unlinked:
            add(out, "NET212", f"{name(node, pdo)} (COB-ID {cob(pdo)}) is consumed by no "
                "RPDO of the network", where_of(network, node, pdo))


def _fields(pdo: Pdo) -> list[tuple[int, int, object]]:
    """(bit offset, length, mapped entry) of every entry of a mapping, dummies included."""
    out, at = [], 0
    for m in pdo.mapping:
        out.append((at, m.bits, m))
        at += m.bits
    return out


def _type_name(code: int | None) -> str:
    t = dt.BY_CODE.get(code) if code is not None else None
    return t.name if t is not None else f"type 0x{code:04X}"


def mappings(network: Network, links: Links, out: Diagnostics) -> None:
    """Each consumer against its producer: length, field positions, field types."""
    for node, pdo in existing(network, RPDO):
        found = links.producer_of(pdo)
        if found is None:
            continue
        pnode, prod = found
        where = where_of(network, node, pdo)
        them = f"{name(pnode, prod)} at {where_of(network, pnode, prod)}"
        if pdo.bits > prod.bits:
            add(out, "NET220", f"{name(node, pdo)} maps {pdo.bits} bits but its producer "
                f"{them} sends {prod.bits}: every PDO would arrive too short "
                "(EMCY 0x8210)", where)
        elif pdo.bits < prod.bits:
            add(out, "NET221", f"{name(node, pdo)} maps {pdo.bits} bits of the "
                f"{prod.bits} its producer {them} sends", where)
        sent = {(at, bits): m for at, bits, m in _fields(prod)}
        moved = typed = None
        for at, bits, m in _fields(pdo):
            if m.is_dummy or at + bits > prod.bits:
                continue        # a dummy skips bits; past the end is NET220's
            p = sent.get((at, bits))
            if p is None:
                moved = moved or (at, bits, m)
            elif (typed is None and not p.is_dummy and m.datatype is not None
                  and p.datatype is not None and m.datatype != p.datatype):
                typed = (at, bits, m, p)
        if moved is not None:
            at, bits, m = moved
            add(out, "NET222", f"{name(node, pdo)} maps 0x{m.index:04X}sub{m.sub:X} at bits "
                f"{at}…{at + bits - 1}, where its producer {them} has no field of "
                f"{bits} bits", where)
        if typed is not None:
            at, bits, m, p = typed
            add(out, "NET223", f"{name(node, pdo)} maps 0x{m.index:04X}sub{m.sub:X} "
                f"({_type_name(m.datatype)}) at bits {at}…{at + bits - 1}, where its "
                f"producer {them} sends 0x{p.index:04X}sub{p.sub:X} "
                f"({_type_name(p.datatype)})", where)


def _sources(links: Links, pdo: Pdo) -> dict[tuple, tuple]:
    """Each object an RPDO writes -> (where its value comes from: the producer's node and
    the object it sends at the same bits, None when there is no producer or no field
    there; the object as findings name it). A PLC mirror's entry is its variable (the
    slave object it stands for, whether it is placed yet or not: a PLC that could not
    place its variables still maps the slaves' objects, of different slaves alike)."""
    found = links.producer_of(pdo)
    sent = {}
    if found is not None:
        pnode, prod = found
        sent = {(at, bits): (pnode.node_id, m.index, m.sub) for at, bits, m in _fields(prod)}
    out = {}
    for at, bits, m in _fields(pdo):
        if m.is_dummy:
            continue
        obj = ("var", m.name.casefold()) if pdo.mirror_of is not None and m.name \
            else (m.index, m.sub)
        out[obj] = (sent.get((at, bits)), (m.index, m.sub))
    return out


def written_twice(network: Network, links: Links, out: Diagnostics) -> None:
    """NET224: one object written by two RPDOs of a node with values from different
    places. The same value twice is no conflict: a PLC variable that D-17 maps in the
    mirrors of two PDOs of one slave object, or a slave object fed by two PLC PDOs that
    send one variable."""
    for node in network.nodes:
        if node.role == MASTER and node.device is None:
            continue     # a master without dcf: its mirrors name the slaves' own objects
        first: dict[tuple[int, int], tuple[Pdo, tuple | None]] = {}
        for pdo in node.pdos:
            if not pdo.exists or pdo.broken or pdo.kind != RPDO:
                continue
            for obj, (source, (index, sub)) in _sources(links, pdo).items():
                other, was = first.setdefault(obj, (pdo, source))
                if other is pdo or (source is not None and source == was):
                    continue
                add(out, "NET224", f"{name(node, pdo)} maps 0x{index:04X}sub{sub:X}, "
                    f"as {other.label} at {where_of(network, node, other)} does: the "
                    "later frame overwrites it", where_of(network, node, pdo))
