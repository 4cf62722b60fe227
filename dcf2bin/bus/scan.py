"""Which nodes answer on the bus, and is each the device the master will accept (SPEC §10.5).

A scan listens for boot-up and heartbeat messages (0x700 + node-ID) and, at the same
time, sends an SDO upload of 0x1000 to every node-ID 1…127 back to back: every answer,
data or abort, is a node. Then 0x1018 sub 1…4 are read from the nodes that answered,
again one request to every node at once and one sub-index after the other. A round
ends as soon as every node asked has answered, so a scan of a bus whose nodes answer
is about as long as the listening window.

Worst case, whatever the nodes answer (no node answers a round before its time-out, or
each answers what ends its upload only then):

    max(listen, (retries + 1) × timeout) + 4 × (retries + 1) × timeout

which with the defaults (listen 0.5 s, timeout 0.3 s, no retry) is 1.7 s, plus the
time to send 127 requests at the bit rate (about 30 ms at 500 kbit/s, 120 ms at 125).

Each node's answers go through its own ``sdo.Upload`` (bus/sdo.py), so that all 127
uploads can be in flight at once: a segmented answer is read on within the same round,
and every entry read is an UNSIGNED32, so a node that announces or sends more than 4
bytes, toggles for ever, or answers a malformed frame or another entry's answer, has that
answer recorded as what it did (``Answer.problem``) and the round goes on. The
comparison with what the master enforces (0x1F84…0x1F88) is :func:`compare`; nothing
here imports click.
"""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass, field

from dcf2bin.bus import sdo
from dcf2bin.bus.link import abort_message, is_virtual

LISTEN, TIMEOUT, RETRIES = 0.5, 0.3, 0
NODE_IDS = range(1, 128)
HEARTBEAT = 0x700
SDO_TX, SDO_RX = 0x580, 0x600          # server → client, client → server
IDENTITY_SUBS = (1, 2, 3, 4)

# what the master enforces (CiA 302: 0x1F84…0x1F88) and the slave entry it compares
ENFORCED = {0x1F84: (0x1000, 0, "device type"), 0x1F85: (0x1018, 1, "vendor-ID"),
            0x1F86: (0x1018, 2, "product code"), 0x1F87: (0x1018, 3, "revision number"),
            0x1F88: (0x1018, 4, "serial number")}

_STATES = {0x00: "boot-up", 0x04: "stopped", 0x05: "operational", 0x7F: "pre-operational"}
_SEND_TRIES, _SEND_PAUSE = 200, 0.002   # a full transmit queue (socketcan's is 10 frames)


def worst_case(listen: float = LISTEN, timeout: float = TIMEOUT, retries: int = RETRIES) -> float:
    """Seconds a scan takes at most, whatever the nodes answer (see above)."""
    per = (retries + 1) * timeout
    return max(listen, per) + len(IDENTITY_SUBS) * per


@dataclass
class Answer:
    """What one node-ID gave for one entry: ``data``, an abort ``code``, an answer that is
    none (``problem``: what the node did, "answered a 3-byte frame to ..."), or nothing."""
    data: bytes | None = None
    code: int | None = None
    segmented: bool = False
    problem: str | None = None

    @property
    def value(self) -> int | None:
        if self.data is None or not self.data:
            return None
        return int.from_bytes(self.data[:4], "little")


@dataclass
class Found:
    """A node that was heard or answered."""
    node_id: int
    heard: str | None = None                 # the NMT state of its last boot-up/heartbeat
    answered: bool = False                   # it answered an SDO request
    entries: dict[tuple[int, int], Answer] = field(default_factory=dict)

    def value(self, index: int, sub: int) -> int | None:
        a = self.entries.get((index, sub))
        return a.value if a is not None else None

    @property
    def device_type(self) -> int | None:
        return self.value(0x1000, 0)


@dataclass
class Expected:
    """A node the network file names, and what the master enforces of it (0x1F84… → value;
    only the nonzero ones: a zero turns that check off)."""
    node_id: int
    name: str
    identity: dict[int, int] = field(default_factory=dict)
    master: bool = False
    from_file: bool = False      # a .cpj node: the identity its own DCF states, no master

    def expects(self, key: int, want: int) -> str:
        return expects(key, want, self.from_file)


def expects(key: int, want: int, from_file: bool) -> str:
    """Whose is the identity value ``want`` of 0x1F84… ``key``: the master's, or with
    ``from_file`` (a .cpj node) the node's own DCF's."""
    if from_file:
        return f"its DCF states 0x{want:08X}"
    return f"the master expects 0x{want:08X} (0x{key:04X})"


@dataclass
class Finding:
    kind: str                    # "missing", "unexpected", "mismatch", "unread", "silent"
    node_id: int
    name: str | None             # the network's name of the node (None: not in the network)
    text: str
    entry: tuple[int, int] | None = None
    expected: int | None = None
    actual: int | None = None
    code: int | None = None      # SDO abort code of an unreadable entry

    def as_dict(self) -> dict:
        d = {"kind": self.kind, "node_id": self.node_id, "name": self.name, "text": self.text}
        if self.entry is not None:
            d["index"], d["sub"] = self.entry
        for key in ("expected", "actual", "code"):
            if getattr(self, key) is not None:
                d[key] = getattr(self, key)
        return d


@dataclass
class Scan:
    found: dict[int, Found]
    seconds: float
    virtual: bool = False        # on python-can's virtual bus (the table says what it reaches)


class _Round:
    """One SDO upload of ``index``/``sub`` from every node-ID of ``ids`` at once, each
    node's answers taken by its own ``sdo.Upload`` (a segmented answer is read on at once,
    from the notifier thread); collects the answers. An answer for an entry asked in an
    earlier round (``earlier``) is a late one and passed over."""

    def __init__(self, net, ids, index: int, sub: int, earlier=()):
        self.net, self.ids, self.index, self.sub = net, list(ids), index, sub
        self.earlier = {index.to_bytes(2, "little") + bytes([sub]) for index, sub in earlier}
        self.answers: dict[int, Answer] = {}
        self.uploads: dict[int, object] = {}
        self.lock = threading.Lock()
        self.done = threading.Event()
        self.callbacks = {}

    def _on(self, node_id: int):
        def callback(can_id, data, timestamp):
            frame = bytes(data)
            if len(frame) == 8 and frame[0] & 0xE0 in (0x40, 0x80) and frame[1:4] in self.earlier:
                return               # a late answer to an earlier round
            with self.lock:
                m = self.uploads.get(node_id)
                if m is None or node_id in self.answers:
                    return
                try:
                    request = m.take(frame)
                except sdo.Aborted as exc:
                    self._answer(node_id, Answer(code=exc.code))
                except sdo.SdoError as exc:
                    self._answer(node_id, Answer(problem=exc.what))
                else:
                    if request is None:
                        self._answer(node_id, Answer(data=bytes(m.data),
                                                     segmented=m.segmented))
                    else:
                        _send(self.net, SDO_RX + node_id, request)
        return callback

    def _answer(self, node_id: int, answer: Answer) -> None:
        self.answers[node_id] = answer
        if len(self.answers) == len(self.ids):
            self.done.set()

    def run(self, timeout: float, retries: int) -> dict[int, Answer]:
        for node_id in self.ids:
            cb = self._on(node_id)
            self.callbacks[node_id] = cb
            self.net.subscribe(SDO_TX + node_id, cb)
        try:
            for _ in range(retries + 1):
                with self.lock:
                    waiting = [i for i in self.ids if i not in self.answers]
                    for node_id in waiting:     # each try starts the upload again
                        self.uploads[node_id] = sdo.Upload(self.index, self.sub, max_size=4)
                if not waiting:
                    break
                for node_id in waiting:
                    _send(self.net, SDO_RX + node_id, self.uploads[node_id].request)
                self.done.wait(timeout)
        finally:
            for node_id, cb in self.callbacks.items():
                self.net.unsubscribe(SDO_TX + node_id, cb)
        with self.lock:
            return dict(self.answers)


def _send(net, can_id: int, data: bytes) -> None:
    """Send one frame; a full transmit queue is waited out (up to 0.4 s)."""
    import can
    for attempt in range(_SEND_TRIES):
        try:
            net.send_message(can_id, data)
            return
        except can.CanOperationError:
            if attempt == _SEND_TRIES - 1:
                raise
            time.sleep(_SEND_PAUSE)


def scan(net, *, listen: float = LISTEN, timeout: float = TIMEOUT, retries: int = RETRIES,
         ids=NODE_IDS) -> Scan:
    """Listen and ask every node-ID of ``ids``; the nodes heard or answering."""
    start = time.monotonic()
    found: dict[int, Found] = {}
    lock = threading.Lock()

    def heard(can_id, data, timestamp):
        node_id = can_id - HEARTBEAT
        if not data:
            return
        state = _STATES.get(data[0] & 0x7F, f"state 0x{data[0] & 0x7F:02X}")
        with lock:
            found.setdefault(node_id, Found(node_id)).heard = state

    hb = {i: HEARTBEAT + i for i in ids}
    for cob in hb.values():
        net.subscribe(cob, heard)
    try:
        probe = _Round(net, ids, 0x1000, 0)
        answers = probe.run(timeout, retries)
        rest = listen - (time.monotonic() - start)
        if rest > 0:
            time.sleep(rest)
    finally:
        for cob in hb.values():
            net.unsubscribe(cob, heard)
    with lock:
        for node_id, a in answers.items():
            f = found.setdefault(node_id, Found(node_id))
            f.answered = True
            f.entries[(0x1000, 0)] = a
    present = sorted(i for i, f in found.items() if f.answered)
    asked = [(0x1000, 0)]
    for sub in IDENTITY_SUBS:
        got = (_Round(net, present, 0x1018, sub, asked).run(timeout, retries) if present
               else {})
        asked.append((0x1018, sub))
        for node_id in present:
            found[node_id].entries[(0x1018, sub)] = got.get(node_id, Answer())
    return Scan(dict(sorted(found.items())), time.monotonic() - start, is_virtual(net))


# -- the comparison -------------------------------------------------------------------------

def entry_label(index: int, sub: int) -> str:
    """An identity entry as messages name it (0x1000 has no sub-index to name)."""
    return f"0x{index:04X}" if index == 0x1000 else f"0x{index:04X} sub {sub}"


def compare(scan_: Scan, expected: list[Expected]) -> list[Finding]:
    """Missing nodes, unexpected nodes, and each present node's entries against what the
    master enforces, in node-ID order. The master's own node-ID is never missing nor
    unexpected, and nothing is enforced of it."""
    by_id = {e.node_id: e for e in expected}
    out: list[Finding] = []
    for node_id in sorted(set(by_id) | set(scan_.found)):
        e, f = by_id.get(node_id), scan_.found.get(node_id)
        if e is not None and e.master:
            continue
        if e is None:
            what = "answers" if f.answered else f"is heard ({f.heard})"
            dtype = f.device_type
            more = f", device type 0x{dtype:08X}" if dtype is not None else ""
            out.append(Finding("unexpected", node_id, None,
                               f"node {node_id} {what} but is not in the network{more}"))
            continue
        label = f"node {node_id} ({e.name})"
        if f is None:
            out.append(Finding("missing", node_id, e.name,
                               f"{label} is in the network but does not answer"))
            continue
        if not f.answered:
            out.append(Finding("silent", node_id, e.name,
                               f"{label} is heard ({f.heard}) but does not answer SDO "
                               "requests: its identity cannot be read"))
            continue
        for key in sorted(e.identity):
            want = e.identity[key]
            index, sub, what = ENFORCED[key]
            a = f.entries.get((index, sub), Answer())
            where = f"{entry_label(index, sub)} ({what})"
            if a.code is not None:
                out.append(Finding("unread", node_id, e.name,
                                   f"{label}: {where} cannot be read: "
                                   f"{abort_message(a.code)}; "
                                   f"{e.expects(key, want)}", (index, sub), want, None,
                                   a.code))
            elif a.problem is not None:
                out.append(Finding("unread", node_id, e.name,
                                   f"{label} {a.problem}; {e.expects(key, want)}",
                                   (index, sub), want))
            elif a.value is None:
                out.append(Finding("unread", node_id, e.name,
                                   f"{label}: {where} was not answered; "
                                   f"{e.expects(key, want)}", (index, sub), want))
            elif a.value != want:
                out.append(Finding("mismatch", node_id, e.name,
                                   f"{label}: {where} is 0x{a.value:08X}, "
                                   f"{e.expects(key, want)}"
                                   + ("" if e.from_file else ": it will not boot this node"),
                                   (index, sub), want, a.value))
    return out
