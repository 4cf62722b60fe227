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
