"""Where a lely master puts the slaves' data (D-21, dcfgen's layout).

Master RPDO n (mirroring a slave TPDO) maps into the record 0x2000+n-1, master TPDO n
(mirroring a slave RPDO) into 0x2200+n-1. Sub i of that record is the i-th object of that
PDO that no earlier PDO of the same slave and direction maps; an object mapped again maps
to the record and sub where it first came. A PDO that brings no new object has no record.
Each sub is named "<slave>: <object name>", has the object's data type and access rww
(received) or rwr (sent), and may be mapped. The remote-PDO records (``dcfgen -r``, read
by ros2_canopen's drivers) name, per master PDO, the slave PDO's number and node-ID
(0x5800/0x5C00+n-1) and the slave's own mapping (0x5A00/0x5E00+n-1).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.network.model import RPDO, Mapped, Network, Node, Pdo

RECEIVED, SENT = 0x2000, 0x2200


@dataclass
class AppSub:
    name: str
    datatype: int


@dataclass
class AppRecord:
    """One record of application objects: index, ParameterName, its subs 1..n."""
    index: int
    title: str
    subs: list[AppSub] = field(default_factory=list)


@dataclass
class MasterPdo:
    """A lely master's PDO: the mirror (number, COB-ID, timing), the slave PDO it mirrors,
    its mapping values (into the application records) and the slave's own."""
    mirror: Pdo
    slave: Node
    mapping: list[int] = field(default_factory=list)

    @property
    def src(self) -> Pdo:
        return self.mirror.mirror_of

    @property
    def remote(self) -> list[int]:
        return [_value(m.index, m.sub, m.bits) for m in self.src.mapping]


@dataclass
class Layout:
    rpdos: list[MasterPdo]
    tpdos: list[MasterPdo]
    records: list[AppRecord]          # by index


def _value(index: int, sub: int, bits: int) -> int:
    return (index << 16) | (sub << 8) | bits


def object_name(slave: Node, m: Mapped) -> str:
    """dcfgen's name of a mapped object: its Denotation, else its ParameterName; a dummy
    entry is named by its data type."""
    if m.is_dummy:
        dtype = dt.BY_CODE.get(m.index)
        return dtype.name if dtype else f"0x{m.index:04X}"
    e = slave.device.entry(m.index, m.sub) if slave.device is not None else None
    if e is None:
        return f"0x{m.index:04X}sub{m.sub:X}"
    return e.denotation or e.name


def layout(net: Network) -> Layout:
    master = net.master
    by_id = {n.node_id: n for n in net.slaves}
    out = Layout([], [], [])
    for kind, base, title in ((RPDO, RECEIVED, "RPDO"), ("tpdo", SENT, "TPDO")):
        seen: dict[tuple[int, int, int], tuple[int, int]] = {}
        rows = out.rpdos if kind == RPDO else out.tpdos
        for m in master.pdos:
            if m.kind != kind or m.mirror_of is None:
                continue
            slave = by_id[m.mirror_of.node_id]
            mp = MasterPdo(m, slave)
            record = AppRecord(base + m.number - 1,
                               f"Mapped application objects for {title} {m.number}")
            for e in m.mirror_of.mapping:
                key = (slave.node_id, e.index, e.sub)
                place = seen.get(key)
                if place is None:
                    record.subs.append(AppSub(f"{slave.name}: {object_name(slave, e)}",
                                              e.datatype or e.index))
                    place = seen[key] = (record.index, len(record.subs))
                mp.mapping.append(_value(place[0], place[1], e.bits))
            rows.append(mp)
            if record.subs:
                out.records.append(record)
    return out


def places(net: Network) -> dict[tuple[int, int, int, str], tuple[int, int]]:
    """(slave node-ID, index, sub, "input"/"output") -> (index, sub) of the master's
    application object that each slave object is mapped to: where ``show`` says a lely
    master keeps each variable (a dummy entry is no variable)."""
    lay = layout(net)
    out: dict[tuple[int, int, int, str], tuple[int, int]] = {}
    for rows, direction in ((lay.rpdos, "input"), (lay.tpdos, "output")):
        for mp in rows:
            for e, value in zip(mp.src.mapping, mp.mapping):
                if not e.is_dummy:
                    out.setdefault((mp.slave.node_id, e.index, e.sub, direction),
                                   (value >> 16, (value >> 8) & 0xFF))
    return out
