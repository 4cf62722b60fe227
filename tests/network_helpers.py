"""Configured networks built by hand from dcf2bin.network.model (no reader involved), for
the tests of `network show`, its picture, `download` and `scan`."""
from __future__ import annotations

from dcf2bin.diagnostics import Where
from dcf2bin.network.model import (MASTER, RPDO, SLAVE, TPDO, Mapped, Network, Node, Pdo,
                                   Variable, Write)

U8, U16, I32 = 0x05, 0x06, 0x04
BITS = {U8: 8, U16: 16, I32: 32}


def _mirror(plc: Node, kind: str, number: int, p: Pdo) -> Pdo:
    m = Pdo(plc.node_id, kind, number, p.cob_id, p.transmission, p.inhibit_time,
            p.event_timer, mapping=[Mapped(0xA040, k + 1, e.bits, e.datatype)
                                    for k, e in enumerate(p.mapping)], mirror_of=p,
            where=p.where)
    plc.pdos.append(m)
    return m


def network(slaves: int = 2, tpdos: int = 1, rpdos: int = 1, *, plc_id: int = 16,
            path: str = "bus.yml", slave_link: bool = True) -> Network:
    """A PLC (node ``plc_id``) and ``slaves`` slaves io1, io2, … (node-IDs 2, 3, … without
    ``plc_id``), each with ``tpdos`` TPDOs to the PLC and ``rpdos`` RPDOs from it (event
    timer 10 ms ×PDO number), the PLC mirroring them; with ``slave_link``, io2's RPDO 4
    also listens to io1's TPDO1 (a slave-to-slave link)."""
    net = Network(path)
    plc = Node("plc", plc_id, MASTER, where=Where(path, 1))
    net.nodes.append(plc)
    ids = [i for i in range(2, 128) if i != plc_id][:slaves]
    in_no = out_no = 0
    for k, nid in enumerate(ids):
        name = f"io{k + 1}"
        node = Node(name, nid, SLAVE, where=Where(path, 10 + 20 * k))
        node.identity = {0x1F84: 0x000F0191, 0x1F85: 0xAB, 0x1F86: 0x100 + k}
        for n in range(1, tpdos + 1):
            cob = 0x180 + 0x100 * (n - 1) + nid if n <= 4 else 0x680 + 8 * nid + n
            objs = [(0x6000, n, U8), (0x6401, n, U16)]
            p = Pdo(nid, TPDO, n, cob, 255, 0, 10 * n, listed=True,
                    where=Where(path, node.where.line + n),
                    mapping=[Mapped(i, s, BITS[t], t, f"{name}_{i:04X}_{s:X}") for i, s, t in objs])
            node.pdos.append(p)
            in_no += 1
            _mirror(plc, RPDO, in_no, p)
            for i, s, t in objs:
                net.variables.append(Variable(f"{name}_{i:04X}_{s:X}", "input", t, nid, i, s,
                                              0xA040, len(net.variables) + 1,
                                              len(net.variables)))
        for n in range(1, rpdos + 1):
            cob = 0x200 + 0x100 * (n - 1) + nid if n <= 4 else 0x6C0 + nid
            objs = [(0x6200, n, U8)]
            p = Pdo(nid, RPDO, n, cob, 255, 0, 0, listed=True,
                    where=Where(path, node.where.line + 10 + n),
                    mapping=[Mapped(i, s, BITS[t], t, f"{name}_{i:04X}_{s:X}") for i, s, t in objs])
            node.pdos.append(p)
            out_no += 1
            _mirror(plc, TPDO, out_no, p)
        node.writes = [
            Write(0x1800, 1, 0x07, 0x80000180 + nid, (0x80000180 + nid).to_bytes(4, "little"),
                  "COB-ID used by TPDO 1", "TPDO1 COB-ID, invalid while configuring",
                  Where(path, node.where.line + 1)),
            Write(0x1800, 2, 0x05, 255, b"\xff", "Transmission type", "TPDO1 transmission",
                  Where(path, node.where.line + 2)),
            Write(0x1800, 1, 0x07, 0x180 + nid, (0x180 + nid).to_bytes(4, "little"),
                  "COB-ID used by TPDO 1", "TPDO1 COB-ID", Where(path, node.where.line + 1)),
            Write(0x1017, 0, 0x06, 100, (100).to_bytes(2, "little"), "Producer heartbeat time",
                  "heartbeat_producer", Where(path, node.where.line + 3)),
        ]
        net.nodes.append(node)
    if slave_link and len(ids) >= 2:
        first = net.nodes[1]
        second = net.nodes[2]
        src = first.pdo(TPDO, 1)
        second.pdos.append(Pdo(second.node_id, RPDO, 4, src.cob_id, 255, listed=True,
                               mapping=[Mapped(0x6200, 4, 8, U8)]))
    net.nodes.sort(key=lambda n: n.node_id)
    net.configured = True
    return net


def line_diff(before: bytes, after: bytes) -> str:
    """The lines ``after`` changes in ``before`` as a unified diff without context, each
    line split at LF only, a CR shown as ``\\r`` (and a backslash as ``\\\\``): the same
    ``before`` and the same diff give the same bytes, so a golden diff pins an output
    built from a file the project does not copy (the corpus)."""
    import difflib

    def lines(data: bytes) -> list[str]:
        text = data.decode("latin-1").replace("\\", "\\\\").replace("\r", "\\r")
        return text.split("\n")
    return "".join(line + "\n" for line in difflib.unified_diff(
        lines(before), lines(after), "file", "built", n=0, lineterm=""))
