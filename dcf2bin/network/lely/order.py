"""The order in which dcfgen sees the slaves, and the lely master's PDO numbers (D-21).

dcfgen numbers the master's PDOs in the order it reads the slaves: the flat layout's YAML
order, and for ros2_canopen's ``nodes:`` layout the order its generator (cogen) hands
dcfgen -- it writes the expanded file with PyYAML's ``dump``, which sorts the keys, so the
node names sorted. Within a slave, by PDO number. Master RPDO n mirrors the n-th slave
TPDO that exists, master TPDO n the n-th slave RPDO that the master feeds.
"""
from __future__ import annotations

from dcf2bin.network.model import RPDO, TPDO, Network, Node, Pdo


def dcfgen_order(net: Network) -> list[Node]:
    """The slaves as dcfgen sees them."""
    slaves = net.slaves
    if net.layout == "nodes":
        return sorted(slaves, key=lambda n: n.name)
    return sorted(slaves, key=lambda n: (n.where.line or 0) if n.where else 0)


def renumber(net: Network, mirrors: list[Pdo]) -> None:
    """Number a lely master's mirrors as dcfgen does (``links`` numbered them by
    node-ID); ``mirrors`` and ``master.pdos`` end up in that order too."""
    rank = {id(n): k for k, n in enumerate(dcfgen_order(net))}
    by_id = {n.node_id: n for n in net.slaves}

    def key(m: Pdo):
        src = m.mirror_of
        return rank[id(by_id[src.node_id])], src.number

    ordered = []
    for kind in (RPDO, TPDO):
        mine = sorted((m for m in mirrors if m.kind == kind), key=key)
        for number, m in enumerate(mine, 1):
            m.number = number
        ordered += mine
    mirrors[:] = ordered
    master = net.master
    master.pdos[:] = [p for p in master.pdos if p.mirror_of is None] + ordered
