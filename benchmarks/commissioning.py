"""Commissioning 32 slaves on python-can's virtual bus: `network lss`, `network download` and
`network upload`, the time per node of each step and of all three, and what each waited for.

    python benchmarks/commissioning.py                 # 32 slaves, best of 3
    python benchmarks/commissioning.py --slaves 8 --repeat 1

The slaves are software nodes from samples/device.eds with the whole identity object
(0x1018 sub 1-4, as a real IO module's EDS has it), each answering LSS without a node-ID
(0xFF) and with a serial number of its own, each on a network of its own on one virtual
channel (as separate devices are). A generated network file (a lely master, whose PDOs
`network` makes as it needs them) gives them node-IDs 2, 3, ... with their full
identities, a heartbeat, a TPDO mapping and a string to write. The three
commands run as a user runs them -- `dcf2bin network lss|download|upload FILE`, through
click's test runner in this process (the virtual bus reaches no other), `-q` -- and each
run starts from nodes without a node-ID; the best of `--repeat` runs is shown per step.

What each step waited for is counted where dcf2bin waits (the wait primitives of
bus/sdo.py, bus/scan.py, bus/lss.py and bus/lssnet.py, wrapped for the run):

* ended by an answer -- an SDO answer, an LSS answer, a boot-up message, every node of a
  scan round answering: the wait is as long as the node takes;
* ended by silence -- the wait ran to its time-out: an SDO request or LSS request nobody
  answered, a scan round some node did not answer, a boot-up message that did not come;
* fixed -- a fastscan or identify step, where silence is an answer and the window is
  `--scan-wait`.

For comparison, in the same run: the SDO reading of the upload alone (no network file,
no DCF written), by dcf2bin's reader one node at a time and four at a time (`-j 4`, the
default) and by python canopen's SDO client one node at a time, with their ratios.

The check (exit 1 when it fails): download and upload wait only for answers; lss waits
for answers, but for its one check round before it changes anything -- an SDO upload of
0x1000 to the node-IDs of the file, which nobody may answer yet, so that round lasts its
`--check-wait` (0.3 s, network scan's time for an SDO answer; it was `--timeout`, 0.5 s)
-- and makes no fixed wait (the file gives every identity: no fastscan).
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from dataclasses import dataclass, field

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
sys.path.insert(0, os.path.join(ROOT, "tests"))

# tests/: the software slaves and the runner of the commissioning loop test
from bus_helpers import Bench, run  # noqa: E402
from lss_helpers import io8_eds, lss_node  # noqa: E402


def network_file(folder: str, eds: str, n: int) -> str:
    lines = ["master:", "  node_id: 1", "  sync_period: 10000"]
    for k in range(n):
        lines += [f"io{k + 1}:", f"  dcf: {eds}", f"  node_id: {k + 2}", "  vendor_id: 0xAB",
                  "  product_code: 8", "  revision_number: 0x00010002",
                  f"  serial_number: {0x1000 + k}", "  heartbeat_producer: 200",
                  "  sdo:", f"    - {{index: 0x2000, sub_index: 0, value: \"Rack {k + 1}\"}}",
                  "  tpdo:", "    1:", "      transmission: 1", "      mapping:",
                  f"        - {{index: 0x2001, sub_index: 0, name: pos{k + 1}}}"]
    path = os.path.join(folder, f"bus-{n}.yml")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    return path


# -- the waits ---------------------------------------------------------------------------------

@dataclass
class Waits:
    """The waits of one step: how many an answer ended, how many silence ended (and their
    seconds), how many fixed ones (and their seconds)."""
    answered: int = 0
    silent: int = 0
    silent_seconds: float = 0.0
    fixed: int = 0
    fixed_seconds: float = 0.0
    what: dict = field(default_factory=dict)     # what silence ended -> how many

    def heard(self, answered: bool, seconds: float, what: str) -> None:
        if answered:
            self.answered += 1
        else:
            self.silent += 1
            self.silent_seconds += seconds
            self.what[what] = self.what.get(what, 0) + 1


class Counting:
    """Wraps dcf2bin's wait primitives while a step runs; ``waits`` collects them."""

    def __init__(self):
        self.waits = Waits()
        self._undo = []

    def __enter__(self) -> Waits:
        from dcf2bin.bus import lss, lssnet, scan, sdo
        w = self.waits

        class Frames:
            """sdo.Channel's queue of answers: a get that times out is silence."""

            def __init__(self):
                self.q = _queue.SimpleQueue()

            def put(self, item):
                self.q.put(item)

            def get_nowait(self):
                return self.q.get_nowait()

            def get(self, timeout=None):
                start = time.monotonic()
                try:
                    got = self.q.get(timeout=timeout)
                except _queue.Empty:
                    w.heard(False, time.monotonic() - start, "SDO request unanswered")
                    raise
                if got[0] == "sdo":
                    w.heard(True, 0.0, "")
                return got

        import queue as _queue
        shim = type("queue", (), {"SimpleQueue": Frames, "Empty": _queue.Empty})
        self._patch(sdo, "queue", shim)

        ask = lss.Master._ask

        def timed_ask(master, frames, answer, size=1):
            start = time.monotonic()
            got = ask(master, frames, answer, size)
            w.heard(got is not None, time.monotonic() - start, "LSS request unanswered")
            return got
        self._patch(lss.Master, "_ask", timed_ask)

        count = lss.Master._count

        def timed_count(master, frames, answer):
            start = time.monotonic()
            try:
                return count(master, frames, answer)
            finally:
                w.fixed += 1
                w.fixed_seconds += time.monotonic() - start
        self._patch(lss.Master, "_count", timed_count)

        boot_wait = lssnet._BootUp.wait

        def timed_boot(boot, timeout):
            start = time.monotonic()
            got = boot_wait(boot, timeout)
            w.heard(got, time.monotonic() - start, "boot-up message missing")
            return got
        self._patch(lssnet._BootUp, "wait", timed_boot)

        round_run = scan._Round.run

        def timed_round(rnd, timeout, retries):
            start = time.monotonic()
            got = round_run(rnd, timeout, retries)
            w.heard(len(got) == len(rnd.ids), time.monotonic() - start,
                    "scan round not answered by every node")
            return got
        self._patch(scan._Round, "run", timed_round)
        return w

    def _patch(self, owner, name, value) -> None:
        self._undo.append((owner, name, getattr(owner, name)))
        setattr(owner, name, value)

    def __exit__(self, *exc) -> None:
        for owner, name, value in reversed(self._undo):
            setattr(owner, name, value)


STEPS = ("lss", "download", "upload")


def one_run(eds: str, network: str, n: int, folder: str) -> dict[str, tuple[float, Waits]]:
    """``n`` software slaves without a node-ID, each on a network of its own, commissioned."""
    bench = Bench(f"bench-commissioning-{n}-{time.monotonic_ns()}")
    bus = ["-i", "virtual", "--channel", bench.channel]
    args = {"lss": ["network", "lss", network, "-q", *bus],
            "download": ["network", "download", network, "-q", *bus],
            "upload": ["network", "upload", network, "-o", os.path.join(folder, "up"), "-q",
                       *bus]}
    out = {}
    try:
        for k in range(n):
            lss_node(bench, 0x1000 + k, path=eds)
        for step in STEPS:
            with Counting() as waits:
                start = time.perf_counter()
                r = run(*args[step])
                seconds = time.perf_counter() - start
            if r.exit_code != 0:
                raise SystemExit(f"network {step} failed ({r.exit_code}): {r.stderr}")
            out[step] = (seconds, waits)
        # the SDO reading alone, three ways, on the nodes as the steps left them
        for way in ("dcf2bin -j 1", "dcf2bin -j 4", "canopen"):
            out[way] = (read_alone(way, bench.channel, eds, n), Waits())
    finally:
        bench.close()
    return out


def read_alone(way: str, channel: str, eds: str, n: int) -> float:
    """Seconds to read the entries `upload` reads from every node, and nothing else (no
    network file, no DCF written): dcf2bin's reader (bus.upload.read_nodes, one node or
    four at a time) or python canopen's SDO client, one node at a time."""
    import canopen

    from dcf2bin import formats
    from dcf2bin.bus import link
    from dcf2bin.bus import upload as up
    todo, _ = up.targets(formats.load(eds))
    net = link.open_network(link.BusConfig("virtual", channel))
    try:
        if way == "canopen":
            nodes = [net.add_node(canopen.RemoteNode(k + 2, canopen.ObjectDictionary()))
                     for k in range(n)]
            start = time.perf_counter()
            for node in nodes:
                for t in todo:
                    node.sdo.upload(t.index, t.sub)
            return time.perf_counter() - start
        with open(eds, "rb") as f:
            desc = up.description(f.read(), eds, 2)
        jobs = [up.Job(up.Description(desc.device, desc.text, desc.ini, eds, k + 2), todo)
                for k in range(n)]
        start = time.perf_counter()
        results = up.read_nodes(net, jobs, up.Options(), parallel=int(way[-1]))
        seconds = time.perf_counter() - start
        if any(r.status != up.UPLOADED for r in results):
            raise SystemExit(f"{way}: not every node was read")
        return seconds
    finally:
        link.close_network(net)


def check(step: str, waits: Waits) -> str | None:
    """What is wrong with the waits of a step (None: nothing)."""
    if step == "lss":
        allowed = {"scan round not answered by every node": 1}
        extra = {k: v for k, v in waits.what.items() if v > allowed.get(k, 0)}
        if extra or waits.fixed:
            return f"lss waited for silence: {extra or waits.what}, {waits.fixed} fixed waits"
        return None
    if waits.silent or waits.fixed:
        return f"{step} waited for silence: {waits.what}, {waits.fixed} fixed waits"
    return None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--slaves", type=int, default=32)
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    best: dict[str, tuple[float, Waits]] = {}
    totals = []
    with tempfile.TemporaryDirectory() as folder:
        eds = io8_eds(folder)
        network = network_file(folder, eds, a.slaves)
        for _ in range(a.repeat):
            steps = one_run(eds, network, a.slaves, folder)
            totals.append(sum(steps[s][0] for s in STEPS))
            for step, (seconds, waits) in steps.items():
                if step not in best or seconds < best[step][0]:
                    best[step] = (seconds, waits)
    n = a.slaves
    print(f"{n} slaves, best of {a.repeat} per step")
    print(f"{'step':<9} {'seconds':>8} {'per node':>9}  {'answered':>8}  {'silence ended':>22}"
          f"  {'fixed':>14}")
    problems = []
    for step in STEPS:
        seconds, w = best[step]
        print(f"{step:<9} {seconds:8.3f} {seconds / n:8.4f}s  {w.answered:8d}  "
              f"{w.silent:4d} ({w.silent_seconds:6.3f} s)      {w.fixed:4d} "
              f"({w.fixed_seconds:5.3f} s)")
        problem = check(step, w)
        if problem:
            problems.append(problem)
    whole = sum(best[s][0] for s in STEPS)
    print(f"{'all':<9} {whole:8.3f} {whole / n:8.4f}s  (best run in all: {min(totals):.3f} s, "
          f"{min(totals) / n:.4f} s/node)")
    j1, j4, co = (best[w][0] for w in ("dcf2bin -j 1", "dcf2bin -j 4", "canopen"))
    print(f"the SDO reading of upload alone: dcf2bin -j 1 {j1:.3f} s ({j1 / n:.4f} s/node), "
          f"-j 4 {j4:.3f} s, canopen's client {co:.3f} s; canopen/dcf2bin -j 1 = "
          f"{co / j1:.2f}, dcf2bin -j 1/-j 4 = {j1 / j4:.2f}")
    print(f"share of all spent waiting for silence: "
          f"{sum(best[s][1].silent_seconds for s in STEPS) / whole:.0%}")
    for step in STEPS:
        what = best[step][1].what
        if what:
            print(f"  {step}: silence ended " + ", ".join(f"{v} x {k}" for k, v in what.items()))
    if problems:
        for p in problems:
            print(f"CHECK FAILED: {p}")
        raise SystemExit(1)
    print("check: download and upload waited for answers only; lss for answers and its one "
          "check round (node-IDs nobody may answer yet); no fixed wait")


if __name__ == "__main__":
    main()
