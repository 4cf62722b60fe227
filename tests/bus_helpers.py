"""Shared pieces of the bus tests: the command runner, software nodes on a virtual bus
that are always taken down, and how long to wait for threads (fixtures: bus_fixtures.py)."""
from __future__ import annotations

import threading
import time

from click.testing import CliRunner

from dcf2bin.cli import main

# SDO response timeout of the tests that expect answers: generous, since an answer ends
# the wait at once and a loaded machine must not fail them (the silence tests use 0.05 s)
TIMEOUT = "2"
# what a "did not answer" says on python-can's virtual bus
VIRTUAL = ("; python-can's virtual bus reaches only this process: a node run by another "
           "process cannot answer")


def run(*args):
    return CliRunner().invoke(main, list(args), catch_exceptions=False)


def eventually(condition, timeout: float = 2.0) -> bool:
    """Poll ``condition`` until it holds (True) or ``timeout`` seconds pass (False)."""
    end = time.monotonic() + timeout
    while not condition():
        if time.monotonic() > end:
            return False
        time.sleep(0.005)
    return True


def threads_settle(before: set, wait: float = 2.0) -> list[str]:
    """Names of threads started since ``before`` still alive after ``wait`` seconds."""
    end = time.monotonic() + wait
    while True:
        extra = [t.name for t in threading.enumerate() if t.ident not in before]
        if not extra or time.monotonic() > end:
            return extra
        time.sleep(0.01)


class Bench:
    """Networks and software nodes on one virtual channel, all closed by ``close``."""

    def __init__(self, channel: str):
        from dcf2bin.bus import link
        link.quiet_libraries()
        self.channel = channel
        self.nets, self.nodes = [], []

    def network(self):
        from dcf2bin.bus import link
        net = link.open_network(link.BusConfig("virtual", self.channel))
        self.nets.append(net)
        return net

    def add(self, node, *, operational: bool = False):
        node.attach(self.network(), operational=operational)
        self.nodes.append(node)
        return node

    def device(self, node_id: int = 3, path: str = "samples/device.eds"):
        from dcf2bin.bus.node import from_file
        node, errors = from_file(path, node_id)
        assert errors == []
        return self.add(node)

    def sdo(self, node_id: int, timeout: float = 2.0):
        from dcf2bin.bus.download import sdo_client
        return sdo_client(self.network(), node_id, timeout=timeout, retries=0)

    def close(self) -> None:
        from dcf2bin.bus import link
        try:
            for node in self.nodes:
                if getattr(node, "misbehaving", None) is not None:
                    node.misbehaving.undo()
                node.detach()
        finally:
            for net in self.nets:
                link.close_network(net)


def bus_args(channel: str) -> list[str]:
    return ["-i", "virtual", "--channel", channel, "--timeout", TIMEOUT, "--retries", "0"]


def beside_target(scenario, plc_bin: str, node_id: int, channel: str, duration: int, bench):
    """Run ``scenario()`` in a thread while ``dcf2bin node --container PLC_BIN`` runs in
    this one (it needs the main thread for its Ctrl-C); when the scenario ends, Ctrl-C
    stops the node. The scenario's exception is raised here; the node's result returned."""
    import _thread
    failure: list[BaseException] = []

    def body():
        try:
            scenario()
        except BaseException as exc:   # handed to the test in the main thread
            failure.append(exc)
        finally:
            _thread.interrupt_main()                         # Ctrl-C for the node

    t = threading.Thread(target=body)
    t.start()
    try:
        r = run("node", "--container", plc_bin, "--node-id", str(node_id), "--show-pi",
                "-i", "virtual", "--channel", channel, "--duration", str(duration))
    finally:
        t.join()
        bench.close()
    if failure:
        raise failure[0]
    return r


def run_within(seconds: float, *args):
    """Run the command in a thread of its own and fail unless it ends within ``seconds``:
    the time bound of a command against a misbehaving node, asserted without sleeping
    (the thread is a daemon, so a command that hangs fails its test, not the run)."""
    box: dict = {}
    t = threading.Thread(target=lambda: box.setdefault("result", run(*args)), daemon=True)
    t.start()
    t.join(seconds)
    assert not t.is_alive(), f"dcf2bin {' '.join(args)} still runs after {seconds:.2f} s"
    assert "result" in box, f"dcf2bin {' '.join(args)} raised (see the thread's traceback)"
    return box["result"]
