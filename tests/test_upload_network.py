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
    for nid in (2, 3, 4):
        bench.device(nid, EDS)
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
    assert sorted(p.name for p in read.iterdir()) == ["dev2.dcf", "dev3.dcf", "dev4.dcf"]
    for name, nid in (("dev2", 2), ("dev3", 3), ("dev4", 4)):
        want, got = configured(built / f"{name}.dcf", nid), configured(read / f"{name}.dcf", nid)
        assert {k: got[k] for k in want} == want, name
        assert len(want) == {"dev2": 6, "dev3": 3, "dev4": 0}[name]
        assert section((read / f"{name}.dcf").read_text(), "DeviceComissioning") == [
            "[DeviceComissioning]", f"NodeID={nid}", f"NodeName={name}"]
    assert configured(read / "dev3.dcf", 3)[(0x2002, 0)] == b"\x00\x00\x20\x40"   # 2.5
    assert configured(read / "dev2.dcf", 2)[(0x1A00, 1)] == b"\x18\x00\x01\x20"


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
    assert sorted(p.name for p in out.iterdir()) == ["dev2.dcf", "dev3.dcf"]   # not dev4
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
