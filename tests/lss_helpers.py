"""Software LSS slaves on the bench's virtual bus, for the LSS tests (several in one
process, each with a network of its own, as separate devices would be)."""
from __future__ import annotations

import os
import re
import threading
import time

IO8 = "samples/device.eds"                         # [DeviceInfo]: 0xAB, 8, 0x00010002
IO8_INFO = {2: 8, 3: 0x00010002}                   # its 0x1018 has sub 1 only
AI = "tests/fixtures/network/IoX4_8AI.eds"         # 0x1018: 63, 3001003, 0x01390538
AI_ID = (0x3F, 0x2DCAAB, 0x01390538)
DRIVE_ID = (0x1A3, 0xC01, 0x00010004)              # drive_eds
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# 0x1018 with sub 1-4, in io8_eds's EDS (its revision and serial number are read back)
IO8_IDENTITY = """[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=5

[1018sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=4

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x000000AB

[1018sub2]
ParameterName=Product code
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00000008

[1018sub3]
ParameterName=Revision number
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00010002

[1018sub4]
ParameterName=Serial number
ObjectType=0x7
DataType=0x0007
AccessType=ro

"""


def io8_eds(folder) -> str:
    """samples/device.eds with the whole identity object (sub 1-4), as a real IO module's
    EDS has it, so that the serial number a slave holds is read back and compared: written
    as ``folder``/io8.eds (for the tests and benchmarks/commissioning.py)."""
    with open(os.path.join(ROOT, IO8), encoding="utf-8") as f:
        text = f.read()
    start, end = text.index("[1018]"), text.index("[1800]")
    path = os.path.join(folder, "io8.eds")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text[:start] + IO8_IDENTITY + text[end:])
    return path


def drive_eds(folder, more: str = "") -> str:
    """tests/fixtures/network/technosoft.eds, a real drive's EDS, with its product code and
    revision in [DeviceInfo] (the file gives neither: LSS needs them to select a drive by
    its whole identity), and ``more`` sections at its end. Its 0x1014 (EMCY) and 0x1200
    (SDO server) COB-IDs, and its PDOs', are $NODEID formulas."""
    from conftest import ROOT
    text = (ROOT / "tests" / "fixtures" / "network" / "technosoft.eds").read_text()
    text = text.replace("VendorNumber=0x000001A3\n", "VendorNumber=0x000001A3\n"
                        "ProductNumber=0x00000C01\nRevisionNumber=0x00010004\n", 1)
    path = folder / "drive.eds"
    path.write_text(text + more)
    return str(path)


def lss_node(bench, serial: int, *, path: str = IO8, node_id: int | None = None, **faults):
    """A node from ``path`` answering LSS with ``serial``: without a node-ID (0xFF) unless
    ``node_id`` is given."""
    from dcf2bin.bus.lss_slave import attach_lss
    from dcf2bin.bus.node import from_file
    node, errors = from_file(path, node_id or 1)
    assert errors == []
    attach_lss(node, serial=serial, unconfigured=node_id is None,
               info=IO8_INFO if path == IO8 else None, **faults)
    return bench.add(node)


def plain_node(bench, node_id: int, path: str = IO8):
    """A node that does not answer LSS."""
    from dcf2bin.bus.node import from_file
    node, errors = from_file(path, node_id)
    assert errors == []
    return bench.add(node)


def seconds_out(text: str) -> str:
    """The text with its run time (``(1.23 s)``, ``in 1.23 s``) written as ``S``."""
    return re.sub(r"\d+\.\d\d s\b", "S s", text)


class Frames:
    """Every frame of some COB-IDs seen on a network (from the notifier thread)."""

    def __init__(self, net, *cob_ids):
        self.got: list[tuple[int, bytes]] = []
        self.lock = threading.Lock()
        for cob in cob_ids:
            net.subscribe(cob, self._on)

    def _on(self, can_id, data, timestamp):
        with self.lock:
            self.got.append((can_id, bytes(data)))

    def wait(self, n: int = 1, timeout: float = 2.0) -> list[tuple[int, bytes]]:
        end = time.monotonic() + timeout
        while len(self.got) < n and time.monotonic() < end:
            time.sleep(0.005)
        with self.lock:
            return list(self.got)
