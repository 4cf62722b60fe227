"""A live node as a ``Side``: the entries the file it is compared with lists, read by
``dcf2bin upload``'s reader (``bus.upload.read_node``: one request in flight, each transfer
bounded in time and bytes as bus/sdo.py bounds it, a boot-up message during the reading a
failure, refusals kept as data).

Read are the file's entries that take part in the comparison (the node's state and
``--ignore`` left out before the bus is asked), that can be read (not ``wo``; a
container's entry with its read bit) and for which the file states a value; the others
are ``Side.unread`` and not compared. Each is read as upload reads it: a fixed-size entry
as at most 8 bytes (so that a node answering 4 bytes for an UNSIGNED8 shows them), any
other as at most ``sdo.MAX_DOMAIN``. Upload states only the bytes that are a value of the
entry's type; diff compares whatever the node answered, so an unfit answer's bytes are
its value here. An entry the node does not have (SDO abort 0x06020000 or 0x06090011) is
missing from the node's side; any other abort is the entry's value, as a problem ("SDO
abort 0x06010001: ..."); a node that stops answering, answers what SDO does not allow or
restarts ends the reading (``NodeStopped``, with upload's words for the entry).
"""
from __future__ import annotations

from collections.abc import Callable

from dcf2bin.compare.scope import Scope, state_reason
from dcf2bin.compare.side import NODE, Item, Side, Value, objects_of


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


def read_entries(net, node_id: int, items: list[Item], *, timeout: float, retries: int,
                 progress: Callable[[], None] | None = None) -> dict:
    """(index, sub) -> the bytes the node holds, or the abort code it answered, for each
    of ``items``, read by upload's reader. Raises ``NodeStopped``."""
    from dcf2bin.bus import sdo, upload
    todo = [upload.Target(it.index, it.sub, it.dtype, None, _most(it.dtype)) for it in items]
    options = upload.Options(timeout=timeout, retries=retries)
    with sdo.Channel(net, node_id, timeout=timeout, retries=retries) as ch:
        got = upload.read_node(ch, todo, options,
                               progress=None if progress is None else lambda t: progress())
    failed = got.failures
    if failed:
        raise NodeStopped(failed[0].text)
    out: dict = {key: data for key, (_, data) in got.values.items()}
    for note in got.notes:
        key = (note.target.index, note.target.sub)
        out[key] = note.code if note.kind == upload.REFUSED else note.data
    return out


def _most(dtype) -> int:
    """The most bytes an entry is read as: upload's rule."""
    from dcf2bin.bus import sdo, upload
    size = dtype.size if dtype is not None else None
    return max(size, upload.FIXED_MOST) if size is not None else sdo.MAX_DOMAIN


def node_side(net, node_id: int, other: Side, scope: Scope, *, timeout: float,
              retries: int, progress: Callable[[], None] | None = None) -> Side:
    from dcf2bin.bus.link import abort_message
    from dcf2bin.bus.upload import NO_SUCH_ENTRY
    read, unread = wanted(other, scope)
    got = read_entries(net, node_id, read, timeout=timeout, retries=retries,
                       progress=progress)
    label = f"node {node_id}"
    items = {}
    for key, data in sorted(got.items()):
        if isinstance(data, bytes):
            value = Value(data)
        elif data in NO_SUCH_ENTRY:
            continue
        else:
            value = Value(problem=abort_message(data))
        items[key] = Item(key[0], key[1], value, where=label)
    return Side(label, "node", NODE, items, objects_of(items), node_id=node_id,
                unread=unread)


def total(other: Side, scope: Scope) -> int:
    """How many entries ``node_side`` reads (for a progress bar)."""
    return len(wanted(other, scope)[0])
