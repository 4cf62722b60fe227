"""A live node as a ``Side``: the entries the file it is compared with lists, read by SDO
(``bus.sdo.Channel``: each transfer bounded in time and bytes).

Read are the file's entries that take part in the comparison (the node's state and
``--ignore`` left out before the bus is asked), that can be read (not ``wo``; a
container's entry with its read bit) and for which the file states a value; the others
are ``Side.unread`` and not compared. An entry the node does not have (SDO abort
0x06020000 or 0x06090011) is missing from the node's side; any other abort is the
entry's value, as a problem ("SDO abort 0x06010001: ..."); a node that stops answering
or answers what SDO does not allow ends the reading (``NodeStopped``).

``read_entries`` is the one function that talks to the node; it stands in for the
reader of ``dcf2bin upload`` (``bus/upload.py``, branch ``upload``) until that lands.
"""
from __future__ import annotations

from collections.abc import Callable

from dcf2bin.compare.scope import Scope, state_reason
from dcf2bin.compare.side import NODE, Item, Side, Value, objects_of

MISSING = (0x06020000, 0x06090011)   # object / sub-index does not exist


class NodeStopped(Exception):
    """The node did not answer, or not as SDO allows; the message names the entry."""


def wanted(other: Side, scope: Scope) -> tuple[list[Item], dict]:
    """The entries of ``other`` to read from the node, and those left unread (-> why)."""
    read, unread = [], {}
    for key, it in sorted(other.items.items()):
        if scope.ignored(key):
            unread[key] = "ignored"
        elif scope.state and state_reason(key, (it,), other.is_complex(key[0])):
            unread[key] = "state"
        elif it.readable is False:
            unread[key] = "write-only"
        elif not it.value.stated or it.value.implied:
            unread[key] = "no value"
        else:
            read.append(it)
    return read, unread


def read_entries(net, node_id: int, entries: list[tuple[int, int, int]], *, timeout: float,
                 retries: int, progress: Callable[[], None] | None = None) -> dict:
    """(index, sub) -> the bytes the node holds, or its ``sdo.Aborted``, for each of
    ``entries`` (index, sub, most bytes it may hold). Raises ``NodeStopped``."""
    from dcf2bin.bus import sdo
    out: dict = {}
    with sdo.Channel(net, node_id, timeout=timeout, retries=retries) as ch:
        for index, sub, most in entries:
            try:
                out[(index, sub)] = ch.upload(index, sub, max_size=most)
            except sdo.Aborted as exc:
                out[(index, sub)] = exc
            except sdo.SdoError as exc:
                raise NodeStopped(f"{exc} (reading {sdo.entry_name(index, sub)})") from None
            if progress is not None:
                progress()
    return out


def node_side(net, node_id: int, other: Side, scope: Scope, *, timeout: float,
              retries: int, progress: Callable[[], None] | None = None) -> Side:
    from dcf2bin.bus.sdo import MAX_DOMAIN
    read, unread = wanted(other, scope)
    sizes = []
    for it in read:
        t = it.dtype
        sizes.append((it.index, it.sub, t.size if t is not None and t.size else MAX_DOMAIN))
    got = read_entries(net, node_id, sizes, timeout=timeout, retries=retries,
                       progress=progress)
    label = f"node {node_id}"
    items = {}
    for key, data in got.items():
        if isinstance(data, bytes):
            value = Value(data)
        elif data.code in MISSING:
            continue
        else:
            value = Value(problem=data.what)
        items[key] = Item(key[0], key[1], value, where=label)
    return Side(label, "node", NODE, items, objects_of(items), node_id=node_id,
                unread=unread)


def total(other: Side, scope: Scope) -> int:
    """How many entries ``node_side`` reads (for a progress bar)."""
    return len(wanted(other, scope)[0])
