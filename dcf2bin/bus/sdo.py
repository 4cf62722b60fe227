"""The SDO client of dcf2bin: expedited and segmented upload and download (CiA 301 §7.2.4),
each transfer bounded in time and in bytes, each answer matched to its request.

canopen's ``SdoClient`` reads a segmented upload until the node says it is the last
segment: a node that never says so is read for ever, and a frame shorter than 8 bytes
escapes as ``struct.error``. Here the protocol is two small state machines (``Upload``,
``Download``: a frame in, the next request out) and one ``Channel`` that runs them on a
``canopen.Network``, so that every way a transfer can end is one ``SdoError`` whose text
says what the node did:

* a transfer of N bytes is 1 + ceil(N / 7) exchanges (request, answer), each waited for
  at most ``timeout`` and sent at most ``retries + 1`` times: ``bound(N, timeout,
  retries)`` seconds in all, and the transfer is given up when that has passed;
* an upload reads at most ``max_size`` bytes (the largest the entry can be): a node that
  announces more, or sends more than it announced, or more than ``max_size``, is stopped;
* every answer must be the 8-byte frame the request asks for, for the same index and
  sub-index, with the toggle bit alternating; anything else is named as heard
  ("answered a 3-byte frame to an SDO upload of 0x1018 sub 1");
* a node that answers twice is said to (except the late answers of a request that was
  sent again after a time-out, which any slow node gives);
* with ``watch_restarts()``, a boot-up message (0x700 + node-ID, data 0x00) is a
  ``Restarted`` error at the next exchange: the node lost what it was written.

Block transfer is not used. The scan asks all 127 nodes at once with the same ``Upload``
machine (bus/scan.py); everything else goes through a ``Channel``:

    with Channel(net, 5, timeout=1.0, retries=2) as ch:
        ch.download(0x1017, 0, b"\\xc8\\x00")
        vendor = ch.upload(0x1018, 1, max_size=4)
"""
from __future__ import annotations

import queue
import time

from dcf2bin.bus.link import VIRTUAL_NOTE, abort_message, is_virtual

SDO_TX, SDO_RX, HEARTBEAT = 0x580, 0x600, 0x700     # server -> client, client -> server
MAX_DOMAIN = 1 << 20      # default bound of an upload whose type has no size (DOMAIN, strings)

# client command specifiers (bits 7..5 of the first byte)
_INIT_DOWNLOAD, _DOWNLOAD_SEGMENT, _INIT_UPLOAD, _UPLOAD_SEGMENT = 0x20, 0x00, 0x40, 0x60
_ABORT = 0x80
# server command specifiers
_UPLOAD_SEGMENT_ANSWER, _DOWNLOAD_SEGMENT_ANSWER = 0x00, 0x20
_INIT_UPLOAD_ANSWER, _INIT_DOWNLOAD_ANSWER = 0x40, 0x60
# abort codes the client sends when it gives up a transfer
TOGGLE, TIMED_OUT, BAD_COMMAND, OUT_OF_MEMORY = 0x05030000, 0x05040000, 0x05040001, 0x05040005
GENERAL = 0x08000000


class SdoError(Exception):
    """An SDO transfer that did not end as it should. ``what`` is the plain reason with
    the node left out ("answered a 3-byte frame to an SDO upload of 0x1018 sub 1");
    ``str()`` puts the node in front once ``node_id`` is known."""

    def __init__(self, what: str, node_id: int | None = None):
        super().__init__(what)
        self.what, self.node_id = what, node_id

    def __str__(self) -> str:
        return self.what if self.node_id is None else f"node {self.node_id} {self.what}"


class Aborted(SdoError):
    """The node answered with an SDO abort."""

    def __init__(self, code: int, node_id: int | None = None):
        super().__init__(abort_message(code), node_id)
        self.code = code


class NoAnswer(SdoError):
    """No answer within ``timeout``, ``tries`` times (``virtual``: on python-can's
    virtual bus, which the message says)."""

    def __init__(self, tries: int, timeout: float, node_id: int | None = None,
                 virtual: bool = False):
        note = f"; {VIRTUAL_NOTE}" if virtual else ""
        super().__init__(f"did not answer (no SDO response within {timeout:g} s, {tries} "
                         f"{'try' if tries == 1 else 'tries'}{note})", node_id)
        self.tries, self.timeout = tries, timeout


class Restarted(SdoError):
    """A boot-up message of the node was heard while it was being written."""


def entry_name(index: int, sub: int) -> str:
    return f"0x{index:04X} sub {sub}"


def exchanges(size: int) -> int:
    """Request/answer pairs a transfer of ``size`` bytes needs at most: the initiation and
    one for each segment of up to 7 bytes (at least one: a node may answer even a short
    value segmented)."""
    return 1 + max(1, -(-size // 7))


def bound(size: int, timeout: float, retries: int) -> float:
    """Seconds a transfer of ``size`` bytes is given: each exchange waited for at most
    ``timeout``, ``retries + 1`` times."""
    return exchanges(size) * (retries + 1) * timeout


def _heard(frame: bytes) -> str:
    """What a frame from the node is, in words (for the messages)."""
    if len(frame) != 8:
        return f"a {len(frame)}-byte frame"
    cmd = frame[0] & 0xE0
    mux = entry_name(int.from_bytes(frame[1:3], "little"), frame[3])
    return {_INIT_UPLOAD_ANSWER: f"an upload answer for {mux}",
            _INIT_DOWNLOAD_ANSWER: f"a download answer for {mux}",
            _ABORT: f"an SDO abort for {mux}",
            _UPLOAD_SEGMENT_ANSWER: "an upload segment",
            _DOWNLOAD_SEGMENT_ANSWER: "a download segment answer"}.get(
                cmd, f"a frame with command byte 0x{frame[0]:02X}")


def _abort_frame(index: int, sub: int, code: int) -> bytes:
    return bytes([_ABORT]) + index.to_bytes(2, "little") + bytes([sub]) + code.to_bytes(4, "little")


class _Transfer:
    """What both directions share: the request to send, the checks of an answer."""

    op = ""

    def __init__(self, index: int, sub: int):
        self.index, self.sub = index, sub
        self.mux = index.to_bytes(2, "little") + bytes([sub])
        self.toggle = 0
        self.segment = 0           # segments exchanged so far
        self.request = b""
        self.give_up = GENERAL     # the abort code to send if the transfer is given up

    @property
    def name(self) -> str:
        return f"an SDO {self.op} of {entry_name(self.index, self.sub)}"

    def fail(self, what: str, code: int = GENERAL) -> SdoError:
        self.give_up = code
        return SdoError(what)

    def check(self, frame: bytes, expect: int) -> None:
        """``frame`` must be the 8-byte answer ``expect`` (a server command specifier)."""
        if len(frame) != 8:
            raise self.fail(f"answered a {len(frame)}-byte frame to {self.name}")
        cmd = frame[0] & 0xE0
        if cmd == _ABORT:
            if frame[1:4] != self.mux:
                raise self.fail(f"answered {self.name} with {_heard(frame)}")
            self.give_up = 0       # the node ended it itself
            raise Aborted(int.from_bytes(frame[4:8], "little"))
        if cmd != expect:
            raise self.fail(f"answered {self.name} with {_heard(frame)}", BAD_COMMAND)
        if expect in (_INIT_UPLOAD_ANSWER, _INIT_DOWNLOAD_ANSWER) and frame[1:4] != self.mux:
            raise self.fail(f"answered {self.name} with {_heard(frame)}", BAD_COMMAND)
        if expect in (_UPLOAD_SEGMENT_ANSWER, _DOWNLOAD_SEGMENT_ANSWER) and \
                frame[0] & 0x10 != self.toggle:
            raise self.fail(f"did not alternate the toggle bit in segment {self.segment + 1} "
                            f"of {self.name}", TOGGLE)

    def abort_request(self) -> bytes | None:
        """The abort frame to send when the transfer is given up (None: nothing to end)."""
        if not self.give_up:
            return None
        return _abort_frame(self.index, self.sub, self.give_up)


class Upload(_Transfer):
    """The client side of one upload: ``request`` is the frame to send; ``take(answer)``
    returns the next request, or None when ``data`` is complete; it raises ``SdoError``."""

    op = "upload"

    def __init__(self, index: int, sub: int, max_size: int = MAX_DOMAIN):
        super().__init__(index, sub)
        self.max_size = max_size
        self.expected = max_size       # bytes expected: max_size, then what the node announces
        self.announced: int | None = None
        self.data = bytearray()
        self.segmented = False
        self.request = bytes([_INIT_UPLOAD]) + self.mux + bytes(4)

    def take(self, frame: bytes) -> bytes | None:
        if not self.segmented:
            return self._initiated(frame)
        self.check(frame, _UPLOAD_SEGMENT_ANSWER)
        cmd = frame[0]
        n = 7 - ((cmd >> 1) & 7)
        last = bool(cmd & 0x01)
        if not last and n == 0:
            raise self.fail(f"sent segment {self.segment + 1} of {self.name} without data "
                            "and without ending the transfer", BAD_COMMAND)
        self.data += frame[1:1 + n]
        self.segment += 1
        if len(self.data) > self.expected:
            raise self.fail(self._overlong(), OUT_OF_MEMORY)
        if last:
            self.give_up = 0
            if self.announced is not None and len(self.data) != self.announced:
                raise self.fail(f"ended {self.name} after {len(self.data)} of the "
                                f"{self.announced} bytes it announced", 0)
            return None
        self.toggle ^= 0x10
        self.request = bytes([_UPLOAD_SEGMENT | self.toggle]) + bytes(7)
        return self.request

    def _overlong(self) -> str:
        if self.announced is not None:
            return f"sent more than the {self.announced} bytes it announced for {self.name}"
        return f"sent more than {self.max_size} bytes for {self.name} without ending it"

    def _initiated(self, frame: bytes) -> bytes | None:
        self.check(frame, _INIT_UPLOAD_ANSWER)
        cmd = frame[0]
        if cmd & 0x02:                          # expedited: the data are in the frame
            self.give_up = 0
            n = 4 - ((cmd >> 2) & 3) if cmd & 0x01 else 4
            if n > self.max_size:
                raise self.fail(f"answered {n} bytes to {self.name}, more than the "
                                f"{self.max_size} it can hold", 0)
            self.data = bytearray(frame[4:4 + n])
            return None
        self.segmented = True
        if cmd & 0x01:
            self.announced = int.from_bytes(frame[4:8], "little")
            if self.announced > self.max_size:
                raise self.fail(f"announced {self.announced} bytes for {self.name}, more "
                                f"than the {self.max_size} expected", OUT_OF_MEMORY)
            self.expected = self.announced
        self.request = bytes([_UPLOAD_SEGMENT]) + bytes(7)
        return self.request


class Download(_Transfer):
    """The client side of one download (expedited up to 4 bytes, else segmented)."""

    op = "download"

    def __init__(self, index: int, sub: int, data: bytes):
        super().__init__(index, sub)
        self.data = bytes(data)
        self.expected = len(self.data)
        self.pos = 0
        self.started = False           # the node took the initiate request
        n = len(self.data)
        self.expedited = 1 <= n <= 4
        if self.expedited:
            cmd = _INIT_DOWNLOAD | 0x03 | ((4 - n) << 2)
            self.request = bytes([cmd]) + self.mux + self.data.ljust(4, b"\0")
        else:
            self.request = bytes([_INIT_DOWNLOAD | 0x01]) + self.mux + n.to_bytes(4, "little")

    def take(self, frame: bytes) -> bytes | None:
        if not self.started:
            self.check(frame, _INIT_DOWNLOAD_ANSWER)
            self.started = True
            if self.expedited:
                self.give_up = 0
                return None
            return self._next_segment()
        self.check(frame, _DOWNLOAD_SEGMENT_ANSWER)
        self.segment += 1
        self.toggle ^= 0x10
        if self.pos >= len(self.data):
            self.give_up = 0
            return None
        return self._next_segment()

    def _next_segment(self) -> bytes:
        chunk = self.data[self.pos:self.pos + 7]
        self.pos += len(chunk)
        last = self.pos >= len(self.data)
        cmd = _DOWNLOAD_SEGMENT | self.toggle | ((7 - len(chunk)) << 1) | (0x01 if last else 0)
        self.request = bytes([cmd]) + chunk.ljust(7, b"\0")
        return self.request


class Channel:
    """One SDO channel to one node (requests on 0x600 + node-ID, answers on 0x580 +
    node-ID) on a connected ``canopen.Network``; close it (or use it as a context manager)
    to stop listening. ``watch_restarts()`` turns the node's boot-up messages into
    ``Restarted``."""

    def __init__(self, net, node_id: int, *, timeout: float, retries: int):
        self.net, self.node_id, self.timeout, self.retries = net, node_id, timeout, retries
        self.frames: queue.SimpleQueue = queue.SimpleQueue()
        self.watching = False
        self.last: tuple[bytes, str] | None = None   # the last answer, and to what
        self.echoes = 0          # late answers still allowed: one per extra try of the last
        self.virtual = is_virtual(net)
        self._subs = [(SDO_TX + node_id, self._on_sdo), (HEARTBEAT + node_id, self._on_state)]
        for cob, cb in self._subs:
            net.subscribe(cob, cb)

    @property
    def tries(self) -> int:
        return self.retries + 1

    # -- frames from the notifier thread, in the order they were received --------------------
    def _on_sdo(self, can_id, data, timestamp) -> None:
        self.frames.put(("sdo", bytes(data)))

    def _on_state(self, can_id, data, timestamp) -> None:
        if len(data) >= 1 and data[0] & 0x7F == 0:      # a boot-up message
            self.frames.put(("boot", bytes(data)))

    def close(self) -> None:
        for cob, cb in self._subs:
            if cb in self.net.subscribers.get(cob, ()):
                self.net.unsubscribe(cob, cb)
        self._subs = []

    def __enter__(self) -> Channel:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def watch_restarts(self) -> None:
        """From now on a boot-up message of the node is an error (earlier ones are not)."""
        self.check_between()
        self.watching = True

    def check_between(self) -> None:
        """The frames that came since the last answer: a boot-up (watched) is
        ``Restarted``, an answer nobody asked for an ``SdoError``."""
        while True:
            try:
                kind, frame = self.frames.get_nowait()
            except queue.Empty:
                return
            if not self._passed_over(kind, frame):
                raise self._unasked(frame)

    # -- transfers -------------------------------------------------------------------------
    def upload(self, index: int, sub: int, *, max_size: int = MAX_DOMAIN,
               deadline: float | None = None) -> bytes:
        """The value of an entry, at most ``max_size`` bytes; ``SdoError`` otherwise.
        ``deadline`` (a ``time.monotonic()`` value) ends the transfer before its own
        bound when it comes first."""
        m = Upload(index, sub, max_size)
        self._run(m, deadline)
        return bytes(m.data)

    def download(self, index: int, sub: int, data: bytes, *,
                 deadline: float | None = None) -> None:
        """Write ``data`` to an entry; ``SdoError`` when the node does not take it."""
        self._run(Download(index, sub, data), deadline)

    def _run(self, m: _Transfer, deadline: float | None) -> None:
        start = time.monotonic()
        try:
            self.check_between()
            request = m.request
            while request is not None:
                end = start + bound(m.expected, self.timeout, self.retries)
                if deadline is not None:
                    end = min(end, deadline)
                frame = self._exchange(request, m, end, max(end - start, 0.0))
                try:
                    request = m.take(frame)
                except Aborted:
                    raise
                except SdoError:
                    if self.last is not None and frame == self.last[0]:
                        raise SdoError(f"answered {self.last[1]} twice") from None
                    raise
                finally:
                    self.last = (frame, m.name)
        except SdoError as exc:
            exc.node_id = self.node_id
            give_up = m.abort_request()
            if give_up is not None and not isinstance(exc, Restarted):
                self._send(give_up, quiet=True)
            raise

    def _exchange(self, request: bytes, m: _Transfer, end: float, given: float) -> bytes:
        """Send ``request`` (again after each time-out) and return the node's answer; the
        transfer ends at ``end``, ``given`` seconds after it started."""
        tries = 0
        while True:
            now = time.monotonic()
            if tries == self.tries:
                m.give_up = TIMED_OUT
                raise NoAnswer(tries, self.timeout, virtual=self.virtual)
            if now >= end:
                m.give_up = TIMED_OUT
                raise SdoError(f"did not end {m.name} within {given:.3g} s")
            self._send(request)
            tries += 1
            wait_end = min(now + self.timeout, end)
            while True:
                try:
                    kind, frame = self.frames.get(timeout=max(wait_end - time.monotonic(), 0))
                except queue.Empty:
                    break
                if self._passed_over(kind, frame):
                    continue
                self.echoes = tries - 1
                return frame

    def _passed_over(self, kind: str, frame: bytes) -> bool:
        """A frame that is no answer: a late answer to a request sent again after a
        time-out, a boot-up message before ``watch_restarts`` (after it: ``Restarted``)."""
        if kind == "boot":
            if self.watching:
                raise Restarted("restarted (its boot-up message was heard)",
                                self.node_id)
            return True
        if self.last is not None and frame == self.last[0] and self.echoes > 0:
            self.echoes -= 1
            return True
        return False

    def _unasked(self, frame: bytes) -> SdoError:
        if self.last is not None and frame == self.last[0]:
            return SdoError(f"answered {self.last[1]} twice", self.node_id)
        after = f" after {self.last[1]}" if self.last is not None else ""
        return SdoError(f"sent {_heard(frame)} that was not asked for{after}", self.node_id)

    def _send(self, frame: bytes, quiet: bool = False) -> None:
        import can
        try:
            self.net.send_message(SDO_RX + self.node_id, frame)
        except can.CanError as exc:
            if not quiet:
                raise SdoError(f"could not be sent an SDO request: {exc}") from None
