"""How long `network upload` takes on python-can's virtual bus, one slave at a time against
several at once (`-j`).

    python benchmarks/network_upload.py                     # 8 and 32 slaves, -j 1,2,4,8
    python benchmarks/network_upload.py --slaves 32 --jobs 1,4 --repeat 3

Each slave is a software node from samples/device.eds (19 entries to read, two of them
strings), all on one network object of their own, so that their SDO servers share one
notifier thread: the far side of the bus is one process, as a bench of real slaves is
many. The command runs in this process (the virtual bus reaches no other) through click's
test runner, writing the DCFs to a temporary folder. Prints, per run, the best time, the
time per slave and per entry, and the speed-up against -j 1.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

EDS = os.path.join(ROOT, "samples", "device.eds")
ENTRIES = 19          # what upload reads of samples/device.eds


def network_file(folder: str, slaves: int) -> str:
    path = os.path.join(folder, "bus.yml")
    with open(path, "w") as f:
        f.write(f"master:\n  node_id: 1\n  name: plc\n  dcf: {ROOT}/tests/fixtures/network/plc.dcf\n")
        for nid in range(2, slaves + 2):
            f.write(f"dev{nid}:\n  dcf: {EDS}\n  node_id: {nid}\n  product_code: 0\n")
    return path


def run(slaves: int, jobs: int, repeat: int) -> float:
    from click.testing import CliRunner

    from dcf2bin.bus import link
    from dcf2bin.bus.node import from_file
    from dcf2bin.cli import main
    link.quiet_libraries()
    channel = f"bench-upload-{slaves}-{jobs}-{time.monotonic_ns()}"
    nodes_net = link.open_network(link.BusConfig("virtual", channel))
    nodes = []
    best = float("inf")
    try:
        for nid in range(2, slaves + 2):
            node, _ = from_file(EDS, nid)
            node.attach(nodes_net)
            nodes.append(node)
        with tempfile.TemporaryDirectory() as tmp:
            path = network_file(tmp, slaves)
            args = ["network", "upload", path, "-o", os.path.join(tmp, "out"), "-q",
                    "-j", str(jobs), "-i", "virtual", "--channel", channel]
            for _ in range(repeat):
                start = time.perf_counter()
                r = CliRunner().invoke(main, args, catch_exceptions=False)
                best = min(best, time.perf_counter() - start)
                if r.exit_code != 0:
                    raise SystemExit(f"network upload failed: {r.stderr}")
    finally:
        for node in nodes:
            node.detach()
        link.close_network(nodes_net)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--slaves", default="8,32")
    ap.add_argument("--jobs", default="1,2,4,8")
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    for n in (int(x) for x in a.slaves.split(",")):
        base = None
        for j in (int(x) for x in a.jobs.split(",")):
            seconds = run(n, j, a.repeat)
            base = base or seconds
            print(f"{n:>3} slaves  -j {j}:  {seconds:6.3f} s  {seconds / n * 1000:6.1f} ms/slave  "
                  f"{seconds / (n * ENTRIES) * 1000:5.2f} ms/entry  x{base / seconds:4.2f}")
    print(f"(load average {os.getloadavg()[0]:.2f})")


if __name__ == "__main__":
    main()
