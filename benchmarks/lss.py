"""How long `network lss` takes per node on python-can's virtual bus, and what it waits for.

    python benchmarks/lss.py                     # 32 selective, 4 fastscan, 4 canopen
    python benchmarks/lss.py --nodes 64 --fastscan 8 --canopen 0

Every slave is a software node from samples/device.eds answering LSS, without a node-ID
(0xFF), each on a network of its own on one virtual channel (as separate devices are).
A generated network file gives them node-IDs 2, 3, ...; the run is `network lss`'s own
work (lssnet.commission: find, check, assign, store, reset, scan) on the network read
and configured from that file (the file's time is printed apart). Three ways:

* selective -- the file gives every slave's full identity (serial numbers 0x1000 + k):
  switch state selective, every wait ended by an answer;
* fastscan -- the file gives no serial number (each slave of its own product code): the
  serial is scanned, 33 steps of --scan-wait each, where silence is an answer;
* canopen -- python canopen's LssMaster doing the selective way by hand (switch state
  selective, configure node-ID, store, switch state global), for comparison: it sleeps
  0.2 s after each of the four selective frames.

Prints the seconds per node of each, how many waits of --scan-wait were made (0 means no
wait a silence had to end), and the ratios.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

DEVICE = os.path.join(ROOT, "samples", "device.eds")       # [DeviceInfo]: 0xAB, 8, 0x10002
PLC = os.path.join(ROOT, "tests", "fixtures", "network", "plc.dcf")


def network_file(folder: str, n: int, serials: bool) -> str:
    lines = ["master:", "  node_id: 1", "  name: plc", f"  dcf: {PLC}"]
    for k in range(n):
        lines += [f"io{k + 1}:", f"  dcf: {DEVICE}", f"  node_id: {k + 2}",
                  "  revision_number: 0x00010002"]
        lines += [f"  serial_number: {0x1000 + k}"] if serials else \
            [f"  product_code: {100 + k}"]
    path = os.path.join(folder, f"bus-{n}-{'serial' if serials else 'product'}.yml")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")
    return path


class Bus:
    """Software LSS slaves without a node-ID, and the master's network, on one channel."""

    def __init__(self, n: int, serials: bool):
        from dcf2bin.bus import link
        from dcf2bin.bus.lss_slave import attach_lss
        from dcf2bin.bus.node import from_file
        link.quiet_libraries()
        self.channel = f"bench-lss-{n}-{time.monotonic_ns()}"
        self.nets, self.nodes = [], []
        for k in range(n):
            node, _ = from_file(DEVICE, 1)
            info = {2: 8 if serials else 100 + k, 3: 0x10002}
            attach_lss(node, serial=0x1000 + k, unconfigured=True, info=info)
            node.attach(self.open())
            self.nodes.append(node)
        self.master = self.open()

    def open(self):
        from dcf2bin.bus import link
        net = link.open_network(link.BusConfig("virtual", self.channel))
        self.nets.append(net)
        return net

    def close(self) -> None:
        from dcf2bin.bus import link
        for node in self.nodes:
            node.detach()
        for net in self.nets:
            link.close_network(net)


def run_dcf2bin(n: int, serials: bool, folder: str, wait: float) -> tuple[float, float, int]:
    """(seconds of the bus work, seconds reading the file, waits of ``wait``)."""
    from dcf2bin.bus import lssnet
    from dcf2bin.cli.network.lss import wanted_of
    from dcf2bin.network import configure
    from dcf2bin.network.check import read_network
    start = time.perf_counter()
    network = read_network(network_file(folder, n, serials))
    configure(network)
    wanted = wanted_of(network)
    file_seconds = time.perf_counter() - start
    bus = Bus(n, serials)
    try:
        start = time.perf_counter()
        result = lssnet.commission(bus.master, wanted, lssnet.Options(wait=wait))
        seconds = time.perf_counter() - start
    finally:
        bus.close()
    bad = [r for r in result.rows if r.status != lssnet.ASSIGNED or not r.answers]
    if bad or result.problems:
        raise SystemExit(f"not all assigned: {bad or result.problems}")
    return seconds, file_seconds, result.steps


def run_canopen(n: int) -> float:
    """python canopen's LssMaster, the selective way, by hand."""
    bus = Bus(n, True)
    lss = bus.master.lss
    try:
        start = time.perf_counter()
        for k in range(n):
            if not lss.send_switch_state_selective(0xAB, 8, 0x10002, 0x1000 + k):
                raise SystemExit(f"canopen: node {k} did not answer")
            lss.configure_node_id(k + 2)
            lss.store_configuration()
            lss.send_switch_state_global(lss.WAITING_STATE)
        return time.perf_counter() - start
    finally:
        bus.close()


def main() -> None:
    from dcf2bin.bus.lss import WAIT
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", type=int, default=32, help="slaves of the selective run")
    ap.add_argument("--fastscan", type=int, default=4, help="slaves of the fastscan run")
    ap.add_argument("--canopen", type=int, default=4, help="slaves of the canopen run")
    ap.add_argument("--scan-wait", type=float, default=WAIT)
    a = ap.parse_args()
    per = {}
    with tempfile.TemporaryDirectory() as folder:
        seconds, file_s, steps = run_dcf2bin(a.nodes, True, folder, a.scan_wait)
        per["selective"] = seconds / a.nodes
        print(f"selective  {a.nodes:>3} nodes: {seconds:7.3f} s, {per['selective']:.4f} s/node, "
              f"{steps} waits of {a.scan_wait:g} s (network file read and configured: "
              f"{file_s:.3f} s)")
        if a.fastscan:
            seconds, file_s, steps = run_dcf2bin(a.fastscan, False, folder, a.scan_wait)
            per["fastscan"] = seconds / a.fastscan
            print(f"fastscan   {a.fastscan:>3} nodes: {seconds:7.3f} s, "
                  f"{per['fastscan']:.4f} s/node, {steps} waits of {a.scan_wait:g} s "
                  f"({steps * a.scan_wait:.2f} s of them)")
    if a.canopen:
        seconds = run_canopen(a.canopen)
        per["canopen"] = seconds / a.canopen
        print(f"canopen    {a.canopen:>3} nodes: {seconds:7.3f} s, {per['canopen']:.4f} s/node "
              "(LssMaster by hand: no reset, no check, no scan)")
    for other in ("fastscan", "canopen"):
        if other in per:
            print(f"{other}/selective per node: {per[other] / per['selective']:.1f}x")


if __name__ == "__main__":
    main()
