"""Which nodes answer on the bus, and is each the device the master will accept (SPEC §10.5).

A scan listens for boot-up and heartbeat messages (0x700 + node-ID) and, at the same
time, sends an SDO upload of 0x1000 to every node-ID 1…127 back to back: every answer,
data or abort, is a node. Then 0x1018 sub 1…4 are read from the nodes that answered,
again one request to every node at once and one sub-index after the other. A round
ends as soon as every node asked has answered, so a scan of a bus whose nodes answer
is about as long as the listening window.

Worst case (no node answers a round before its time-out):

    max(listen, (retries + 1) × timeout) + 4 × (retries + 1) × timeout
    (+ (retries + 1) × timeout when a node answers 0x1000 segmented, which is not CiA 301's way)

which with the defaults (listen 0.5 s, timeout 0.3 s, no retry) is 1.7 s, plus the
time to send 127 requests at the bit rate (about 30 ms at 500 kbit/s, 120 ms at 125).

The requests are SDO upload-initiate frames (CiA 301 §7.2.4.3.3): the one part of the SDO
protocol spoken here, so that all 127 can be in flight at once; an answer that is not an
expedited upload (a segmented one) is read again through canopen's SDO client. The
comparison with what the master enforces (0x1F84…0x1F88) is :func:`compare`; nothing
here imports click.
"""
from __future__ import annotations

import struct
import threading
import time
from dataclasses import dataclass, field

from dcf2bin.bus.link import abort_text

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
    """Seconds a scan takes at most when 0x1000 is answered expedited (see above)."""
    per = (retries + 1) * timeout
    return max(listen, per) + len(IDENTITY_SUBS) * per


@dataclass
class Answer:
    """What one node-ID gave for one entry: ``data``, an abort ``code``, or nothing."""
    data: bytes | None = None
    code: int | None = None
    segmented: bool = False

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
        if self.from_file:
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


class _Round:
    """One SDO upload request to every node-ID of ``ids`` at once; collects the answers."""

    def __init__(self, net, ids, index: int, sub: int):
        self.net, self.ids, self.index, self.sub = net, list(ids), index, sub
        self.answers: dict[int, Answer] = {}
        self.lock = threading.Lock()
        self.done = threading.Event()
        self.mux = struct.pack("<HB", index, sub)
        self.callbacks = {}

    def _on(self, node_id: int):
        def callback(can_id, data, timestamp):
            data = bytes(data)
            if len(data) < 8 or data[1:4] != self.mux:
                return               # a late answer of another round, or not ours
            cmd = data[0]
            if cmd == 0x80:
                answer = Answer(code=int.from_bytes(data[4:8], "little"))
            elif cmd & 0xE0 == 0x40:
                if cmd & 0x02:       # expedited: the data are in the frame
                    n = (cmd >> 2) & 3 if cmd & 0x01 else 0
                    answer = Answer(data=data[4:8 - n])
                else:
                    answer = Answer(segmented=True)
            else:
                return
            with self.lock:
                if node_id in self.answers:
                    return
                self.answers[node_id] = answer
                if len(self.answers) == len(self.ids):
                    self.done.set()
        return callback

    def run(self, timeout: float, retries: int) -> dict[int, Answer]:
        for node_id in self.ids:
            cb = self._on(node_id)
            self.callbacks[node_id] = cb
            self.net.subscribe(SDO_TX + node_id, cb)
        try:
            for _ in range(retries + 1):
                with self.lock:
                    waiting = [i for i in self.ids if i not in self.answers]
                if not waiting:
                    break
                request = bytes([0x40]) + self.mux + bytes(4)
                for node_id in waiting:
                    _send(self.net, SDO_RX + node_id, request)
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
    for sub in IDENTITY_SUBS:
        got = _Round(net, present, 0x1018, sub).run(timeout, retries) if present else {}
        for node_id in present:
            found[node_id].entries[(0x1018, sub)] = got.get(node_id, Answer())
    _reread_segmented(net, found, timeout, retries)
    return Scan(dict(sorted(found.items())), time.monotonic() - start)


def _reread_segmented(net, found: dict[int, Found], timeout: float, retries: int) -> None:
    """Entries answered as a segmented upload, read through canopen's SDO client."""
    from canopen import SdoAbortedError, SdoCommunicationError

    from dcf2bin.bus.download import sdo_client
    for f in found.values():
        for (index, sub), a in f.entries.items():
            if not a.segmented:
                continue
            sdo = sdo_client(net, f.node_id, timeout=timeout, retries=retries)
            try:
                f.entries[(index, sub)] = Answer(data=sdo.upload(index, sub))
            except SdoAbortedError as exc:
                f.entries[(index, sub)] = Answer(code=exc.code)
            except SdoCommunicationError:
                f.entries[(index, sub)] = Answer()


# -- the comparison -------------------------------------------------------------------------

def _entry(index: int, sub: int) -> str:
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
            where = f"{_entry(index, sub)} ({what})"
            if a.code is not None:
                out.append(Finding("unread", node_id, e.name,
                                   f"{label}: {where} cannot be read: SDO abort "
                                   f"0x{a.code:08X}: {abort_text(a.code)}; "
                                   f"{e.expects(key, want)}", (index, sub), want, None,
                                   a.code))
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
