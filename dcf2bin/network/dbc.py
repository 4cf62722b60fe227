"""`network show -f dbc`: a network's PDOs as a CAN database (DBC), for loggers and bus
analysers (issue 27 item 5; docs/network.md "The PDOs as a CAN database").

Built from the links of :mod:`dcf2bin.network.show` and written by cantools (optional:
``pip install cantools``, or the ``dbc`` extra from a checkout; imported only here, only when called):

* one message per PDO COB-ID (SYNC and heartbeats are not PDOs), named
  ``<producer>_<PDO>`` (``sensor_TPDO1``, ``plc_TPDO2``), sent by its producer node, its
  DLC the mapped bits in bytes, a 29-bit COB-ID an extended frame; an RPDO whose COB-ID no
  node sends is a message named after its first consumer, with no sender;
* one signal per mapped object, at its bit position (CANopen is little-endian: Intel
  byte order), of its mapped length: BOOLEAN 1 bit, INTEGERn signed, REAL32/REAL64 IEEE
  floats, everything else unsigned; a dummy entry is a gap, not a signal;
* a signal is named as the object's variable is (``name:``, ``names:``, else
  ``<slave>_<INDEX>_<SUB>``, ``_in``/``_out`` for an object mapped both ways: SPEC §10.2,
  D-17), for a PLC master and a lely master alike; an object of a PDO no master PDO
  mirrors (only slaves receive it, nobody sends it, a .cpj project) by its mapping's
  ``name:``, else ``<node>_<INDEX>_<SUB>``. Characters outside
  ``[A-Za-z0-9_]`` become ``_``, a leading digit gets ``_`` before it, and a name taken
  twice in one message (or a node name twice in the network) gets ``_2``, ``_3``...;
* the receivers of every signal are the consumers of the frame; comments name the node
  (its node-ID), the PDO (COB-ID, transmission type, event timer, consumers) and each
  signal's object (index, sub, name, data type); the event timer of a PDO sent on an
  event (types 254, 255) is the message's ``GenMsgCycleTime``; the bitrate the network
  file gives (the master's ``bitrate:``/``baudrate:``) the database's ``Baudrate``.

The text is cantools' (CRLF line ends, names over 32 characters cut with the full name in
``System...LongSymbol``, as Vector's tools do), encoded as cantools writes a .dbc file:
cp1252, a character it lacks written as ``?``. Deterministic: same network, same bytes.

    data = dump(network)            # bytes
    db = database(network)          # the cantools Database
"""
from __future__ import annotations

import os
import re

from dcf2bin import datatypes as dt
from dcf2bin.network.model import Network, Node, Pdo
from dcf2bin.network.show import Link, View, build, carried
from dcf2bin.network.variables import default_name

MISSING = "dcf2bin network show -f dbc needs cantools: pip install cantools (or, from a checkout, pip install '.[dbc]')"
_NOT_DBC = re.compile(r"[^A-Za-z0-9_]")
_EVENT = (254, 255)


class CantoolsMissing(RuntimeError):
    """cantools cannot be imported (not installed, or broken): the message is MISSING."""


def require():
    """The cantools module, or CantoolsMissing."""
    try:
        import cantools
        import cantools.database.can  # noqa: F401
    except ImportError as exc:
        raise CantoolsMissing(MISSING) from exc
    return cantools


def identifier(name: str) -> str:
    """``name`` as a DBC identifier: ``[A-Za-z_][A-Za-z0-9_]*``."""
    out = _NOT_DBC.sub("_", name)
    return "_" + out if not out or out[0].isdigit() else out


def unique(name: str, taken: set[str]) -> str:
    """``name``, or ``name_2``, ``name_3``... the first not in ``taken`` (added to it)."""
    out, k = name, 1
    while out in taken:
        k += 1
        out = f"{name}_{k}"
    taken.add(out)
    return out


def node_names(view: View) -> dict[int, str]:
    """node-ID -> its DBC name, in node-ID order."""
    taken: set[str] = set()
    return {n.node_id: unique(identifier(n.node), taken) for n in view.nodes}


def object_text(node: Node, index: int, sub: int, datatype: int | None) -> str:
    """``sensor: Temperature (0x2000sub0, REAL32)``: the node, the object's ParameterName
    (its Denotation in a DCF that gives one; a lely master names its object so), the
    object and its data type."""
    entry = node.device.entry(index, sub) if node.device is not None else None
    t = dt.BY_CODE.get(datatype) if datatype is not None else None
    name = f": {entry.denotation or entry.name}" if entry is not None else ""
    return (f"{node.name}{name} (0x{index:04X}sub{sub:X}, "
            f"{t.name if t else 'unknown type'})")


def _kind(datatype: int | None) -> tuple[bool, bool]:
    """(signed, float) of a signal of that CiA 301 type."""
    t = dt.BY_CODE.get(datatype) if datatype is not None else None
    if t is None:
        return False, False
    if t.kind == dt.REAL:
        return True, True
    return t.kind == dt.SINT, False


def _transmission(pdo: Pdo) -> str:
    t = pdo.transmission
    text = f"transmission type {t}"
    if t in _EVENT and pdo.event_timer:
        text += f", event timer {pdo.event_timer} ms"
    return text


def message_comment(link: Link) -> str:
    cob = link.cob_text
    if link.producer is None:
        return (f"{link.consumers[0].node} {link.what} (node-ID {link.consumers[0].node_id}),"
                f" COB-ID {cob}: no node of the network sends it")
    p = link.producer
    out = f"{p.node} {p.pdo} (node-ID {p.node_id}), COB-ID {cob}, {_transmission(link.pdo)}"
    if link.consumers:
        return out + "; received by " + ", ".join(str(c) for c in link.consumers)
    return out + "; received by no node of the network"


def _signals(network: Network, link: Link, receivers: list[str]):
    from cantools.database.can import Signal
    from cantools.database.conversion import BaseConversion
    pdo = link.pdo
    source = pdo.mirror_of if pdo.mirror_of is not None else pdo
    owner = network.node(source.node_id)
    taken: set[str] = set()
    out, at = [], 0
    for m, variable in carried(pdo):
        start, at = at, at + m.bits
        if m.is_dummy:
            continue               # a gap
        signed, real = _kind(m.datatype)
        base = variable or default_name(owner.name, m.index, m.sub)
        comment = object_text(owner, m.index, m.sub, m.datatype)
        out.append(Signal(unique(identifier(base), taken), start, m.bits,
                          byte_order="little_endian", is_signed=signed,
                          conversion=BaseConversion.factory(is_float=real),
                          receivers=list(receivers), comment=comment))
    return out


def _message(network: Network, link: Link, names: dict[int, str], taken: set[str]):
    from cantools.database.can import Message
    pdo = link.pdo
    first = link.producer or link.consumers[0]
    receivers = list(dict.fromkeys(names[c.node_id] for c in link.consumers))
    name = unique(identifier(f"{names[first.node_id]}_{first.pdo}"), taken)
    cycle = None
    if link.producer is not None and pdo.transmission in _EVENT and pdo.event_timer:
        cycle = pdo.event_timer
    return Message(link.can_id, name, (pdo.bits + 7) // 8,
                   _signals(network, link, receivers),
                   senders=[names[link.producer.node_id]] if link.producer else [],
                   comment=message_comment(link), cycle_time=cycle,
                   is_extended_frame=link.extended, strict=False)


def bitrate(network: Network) -> int | None:
    """The bitrate the network file gives (the master's ``bitrate:`` or ``baudrate:``),
    else None: the 500 kbit/s the load estimate assumes is not written as a fact."""
    master = network.master
    if master is not None and ("bitrate" in master.config or "baudrate" in master.config):
        return network.bitrate
    return None


def database(network: Network, view: View | None = None):
    """The cantools Database of a configured network's PDOs (CantoolsMissing without
    cantools). ``view``: show's view of it, when the caller has it."""
    require()
    from cantools.database.can import Bus, Database
    from cantools.database.can import Node as DbcNode
    view = view if view is not None else build(network)
    names = node_names(view)
    taken: set[str] = set()
    messages = [_message(network, k, names, taken) for k in view.links
                if k.is_pdo and k.pdo is not None]
    nodes = [DbcNode(names[n.node_id], comment=f"node-ID {n.node_id}"
                     + (", the master" if n.master else "")) for n in view.nodes]
    bus = Bus("", comment="PDOs of the CANopen network "
              f"{os.path.basename(view.path) or view.path}", baudrate=bitrate(network))
    return Database(messages, nodes, [bus], strict=False, sort_signals=None)


def dump(network: Network, view: View | None = None) -> bytes:
    """The DBC file of a configured network's PDOs, as cantools writes one."""
    text = database(network, view).as_dbc_string(sort_signals=None,
                                                 sort_attribute_signals=None)
    return text.encode("cp1252", "replace")
