"""dcf2bin lss scan, dcf2bin lss set, and dcf2bin node answering LSS (--serial,
--lss-unconfigured), on python-can's virtual bus with software LSS slaves."""
from __future__ import annotations

import _thread
import json
import signal
import threading

import pytest
from bus_helpers import Bench, eventually, run
from lss_helpers import AI, AI_ID, Frames, lss_node, plain_node, seconds_out

from dcf2bin.bus import lss as L

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

IO8 = (0xAB, 8, 0x00010002)


def bus(bench, *more):
    return ["-i", "virtual", "--channel", bench.channel, *more]


# -- lss scan ---------------------------------------------------------------------------------

def test_lss_scan_lists_the_nodes_without_a_node_id(bench):
    ai = lss_node(bench, 0x66, path=AI)
    io = lss_node(bench, 0x1002)
    lss_node(bench, 0x1001, node_id=9)                  # has a node-ID: not listed
    r = run("lss", "scan", *bus(bench, "--scan-wait", "0.02"))
    assert (r.exit_code, r.stderr) == (0, "")
    assert seconds_out(r.stdout).splitlines() == [
        "lss scan: 2 nodes without a node-ID, found by fastscan in S s (at most S s)",
        "vendor-ID   product code  revision    serial",
        "0x0000003F  0x002DCAAB    0x01390538  0x00000066",
        "0x000000AB  0x00000008    0x00010002  0x00001002"]
    # three fastscans (two nodes, then none left) of 134 steps, or one more where a busy
    # machine let a node answer a step later than --scan-wait (each is retried)
    assert any(r.stdout.splitlines()[0].endswith(f"(at most {k * 134 * 0.02:.2f} s)")
               for k in (3, 4, 5)), r.stdout
    # nothing changed: both back in waiting, still without a node-ID
    assert [(n.lss.state, n.lss.active) for n in (ai, io)] == [(L.WAITING, 0xFF)] * 2


def test_lss_scan_says_how_many_nodes_share_an_identity(bench):
    """Three nodes alike in all four parts: fastscan finds the identity once (they answer
    every step together); its last confirmation and identify remote slave are answered
    three times."""
    twins = [lss_node(bench, 0x1001) for _ in range(3)]
    r = run("lss", "scan", *bus(bench, "--scan-wait", "0.02"))
    assert r.exit_code == 1
    assert seconds_out(r.stdout).splitlines()[1:] == [
        "vendor-ID   product code  revision    serial",
        "0x000000AB  0x00000008    0x00010002  0x00001001"]
    assert r.stderr == (
        "dcf2bin: error: 3 nodes share the identity vendor-ID 0x000000AB, product code "
        "0x00000008, revision 0x00010002, serial 0x00001001 (or a node answers twice): LSS "
        "cannot tell them apart (give them distinct serial numbers)\n")
    assert [(n.lss.state, n.lss.active) for n in twins] == [(L.WAITING, 0xFF)] * 3
    r = run("lss", "scan", "-f", "json", *bus(bench, "--scan-wait", "0.02"))
    assert r.exit_code == 1
    d = json.loads(r.stdout)
    assert d["nodes"] == [{"vendor_id": "0x000000AB", "product_code": "0x00000008",
                           "revision_number": "0x00010002", "serial_number": "0x00001001",
                           "answers": 3}]
    jsonschema = pytest.importorskip("jsonschema")
    from dcf2bin import schemas
    jsonschema.validate(d, schemas.load("lss-scan"))


def test_lss_scan_json_of_an_empty_bus(bench):
    plain_node(bench, 3)
    r = run("lss", "scan", "-f", "json", *bus(bench))
    assert (r.exit_code, r.stderr) == (0, "")
    d = json.loads(r.stdout)
    assert (d["format"], d["version"], d["nodes"], d["complete"]) == (
        "dcf2bin-lss-scan", 1, [], True)
    assert d["at_most_seconds"] == round(134 * 0.05, 3)     # the default wait, one reset
    assert d["seconds"] < d["at_most_seconds"]
    jsonschema = pytest.importorskip("jsonschema")
    from dcf2bin import schemas
    jsonschema.validate(d, schemas.load("lss-scan"))


# -- lss set ----------------------------------------------------------------------------------

def test_lss_set_with_the_full_identity(bench):
    node = lss_node(bench, 0x1001, node_id=4)
    r = run("lss", "set", "--serial", "0x1001", "--vendor", "0xAB", "--product", "8",
            "--revision", "0x00010002", "-n", "9", *bus(bench))
    assert (r.exit_code, r.stderr) == (0, "")
    assert seconds_out(r.stdout).splitlines() == [
        "lss set: 1 assigned, 0 already right, 0 not found, 0 refused (S s)",
        "node  name  status    found by          was  vendor-ID   product code  revision    "
        "serial      answers  note",
        "9     -     assigned  selective switch  4    0x000000AB  0x00000008    0x00010002  "
        "0x00001001  yes"]
    assert (node.id, node.lss.stored) == (9, 4)        # without --store: not stored


def test_lss_set_by_fastscan_and_store(bench):
    """The revision is not given: fastscan confirms vendor-ID, product code and serial
    (leaving the revision out), and the revision is inquired."""
    lss_node(bench, 0x1002)
    node = lss_node(bench, 0x1001)
    r = run("lss", "set", "--serial", "0x1001", "--vendor", "0xAB", "--product", "8",
            "-n", "6", "--store", "-f", "json", *bus(bench))
    assert (r.exit_code, r.stderr) == (0, "")
    d = json.loads(r.stdout)
    assert d["file"] is None
    row = d["nodes"][0]
    assert (row["status"], row["found_by"], row["was"], row["name"]) == (
        "assigned", "fastscan", 255, None)
    assert row["identity"]["revision_number"] == "0x00010002"
    assert (node.id, node.lss.stored) == (6, 6)
    jsonschema = pytest.importorskip("jsonschema")
    from dcf2bin import schemas
    jsonschema.validate(d, schemas.load("lss"))


def test_lss_set_a_node_id_that_is_taken(bench):
    node = lss_node(bench, 0x1001)
    plain_node(bench, 5)
    r = run("lss", "set", "--serial", "0x1001", "--vendor", "0xAB", "--product", "8",
            "--revision", "0x00010002", "-n", "5", *bus(bench))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == ("dcf2bin: error: node 5: node-ID 5 is taken: another node answers "
                        "there (vendor-ID 0x000000AB); nothing changed\n")
    assert node.lss.pending == 0xFF


def test_lss_set_of_a_node_that_is_not_there(bench):
    r = run("lss", "set", "--serial", "7", "--vendor", "0xAB", "--product", "8",
            "--revision", "1", "-n", "5", *bus(bench, "--timeout", "0.1"))
    assert r.exit_code == 1
    assert r.stderr == ("dcf2bin: error: node 5: not found by LSS (vendor-ID 0x000000AB, "
                        "product code 0x00000008, revision 0x00000001, serial 0x00000007)\n")


TWINS_ERROR = (
    "two or more nodes answer to the identity vendor-ID 0x000000AB, product code 0x00000008, "
    "revision 0x00010002, serial 0x0000002A (or a node answers twice): LSS cannot tell "
    "them apart (give them distinct serial numbers)")


@pytest.mark.parametrize("given", [[], ["--vendor", "0xAB", "--product", "8"],
                                   ["--vendor", "0xAB", "--product", "8",
                                    "--revision", "0x00010002"]])
def test_lss_set_of_two_nodes_with_one_identity_changes_nothing(bench, given):
    """The reviewer's case: both nodes answered the selection, both took node-ID 30, and
    lss set said "1 assigned". The answers are counted: the second one stops it before any
    node-ID is given (fastscan's last confirmation, or switch state selective)."""
    twins = [lss_node(bench, 42), lss_node(bench, 42)]
    r = run("lss", "set", "--serial", "42", "-n", "30", *given,
            *bus(bench, "--scan-wait", "0.02"))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == f"dcf2bin: error: node 30: {TWINS_ERROR}; nothing changed\n"
    assert [(n.lss.state, n.lss.active, n.lss.pending, n.id) for n in twins] == [
        (L.WAITING, 0xFF, 0xFF, 1)] * 2


def test_lss_set_of_two_configured_nodes_with_one_identity(bench):
    """Found by identify remote slave (both at factory node-ID 7): the selective switch
    that asks their node-ID gets two answers."""
    twins = [lss_node(bench, 42, node_id=7), lss_node(bench, 42, node_id=7)]
    r = run("lss", "set", "--serial", "42", "--vendor", "0xAB", "--product", "8", "-n", "30",
            *bus(bench, "--scan-wait", "0.02"))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == f"dcf2bin: error: node 30: {TWINS_ERROR}; nothing changed\n"
    assert [(n.lss.state, n.lss.pending, n.id) for n in twins] == [(L.WAITING, 7, 7)] * 2


def test_lss_set_usage():
    r = run("lss", "set", "-n", "5")
    assert (r.exit_code, r.stderr.splitlines()[-1]) == (
        2, "Error: Missing option '--serial'.")
    r = run("lss", "set", "--serial", "0x100000000", "-n", "5")
    assert r.exit_code == 2


def test_the_default_scan_wait_is_the_libraries():
    from dcf2bin.cli import main
    for path in (("network", "lss"), ("lss", "set"), ("lss", "scan")):
        cmd = main
        for name in path:
            cmd = cmd.commands[name]
        wait = next(p for p in cmd.params if p.name == "scan_wait")
        assert wait.default == L.WAIT == 0.05, path


def test_the_default_check_wait_is_network_scans():
    """The check before any change is an SDO round that hopes for silence: it waits as
    long as network scan gives a node to answer, not the LSS --timeout (0.5 s)."""
    from dcf2bin.bus import lssnet, scan
    from dcf2bin.cli import main
    for path in (("network", "lss"), ("lss", "set")):
        cmd = main
        for name in path:
            cmd = cmd.commands[name]
        wait = next(p for p in cmd.params if p.name == "check_wait")
        assert wait.default == lssnet.Options().check_wait == scan.TIMEOUT == 0.3, path


# -- dcf2bin node answers LSS -------------------------------------------------------------------

def node_beside(scenario, channel: str, *args):
    """Run ``dcf2bin node ARGS`` in this thread while ``scenario(net)`` runs in another on
    a network of its own; Ctrl-C stops the node when the scenario ends."""
    old = signal.signal(signal.SIGINT, signal.default_int_handler)
    bench = Bench(channel)
    failure: list[BaseException] = []

    def body():
        try:
            scenario(bench)
        except BaseException as exc:        # handed to the test in the main thread
            failure.append(exc)
        finally:
            _thread.interrupt_main()
    t = threading.Thread(target=body)
    try:
        t.start()
        r = run("node", *args, "-i", "virtual", "--channel", channel, "--duration", "20")
    finally:
        t.join()
        bench.close()
        signal.signal(signal.SIGINT, old)
    if failure:
        raise failure[0]
    return r


def test_node_without_a_node_id_is_given_one(channel):
    seen = {}

    def scenario(bench):
        m = L.Master(bench.network(), timeout=2)
        frames = Frames(m.net, 0x706, 0x581)
        assert eventually(lambda: m.non_configured() == 1, 5)     # the node has started
        assert m.select(L.Identity(*AI_ID, 0x4D))
        seen["before"] = list(frames.got)
        assert m.configure_node_id(6).ok and m.store().ok
        m.switch_global(configuration=False)
        seen["boot"] = frames.wait(1)[0]
        seen["serial"] = bench.sdo(6).upload(0x1018, 4)
        m.close()
    r = node_beside(scenario, channel, AI, "--lss-unconfigured", "--serial", "0x4D", "-v")
    assert r.exit_code == 0
    assert seen == {"before": [], "boot": (0x706, b"\x00"),
                    "serial": (0x4D).to_bytes(4, "little")}
    assert r.stderr.splitlines()[:2] == [
        f"{AI}: node without a node-ID (LSS serial 0x0000004D) on the bus (interface "
        f"virtual, channel {channel}: python-can's virtual bus reaches only this process); Ctrl-C stops it",
        "node 6: node-ID 6 from LSS"]


def test_node_identity_from_device_info(channel):
    """samples/device.eds has 0x1018 sub 1 only: product code and revision come from its
    [DeviceInfo], and 0x1018 gets them."""
    seen = {}

    def scenario(bench):
        m = L.Master(bench.network(), timeout=0.1)
        assert eventually(lambda: m.select(L.Identity(*IO8, 5)), 5)   # it has started
        seen["lss"] = [m.inquire(k) for k in range(4)] + [m.inquire_node_id()]
        m.switch_global(configuration=False)
        seen["sdo"] = [bench.sdo(3).upload(0x1018, k) for k in (1, 2, 3, 4)]
        m.close()
    r = node_beside(scenario, channel, "samples/device.eds", "-n", "3", "--serial", "5", "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    assert seen == {"lss": [*IO8, 5, 3],
                    "sdo": [v.to_bytes(4, "little") for v in (*IO8, 5)]}


def test_an_emulated_target_answers_lss_too(channel, tmp_path):
    """Its object dictionary holds raw bytes: the identity is read and added as bytes."""
    plc_bin = str(tmp_path / "plc.bin")
    assert run("compile", "samples/bench_plc.dcf", "-o", plc_bin).exit_code == 0
    seen = {}

    def scenario(bench):
        m = L.Master(bench.network(), timeout=0.1)
        identity = L.Identity(0xAB, 0, 0, 9)           # 0x1018 sub 1 of the static OD
        assert eventually(lambda: m.select(identity), 5)
        seen["node_id"] = m.inquire_node_id()
        m.switch_global(configuration=False)
        seen["sdo"] = [bench.sdo(16).upload(0x1018, k) for k in (0, 1, 4)]
        m.close()
    r = node_beside(scenario, channel, "--container", plc_bin, "-n", "16", "--static-od",
                    "samples/device.eds", "--serial", "9", "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    assert seen == {"node_id": 16, "sdo": [b"\x04", b"\xab\0\0\0", b"\x09\0\0\0"]}
