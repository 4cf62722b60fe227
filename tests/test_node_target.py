"""dcf2bin node --container: an emulated SYS TEC target. DynBuildOd is applied at start
(SPEC §8); a container it refuses keeps the node off the bus, with its return code."""
from __future__ import annotations

import importlib.util
import threading

import pytest
from bus_helpers import Bench, run

pytest_plugins = ["bus_fixtures"]
pytestmark = [pytest.mark.usefixtures("at_root"),
              pytest.mark.skipif(importlib.util.find_spec("dcf2bin.dynod") is None,
                                 reason="needs dcf2bin.dynod")]


@pytest.fixture
def plc_bin(tmp_path):
    path = str(tmp_path / "bench_plc.bin")
    assert run("compile", "samples/bench_plc.dcf", "-o", path).exit_code == 0
    return path


def test_refuses_to_start_when_the_pi_memory_is_too_small(plc_bin):
    r = run("node", "--container", plc_bin, "-n", "16", "--pi-size", "4",
            "-i", "no-such-interface")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{plc_bin}: error: DynBuildOd returns 0xA0 kCopDynNoMemory: the "
                        "process image needs 12 bytes, the target gives 4; the node does not "
                        "start\n")


def test_refusal_names_the_failing_entry(plc_bin):
    r = run("node", "--container", plc_bin, "-n", "16", "--rx-cobs", "0",
            "-i", "no-such-interface")
    assert r.exit_code == 1
    assert r.stderr == (f"{plc_bin}:0xA8: error: 0x1400sub1: DynBuildOd returns 0x20 "
                        "kCopCobNoFreeEntry: RPDO1 (0x1400) would be valid RX PDO number 1; "
                        "the target's RX COB table holds 0; the node does not start\n")


def test_not_a_container(tmp_path):
    r = run("node", "--container", "samples/device.dcf", "-n", "16")
    assert r.exit_code == 1
    assert r.stderr == ("samples/device.dcf: error: samples/device.dcf is DCF/EDS text, not a "
                        "binary container or its JSON form; use dcf2bin compile to make a "
                        "container of it (dcf2bin validate checks it)\n")


def _serve(channel, args, reads):
    """Run the node command while another thread reads entries by SDO, then Ctrl-C."""
    b = Bench(channel)
    got, boot = {}, threading.Event()
    net = b.network()
    net.subscribe(0x710, lambda *a: boot.set())

    def client():
        try:
            boot.wait(2)
            from dcf2bin.bus.download import sdo_client
            sdo = sdo_client(net, 16, timeout=2.0, retries=0)
            for key in reads:
                got[key] = sdo.upload(*key)
        finally:
            import _thread
            _thread.interrupt_main()
    t = threading.Thread(target=client)
    t.start()
    try:
        r = run("node", *args, "-n", "16", "-q", "-i", "virtual", "--channel", channel,
                "--duration", "20")
    finally:
        t.join()
        b.close()
    return r, got


def test_the_target_serves_its_network_variables_and_pdo_objects(channel, plc_bin):
    r, got = _serve(channel, ["--container", plc_bin], [(0x1400, 1), (0xA140, 2), (0xA580, 0)])
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    assert got == {(0x1400, 1): bytes.fromhex("83010000"), (0xA140, 2): b"\0\0\0",
                   (0xA580, 0): b"\x02"}


def test_static_od_objects_are_there_too(channel, plc_bin):
    r, got = _serve(channel, ["--container", plc_bin, "--static-od", "samples/device.eds"],
                    [(0x1000, 0), (0x1018, 1), (0xA4C0, 1)])
    assert r.exit_code == 0
    assert got == {(0x1000, 0): bytes.fromhex("91010F00"), (0x1018, 1): bytes.fromhex("AB000000"),
                   (0xA4C0, 1): b"\0"}
