"""The network on one virtual bus, end to end: `network build` makes the PLC's DCF from
tests/fixtures/network_show/bus.yml, `compile` its container, and the PLC runs as the
emulated SYS TEC target (`node --container`); the slaves are canopen LocalNodes from
their own EDS/DCF files, as they come from the factory; `network download` configures
them (identity check, D-18 writes, read-back). Then a value a slave sends in its TPDO
appears in the PLC's process image at the address `map` gives for that variable, and a
value written at an output variable's address in the PLC reaches the slave's object
(SPEC §10.5; issue 21).
"""
from __future__ import annotations

import importlib.util
import json
import time

import pytest

from bus_helpers import Bench, TIMEOUT, beside_target, run

pytest_plugins = ["bus_fixtures"]
pytestmark = [pytest.mark.usefixtures("at_root"),
              pytest.mark.skipif(importlib.util.find_spec("dcf2bin.dynod") is None,
                                 reason="needs dcf2bin.dynod")]

NETWORK = "tests/fixtures/network_show/bus.yml"
PLC_ID = 16
SLAVES = {2: "tests/fixtures/network/check/io.dcf", 3: "samples/device.eds",
          5: "tests/fixtures/network/IoX4_8AI.eds"}           # the files bus.yml names


def frames_on(net, *cob_ids):
    got: list[tuple[int, bytes]] = []
    for cob in cob_ids:
        net.subscribe(cob, lambda can_id, data, ts: got.append((can_id, bytes(data))))
    return got


def wait_for(got, cob: int, n: int = 1, timeout: float = 3.0) -> list[bytes]:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        frames = [d for c, d in got if c == cob]
        if len(frames) >= n:
            return frames
        time.sleep(0.005)
    raise AssertionError(f"no {n} frames on 0x{cob:X} within {timeout} s")


def map_of(dcf: str) -> dict[str, dict]:
    r = run("map", dcf, "--format", "json")
    assert r.exit_code == 0, r.output
    # the map writes indexes as "0xA040" strings; SDO wants the number
    return {v["name"]: dict(v, index=int(v["index"], 16))
            for v in json.loads(r.stdout)["variables"]}


def test_build_download_and_the_pdos_reach_the_plcs_process_image(channel, tmp_path):
    out = tmp_path / "build"
    r = run("network", "build", NETWORK, "-o", str(out), "-q")
    assert r.exit_code == 0, r.output
    plc_dcf, plc_bin = str(out / "plc.dcf"), str(tmp_path / "plc.bin")
    assert run("compile", plc_dcf, "-o", plc_bin, "-q").exit_code == 0
    var = map_of(plc_dcf)
    door, position, lamp = var["door_closed"], var["position"], var["lamp"]
    assert (door["direction"], position["direction"], lamp["direction"]) == (
        "input", "input", "output")

    bench = Bench(channel)
    mon = bench.network()
    got = frames_on(mon, 0x700 + PLC_ID, 0x182, 0x183, 0x202)
    seen: dict = {}

    def scenario():
        wait_for(got, 0x700 + PLC_ID)                   # the PLC target has booted
        slaves = {}
        for nid, path in SLAVES.items():
            from dcf2bin.bus.node import from_file
            node, errors = from_file(path, nid)
            assert errors == []
            slaves[nid] = bench.add(node)
        seen["download"] = run("network", "download", NETWORK, "--verify",
                               "-i", "virtual", "--channel", channel,
                               "--timeout", TIMEOUT, "--retries", "0")
        # the slaves' inputs: io1 6000 sub 1 (door_closed), dev3 0x2001 (position)
        slaves[2].sdo[0x6000][1].raw = 0x5A
        slaves[3].sdo[0x2001].raw = 0x123456
        mon.nmt.state = "OPERATIONAL"                    # NMT start, all nodes
        mon.sync.transmit()                              # TPDO1 of io1/dev3: type 1
        seen["io1_tpdo"] = wait_for(got, 0x182)[0]
        seen["dev3_tpdo"] = wait_for(got, 0x183)[0]
        plc = bench.sdo(PLC_ID)
        seen["door"] = plc.upload(door["index"], door["subindex"])
        seen["position"] = plc.upload(position["index"], position["subindex"])
        # an output: the PLC's TPDO (type 255) goes out when a mapped value changes
        plc.download(lamp["index"], lamp["subindex"], b"\x01")
        seen["plc_tpdo"] = wait_for(got, 0x202)[-1]
        deadline = time.monotonic() + 3
        while slaves[2].sdo[0x6200][1].raw != 1 and time.monotonic() < deadline:
            time.sleep(0.005)
        seen["lamp"] = slaves[2].sdo[0x6200][1].raw

    r = beside_target(scenario, plc_bin, PLC_ID, channel, 30, bench)
    d = seen["download"]
    assert d.exit_code == 0, d.output
    assert d.stdout.splitlines() == [
        "node 2 (io1): identity checked, 14 entries written, read back equal",
        "node 3 (dev3): identity checked, 7 entries written, read back equal",
        "node 5 (ai5): identity checked, 11 entries written, read back equal",
        f"{NETWORK}: 3 configured, 0 failed, 0 skipped",
        "  configured  node 2 (io1)  14 entries",
        "  configured  node 3 (dev3)  7 entries",
        "  configured  node 5 (ai5)  11 entries"]
    assert r.exit_code == 0, r.output
    # io1 TPDO1 as configured: door_closed, light_barrier; dev3 TPDO1: position (24 bits)
    assert seen["io1_tpdo"][:1] == b"\x5a"
    assert seen["dev3_tpdo"] == bytes.fromhex("563412")
    assert seen["door"] == b"\x5a" and seen["position"] == bytes.fromhex("563412")
    # the process image the target printed: the inputs at the addresses map gives
    images: list[bytes] = []
    for line in r.stdout.splitlines():
        if line.startswith("node 16: process image"):
            images.append(b"")
        elif line.startswith("0x"):
            images[-1] += bytes.fromhex(" ".join(line.split()[1:]))
    full = [img for img in images if img[position["address"]:position["address"] + 3]
            == bytes.fromhex("563412")]
    assert full, r.stdout
    assert full[-1][door["address"]] == 0x5A
    assert len(full[-1]) >= lamp["address"] + 1
    # the output: lamp's byte at its PI address went out in the PLC's TPDO to io1's RPDO1
    assert seen["plc_tpdo"][:1] == b"\x01"
    assert seen["lamp"] == 1
