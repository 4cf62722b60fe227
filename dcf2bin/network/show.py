"""What `network show` prints (SPEC §10.5): the links of a configured network as data, and
its text and JSON forms (the picture is :mod:`dcf2bin.network.svg`).

* per COB-ID (D-20's rows): the producer (node, PDO), the consumers, data bytes, frames
  per second (None: the configuration does not say), bits of a frame, share of the bus;
  an RPDO whose COB-ID no node produces is listed too, with no producer;
* per PLC variable: the slave and object it comes from or goes to, and its PLC entry;
* per slave: the identity the master will enforce (0x1F84…0x1F88; for a .cpj project,
  which has no master, the identity each node's DCF states);
* with ``writes``: a slave's decoded D-18 write list (index, sub, name, value, why).

    view = build(network, writes=None | "all" | node-name-or-ID)
    text(view), as_json(view)
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import DcfError
from dcf2bin.network.model import COB_EXTENDED, RPDO, Mapped, Network, Node, Pdo

IDENTITY_ENTRIES = {0x1F84: (0x1000, 0), 0x1F85: (0x1018, 1), 0x1F86: (0x1018, 2),
                    0x1F87: (0x1018, 3), 0x1F88: (0x1018, 4)}
IDENTITY_NAMES = {0x1F84: "device type", 0x1F85: "vendor-ID", 0x1F86: "product code",
                  0x1F87: "revision number", 0x1F88: "serial number"}


@dataclass
class End:
    """One end of a link: a node and the PDO it sends or receives the frame with."""
    node: str
    node_id: int
    pdo: str | None            # "TPDO1", "RPDO3"; None for SYNC and heartbeat ends
    master: bool = False

    def __str__(self) -> str:
        return f"{self.node} {self.pdo}" if self.pdo else self.node

    def as_dict(self) -> dict:
        return {"node": self.node, "node_id": self.node_id, "pdo": self.pdo}


@dataclass
class Link:
    can_id: int
    extended: bool
    what: str                          # "TPDO1", "SYNC", "heartbeat", "RPDO2" (no producer)
    producer: End | None
    consumers: list[End]
    content: list[str]                 # what the frame carries: variable or object names
    bytes: int
    rate: float | None
    bits: int
    share: float
    pdo: Pdo | None = field(default=None, repr=False, compare=False)
    # the PDO whose mapping the frame carries: its producer's TPDO, or for an RPDO that
    # nobody produces the first such RPDO (the DBC writer reads it, network/dbc.py)

    @property
    def cob_text(self) -> str:
        return f"0x{self.can_id:08X}" if self.extended else f"0x{self.can_id:03X}"

    @property
    def is_pdo(self) -> bool:
        return self.what not in ("SYNC", "heartbeat")


@dataclass
class VarRow:
    name: str
    direction: str
    datatype: str
    node: str
    node_id: int
    index: int
    sub: int
    pi_index: int | None
    pi_sub: int | None
    pi_offset: int | None
    app: tuple[int, int] | None = None      # a lely master's 0x2000/0x2200 record and sub


@dataclass
class WriteRow:
    index: int
    sub: int
    name: str
    value: object
    data: bytes
    why: str
    where: str


@dataclass
class SlaveRow:
    name: str
    node_id: int
    identity: dict[int, int]
    writes: list[WriteRow] | None = None      # None: not asked for


@dataclass
class View:
    path: str
    bitrate: int
    nodes: list[End]
    links: list[Link]
    total: float
    unknown: int
    variables: list[VarRow] = field(default_factory=list)
    slaves: list[SlaveRow] = field(default_factory=list)
    kind: str = "yaml"                        # "yaml" or "cpj"
    lely: bool = False                        # a lely master (no dcf:): no PLC variables


def identity_of(network, node) -> dict[int, int]:
    """What a node must be (0x1F84…0x1F88 → value, the nonzero ones): for a YAML network
    what the master will enforce; for a .cpj project, which has no master, the node's own
    DCF (its 0x1000 and 0x1018 sub 1…4)."""
    if network.kind != "cpj":
        return {k: v for k, v in node.identity.items() if v}
    out = {}
    dev = node.device
    for key, (index, sub) in IDENTITY_ENTRIES.items():
        entry = dev.entry(index, sub) if dev is not None else None
        if entry is None:
            continue
        try:
            value = dev.effective_int(entry)
        except DcfError:         # a value the file's own findings already report
            continue
        if value:
            out[key] = value
    return out


def _end(node: Node, pdo: Pdo | None) -> End:
    return End(node.name, node.node_id, pdo.label if pdo is not None else None,
               node.role == "master")


def carried(pdo: Pdo) -> list[tuple[Mapped, str | None]]:
    """What a PDO's frame carries: each entry of its mapping -- a PLC mirror's those of
    the slave PDO it mirrors, the slave's objects -- with the name of the PLC variable it
    is (None: it is none, as in a PDO that no master PDO mirrors). The names are the
    mirror's, so an object mapped both ways is named for this direction (``_in`` in a
    slave TPDO, ``_out`` in its RPDO)."""
    source = pdo.mirror_of if pdo.mirror_of is not None else pdo
    mirror = pdo if pdo.mirror_of is not None else pdo.mirrored_by
    names: list[str | None] = [None] * len(source.mapping)
    if mirror is not None and len(mirror.mapping) == len(source.mapping):
        names = [m.name for m in mirror.mapping]
    return [(m, names[k] or m.name) for k, m in enumerate(source.mapping)]


def _content(pdo: Pdo | None) -> list[str]:
    """The names of what a PDO carries: each mapped object's PLC variable, else its index
    and sub."""
    if pdo is None:
        return []
    return [f"dummy {m.bits} bits" if m.is_dummy else name or f"0x{m.index:04X}sub{m.sub:X}"
            for m, name in carried(pdo)]


def find_node(network: Network, which: str) -> Node | None:
    """A node by its name or its node-ID (decimal or 0x hex)."""
    for n in network.nodes:
        if n.name == which:
            return n
    try:
        nid = int(which, 0)
    except ValueError:
        return None
    return network.node(nid)


def build(network: Network, writes: str | None = None) -> View:
    """The view of a configured network. ``writes``: None, "all", or one node's name/ID
    (the caller has checked it with :func:`find_node`)."""
    from dcf2bin.network.load import estimate
    load = estimate(network)
    nodes = [_end(n, None) for n in sorted(network.nodes, key=lambda n: n.node_id)]
    links = []
    produced = set()
    for r in load.rows:
        produced.add((r.can_id, r.extended))
        ends = [_end(n, p) for n, p in r.consumers]
        if r.pdo is None:          # SYNC, heartbeat: each consuming node once
            ends = list({e.node_id: _end(n, None) for e, (n, _p) in zip(ends, r.consumers)}
                        .values())
        links.append(Link(r.can_id, r.extended, r.what, _end(r.producer, r.pdo), ends,
                          _content(r.pdo), r.bytes, r.rate, r.bits, r.share, r.pdo))
    orphans: dict[tuple[int, bool], list] = {}
    for node in network.nodes:
        for p in node.pdos:
            key = (p.can_id, bool(p.cob_id & COB_EXTENDED))
            if p.exists and p.kind == RPDO and key not in produced:
                orphans.setdefault(key, []).append((node, p))
    for (can_id, ext), ends in orphans.items():
        node, p = ends[0]
        links.append(Link(can_id, ext, p.label, None, [_end(n, q) for n, q in ends],
                          _content(p), (p.bits + 7) // 8, None, 0, 0.0, p))
    links.sort(key=lambda k: (k.extended, k.can_id))
    view = View(network.path, network.bitrate, nodes, links, load.total, len(load.unknown),
                kind=network.kind)
    by_id = {n.node_id: n for n in network.nodes}
    master = network.master
    # a lely master: a YAML master without dcf: (master_kind's rule), whose variables no
    # PLC's file holds
    view.lely = (network.kind == "yaml" and master is not None and master.file is None
                 and not any(v.pi_index is not None for v in network.variables))
    places = {}
    if view.lely and network.variables:     # D-21: the records 0x2000/0x2200 dcfgen makes
        from dcf2bin.network.lely.layout import places as lely_places
        places = lely_places(network)
    for v in network.variables:
        t = dt.BY_CODE.get(v.datatype)
        slave = by_id.get(v.node_id)
        view.variables.append(VarRow(v.name, v.direction, t.name if t else f"0x{v.datatype:04X}",
                                     slave.name if slave else "?", v.node_id, v.index, v.sub,
                                     v.pi_index, v.pi_sub, v.pi_offset,
                                     places.get((v.node_id, v.index, v.sub, v.direction))))
    chosen = None if writes in (None, "all") else find_node(network, writes)
    for n in sorted(network.slaves, key=lambda n: n.node_id):
        row = SlaveRow(n.name, n.node_id, dict(sorted(identity_of(network, n).items())))
        if writes == "all" or (chosen is not None and chosen is n):
            row.writes = [WriteRow(w.index, w.sub, w.name, w.value, w.data, w.why,
                                   str(w.where) if w.where is not None else "")
                          for w in n.writes]
        view.slaves.append(row)
    return view


# -- text -----------------------------------------------------------------------------------

def rate_text(rate: float | None) -> str:
    if rate is None:
        return "?"
    return f"{rate:.4g}/s"


def value_text(w: WriteRow) -> str:
    v = w.value
    if isinstance(v, bool):
        return str(v).lower()
    if isinstance(v, int):
        width = max(2, 2 * len(w.data))
        return f"0x{v:0{width}X} ({v})" if v > 9 else str(v)
    if isinstance(v, float):
        return repr(v)
    if isinstance(v, (bytes, bytearray)):
        return bytes(v).hex(" ").upper() or "(0 bytes)"
    return json.dumps(v) if isinstance(v, str) else str(v)


def table(head: list[str], rows: list[list[str]]) -> list[str]:
    widths = [max(len(head[i]), *(len(r[i]) for r in rows)) if rows else len(head[i])
              for i in range(len(head))]
    fmt = lambda r: "  ".join(c.ljust(w) for c, w in zip(r, widths)).rstrip()  # noqa: E731
    return [fmt(head)] + [fmt(r) for r in rows]


def variables_title(view: View) -> str:
    """The heading of the variables: a PLC's network variables, or for a lely master
    (D-21) the application objects its PDOs map the slaves' data into."""
    if view.lely:
        return "Mapped application objects of the lely master (0x2000/0x2200)"
    return "PLC variables"


def variable_table(view: View, short: bool) -> tuple[list[str], list[list[str]]]:
    """The head and rows of the variables (``short``: ``in``/``out`` for the direction):
    a PLC's entry and offset, or the lely master's application object."""
    def direction(v: VarRow) -> str:
        return ("in" if v.direction == "input" else "out") if short else v.direction

    def entry(place) -> str:
        return f"0x{place[0]:04X}sub{place[1]:X}" if place is not None else ""
    head = ["variable", "dir" if short else "direction", "type", "node", "object"]
    common = [[v.name, direction(v), v.datatype, f"{v.node} ({v.node_id})",
               f"0x{v.index:04X}sub{v.sub:X}"] for v in view.variables]
    if view.lely:
        return head + ["master entry"], [row + [entry(v.app)]
                                         for row, v in zip(common, view.variables)]
    return head + ["PLC entry", "offset"], [
        row + [entry((v.pi_index, v.pi_sub) if v.pi_index is not None else None),
               str(v.pi_offset) if v.pi_offset is not None else ""]
        for row, v in zip(common, view.variables)]


def text(view: View) -> str:
    out = [f"{view.path}: {len(view.nodes)} nodes, {sum(k.is_pdo for k in view.links)} PDO "
           f"COB-IDs, estimated bus load {view.total:.1f} % of {view.bitrate // 1000} kbit/s"
           + (f" ({view.unknown} frame{'s' if view.unknown != 1 else ''} of unknown rate "
              "counted as 0)" if view.unknown else ""), ""]
    rows = [[k.cob_text, k.what,
             str(k.producer) if k.producer else "(nobody)",
             ", ".join(str(c) for c in k.consumers) or "(nobody)",
             str(k.bytes), rate_text(k.rate), f"{k.share:.2f} %",
             ", ".join(k.content)] for k in view.links]
    out += table(["COB-ID", "frame", "producer", "consumers", "bytes", "rate", "load",
                   "content"], rows)
    if view.variables:
        head, rows = variable_table(view, short=True)
        out += ["", f"{variables_title(view)}:"]
        out += table(head, rows)
    if view.slaves:
        out += ["", "Identity the master enforces:" if view.kind != "cpj" else
                "Identity each node's DCF states (a .cpj project has no master):"]
        cols = [0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88]
        out += table(["node", *(IDENTITY_NAMES[c] for c in cols)],
                      [[f"{s.name} ({s.node_id})",
                        *(f"0x{s.identity[c]:08X}" if c in s.identity else "-" for c in cols)]
                       for s in view.slaves])
    for s in view.slaves:
        if s.writes is None:
            continue
        n = len(s.writes)
        out += ["", f"{s.name} (node {s.node_id}): {n} SDO write{'s' if n != 1 else ''}"]
        out += table(["#", "entry", "name", "value", "why", "source"],
                      [[str(k + 1), f"0x{w.index:04X}sub{w.sub:X}", w.name, value_text(w),
                        w.why, w.where] for k, w in enumerate(s.writes)])
    return "\n".join(out) + "\n"


# -- JSON -----------------------------------------------------------------------------------

def _jvalue(v, size: int):
    """A written value: an unsigned number as hex of its entry's width (a COB-ID
    ``"0x80000183"``, a count ``"0x00"``), a signed or real number as a JSON number, a
    string as it is, a domain as hex pairs."""
    if isinstance(v, (bytes, bytearray)):
        return bytes(v).hex().upper()
    if isinstance(v, int) and not isinstance(v, bool) and v >= 0 and 1 <= size <= 8:
        return f"0x{v:0{2 * size}X}"
    return v


FORMAT, VERSION = "dcf2bin-network-show", 1     # schema: dcf2bin/schemas/network-show.json


def _hex16(v: int | None) -> str | None:
    return None if v is None else f"0x{v:04X}"


def as_dict(view: View) -> dict:
    """The JSON document (docs/options.md, "JSON outputs"): indexes ``"0x1800"``, COB-IDs,
    CAN-IDs and identity values ``"0x%08X"``, every other number a JSON integer."""
    return {
        "format": FORMAT,
        "version": VERSION,
        "file": view.path,
        "bitrate": view.bitrate,
        "bus_load_percent": round(view.total, 4),
        "unknown_rates": view.unknown,
        "nodes": [{"name": n.node, "node_id": n.node_id,
                   "role": "master" if n.master else "slave"} for n in view.nodes],
        "links": [{"cob_id": f"0x{k.can_id | (COB_EXTENDED if k.extended else 0):08X}",
                   "can_id": f"0x{k.can_id:08X}", "extended": k.extended, "frame": k.what,
                   "producer": k.producer.as_dict() if k.producer else None,
                   "consumers": [c.as_dict() for c in k.consumers],
                   "content": k.content, "bytes": k.bytes, "rate": k.rate, "bits": k.bits,
                   "load_percent": round(k.share, 4)} for k in view.links],
        "variables": [{"name": v.name, "direction": v.direction, "type": v.datatype,
                       "node": v.node, "node_id": v.node_id, "index": _hex16(v.index),
                       "subindex": v.sub, "plc_index": _hex16(v.pi_index),
                       "plc_subindex": v.pi_sub, "offset": v.pi_offset}
                      for v in view.variables],
        "slaves": [{"name": s.name, "node_id": s.node_id,
                    "identity": {f"0x{k:04X}": f"0x{v:08X}" for k, v in s.identity.items()},
                    "writes": None if s.writes is None else [
                        {"index": _hex16(w.index), "subindex": w.sub, "name": w.name,
                         "value": _jvalue(w.value, len(w.data)), "data": w.data.hex().upper(), "why": w.why,
                         "source": w.where} for w in s.writes]} for s in view.slaves],
    }


def as_json(view: View) -> str:
    return json.dumps(as_dict(view), indent=2) + "\n"

