"""dcf2bin node: a canopen LocalNode from an EDS/DCF on python-can's virtual bus —
SDO server, boot-up, heartbeat, NMT, PDOs as its mapping says — and the command that
runs it until Ctrl-C (or --duration)."""
from __future__ import annotations

import _thread
import signal
import threading
import time

import pytest
from bus_helpers import Bench, bus_args, eventually, run
from conftest import SAMPLES

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

DCF = "samples/device.dcf"


class Frames:
    """Every frame of some COB-IDs seen on a network (from the notifier thread)."""

    def __init__(self, net, *cob_ids):
        self.got: list[tuple[int, bytes]] = []
        self.event = threading.Event()
        for cob in cob_ids:
            net.subscribe(cob, self._on)

    def _on(self, can_id, data, timestamp):
        self.got.append((can_id, bytes(data)))
        self.event.set()

    def wait(self, n: int = 1, timeout: float = 2.0) -> list[tuple[int, bytes]]:
        end = time.monotonic() + timeout
        while len(self.got) < n and time.monotonic() < end:
            time.sleep(0.005)
        return list(self.got)


# -- the node as a library ------------------------------------------------------------------

def test_node_boots_and_serves_its_files_values(bench):
    net = bench.network()
    boot = Frames(net, 0x703)
    from dcf2bin.bus.node import from_file
    node, errors = from_file(DCF, None)             # node-ID from [DeviceComissioning]
    assert (node.id, errors) == (3, [])
    bench.add(node)
    assert boot.wait(1)[0] == (0x703, b"\x00")
    sdo = bench.sdo(3)
    assert sdo.upload(0x1017, 0) == b"\xf4\x01"     # the DCF's ParameterValue
    assert sdo.upload(0x2001, 0) == b"\x00\x00\x80"
    assert sdo.upload(0x1016, 2) == bytes.fromhex("C8000200")
    assert node.nmt.state == "PRE-OPERATIONAL"


def test_heartbeat_from_0x1017(bench):
    net = bench.network()
    beats = Frames(net, 0x703)
    bench.device(path="samples/device.dcf")          # 0x1017 = 500 ms
    got = beats.wait(2, timeout=1.5)
    assert got[:2] == [(0x703, b"\x00"), (0x703, bytes([127]))]


def test_tpdo_on_sync_as_the_downloaded_mapping_says(bench):
    node = bench.device()                           # from the EDS: TPDO1 off
    net = bench.network()
    tpdo = Frames(net, 0x183)
    r = run("download", DCF, "-n", "3", "-q", *bus_args(bench.channel))
    assert r.exit_code == 0
    sdo = bench.sdo(3)
    sdo.download(0x2001, 0, bytes.fromhex("563412"))
    net.nmt.state = "OPERATIONAL"
    net.sync.transmit()             # the node takes both in order, NMT start first
    assert eventually(lambda: node.nmt.state == "OPERATIONAL")                             # transmission type 1: every SYNC
    # 0x2001 (24 bits) then the UNSIGNED8 dummy
    assert tpdo.wait(1) == [(0x183, bytes.fromhex("56341200"))]


def test_no_pdo_before_operational(bench):
    bench.device(path="samples/device.dcf")
    net = bench.network()
    tpdo = Frames(net, 0x183)
    net.sync.transmit()
    # the node answers this after it has taken the SYNC, and on the same network any TPDO
    # it had sent for that SYNC would have arrived before the answer
    from dcf2bin.bus.download import sdo_client
    assert sdo_client(net, 3, timeout=2.0, retries=0).upload(0x1017, 0) == b"\xf4\x01"
    assert tpdo.got == []


def test_event_driven_tpdo_and_rpdo(bench, tmp_path):
    """A node whose TPDO (type 254) sends on change and whose RPDO writes its entries."""
    bench_text = (SAMPLES / "device.eds").read_text()
    text = bench_text
    text = text.replace("[1800sub2]\nParameterName=Transmission type\nObjectType=0x7\n"
                        "DataType=0x0005\nAccessType=rw\nDefaultValue=255",
                        "[1800sub2]\nParameterName=Transmission type\nObjectType=0x7\n"
                        "DataType=0x0005\nAccessType=rw\nDefaultValue=254")
    assert text != bench_text
    eds = tmp_path / "io.eds"
    eds.write_text(text)
    node = bench.device(path=str(eds))
    net = bench.network()
    tpdo = Frames(net, 0x183)
    sdo = bench.sdo(3)
    # configure TPDO1 the CiA 301 way, by SDO
    sdo.download(0x1A00, 0, b"\x00")
    sdo.download(0x1A00, 1, (0x20010018).to_bytes(4, "little"))
    sdo.download(0x1A00, 0, b"\x01")
    sdo.download(0x1800, 1, (0x183).to_bytes(4, "little"))
    node.go_operational()
    sdo.download(0x2001, 0, bytes.fromhex("010203"))
    assert tpdo.wait(1) == [(0x183, bytes.fromhex("010203"))]


def test_a_tpdo_and_an_rpdo_carry_a_field_that_starts_inside_a_byte(bench):
    """A BOOLEAN dummy (1 bit) first puts 0x2001 (INTEGER24) at bit 1: its 24 bits span
    four bytes. python-canopen's PdoVariable reads and writes such a field in the bytes of
    its type only (three here) and loses its top bit, or raises; the node packs the bits
    itself (CiA 301: bit 0 of byte 0 first, little-endian)."""
    node = bench.device()
    net = bench.network()
    tpdo = Frames(net, 0x183)
    sdo = bench.sdo(3)
    for index in (0x1A00, 0x1600):
        sdo.download(index, 0, b"\x00")
        sdo.download(index, 1, (0x00010001).to_bytes(4, "little"))
        sdo.download(index, 2, (0x20010018).to_bytes(4, "little"))
        sdo.download(index, 0, b"\x02")
    sdo.download(0x1800, 2, b"\x01")                  # every SYNC
    sdo.download(0x1800, 1, (0x183).to_bytes(4, "little"))
    sdo.download(0x1400, 1, (0x203).to_bytes(4, "little"))
    sdo.download(0x2001, 0, bytes.fromhex("5634D2"))   # 0xD23456: negative, top bit set
    node.go_operational()
    net.sync.transmit()
    # 0xD23456 << 1 = 0x1A468AC: bytes AC 68 A4 01
    assert tpdo.wait(1) == [(0x183, bytes.fromhex("AC68A401"))]
    net.send_message(0x203, bytes.fromhex("FDFFFF01"))   # bits 1-24: 0xFFFFFE
    assert eventually(lambda: sdo.upload(0x2001, 0) == bytes.fromhex("FEFFFF"))


# -- NMT ------------------------------------------------------------------------------------

def test_nmt_reset_node_restores_the_files_values(bench):
    node = bench.device(path="samples/device.dcf")
    net = bench.network()
    boot = Frames(net, 0x703)
    sdo = bench.sdo(3)
    sdo.download(0x2003, 0, bytes.fromhex("01020304"))
    net.send_message(0, [0x81, 3])
    assert boot.wait(1)[0] == (0x703, b"\x00")
    assert sdo.upload(0x2003, 0) == bytes.fromhex("DEADBEEF")
    assert node.nmt.state == "PRE-OPERATIONAL"


# -- the command ----------------------------------------------------------------------------

def test_node_command_runs_for_its_duration(channel):
    b = Bench(channel)
    try:
        net = b.network()
        boot = Frames(net, 0x703)
        answers = []

        def client():
            boot.wait(1)
            from dcf2bin.bus.download import sdo_client
            answers.append(sdo_client(net, 3, timeout=2.0, retries=0).upload(0x1017, 0))
        t = threading.Thread(target=client)
        t.start()
        r = run("node", DCF, "-i", "virtual", "--channel", channel, "--duration", "0.4")
        t.join()
    finally:
        b.close()
    assert r.exit_code == 0
    assert r.stdout == ""
    assert r.stderr == (f"{DCF}: node 3 on the bus (interface virtual, channel {channel}: "
                        "python-can's virtual bus reaches only this process); Ctrl-C stops it\n"
                        f"{DCF}: node 3 stopped\n")
    assert answers == [b"\xf4\x01"]


def test_ctrl_c_stops_the_node_cleanly(channel):
    """An injected KeyboardInterrupt (Ctrl-C) ends the node with exit 0, nothing left."""
    # a suite started in the background by a non-interactive shell inherits SIGINT ignored,
    # and interrupt_main() then does nothing: start from the handler a terminal gives
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    b = Bench(channel)
    try:
        boot = Frames(b.network(), 0x70A)

        def ctrl_c():
            boot.wait(1)
            _thread.interrupt_main()
        t = threading.Thread(target=ctrl_c)
        t.start()
        start = time.monotonic()
        r = run("node", "samples/device.eds", "--node-id", "10", "-q", "-i", "virtual",
                "--channel", channel, "--duration", "30")
        t.join()
    finally:
        b.close()
        signal.signal(signal.SIGINT, old)
    assert time.monotonic() - start < 5
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")


def test_node_verbose_reports_nmt(channel):
    b = Bench(channel)
    try:
        net = b.network()
        boot = Frames(net, 0x703)

        def start():
            boot.wait(1)
            net.nmt.state = "OPERATIONAL"
        t = threading.Thread(target=start)
        t.start()
        r = run("node", DCF, "-v", "-q", "-i", "virtual", "--channel", channel,
                "--duration", "0.3")
        t.join()
    finally:
        b.close()
    assert (r.exit_code, r.stderr) == (0, "node 3: NMT state OPERATIONAL\n")


@pytest.mark.parametrize("args, message", [
    ([], "dcf2bin: error: give an EDS/DCF FILE or --container FILE.bin (one of them)"),
    (["samples/device.eds", "--show-pi"], "dcf2bin: error: --show-pi needs --container"),
    (["samples/device.eds", "--pi-size", "8"], "dcf2bin: error: --pi-size needs --container"),
    (["--container", "samples/plc.bin"],
     "dcf2bin: error: --container needs --node-id N (a container has no node-ID)"),
])
def test_node_usage_errors(args, message):
    r = run("node", *args)
    assert (r.exit_code, r.stderr) == (2, message + "\n")


def test_node_without_node_id(tmp_path):
    r = run("node", "samples/device.eds", "-i", "no-such-interface")
    assert r.exit_code == 1
    assert r.stderr == ("samples/device.eds: error: no node-ID: give --node-id N or set NodeID "
                        "in [DeviceComissioning]\n")


def test_node_interface_that_cannot_open(channel):
    r = run("node", DCF, "-i", "no-such-interface", "--channel", "x")
    assert r.exit_code == 3
    assert r.stderr == ("dcf2bin: error: CAN interface 'no-such-interface': Unknown interface "
                        "type \"no-such-interface\"\n")
