"""The whole loop on one virtual bus: a slave device node (samples/device.eds), an
emulated PLC target (`dcf2bin node --container`, from samples/bench_plc.dcf whose RPDO
receives the slave's TPDO), `dcf2bin download` configuring the slave. The slave's TPDO
value must appear in the target's process image at the variable's PI address, and the
target's TPDO must carry an output variable's bytes back: the DCF, the offsets (SPEC
§2), the container (§3), the DynBuildOd emulation (§8) and the bus agree.

The expected addresses are the ones `dcf2bin map --format json` gives for the same DCF
(issue 12: "at the address `map` gives for that network variable").
"""
from __future__ import annotations

import importlib.util
import json
import time

import pytest

from bus_helpers import Bench, beside_target, bus_args, run
from dcf2bin.cli import main

pytest_plugins = ["bus_fixtures"]
pytestmark = [pytest.mark.usefixtures("at_root"),
              pytest.mark.skipif(importlib.util.find_spec("dcf2bin.dynod") is None,
                                 reason="needs dcf2bin.dynod")]

PLC_ID, SLAVE_ID = 0x10, 3
POSITION, STATUS = (0xA140, 2), (0xA040, 1)          # inputs, from the slave's TPDO
DIGOUT, WORD = (0xA4C0, 1), (0xA580, 2)              # outputs, in the PLC's TPDO


class Frames:
    def __init__(self, net, *cob_ids):
        self.got: list[tuple[int, bytes]] = []
        for cob in cob_ids:
            net.subscribe(cob, lambda can_id, data, ts: self.got.append((can_id, bytes(data))))

    def wait(self, n: int, cob: int, timeout: float = 2.0) -> list[bytes]:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            frames = [d for c, d in self.got if c == cob]
            if len(frames) >= n:
                return frames
            time.sleep(0.005)
        raise AssertionError(f"no {n} frames on 0x{cob:X} within {timeout} s: {self.got}")


def map_addresses(dcf_path: str) -> dict[tuple[int, int], int]:
    """Network variable -> PI address, as `dcf2bin map --format json` gives it."""
    r = run("map", dcf_path, "--format", "json")
    assert r.exit_code == 0, r.output
    return {(int(v["index"], 16), v["subindex"]): v["address"]     # index: "0xA040"
            for v in json.loads(r.stdout)["variables"]}


def test_download_slave_and_see_its_tpdo_in_the_targets_process_image(channel, tmp_path):
    plc_bin = str(tmp_path / "bench_plc.bin")
    assert run("compile", "samples/bench_plc.dcf", "-o", plc_bin).exit_code == 0
    addr = map_addresses("samples/bench_plc.dcf")
    assert addr == {STATUS: 0, POSITION: 3, DIGOUT: 8, WORD: 10}

    bench = Bench(channel)
    mon = bench.network()
    frames = Frames(mon, 0x700 + PLC_ID, 0x180 + SLAVE_ID, 0x180 + PLC_ID)
    seen: dict = {}

    def scenario():
        frames.wait(1, 0x700 + PLC_ID)                  # the target has booted
        bench.device(SLAVE_ID)                           # the slave, from its EDS
        rc = main.main(["download", "samples/device.dcf", "-n", str(SLAVE_ID), "-q",
                        "--verify", *bus_args(channel)], standalone_mode=False)
        seen["download"] = rc
        # Every node takes the frames of the bus in order: NMT start before SYNC, the
        # slave's TPDO before the SDO request that reads the target's image.
        mon.nmt.state = "OPERATIONAL"                    # NMT start, all nodes
        mon.sync.transmit()                              # slave TPDO1 is type 1 (SYNC)
        seen["tpdo1"] = frames.wait(1, 0x180 + SLAVE_ID)[0]
        plc = bench.sdo(PLC_ID)
        seen["position"] = plc.upload(*POSITION)
        # a new value on the slave travels on the next SYNC
        bench.sdo(SLAVE_ID).download(0x2001, 0, bytes.fromhex("563412"))
        mon.sync.transmit()
        seen["tpdo2"] = frames.wait(2, 0x180 + SLAVE_ID)[1]
        # outputs: the target's TPDO (type 254) goes out when a mapped value changes
        plc.download(*WORD, bytes.fromhex("EFBE"))
        plc.download(*DIGOUT, b"\x5a")
        seen["plc_tpdo"] = frames.wait(2, 0x180 + PLC_ID)[-1]

    r = beside_target(scenario, plc_bin, PLC_ID, channel, 20, bench)
    assert seen["download"] is None and r.exit_code == 0
    assert r.stderr == (f"{plc_bin}: node 16 on the bus (interface virtual, channel "
                        f"{channel}: python-can's virtual bus reaches only this process); "
                        f"Ctrl-C stops it\n{plc_bin}: node 16 stopped\n")
    # device.dcf's 0x2001 = -8388608 (INTEGER24 00 00 80), then the dummy byte
    assert seen["tpdo1"] == bytes.fromhex("00008000")
    assert seen["tpdo2"] == bytes.fromhex("56341200")
    assert seen["position"] == bytes.fromhex("000080")
    # the image after each RPDO: Position at its PI address 3, Status (dummy 0) at 0
    first = bytearray(12)
    first[addr[POSITION]:addr[POSITION] + 3] = bytes.fromhex("000080")
    second = bytearray(12)
    second[addr[POSITION]:addr[POSITION] + 3] = bytes.fromhex("563412")
    assert r.stdout == ("node 16: process image (12 bytes)\n"
                        f"0x0000  {first.hex(' ').upper()}\n"
                        "node 16: process image (12 bytes)\n"
                        f"0x0000  {second.hex(' ').upper()}\n")
    assert r.stdout.splitlines()[1] == "0x0000  00 00 00 00 00 80 00 00 00 00 00 00"
    # the target's TPDO: DigOut then Word, the bytes at their PI addresses 8 and 10
    assert seen["plc_tpdo"] == bytes.fromhex("5AEFBE")
