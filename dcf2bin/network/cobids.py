"""COB-ID assignment (SPEC §10.2, D-17).

After ``enabled:`` and the explicit ``cob_id``s, the *used* set holds the CAN-ID of every
PDO whose COB-ID has bit 31 clear (mapped or not, the PLC's own file included). PDO n <= 4
takes its predefined-connection-set ID when that is not used; otherwise the lowest CAN-ID
of 0x181-0x57F, then 0x680-0x6DF, that is neither used nor in the predefined set of a
node-ID present (TPDO1-4 and RPDO1-4 of every node, the master's too). Order: slaves by
node-ID, TPDOs before RPDOs, by number. An assigned COB-ID is the bare 11-bit CAN-ID.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostics, shorten
from dcf2bin.network.model import COB_INVALID, TPDO, Network
from dcf2bin.network.pdos import keep_file_id, needs_id

CANDIDATES = tuple(range(0x181, 0x580)) + tuple(range(0x680, 0x6E0))


def predefined(kind: str, number: int, node_id: int) -> int:
    return (0x180 if kind == TPDO else 0x200) + 0x100 * (number - 1) + node_id


def assign(net: Network, diags: Diagnostics) -> None:
    pending = []
    for node in net.slaves:
        for pdo in node.pdos:
            if needs_id(pdo):
                pending.append((node, pdo))
            else:
                keep_file_id(pdo)
    waiting = {id(p) for _, p in pending}
    used = set()
    for node in net.nodes:
        for pdo in node.pdos:
            if id(pdo) not in waiting and not pdo.cob_id & COB_INVALID:
                used.add(pdo.can_id)
    reserved = set()
    for node in net.nodes:
        if 1 <= node.node_id <= 127:
            for n in range(1, 5):
                reserved.add(predefined(TPDO, n, node.node_id))
                reserved.add(predefined("rpdo", n, node.node_id))
    free = [c for c in CANDIDATES if c not in reserved]
    pos = 0
    pending.sort(key=lambda np: (np[0].node_id, np[1].kind != TPDO, np[1].number))
    for node, pdo in pending:
        if pdo.number <= 4:
            can = predefined(pdo.kind, pdo.number, node.node_id)
            if can <= 0x7FF and can not in used:
                pdo.cob_id = can
                used.add(can)
                continue
        while pos < len(free) and free[pos] in used:
            pos += 1
        if pos == len(free):
            diags.error(f"no free COB-ID left for {shorten(node.name)} {pdo.label} (0x181-0x57F "
                        "and "
                        "0x680-0x6DF are taken)", pdo.where, rule="NET109")
            pdo.cob_id = (pdo.file_cob_id or 0) | COB_INVALID
            continue
        pdo.cob_id = free[pos]
        used.add(free[pos])
        pos += 1
