"""dcf2bin network upload (issue 29 item 2): every slave of a network read back into
<slave>.dcf, named as `network build` names its slaves' DCFs, so that the build's folder
and the upload's compare file by file; all the files or none; on python-can's virtual bus
with three software slaves."""
from __future__ import annotations

import pytest
from bus_helpers import VIRTUAL, run, run_within
from conftest import ROOT
from test_upload import TIMEOUT, configured, falling_silent, node_bound, section

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

EDS = "samples/device.eds"
SLACK = 3.0
IMPLIED = (
    f"{ROOT}/{EDS}:68: info: 0x1016 sub 0: not read: the file only implies it (no section "
    "to state a value in)\n"
    f"{ROOT}/{EDS}:24: info: 0x1400: not read: the file only implies its entries (no "
    "section to state a value in)\n"
    f"{ROOT}/{EDS}:24: info: 0x1600: not read: the file only implies its entries (no "
    "section to state a value in)\n")


@pytest.fixture
def network_file(tmp_path):
    """A PLC and three slaves made from samples/device.eds: dev2 with a TPDO and a
    heartbeat, dev3 with a heartbeat and `sdo` writes, dev4 with its file's values; the
    string 0x2000 written to dev2 and dev3 (the bench node has no value for it)."""
    path = tmp_path / "bus.yml"
    path.write_text(f"""master:
  node_id: 1
  name: plc
  sync_period: 10000
  dcf: {ROOT}/tests/fixtures/network/plc.dcf
dev2:
  dcf: {ROOT}/{EDS}
  node_id: 2
  product_code: 0
  heartbeat_producer: 200
  sdo:
    - {{index: 0x2000, sub_index: 0, value: "Hall 1"}}
  tpdo:
    1:
      transmission: 1
      mapping:
        - {{index: 0x2001, sub_index: 0, name: position}}
dev3:
  dcf: {ROOT}/{EDS}
  node_id: 3
  product_code: 0
  heartbeat_producer: 100
  sdo:
    - {{index: 0x2002, sub_index: 0, value: 2.5}}
    - {{index: 0x2000, sub_index: 0, value: "Hall 2"}}
dev4:
  dcf: {ROOT}/{EDS}
  node_id: 4
  product_code: 0
""")
    return str(path)


def bus(channel: str, timeout: float | str = "2", *more: str) -> list[str]:
    return ["-i", "virtual", "--channel", channel, "--timeout", str(timeout),
            "--retries", "0", *more]


def test_an_upload_of_a_configured_network_agrees_with_its_build(bench, network_file,
                                                                 tmp_path):
    nodes = {nid: bench.device(nid, EDS) for nid in (2, 3, 4)}
    built, read = tmp_path / "built", tmp_path / "read"
    assert run("network", "build", network_file, "-o", str(built), "-q").exit_code == 0
    r = run("network", "download", network_file, *bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    r = run("network", "upload", network_file, "-o", str(read), *bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    assert r.stdout == (
        "node 2 (dev2): 19 entries read\n"
        "node 3 (dev3): 19 entries read\n"
        "node 4 (dev4): 18 of 19 entries read, 1 refused\n"
        f"{network_file}: 3 uploaded, 0 failed, 0 did not answer\n"
        "  uploaded  node 2 (dev2)  19 entries read\n"
        "  uploaded  node 3 (dev3)  19 entries read\n"
        "  uploaded  node 4 (dev4)  18 of 19 entries read, 1 refused\n")
    # the infos once for the file the three share; dev4's string was never written (the
    # bench node has no value for it)
    assert r.stderr == IMPLIED + (
        f"{ROOT}/{EDS}:157: warning: node 4 (dev4): 0x2000 sub 0: the node refused the "
        "upload: SDO abort 0x060A0023: Resource not available\n"
        f"network upload: 3 files in {read}\n")
    # and the lock of the folder, which names the files written (as network build's)
    assert sorted(p.name for p in read.iterdir()) == [".dcf2bin-build.lock", "dev2.dcf", "dev3.dcf", "dev4.dcf"]
    for name, nid in (("dev2", 2), ("dev3", 3), ("dev4", 4)):
        want, got = configured(built / f"{name}.dcf", nid), configured(read / f"{name}.dcf", nid)
        assert {k: got[k] for k in want} == want, name
        assert len(want) == {"dev2": 6, "dev3": 3, "dev4": 0}[name]
        assert section((read / f"{name}.dcf").read_text(), "DeviceComissioning") == [
            "[DeviceComissioning]", f"NodeID={nid}", f"NodeName={name}"]
    assert configured(read / "dev3.dcf", 3)[(0x2002, 0)] == b"\x00\x00\x20\x40"   # 2.5
    assert configured(read / "dev2.dcf", 2)[(0x1A00, 1)] == b"\x18\x00\x01\x20"
    # a value changed on one node by hand: its next upload differs there, and only there
    nodes[3].sdo[0x1017].raw = 999
    again = tmp_path / "again"
    r = run("network", "upload", network_file, "-o", str(again), "-q", *bus(bench.channel))
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    for name in ("dev2.dcf", "dev4.dcf"):
        assert (again / name).read_bytes() == (read / name).read_bytes()
    before, after = configured(read / "dev3.dcf", 3), configured(again / "dev3.dcf", 3)
    assert {k for k in before if before[k] != after[k]} == {(0x1017, 0)}
    assert (before[(0x1017, 0)], after[(0x1017, 0)]) == (b"\x64\x00", b"\xe7\x03")


def network_bound(slaves: int = 3) -> float:
    return slaves * node_bound(EDS) + SLACK


FAILED_ROW = (f"0x1018 sub 0: node 3 did not answer (no SDO response within 0.2 s, 1 try"
              f"{VIRTUAL})")


@pytest.mark.parametrize("jobs", ["1", "4"])
def test_a_slave_that_stops_answering_halfway_writes_no_file(bench, faulty, network_file,
                                                             tmp_path, jobs):
    bench.device(2, EDS)
    falling_silent(faulty, bench.device(3, EDS), after=5)
    out = tmp_path / "read"
    r = run_within(network_bound(), "network", "upload", network_file, "-o", str(out),
                   "-j", jobs, *bus(bench.channel, TIMEOUT))
    assert r.exit_code == 1
    # node 4 is not on the bus; the lines and rows in node-ID order, however many at once
    assert r.stdout == (
        "node 2 (dev2): 18 of 19 entries read, 1 refused\n"
        "node 3 (dev3): 5 of 19 entries read, 1 failed, 13 not read\n"
        "node 4 (dev4): did not answer\n"
        f"{network_file}: 1 uploaded, 1 failed, 1 did not answer\n"
        "  uploaded        node 2 (dev2)  18 of 19 entries read, 1 refused\n"
        f"  failed          node 3 (dev3)  {FAILED_ROW}\n"
        "  did not answer  node 4 (dev4)  0x1000 sub 0: node 4 did not answer (no SDO "
        f"response within 0.2 s, 1 try{VIRTUAL})\n")
    assert r.stderr.splitlines()[-4:] == [
        f"{ROOT}/{EDS}:157: warning: node 2 (dev2): 0x2000 sub 0: the node refused the "
        "upload: SDO abort 0x060A0023: Resource not available",
        f"{ROOT}/{EDS}:91: error: node 3 (dev3): {FAILED_ROW}",
        f"{network_file}:26: error: node 4 (dev4): 0x1000 sub 0: node 4 did not answer (no "
        f"SDO response within 0.2 s, 1 try{VIRTUAL})",
        f"{network_file}: 2 slaves not uploaded, nothing written (--keep-going writes what "
        "was read)"]
    assert not out.exists()


def test_keep_going_writes_the_slaves_that_answered(bench, faulty, network_file, tmp_path):
    bench.device(2, EDS)
    falling_silent(faulty, bench.device(3, EDS), after=5)
    out = tmp_path / "read"
    r = run_within(network_bound(), "network", "upload", network_file, "-o", str(out), "-q",
                   "--keep-going", *bus(bench.channel, TIMEOUT))
    assert (r.exit_code, r.stdout) == (1, "")
    assert [line.split(": error: ")[1] for line in r.stderr.splitlines()] == [
        f"node 3 (dev3): {FAILED_ROW}",
        "node 4 (dev4): 0x1000 sub 0: node 4 did not answer (no SDO response within 0.2 s, "
        f"1 try{VIRTUAL})"]
    assert sorted(p.name for p in out.iterdir()) == [".dcf2bin-build.lock", "dev2.dcf", "dev3.dcf"]   # not dev4
    assert section((out / "dev3.dcf").read_text(), "1018sub0")[-1] == f"; {FAILED_ROW}"


def test_network_name_and_bitrate_in_every_file(bench, network_file, tmp_path):
    for nid in (2, 3, 4):
        bench.device(nid, EDS)
    out = tmp_path / "read"
    r = run("network", "upload", network_file, "-o", str(out), "-q", "--network-name", "line2",
            "--bitrate", "500000", *bus(bench.channel))
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    assert section((out / "dev4.dcf").read_text(), "DeviceComissioning") == [
        "[DeviceComissioning]", "NodeID=4", "NodeName=dev4", "NetworkName=line2",
        "Baudrate=500"]


def test_an_output_that_is_a_file_fails_before_the_bus(network_file, tmp_path):
    f = tmp_path / "file"
    f.write_text("")
    r = run("network", "upload", network_file, "-o", str(f), "-i", "no-such-interface")
    assert (r.exit_code, r.stderr) == (3, f"{f}: error: cannot write: Not a directory\n")


def test_a_network_with_errors_reads_nothing(tmp_path):
    bad = tmp_path / "bus.yml"
    bad.write_text("master:\n  node_id: 1\ndev2:\n  node_id: 2\n")
    r = run("network", "upload", str(bad), "-o", str(tmp_path / "out"), "-i",
            "no-such-interface")
    assert r.exit_code == 1
    assert r.stderr.endswith(f"{bad}: 1 error, nothing read\n")
    assert not (tmp_path / "out").exists()


CPJ = "tests/fixtures/network/check/network.cpj"
CPJ_FILES = {1: "tests/fixtures/network/check/plc.dcf", 2: "tests/fixtures/network/check/io.dcf",
             3: "tests/fixtures/network/check/io3.dcf"}


def test_a_cpj_project_s_nodes_are_read_with_their_dcfs(bench, tmp_path):
    """A .cpj project: each node read with its own DCF (a PLC with network variables
    would not be: this project's plc.dcf has none), named by the project's names."""
    from dcf2bin.bus.node import from_file
    for nid, path in CPJ_FILES.items():
        node, errors = from_file(path, nid)
        assert errors == []
        bench.add(node)
    out = tmp_path / "read"
    r = run("network", "upload", CPJ, "-o", str(out), *bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    assert r.stdout == (
        "node 1 (plc): 55 entries read\n"
        "node 2 (io): 40 entries read\n"
        "node 3 (io3): 40 entries read\n"
        f"{CPJ}: 3 uploaded, 0 failed, 0 did not answer\n"
        "  uploaded  node 1 (plc)  55 entries read\n"
        "  uploaded  node 2 (io)  40 entries read\n"
        "  uploaded  node 3 (io3)  40 entries read\n")
    assert r.stderr == f"network upload: 3 files in {out}\n"
    # each node holds its DCF's values (a node made from it): the upload states them
    for nid, path in CPJ_FILES.items():
        name = {1: "plc", 2: "io", 3: "io3"}[nid]
        want, got = configured(path, nid), configured(out / f"{name}.dcf", nid)
        assert want and {k: got[k] for k in want} == want, name


def test_a_cpj_project_s_plc_is_not_read(bench, tmp_path):
    import shutil
    from dcf2bin.bus.node import from_file
    # the project's PLC of the check fixtures, given one network variable (what makes it
    # a PLC), so that the project has no error that stops every network command
    (tmp_path / "plc.dcf").write_bytes((ROOT / CPJ_FILES[1]).read_bytes() + (
        b"\n[A040]\nParameterName=inputs\nObjectType=0x8\nSubNumber=2\n\n[A040sub0]\n"
        b"ParameterName=count\nDataType=0x0005\nAccessType=ro\nDefaultValue=1\n\n"
        b"[A040sub1]\nParameterName=in1\nDataType=0x0005\nAccessType=ro\nPDOMapping=1\n"))
    shutil.copy(ROOT / CPJ_FILES[2], tmp_path / "io.dcf")
    cpj = tmp_path / "cell.cpj"
    cpj.write_text("[Topology]\nNodes=0x02\nNode1Present=0x01\nNode1Name=plc\n"
                   "Node1DCFName=plc.dcf\nNode2Present=0x01\nNode2Name=io\nNode2DCFName=io.dcf\n")
    node, errors = from_file(str(tmp_path / "io.dcf"), 2)
    bench.add(node)
    out = tmp_path / "read"
    r = run("network", "upload", str(cpj), "-o", str(out), *bus(bench.channel))
    assert r.exit_code == 0, r.stderr
    assert r.stdout == (
        "node 1 (plc): not read (a PLC: its configuration goes with the PLC program)\n"
        "node 2 (io): 40 entries read\n"
        f"{cpj}: 1 uploaded, 0 failed, 0 did not answer, 1 not read (PLC)\n"
        "  not read  node 1 (plc)  a PLC: its configuration goes with the PLC program\n"
        "  uploaded  node 2 (io)  40 entries read\n")
    assert sorted(p.name for p in out.iterdir()) == [".dcf2bin-build.lock", "io.dcf"]
