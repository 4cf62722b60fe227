"""How long `network scan` takes on python-can's virtual bus, against its stated bound.

    python benchmarks/network_scan.py                  # 0, 3, 30 and 127 nodes
    python benchmarks/network_scan.py --nodes 127 --listen 0.5 --timeout 0.3 --silent 2

Each node is a software node from samples/device.eds (device type, vendor-ID and an abort
for 0x1018 sub 2...4); ``--silent N`` of them answer nothing after 0x1000, so each identity
round waits its whole timeout (the worst case a node can cause). Prints, per run, the
time the scan took and ``dcf2bin.bus.scan.worst_case`` for its options.
"""
from __future__ import annotations

import argparse
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)


def run(n: int, listen: float, timeout: float, retries: int, silent: int) -> tuple[float, int]:
    from dcf2bin.bus import link
    from dcf2bin.bus import scan as sc
    from dcf2bin.bus.node import from_file
    link.quiet_libraries()
    channel = f"bench-scan-{n}-{time.monotonic_ns()}"
    nodes_net = link.open_network(link.BusConfig("virtual", channel))
    scanner = link.open_network(link.BusConfig("virtual", channel))
    nodes = []
    try:
        for nid in range(1, n + 1):
            node, _ = from_file(os.path.join(ROOT, "samples", "device.eds"), nid)
            if nid <= silent:
                # answers 0x1000, then nothing for 2 s: the 0x1018 rounds time out (the
                # nodes share one notifier thread, so the others wait too: the worst case)
                node.get_data = (lambda orig: lambda index, sub, check_readable=False: (
                    orig(index, sub, check_readable) if index != 0x1018
                    else time.sleep(2)))(node.get_data)
            node.attach(nodes_net)
            nodes.append(node)
        result = sc.scan(scanner, listen=listen, timeout=timeout, retries=retries)
        return result.seconds, sum(f.answered for f in result.found.values())
    finally:
        for node in nodes:
            node.detach()
        link.close_network(scanner)
        link.close_network(nodes_net)


def main() -> None:
    from dcf2bin.bus.scan import LISTEN, RETRIES, TIMEOUT, worst_case
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nodes", default="0,3,30,127")
    ap.add_argument("--listen", type=float, default=LISTEN)
    ap.add_argument("--timeout", type=float, default=TIMEOUT)
    ap.add_argument("--retries", type=int, default=RETRIES)
    ap.add_argument("--silent", type=int, default=0)
    a = ap.parse_args()
    bound = worst_case(a.listen, a.timeout, a.retries)
    print(f"listen {a.listen} s, timeout {a.timeout} s, retries {a.retries}: "
          f"at most {bound:.2f} s (+ sending 127 frames)")
    for n in (int(x) for x in a.nodes.split(",")):
        seconds, answered = run(n, a.listen, a.timeout, a.retries, min(a.silent, n))
        print(f"{n:>4} nodes ({min(a.silent, n)} silent after 0x1000): {answered} answered, "
              f"{seconds:.3f} s")


if __name__ == "__main__":
    main()
