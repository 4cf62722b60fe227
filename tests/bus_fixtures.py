"""Fixtures of the bus tests, loaded as a plugin (``pytest_plugins = ["bus_fixtures"]``):
a virtual bus of each test's own, a check that no thread outlives a test, and ``at_root``
so that paths in messages read ``samples/device.dcf:84``."""
from __future__ import annotations

import itertools
import threading
import time

import pytest

from bus_helpers import Bench, threads_settle
from conftest import ROOT

_names = itertools.count()


@pytest.fixture
def no_threads_left():
    before = {t.ident for t in threading.enumerate()}
    yield
    assert threads_settle(before) == []


@pytest.fixture
def at_root(monkeypatch):
    """Paths in messages are relative to the repository (samples/device.dcf:84)."""
    monkeypatch.chdir(ROOT)


@pytest.fixture
def channel(no_threads_left, at_root):
    """A virtual bus of this test's own."""
    return f"dcf2bin-test-{next(_names)}-{time.monotonic_ns()}"


@pytest.fixture
def bench(channel):
    b = Bench(channel)
    yield b
    b.close()


# -- software nodes that misbehave on purpose (issue 26, items 9-11) --------------------------
#
# Each takes a node already on the bench (bench.device(...)) and puts itself between the
# bus and the node's canopen SDO server: ``handle(request, serve, send)`` gets every
# request, ``serve()`` lets the real server answer it, ``send(frame)`` sends a frame of its
# own on 0x580 + node-ID.

def _mux(frame: bytes) -> tuple[int, int]:
    return int.from_bytes(frame[1:3], "little"), frame[3]


class Misbehaving:
    """Puts ``handle`` between the bus and ``node``'s SDO server."""

    def __init__(self, node):
        self.node, self.net = node, node.network
        self.requests: list[bytes] = []
        self.net.unsubscribe(node.sdo.rx_cobid, node.sdo.on_request)
        self.net.subscribe(node.sdo.rx_cobid, self._on)
        node.misbehaving = self        # Bench.close gives the node its own server back

    def undo(self) -> None:
        self.net.unsubscribe(self.node.sdo.rx_cobid, self._on)
        self.net.subscribe(self.node.sdo.rx_cobid, self.node.sdo.on_request)

    def _on(self, can_id, data, timestamp) -> None:
        frame = bytes(data)
        self.requests.append(frame)
        self.handle(frame, lambda: self.node.sdo.on_request(can_id, data, timestamp),
                    self.send)

    def send(self, frame: bytes) -> None:
        self.net.send_message(0x580 + self.node.id, frame)

    def handle(self, request: bytes, serve, send) -> None:
        serve()


class TogglesForever(Misbehaving):
    """Answers an upload of one entry segmented and never sends the last segment: every
    segment request gets 7 more bytes, the toggle bit right ("size" given: announces it)."""

    def __init__(self, node, index: int, sub: int, size: int | None = None):
        super().__init__(node)
        self.entry, self.size, self.segments = (index, sub), size, 0

    def handle(self, request, serve, send):
        if request[0] & 0xE0 == 0x40 and _mux(request) == self.entry:      # initiate upload
            if self.size is None:
                send(bytes([0x40]) + request[1:4] + bytes(4))
            else:
                send(bytes([0x41]) + request[1:4] + self.size.to_bytes(4, "little"))
        elif request[0] & 0xE0 == 0x60:                                    # upload segment
            self.segments += 1
            send(bytes([request[0] & 0x10]) + b"LOOPING")
        else:
            serve()


class ShortAnswer(Misbehaving):
    """Answers an upload of one entry with the first ``length`` bytes of the real answer."""

    def __init__(self, node, index: int, sub: int, length: int = 3):
        super().__init__(node)
        self.entry, self.length = (index, sub), length

    def handle(self, request, serve, send):
        if request[0] & 0xE0 == 0x40 and _mux(request) == self.entry:
            real = self.node.sdo.send_response
            self.node.sdo.send_response = lambda frame: real(bytes(frame)[:self.length])
            try:
                serve()
            finally:
                self.node.sdo.send_response = real
        else:
            serve()


class WrongEntry(Misbehaving):
    """Answers an upload of one entry with the answer for another (``instead``)."""

    def __init__(self, node, index: int, sub: int, instead: tuple[int, int]):
        super().__init__(node)
        self.entry, self.instead = (index, sub), instead

    def handle(self, request, serve, send):
        if request[0] & 0xE0 == 0x40 and _mux(request) == self.entry:
            index, sub = self.instead
            serve_other = bytes([0x40]) + index.to_bytes(2, "little") + bytes([sub]) + bytes(4)
            self.node.sdo.on_request(self.node.sdo.rx_cobid, bytearray(serve_other), 0)
        else:
            serve()


class AnswersTwice(Misbehaving):
    """Sends every answer twice."""

    def handle(self, request, serve, send):
        real = self.node.sdo.send_response

        def twice(frame):
            real(frame)
            real(frame)
        self.node.sdo.send_response = twice
        try:
            serve()
        finally:
            self.node.sdo.send_response = real


class RestartsAfter(Misbehaving):
    """Resets itself (NMT reset application: the stored values back, a boot-up message)
    right after it has answered its ``writes``-th download."""

    def __init__(self, node, writes: int):
        super().__init__(node)
        self.writes, self.downloads = writes, 0

    def handle(self, request, serve, send):
        serve()
        if request[0] & 0xE0 == 0x20:                                      # initiate download
            self.downloads += 1
            if self.downloads == self.writes:
                from dcf2bin.bus.node import RESET_NODE
                self.node._reset(RESET_NODE)


@pytest.fixture
def faulty():
    """The misbehaving nodes above, by name (a fixture, so that test modules need not
    import this plugin module themselves)."""
    import types
    return types.SimpleNamespace(Misbehaving=Misbehaving, TogglesForever=TogglesForever,
                                 ShortAnswer=ShortAnswer, WrongEntry=WrongEntry,
                                 AnswersTwice=AnswersTwice, RestartsAfter=RestartsAfter)
