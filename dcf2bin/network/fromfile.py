"""A node as its EDS/DCF is (SPEC §10.1): its PDOs, heartbeat, SYNC, EMCY and TIME read
from the file's effective values. A ``.cpj`` node is exactly this; nothing is configured.

A value the file cannot give (a broken number, a ``$NODEID`` without node-ID) is left at
its default here: the file's own findings (``validate``) say why.
"""
from __future__ import annotations

from dcf2bin.diagnostics import DcfError, Where
from dcf2bin.network.model import (COB_INVALID, RPDO, TPDO, Heartbeat, Mapped, Node, Pdo)

_COMM = ((0x1400, RPDO), (0x1800, TPDO))


def _int(dev, index: int, sub: int) -> int | None:
    e = dev.entry(index, sub)
    if e is None or e.dtype is None or not e.dtype.is_integer or not e.has_value \
            or e.download_file is not None:
        return None
    try:
        return dev.effective_int(e)
    except (DcfError, ValueError, OverflowError):
        return None


def _where(dev, index: int, sub: int) -> Where | None:
    e = dev.entry(index, sub)
    if e is not None and e.where is not None:
        return e.where
    obj = dev.objects.get(index)
    return obj.where if obj is not None else None


def pdos(dev, node_id: int) -> list[Pdo]:
    """Every PDO the file has, with its effective communication and mapping values."""
    out = []
    for base, kind in _COMM:
        for index in range(base, base + 0x200):
            if index not in dev.objects:
                continue
            cob = _int(dev, index, 1)
            p = Pdo(node_id, kind, index - base + 1,
                    COB_INVALID if cob is None else cob,
                    transmission=_val(dev, index, 2, 255),
                    inhibit_time=_val(dev, index, 3, 0) if kind == TPDO else 0,
                    event_timer=_val(dev, index, 5, 0),
                    sync_start=_val(dev, index, 6, 0) if kind == TPDO else 0,
                    where=_where(dev, index, 1))
            p.mapping = _mapping(dev, index + 0x200)
            out.append(p)
    return out


def _val(dev, index: int, sub: int, default: int) -> int:
    v = _int(dev, index, sub)
    return default if v is None else v


def _mapping(dev, index: int) -> list[Mapped]:
    n = _int(dev, index, 0)
    out: list[Mapped] = []
    for k in range(1, min(n or 0, 64) + 1):
        v = _int(dev, index, k)
        if not v:
            return []            # a zero or unreadable entry: the PDO is not counted
        obj, sub, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
        e = dev.entry(obj, sub)
        dtype = obj if 1 <= obj <= 7 else (e.dtype.code if e is not None and e.dtype else None)
        out.append(Mapped(obj, sub, bits, dtype, where=_where(dev, index, k)))
    return out


def node_from_device(node: Node) -> Node:
    """Fill ``node`` (its ``device`` read) from its file; returns it."""
    dev, nid = node.device, node.node_id
    node.pdos = pdos(dev, nid)
    node.heartbeat_producer = _val(dev, 0x1017, 0, 0)
    hb = dev.objects.get(0x1016)
    if hb is not None:
        for k in sorted(hb.entries):
            v = _int(dev, 0x1016, k) if k else None
            if v:
                node.heartbeat_consumers.append(Heartbeat((v >> 16) & 0xFF, v & 0xFFFF,
                                                          _where(dev, 0x1016, k)))
    sync = _int(dev, 0x1005, 0)
    if sync is not None:
        node.sync_cob_id = sync & 0x3FFFFFFF & ~0x40000000
        node.sync_period = _val(dev, 0x1006, 0, 0)
        node.sync_producer = bool(sync & 0x40000000) and node.sync_period != 0
    node.sync_counter = _val(dev, 0x1019, 0, 0)
    node.emcy_cob_id = _int(dev, 0x1014, 0)
    if node.emcy_cob_id is None:
        node.emcy_cob_id = 0x80 + nid
    node.time_cob_id = _int(dev, 0x1012, 0)
    return node
