"""Give nodes the node-IDs a network file names, by LSS (`network lss`, `lss set`).

Three passes, and nothing is changed before the first two are clean:

1. *Find* each slave whose identity is known (vendor-ID and product code at least):
   by switch state selective on its full identity; else among the unconfigured nodes
   by fastscan, the parts the network file gives confirmed, the others scanned (an
   unknown revision is left out when the serial is known, and inquired afterwards);
   else, among nodes that have a node-ID (several may share one factory node-ID), by
   identify remote slave, halving the unknown ranges. Each node found tells its
   node-ID (inquire node-ID; a fastscan finds only nodes without one, 0xFF).
2. *Check*: no two nodes match one slave's identity (a second unconfigured one is
   asked for by fastscan, a second one by the halving); no slave's node-ID answers SDO
   on the bus unless it is held by a slave found here. That SDO round hopes for silence,
   so it lasts its whole wait, ``check_wait``: as long as ``network scan`` gives a node
   to answer (0.3 s), not the LSS ``timeout``. It is not made shorter, as a fastscan
   step's is: a node missed there is not merely "not found" but a node-ID given twice.
3. *Assign*, one slave after the other (those whose new node-ID another one still holds
   after that one): switch state selective, configure node-ID (and bit timing),
   store, switch state global to waiting; a node that had no node-ID takes the new one
   there and boots, one that had one is sent NMT reset communication at its old
   node-ID. The boot-up message at the new node-ID ends the wait for it. Then one
   scan (``scan``) shows whether each node answers at its node-ID with the identity
   found.

    result = commission(net, wanted, Options(timeout=0.5, wait=0.05, check_wait=0.3))

Nothing here imports click; the command renders the rows.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from dcf2bin.bus import lss as L
from dcf2bin.bus import scan as sc

ASSIGNED, ALREADY, NOT_FOUND, REFUSED, NO_ANSWER, SKIPPED = (
    "assigned", "already right", "not found", "refused", "no answer", "skipped")
OK = (ASSIGNED, ALREADY, SKIPPED)
SELECTIVE, FASTSCAN, IDENTIFY = "selective switch", "fastscan", "identify remote slave"
NMT_RESET_COMMUNICATION = 0x82


@dataclass
class Wanted:
    """A node to give a node-ID: what is known of its identity (part 0 vendor-ID ... 3
    serial -> value) and where that is written."""
    name: str
    node_id: int
    known: dict[int, int]
    where: str = ""

    @property
    def label(self) -> str:
        return f"node {self.node_id} ({self.name})" if self.name else f"node {self.node_id}"

    @property
    def identified(self) -> bool:
        return 0 in self.known and 1 in self.known


@dataclass
class Options:
    timeout: float = L.TIMEOUT
    wait: float = L.WAIT
    bitrate: int | None = None          # configure this bit timing too
    store: bool = True
    serial_key: str = "serial_number"   # where the network file gives a serial number
    check_wait: float = sc.TIMEOUT      # the SDO round before any change (silence: free)


@dataclass
class Row:
    """What became of one wanted node."""
    wanted: Wanted
    status: str = NOT_FOUND
    found_by: str | None = None
    identity: L.Identity | None = None
    was: int | None = None              # its node-ID before (0xFF: it had none)
    reply: L.Reply | None = None        # the refusal
    booted: bool = False                # its boot-up message at the new node-ID came
    answers: bool | None = None         # the scan afterwards: at its node-ID, as found
    text: str = ""


@dataclass
class Problem:
    message: str
    where: str


@dataclass
class Result:
    rows: list[Row]
    problems: list[Problem] = field(default_factory=list)   # found before any change
    seconds: float = 0.0
    steps: int = 0                      # waits of Options.wait (silence was an answer)


def file_problems(wanted: list[Wanted], serial_key: str = "serial_number") -> list[Problem]:
    """What the network file leaves open: two slaves with one full identity, and a slave
    without a serial number among several of one vendor-ID and product code."""
    out = []
    kinds: dict[tuple[int, int], list[Wanted]] = {}
    full: dict[tuple, Wanted] = {}
    for w in wanted:
        if not w.identified:
            continue
        kinds.setdefault((w.known[0], w.known[1]), []).append(w)
        if len(w.known) == 4:
            key = tuple(w.known[k] for k in range(4))
            if key in full:
                out.append(Problem(f"{w.label} has the identity of {full[key].label} "
                                   f"({L.Identity(*key).text()}): LSS cannot tell them "
                                   "apart", w.where))
            full.setdefault(key, w)
    for (vendor, product), group in kinds.items():
        if len(group) < 2:
            continue
        for w in group:
            if 3 not in w.known:
                others = ", ".join(o.label for o in group if o is not w)
                out.append(Problem(
                    f"{w.label} has no serial number ({serial_key}), but {others} "
                    f"{'has' if len(group) == 2 else 'have'} its vendor-ID 0x{vendor:08X} "
                    f"and product code 0x{product:08X}: LSS cannot tell which node is "
                    "which", w.where))
    return out


def commission(net, wanted: list[Wanted], options: Options, *,
               check_ids: bool = True) -> Result:
    """Find, check and assign (see above); ``problems`` in the result: nothing changed."""
    start = time.monotonic()
    master = L.Master(net, timeout=options.timeout, wait=options.wait)
    try:
        rows = [Row(w) for w in wanted]
        problems = _find_all(master, rows, options.serial_key)
        if check_ids:
            problems += _taken(net, rows, options)
        if not problems:
            for row in _order([r for r in rows if r.found_by not in (None, "SDO")]):
                _assign(master, net, row, options)
            _confirm(net, rows, options)
        return Result(rows, problems, time.monotonic() - start, master.steps)
    finally:
        master.close()


# -- 1. find ----------------------------------------------------------------------------------

def _find_all(m: L.Master, rows: list[Row], serial_key: str) -> list[Problem]:
    m.switch_global(configuration=False)
    problems = []
    for row in rows:
        w = row.wanted
        if not w.identified and 3 not in w.known:
            row.status, row.text = SKIPPED, ("its identity is not known (vendor-ID and "
                                             "product code, or a serial number)")
            continue
        found = _find(m, w)
        if len(found) == 1 and found[0][2] == IDENTIFY:     # ask its node-ID, count it
            identity = found[0][0]
            node_id, answers = _node_id_of(m, identity)
            found = [(identity, node_id, found[0][2])] * max(answers, 1)
        m.switch_global(configuration=False)     # back to waiting, none given a node-ID
        if len(found) > 1 and found[0][0] == found[1][0]:
            problems.append(Problem(f"{w.label}: {shared_text(found[0][0])}", w.where))
        elif len(found) > 1:
            problems.append(Problem(f"{w.label}: two nodes match its identity "
                                    f"({known_text(w.known)}): {_twins(w, found)}; the "
                                    f"network file must tell them apart ({serial_key})",
                                    w.where))
        elif found:
            row.identity, row.was, row.found_by = found[0]
    return problems


def shared_text(identity: L.Identity) -> str:
    """Nodes alike in all four parts of their identity: nothing LSS sends tells them apart."""
    return (f"two or more nodes answer to the identity {identity.text()} (or a node answers "
            "twice): LSS cannot tell them apart (give them distinct serial numbers)")


def _find(m: L.Master, w: Wanted) -> list[tuple[L.Identity | None, int | None, str]]:
    """The nodes that match: (identity, node-ID or None when not asked yet, how found); a
    second node found by fastscan is not scanned further (identity None). Nodes that
    share one whole identity answer one selective switch or fastscan together: each
    answer is one entry, all with that identity."""
    if len(w.known) == 4:
        identity = L.Identity(*(w.known[k] for k in range(4)))
        answers = m.select(identity)
        if not answers:
            return []
        return [(identity, _node_id_of(m, identity, switch_back=False)[0], SELECTIVE)] * answers
    skip = frozenset({2}) if 2 not in w.known and 3 in w.known else frozenset()
    _, parts = m.fastscan(w.known, skip)
    if parts is not None:
        answers = m.selected
        if 2 in skip:
            parts[2] = m.inquire(2)             # the one node in configuration
        if parts.get(2) is not None:
            identity = L.Identity(*(parts[k] for k in range(4)))
            found = [(identity, L.UNCONFIGURED, FASTSCAN)] * answers
            if answers == 1 and 0 in w.known and m.matches(w.known):   # the first stays
                found.append((None, L.UNCONFIGURED, FASTSCAN))         # in configuration
            return found
    if not w.identified:
        return []
    revisions = (w.known[2],) * 2 if 2 in w.known else (0, L.MAX32)
    serials = (w.known[3],) * 2 if 3 in w.known else (0, L.MAX32)
    return [(L.Identity(w.known[0], w.known[1], rev, serial), None, IDENTIFY)
            for rev, serial in m.search(w.known[0], w.known[1], revisions, serials)]


def _node_id_of(m: L.Master, identity: L.Identity,
                switch_back: bool = True) -> tuple[int | None, int]:
    """The node-ID of the node with this identity, and how many answered its selection
    (``switch_back`` False: it is selected already)."""
    answers = m.selected
    if switch_back:
        answers = m.select(identity)
        if not answers:
            return None, 0
    node_id = m.inquire_node_id()
    if switch_back:
        m.switch_global(configuration=False)
    return node_id, answers


def _twins(w: Wanted, found) -> str:
    """The nodes that match, each by the parts the network file does not give."""
    out = []
    for identity, _, _ in found:
        if identity is None:
            out.append("another node without a node-ID")
            continue
        out.append("the one with " + known_text({k: v for k, v in enumerate(identity.parts)
                                                  if k not in w.known}))
    return " and ".join(out)


def known_text(known: dict[int, int]) -> str:
    """The parts of an identity known, named: 'vendor-ID 0x000000AB, serial 0x00001001'."""
    return ", ".join(f"{L.PARTS[k]} 0x{v:08X}" for k, v in sorted(known.items()))


# -- 2. check ---------------------------------------------------------------------------------

def _taken(net, rows: list[Row], options: Options) -> list[Problem]:
    """Each slave's node-ID, asked by SDO: a node there that is no node found here has
    taken it -- unless it is a slave not found by LSS whose 0x1018 holds the identity
    the network file gives: that one is already right."""
    held = {r.was for r in rows if r.identity is not None}
    asked = {r.wanted.node_id: r for r in rows if r.status != SKIPPED}
    if not asked:
        return []
    scan = sc.scan(net, listen=0, timeout=options.check_wait, retries=0, ids=sorted(asked))
    out = []
    for node_id, row in sorted(asked.items()):
        f = scan.found.get(node_id)
        if f is None or not f.answered or node_id in held:
            continue
        read = {k: f.value(0x1018, k + 1) for k in range(4)}
        if row.identity is None and read[0] is not None and all(
                read[k] == v for k, v in row.wanted.known.items() if read[k] is not None):
            row.status, row.found_by, row.was = ALREADY, "SDO", node_id
            row.identity = L.Identity(*(read[k] if read[k] is not None
                                        else row.wanted.known.get(k, 0) for k in range(4)))
            continue
        out.append(Problem(f"{row.wanted.label}: node-ID {node_id} is taken: another node "
                           f"answers there ({_scanned_text(f)})", row.wanted.where))
    return out


def _scanned_text(f: sc.Found) -> str:
    parts = []
    for sub, name in zip((1, 2, 3, 4), L.PARTS):
        value = f.value(0x1018, sub)
        if value is not None:
            parts.append(f"{name} 0x{value:08X}")
    return ", ".join(parts) or "its identity cannot be read"


# -- 3. assign --------------------------------------------------------------------------------

def _order(rows: list[Row]) -> list[Row]:
    """Node-ID order, except that a node whose new node-ID another one holds comes after
    that one (a ring of them in node-ID order)."""
    rest = sorted(rows, key=lambda r: r.wanted.node_id)
    out = []
    while rest:
        free = next((r for r in rest if not any(o is not r and o.was == r.wanted.node_id
                                                for o in rest)), rest[0])
        rest.remove(free)
        out.append(free)
    return out


def _assign(m: L.Master, net, row: Row, options: Options) -> None:
    target = row.wanted.node_id
    moves = row.was != target
    if not moves and options.bitrate is None:
        row.status = ALREADY
        return
    # counted when it was found (_find): two nodes of one identity never get here
    if not m.select(row.identity, count=False):
        row.status, row.text = NO_ANSWER, "no answer to switch state selective"
        return
    steps = [lambda: m.configure_node_id(target)] if moves else []
    if options.bitrate is not None:
        steps.append(lambda: m.configure_bit_timing(options.bitrate))
    if options.store:
        steps.append(m.store)
    for step in steps:
        reply = step()
        if reply is None or not reply.ok:
            if moves and row.was is not None:
                m.configure_node_id(row.was)      # leave the node as it was
            m.switch_global(configuration=False)
            row.status = NO_ANSWER if reply is None else REFUSED
            row.reply, row.text = reply, ("no answer" if reply is None else reply.text())
            return
    row.status = ASSIGNED
    if options.bitrate is not None:
        row.text = f"bit rate {options.bitrate} bit/s from its next start"
    if not moves:
        m.switch_global(configuration=False)
        return
    boot = _BootUp(net, target)
    try:
        m.switch_global(configuration=False)      # a node without a node-ID starts here
        if row.was not in (None, L.UNCONFIGURED):
            net.send_message(0, bytes([NMT_RESET_COMMUNICATION, row.was]))
        row.booted = boot.wait(options.timeout)
    finally:
        boot.close()


class _BootUp:
    """Waits for the boot-up message (0x700 + node-ID, data 0) of one node."""

    def __init__(self, net, node_id: int):
        self.net, self.cob, self.event = net, 0x700 + node_id, threading.Event()
        net.subscribe(self.cob, self._on)

    def _on(self, can_id, data, timestamp) -> None:
        if bytes(data[:1]) == b"\0":
            self.event.set()

    def wait(self, timeout: float) -> bool:
        return self.event.wait(timeout)

    def close(self) -> None:
        self.net.unsubscribe(self.cob, self._on)


def _confirm(net, rows: list[Row], options: Options) -> None:
    """Each node assigned or already right answers SDO at its node-ID with the identity
    LSS found (the entries of 0x1018 it has), and is alone there: one SDO request, one
    answer."""
    done = {r.wanted.node_id: r for r in rows if r.status in (ASSIGNED, ALREADY)}
    if not done:
        return
    crowd = _answers_at(net, sorted(done), options.timeout, options.wait)
    scan = sc.scan(net, listen=0, timeout=options.timeout, retries=0, ids=sorted(done))
    for node_id, row in done.items():
        f = scan.found.get(node_id)
        if crowd.get(node_id, 0) > 1:
            row.answers = False
            row.text = _join(row.text, f"two nodes answer at node-ID {node_id} (or one "
                             "answers twice)")
            continue
        if f is None or not f.answered:
            row.answers = False
            row.text = _join(row.text, f"no SDO answer at node-ID {node_id}")
            continue
        wrong = [f"0x1018 sub {sub} ({name}) is 0x{f.value(0x1018, sub):08X}, not 0x{want:08X}"
                 for sub, name, want in zip((1, 2, 3, 4), L.PARTS, row.identity.parts)
                 if f.value(0x1018, sub) is not None and f.value(0x1018, sub) != want]
        row.answers = not wrong
        if wrong:
            row.text = _join(row.text, f"node-ID {node_id} answers, but its " + "; ".join(wrong))


def _answers_at(net, ids: list[int], timeout: float, wait: float) -> dict[int, int]:
    """One SDO upload of 0x1000 sub 0 to each node-ID of ``ids`` at once: the answer
    frames of each, counted until ``wait`` seconds after the last first answer (or
    ``timeout``). Nodes that share a node-ID all answer; one node answers once."""
    request = bytes([0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0])
    counts = dict.fromkeys(ids, 0)
    cond = threading.Condition()

    def on(can_id, data, timestamp):
        if bytes(data[1:4]) == request[1:4]:
            with cond:
                counts[can_id - sc.SDO_TX] += 1
                cond.notify_all()
    for node_id in ids:
        net.subscribe(sc.SDO_TX + node_id, on)
    try:
        for node_id in ids:
            sc._send(net, sc.SDO_RX + node_id, request)
        end = time.monotonic() + timeout
        with cond:
            while True:
                now = time.monotonic()
                if all(counts.values()) and end > now + wait:
                    end = now + wait            # every one answered: listen for a second
                if now >= end:
                    return dict(counts)
                cond.wait(end - now)
    finally:
        for node_id in ids:
            net.unsubscribe(sc.SDO_TX + node_id, on)


def _join(a: str, b: str) -> str:
    return f"{a}; {b}" if a else b


def ok(result: Result) -> bool:
    return not result.problems and all(r.status in OK and r.answers is not False
                                       for r in result.rows)

