"""The commissioning loop, end to end (issue 29 item 4), on python-can's virtual bus:
three software slaves start without a node-ID, told apart by their serial numbers;
`network lss` gives them the node-IDs of the network file, `network download` configures
them, `network upload` reads them back, `network build` writes the build's DCFs, and
`diff` of each upload against the build's <slave>.dcf -- and of the two folders, and of
each built DCF against its live node -- finds nothing. A value changed on one node by
hand (an SDO download from here) makes `diff` exit 1 naming exactly that entry. The same
loop with a real drive's EDS (technosoft.eds: 0x1014 and 0x1200 are $NODEID formulas)
shows a node that took its node-ID from LSS holding every COB-ID of that node-ID.

Every step is the CLI (CliRunner: the virtual bus reaches only this process), each
bounded in time by the harness (``run_within``) with the bound its documentation gives,
never by sleeping."""
from __future__ import annotations

import json

import pytest
from bus_helpers import run, run_within
from conftest import ROOT
from lss_helpers import drive_eds, io8_eds, lss_node, seconds_out

pytest_plugins = ["bus_fixtures"]

SDO_TIMEOUT = 1.0           # each SDO answer (it comes in milliseconds on the virtual bus)
LSS_TIMEOUT = 0.5           # network lss's default
CHECK_WAIT = 0.3            # network lss's --check-wait default
SLACK = 3.0                 # what a loaded machine may add to a command's own bound
SERIALS = {"io1": 0x1001, "io2": 0x1002, "io3": 0x1003}
NODE_IDS = {"io1": 2, "io2": 3, "io3": 4}
IDENTITY = "0x000000AB  0x00000008    0x00010002"


def network_file(folder, eds: str) -> str:
    """A PLC and three IO-8 modules of one vendor-ID and product code, each with its whole
    identity in the file; io1 maps a TPDO and writes a string, io2 writes a REAL32 and a
    string, io3 is left at its file's values but for its heartbeat."""
    path = folder / "bus.yml"
    path.write_text(f"""master:
  node_id: 1
  name: plc
  sync_period: 10000
  dcf: {ROOT}/tests/fixtures/network/plc.dcf
io1:
  dcf: {eds}
  node_id: 2
  vendor_id: 0xAB
  product_code: 8
  revision_number: 0x00010002
  serial_number: 0x1001
  heartbeat_producer: 200
  sdo:
    - {{index: 0x2000, sub_index: 0, value: "Hall 1"}}
  tpdo:
    1:
      transmission: 1
      mapping:
        - {{index: 0x2001, sub_index: 0, name: position}}
io2:
  dcf: {eds}
  node_id: 3
  vendor_id: 0xAB
  product_code: 8
  revision_number: 0x00010002
  serial_number: 0x1002
  heartbeat_producer: 100
  sdo:
    - {{index: 0x2002, sub_index: 0, value: 2.5}}
    - {{index: 0x2000, sub_index: 0, value: "Hall 2"}}
io3:
  dcf: {eds}
  node_id: 4
  vendor_id: 0xAB
  product_code: 8
  revision_number: 0x00010002
  serial_number: 0x1003
  heartbeat_producer: 300
  sdo:
    - {{index: 0x2000, sub_index: 0, value: "Hall 3"}}
""")
    return str(path)


def sdo_bus(channel: str) -> list[str]:
    return ["-i", "virtual", "--channel", channel, "--timeout", str(SDO_TIMEOUT),
            "--retries", "0"]


def lss_bound(slaves: int) -> float:
    """network lss: per slave a selective switch (4 answers at most, the last one
    answered), configure node-ID, store, switch back and the boot-up message: 8 waits of
    --timeout at most; before, one SDO round at the node-IDs of the file (--check-wait);
    after, the scan (listen, then 0x1000 and 0x1018 sub 1-4 of each node: 5 rounds)."""
    return (8 * slaves + 6) * LSS_TIMEOUT + CHECK_WAIT + SLACK


def writes_bound(network: str, slaves: int) -> float:
    """network download: each slave's identity (4 reads) and its writes, each an SDO
    transfer bounded as bus/sdo.py bounds it, retries 0 (network show --writes counts
    them)."""
    import json
    shown = json.loads(run("network", "show", network, "-f", "json", "--writes").stdout)
    writes = sum(len(n.get("writes") or []) for n in shown["nodes"])
    return (5 * slaves + 2 * writes) * 2 * SDO_TIMEOUT + SLACK


def upload_bound(eds: str, slaves: int) -> float:
    """network upload: the sum of each node's entries' bounds (upload's own node bound),
    for every slave (-j reads them at once, but the bound does not count on it)."""
    from dcf2bin import formats
    from dcf2bin.bus import upload as up
    todo, _ = up.targets(formats.load(eds), max_upload=256)
    return slaves * up.node_bound(todo, up.Options(SDO_TIMEOUT, 0, 256)) + SLACK


@pytest.fixture
def loop(bench, tmp_path, monkeypatch):
    """Three unconfigured software slaves of the network file, the order on the bus not
    the file's."""
    monkeypatch.chdir(tmp_path)
    eds = io8_eds(tmp_path)
    nodes = {serial: lss_node(bench, serial, path=eds) for serial in (0x1003, 0x1001, 0x1002)}
    return eds, network_file(tmp_path, eds), nodes


def test_lss_download_upload_and_diff_agree_and_a_change_by_hand_is_named(bench, loop):
    eds, network, nodes = loop
    # 1. node-IDs by LSS
    r = run_within(lss_bound(3), "network", "lss", network, "-i", "virtual", "--channel",
                   bench.channel)
    assert (r.exit_code, r.stderr) == (0, "")
    assert seconds_out(r.stdout).splitlines()[2:] == [
        f"2     io1   assigned  selective switch  none  {IDENTITY}  0x00001001  yes",
        f"3     io2   assigned  selective switch  none  {IDENTITY}  0x00001002  yes",
        f"4     io3   assigned  selective switch  none  {IDENTITY}  0x00001003  yes"]
    assert {serial: node.id for serial, node in nodes.items()} == {
        0x1001: 2, 0x1002: 3, 0x1003: 4}
    # 2. configuration by SDO
    r = run_within(writes_bound(network, 3), "network", "download", network,
                   *sdo_bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    assert r.stdout.splitlines()[-4:] == [
        f"{network}: 3 configured, 0 failed, 0 skipped",
        "  configured  node 2 (io1)  8 entries",
        "  configured  node 3 (io2)  3 entries",
        "  configured  node 4 (io3)  2 entries"]
    # 3. read back, 4. the build
    r = run_within(upload_bound(eds, 3), "network", "upload", network, "-o", "up", "-q",
                   *sdo_bus(bench.channel))
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    for name, node_id in NODE_IDS.items():      # the serial number read is its LSS one
        with open(f"up/{name}.dcf", encoding="utf-8") as f:
            text = f.read()
        assert text.split("[DeviceComissioning]\n")[1].split("\n\n")[0].splitlines() == [
            f"NodeID={node_id}", f"NodeName={name}",
            f"LSS_SerialNumber=0x{SERIALS[name]:08X}"]
    r = run("network", "build", network, "-o", "out", "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    # 5. nothing differs: file by file, folder by folder, and each node against its DCF
    for name in NODE_IDS:
        r = run("diff", f"up/{name}.dcf", f"out/{name}.dcf")
        assert (r.exit_code, r.stdout) == (0, ""), (name, r.stdout)
    r = run("diff", "out", "up")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == ("out, up: 3 files equal, 4 files of the build not compared; 102 "
                        "entries compared, 3 of the node's state left out (--all compares "
                        "them)\n")
    for name, node_id in NODE_IDS.items():
        r = run_within(upload_bound(eds, 1), "diff", f"out/{name}.dcf", "-n", str(node_id),
                       *sdo_bus(bench.channel))
        assert (r.exit_code, r.stdout) == (0, ""), (name, r.stdout)
    # 6. io2's heartbeat changed by hand: 100 ms -> 250 ms
    with bench.sdo(3) as ch:
        ch.download(0x1017, 0, (250).to_bytes(2, "little"))
    r = run_within(upload_bound(eds, 3), "network", "upload", network, "-o", "again", "-q",
                   *sdo_bus(bench.channel))
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    diff = ["--- out/io2.dcf", "+++ again/io2.dcf",
            "@@ 0x1017 Producer heartbeat time @@",
            "-0x1017sub0 Producer heartbeat time: 100",
            "+0x1017sub0 Producer heartbeat time: 250"]
    r = run("diff", "out", "again")
    assert r.exit_code == 1
    assert r.stdout.splitlines() == diff
    assert r.stderr == ("out, again: 1 of 3 files differ, 1 entry, 4 files of the build not "
                        "compared; 102 entries compared, 3 of the node's state left out "
                        "(--all compares them)\n")
    r = run("diff", "out/io2.dcf", "again/io2.dcf", "-q")
    assert (r.exit_code, r.stdout.splitlines()) == (1, diff)
    doc = json.loads(run("diff", "out", "again", "-f", "json").stdout)
    assert [(f["a"]["file"], d["index"], d["subindex"], d["change"], d["a"]["value"],
             d["b"]["value"]) for f in doc["files"] for d in f["differences"]] == [
        ("out/io2.dcf", "0x1017", 0, "changed", "100", "250")]
    # the node itself, against its whole DCF and against what the build writes to it
    r = run_within(upload_bound(eds, 1), "diff", "out/io2.dcf", "-n", "3", "-q",
                   *sdo_bus(bench.channel))
    assert (r.exit_code, r.stdout.splitlines()) == (1, ["--- out/io2.dcf", "+++ node 3",
                                                        *diff[2:]])
    r = run_within(upload_bound(eds, 1), "diff", "out/io2.bin", "-n", "3", "-q",
                   *sdo_bus(bench.channel))
    assert r.exit_code == 1
    assert r.stdout.splitlines() == ["--- out/io2.bin", "+++ node 3", "@@ 0x1017 @@",
                                     "-0x1017sub0: 100", "+0x1017sub0: 250"]


def drives_file(folder, eds: str) -> str:
    """A PLC and two drives of one vendor-ID and product code, told apart by serial."""
    path = folder / "drives.yml"
    path.write_text(f"""master:
  node_id: 1
  name: plc
  sync_period: 10000
  dcf: {ROOT}/tests/fixtures/network/plc.dcf
""" + "".join(f"""axis{k}:
  dcf: {eds}
  node_id: {node_id}
  vendor_id: 0x1A3
  product_code: 0xC01
  revision_number: 0x00010004
  serial_number: {serial}
  heartbeat_producer: 100
  tpdo:
    1:
      transmission: 1
      mapping:
        - {{index: 0x6041, sub_index: 0, name: status{k}}}
""" for k, (node_id, serial) in enumerate(((5, 0x2001), (6, 0x2002)), 1)))
    return str(path)


def test_a_drive_given_its_node_id_by_lss_holds_the_cob_ids_of_it(bench, tmp_path,
                                                                   monkeypatch):
    """A node given a node-ID by LSS resets its communication: every entry whose value its
    EDS states as a $NODEID formula takes the new node-ID -- 0x1014 (EMCY), 0x1200 (SDO
    server) and the PDOs' COB-IDs -- so that its upload equals the build's DCF."""
    monkeypatch.chdir(tmp_path)
    eds = drive_eds(tmp_path)
    network = drives_file(tmp_path, eds)
    nodes = [lss_node(bench, serial, path=eds) for serial in (0x2002, 0x2001)]
    r = run_within(lss_bound(2), "network", "lss", network, "-i", "virtual", "--channel",
                   bench.channel)
    assert (r.exit_code, r.stderr) == (0, "")
    assert [n.id for n in nodes] == [6, 5]
    r = run_within(writes_bound(network, 2), "network", "download", network,
                   *sdo_bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    r = run_within(upload_bound(eds, 2), "network", "upload", network, "-o", "up", "-q",
                   *sdo_bus(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("network", "build", network, "-o", "out", "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    for name, node_id in (("axis1", 5), ("axis2", 6)):
        r = run("diff", f"up/{name}.dcf", f"out/{name}.dcf")
        assert (r.exit_code, r.stdout) == (0, ""), (name, r.stdout)
        with bench.sdo(node_id) as ch:
            assert [int.from_bytes(ch.upload(index, sub), "little") for index, sub in (
                (0x1014, 0), (0x1200, 1), (0x1200, 2), (0x1401, 1), (0x1803, 1))] == [
                0x80 + node_id, 0x600 + node_id, 0x580 + node_id, 0x300 + node_id,
                0x80000480 + node_id]
