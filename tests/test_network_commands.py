"""The commands network show, scan and download on the golden network
tests/fixtures/network_show/bus.yml (plc 16; io1 2, dev3 3, ai5 5), the bus ones on
python-can's virtual bus with the slaves as canopen LocalNodes from their files."""
from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import pytest
from bus_helpers import TIMEOUT, run
from canopen import SdoAbortedError

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

NETWORK = "tests/fixtures/network_show/bus.yml"
CPJ = "tests/fixtures/network/check/network.cpj"
FILES = {2: "tests/fixtures/network/check/io.dcf", 3: "samples/device.eds",
         5: "tests/fixtures/network/IoX4_8AI.eds"}            # the files bus.yml names


# io.dcf (shared with the .cpj fixture, whose PLC is node 1) monitors node 1: every network
# command reports what network check reports (issue 26: one verdict)
NET252 = ("tests/fixtures/network/check/io.dcf:116: warning: io1 (node 2) monitors node 1, "
          "which is not in the network [NET252]\n"
          "    hint: remove the consumer entry, or add the node\n")


def slaves(bench, ids=(2, 3, 5)):
    from dcf2bin.bus.node import from_file
    out = {}
    for nid in ids:
        node, errors = from_file(FILES[nid], nid)
        assert errors == []
        out[nid] = bench.add(node)
    return out


def bus(bench, *more):
    return ["-i", "virtual", "--channel", bench.channel, *more]


# -- show -----------------------------------------------------------------------------------

def test_show_text():
    r = run("network", "show", NETWORK)
    assert (r.exit_code, r.stderr) == (0, NET252)
    lines = r.stdout.splitlines()
    assert lines[0] == (f"{NETWORK}: 4 nodes, 5 PDO COB-IDs, estimated bus load 5.6 % of 500 "
                        "kbit/s (2 frames of unknown rate counted as 0)")
    assert lines[2:9] == [
        "COB-ID  frame      producer    consumers       bytes  rate   load    content",
        "0x080   SYNC       plc         io1, dev3, ai5  0      100/s  1.10 %",
        "0x182   TPDO1      io1 TPDO1   plc RPDO1       2      100/s  1.50 %  door_closed, "
        "light_barrier",
        "0x183   TPDO1      dev3 TPDO1  plc RPDO2       3      100/s  1.70 %  position",
        "0x185   TPDO1      ai5 TPDO1   plc RPDO3       4      50/s   0.95 %  pressure, "
        "temperature",
        "0x202   TPDO1      plc TPDO1   io1 RPDO1       2      ?      0.00 %  lamp, horn",
        "0x302   TPDO2      plc TPDO2   io1 RPDO2       1      ?      0.00 %  io1_6200_3"]
    assert "position       in   INTEGER24  dev3 (3)  0x2001sub0  0xA140sub2  3" in lines
    i = lines.index("Identity the master enforces:")
    assert lines[i + 1:i + 5] == [
        "node      device type  vendor-ID   product code  revision number  serial number",
        "io1 (2)   0x000F0191   0x000000AB  0x00000401    -                -",
        "dev3 (3)  0x000F0191   0x000000AB  -             -                -",
        "ai5 (5)   0x00020194   0x0000003F  0x002DCAAB    -                -"]
    assert "SDO writes" not in r.stdout


def test_show_writes_of_one_node():
    r = run("network", "show", NETWORK, "--writes=dev3")
    assert r.exit_code == 0
    tail = r.stdout.split("dev3 (node 3): 7 SDO writes\n")[1].splitlines()
    assert tail[0].split() == ["#", "entry", "name", "value", "why", "source"]
    assert tail[1].startswith("1  0x1800sub1  COB-ID used by TPDO       0x80000183")
    assert tail[1].endswith(f"TPDO1 COB-ID (invalid while configuring)  {NETWORK}:32")
    assert "io1 (node 2)" not in r.stdout
    r = run("network", "show", NETWORK, "--writes=9")
    assert r.exit_code == 2
    assert r.stderr == NET252 + (f"dcf2bin: error: --writes=9: no such node in {NETWORK} "
                                 "(slaves: io1 (2), dev3 (3), ai5 (5))\n")


def test_show_writes_never_takes_the_network_argument():
    """Issue 26: '--writes net/bus.yml' took the path as --writes' value ("Missing argument
    'NETWORK'"). --writes alone is a flag; a node is given only as --writes=NODE."""
    r = run("network", "show", "--writes", NETWORK)
    assert r.exit_code == 0, r.stderr
    assert "dev3 (node 3): 7 SDO writes" in r.stdout and "io1 (node 2): 14 SDO writes" in \
        r.stdout
    assert run("network", "show", NETWORK, "--writes").stdout == r.stdout
    r = run("network", "show", NETWORK, "--writes", "dev3")
    assert r.exit_code == 2
    assert "Got unexpected extra argument (dev3)" in r.stderr
    r = run("network", "show", NETWORK, "--writes=")
    assert r.exit_code == 2
    assert ("Invalid value for '--writes': give the node after '=' (--writes=NODE), or "
            "--writes alone for every slave") in r.stderr
    help_text = run("network", "show", "--help").stdout
    assert "--writes[=NODE]" in help_text


def test_show_json():
    r = run("network", "show", NETWORK, "-f", "json", "--writes")
    d = json.loads(r.stdout)
    assert [n["name"] for n in d["nodes"]] == ["io1", "dev3", "ai5", "plc"]
    assert (d["format"], d["version"], d["file"]) == ("dcf2bin-network-show", 1, NETWORK)
    link = next(k for k in d["links"] if k["cob_id"] == "0x00000182")
    assert link["producer"] == {"node": "io1", "node_id": 2, "pdo": "TPDO1"}
    assert link["consumers"] == [{"node": "plc", "node_id": 16, "pdo": "RPDO1"}]
    assert (link["bytes"], link["rate"], link["bits"]) == (2, 100.0, 75)
    assert d["slaves"][1]["identity"] == {"0x1F84": "0x000F0191", "0x1F85": "0x000000AB"}
    assert d["slaves"][1]["writes"][0] == {
        "index": "0x1800", "subindex": 1, "name": "COB-ID used by TPDO", "value": "0x80000183",
        "data": "83010080", "why": "TPDO1 COB-ID (invalid while configuring)",
        "source": f"{NETWORK}:32"}


def test_show_svg_and_html_to_files(tmp_path):
    svg_path, html_path = tmp_path / "n.svg", tmp_path / "n.html"
    assert run("network", "show", NETWORK, "-f", "svg", "-o", str(svg_path)).exit_code == 0
    assert run("network", "show", NETWORK, "-f", "html", "-o", str(html_path)).exit_code == 0
    root = ET.parse(svg_path).getroot()
    words = ["".join(t.itertext()) for t in root.iter("{http://www.w3.org/2000/svg}text")]
    for name in ("plc", "io1", "dev3", "ai5"):
        assert name in words
    for cob in ("0x080", "0x182", "0x183", "0x185", "0x202", "0x302"):
        assert any(w.startswith(cob + " ") for w in words), cob
    page = html_path.read_text()
    assert "<h2>Frames</h2>" in page and "door_closed" in page


def test_show_golden_svg():
    """docs/network.svg is this network's picture (docs/network.png is rendered from it)."""
    r = run("network", "show", NETWORK, "-f", "svg")
    with open("docs/network.svg", encoding="utf-8") as f:
        assert r.stdout == f.read()


def test_show_cpj():
    r = run("network", "show", CPJ)
    assert r.exit_code == 0
    assert "Identity each node's DCF states (a .cpj project has no master):" in r.stdout
    assert "io (2)   0x000F0191   0x000000AB  0x00000401" in r.stdout


def test_show_network_file_with_errors_shows_nothing(tmp_path):
    bad = tmp_path / "bad.yml"
    bad.write_text("master:\n  node_id: 1\n")
    r = run("network", "show", str(bad))
    assert r.exit_code == 1 and r.stdout == ""
    assert r.stderr == (f"{bad}:1: error: no slave in the network file [NET005]\n"
                        f"{bad}: 1 error, nothing shown (the network file cannot be "
                        "configured)\n")


# -- scan -----------------------------------------------------------------------------------

def test_scan_clean(bench):
    slaves(bench)
    r = run("network", "scan", NETWORK, *bus(bench, "--listen", "0.1", "--timeout", TIMEOUT))
    assert (r.exit_code, r.stderr) == (0, NET252)
    lines = r.stdout.splitlines()
    assert lines[0].startswith(f"{NETWORK}: node-IDs 1-127 scanned in ")
    assert lines[0].endswith("3 answer, 0 findings")
    assert lines[4].split() == ["5", "ai5", "answers", "0x00020194", "0x0000003F",
                                "0x002DCAAB", "0x01390538", "abort", "060A0023"]
    assert lines[5].split() == ["16", "plc", "master,", "not", "on", "the", "bus",
                                "-", "-", "-", "-", "-"]


def test_scan_wrong_vendor_missing_and_extra(bench):
    nodes = slaves(bench, ids=(2, 3))
    nodes[3].sdo[0x1018][1].raw = 0xAC                     # another vendor's device
    from dcf2bin.bus.node import from_file
    extra, _ = from_file(FILES[3], 9)
    bench.add(extra)
    r = run("network", "scan", NETWORK, *bus(bench, "--listen", "0.1", "--timeout", "0.5"))
    assert r.exit_code == 1
    assert r.stderr.splitlines() == NET252.splitlines() + [
        f"{NETWORK}:26: error: node 3 (dev3): 0x1018 sub 1 (vendor-ID) is 0x000000AC, the "
        "master expects 0x000000AB (0x1F85): it will not boot this node",
        f"{NETWORK}:36: error: node 5 (ai5) is in the network but does not answer",
        f"{NETWORK}:5: warning: node 9 answers but is not in the network, device type "
        "0x000F0191"]
    rows = {line.split()[0]: line for line in r.stdout.splitlines()[2:]}
    assert "MISSING" in rows["5"] and "UNEXPECTED, answers" in rows["9"]


def test_scan_json(bench):
    slaves(bench, ids=(2,))
    r = run("network", "scan", NETWORK, "-f", "json",
            *bus(bench, "--listen", "0", "--timeout", "0.2"))
    assert r.exit_code == 1
    d = json.loads(r.stdout)
    assert (d["format"], d["version"], d["file"]) == ("dcf2bin-network-scan", 1, NETWORK)
    assert d["at_most_seconds"] == 1.0
    io1 = d["nodes"][0]
    assert (io1["node_id"], io1["answered"], io1["entries"]["0x1018sub1"]) == (
        2, True, {"value": "0x000000AB"})
    assert [(f["kind"], f["node_id"]) for f in d["findings"]] == [("missing", 3),
                                                                  ("missing", 5)]
    jsonschema = pytest.importorskip("jsonschema")
    from dcf2bin import schemas
    jsonschema.validate(d, schemas.load("network-scan"))     # docs/options.md, "JSON outputs"


def test_scan_an_interface_that_cannot_be_opened():
    r = run("network", "scan", NETWORK, "-i", "no-such-interface")
    assert r.exit_code == 3 and r.stdout == ""


# -- download -------------------------------------------------------------------------------

def refuse(node, index: int, sub: int, code: int = 0x06090030) -> list:
    written = []

    def callback(index, subindex, od, data):
        written.append((index, subindex))
        if (index, subindex) == (index_, sub_):
            raise SdoAbortedError(code)
    index_, sub_ = index, sub
    node.add_write_callback(callback)
    return written


def test_download_abort_stops_the_run(bench):
    nodes = slaves(bench)
    refuse(nodes[3], 0x1800, 2)                        # dev3's second write
    later = refuse(nodes[5], 0, 0)                     # records ai5's writes
    r = run("network", "download", NETWORK, *bus(bench, "--timeout", TIMEOUT))
    assert r.exit_code == 1
    assert r.stderr == NET252 + (
        f"{NETWORK}:33: error: node 3 (dev3): 0x1800sub2 Transmission type (TPDO1 "
        "transmission type): SDO abort 0x06090030: Value range of parameter exceeded; "
        "1 of 7 entries written before it\n")
    assert r.stdout.splitlines() == [
        "node 2 (io1): identity checked, 14 entries written",
        "node 3 (dev3): failed, 1 of 7 entries written",
        f"{NETWORK}: 1 configured, 1 failed, 1 skipped",
        "  configured  node 2 (io1)  14 entries",
        "  failed      node 3 (dev3)  0x1800sub2 Transmission type (TPDO1 transmission type): "
        "SDO abort 0x06090030: Value range of parameter exceeded; 1 of 7 entries written "
        "before it",
        "  skipped     node 5 (ai5)  not written: an earlier node failed (--keep-going goes "
        "on)"]
    assert later == []                                 # nothing more was written


def test_download_keep_going(bench):
    nodes = slaves(bench)
    refuse(nodes[3], 0x1800, 2)
    r = run("network", "download", NETWORK, "--keep-going",
            *bus(bench, "--timeout", TIMEOUT))
    assert r.exit_code == 1
    assert r.stdout.splitlines()[:4] == [
        "node 2 (io1): identity checked, 14 entries written",
        "node 3 (dev3): failed, 6 of 7 entries written",
        "node 5 (ai5): identity checked, 11 entries written",
        f"{NETWORK}: 2 configured, 1 failed, 0 skipped"]
    assert nodes[3].sdo[0x1017].raw == 200             # dev3's writes after the abort
    assert nodes[5].sdo[0x1800][1].raw == 0x185


def test_download_identity_mismatch_writes_nothing(bench):
    nodes = slaves(bench, ids=(2,))
    nodes[2].sdo[0x1018][2].raw = 0x402
    written = refuse(nodes[2], 0, 0)
    r = run("network", "download", NETWORK, "-q", *bus(bench, "--timeout", TIMEOUT))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{NETWORK}:11: error: node 2 (io1): 0x1018 sub 2 (product code) is "
                        "0x00000402, the master expects 0x00000401 (0x1F86): nothing "
                        "written\n")
    assert written == []


def test_download_dry_run_touches_no_bus():
    r = run("network", "download", NETWORK, "--dry-run", "-i", "no-such-interface")
    assert (r.exit_code, r.stderr) == (0, NET252)
    lines = r.stdout.splitlines()
    assert lines[0] == ("node 2 (io1): checks 0x1000 = 0x000F0191, 0x1018 sub 1 = 0x000000AB, "
                        "0x1018 sub 2 = 0x00000401; 14 SDO writes (dry run, nothing sent)")
    assert lines[2].split()[:4] == ["1", "0x1400sub1", "02", "02"]


def test_download_cpj_dry_run_writes_each_dcf():
    r = run("network", "download", CPJ, "--dry-run")
    assert r.exit_code == 0
    heads = [line for line in r.stdout.splitlines() if line.startswith("node ")]
    assert [h.split(":")[0] for h in heads] == ["node 1 (plc)", "node 2 (io)", "node 3 (io3)"]
    assert heads[1].startswith("node 2 (io): checks 0x1000 = 0x000F0191, 0x1018 sub 1 = "
                               "0x000000AB, 0x1018 sub 2 = 0x00000401;")


# -- a .cpj project: no master, each node its DCF -------------------------------------------

CPJ_FILES = {1: "tests/fixtures/network/check/plc.dcf", 2: "tests/fixtures/network/check/io.dcf",
             3: "tests/fixtures/network/check/io3.dcf"}


def test_cpj_scan_and_download(bench):
    from dcf2bin.bus.node import from_file
    nodes = {}
    for nid, path in CPJ_FILES.items():
        node, errors = from_file(path, nid)
        assert errors == []
        nodes[nid] = bench.add(node)
    nodes[3].sdo[0x1018][2].raw = 0x402               # io3 is another product than its DCF
    r = run("network", "scan", CPJ, *bus(bench, "--listen", "0", "--timeout", TIMEOUT))
    assert r.exit_code == 1
    assert r.stderr == (f"{CPJ}:15: error: node 3 (io3): 0x1018 sub 2 (product code) is "
                        "0x00000402, its DCF states 0x00000401\n")
    r = run("network", "download", CPJ, "--verify", "--keep-going",
            *bus(bench, "--timeout", TIMEOUT))
    assert r.exit_code == 1
    assert r.stderr == (f"{CPJ}:15: error: node 3 (io3): 0x1018 sub 2 (product code) is "
                        "0x00000402, its DCF states 0x00000401: nothing written\n")
    assert r.stdout.splitlines()[:4] == [
        "node 1 (plc): identity checked, 36 entries written, read back equal",
        "node 2 (io): identity checked, 25 entries written, read back equal",
        "node 3 (io3): failed, nothing written",
        f"{CPJ}: 2 configured, 1 failed, 0 skipped"]
    # io's DCF reached it: its TPDO1 COB-ID and transmission type as the DCF states them
    assert nodes[2].sdo[0x1800][1].raw == 0x182 and nodes[2].sdo[0x1800][2].raw == 1


# -- a node's file that cannot be read: exit 3 in every network command ---------------------

@pytest.mark.parametrize("command", [("check",), ("show",), ("show", "-f", "svg"),
                                     ("download", "--dry-run"), ("build", "-o", "OUT")])
@pytest.mark.parametrize("dcf", ["nope.eds", "folder.eds"])
def test_a_node_file_that_cannot_be_read_is_exit_3(tmp_path, command, dcf):
    """The exit-code table (docs/options.md): 3 when an input cannot be read (missing, a directory),
    for a node's file as for the network file; one file:line line, no traceback."""
    (tmp_path / "folder.eds").mkdir()
    bus_yml = tmp_path / "bus.yml"
    bus_yml.write_text(f"master:\n  node_id: 1\nio:\n  dcf: {dcf}\n  node_id: 5\n")
    args = [a.replace("OUT", str(tmp_path / "out")) for a in command]
    r = run("network", args[0], str(bus_yml), *args[1:])
    why = "No such file or directory" if dcf == "nope.eds" else "Is a directory"
    text = r.stdout + r.stderr
    assert r.exit_code == 3, text
    assert f"{bus_yml}:4: error: cannot read {tmp_path / dcf}: {why} [NET010]" in text
    assert "Traceback" not in text
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("command", [("check",), ("show",), ("download", "--dry-run"),
                                     ("build", "-o", "OUT")])
def test_a_directory_as_the_network_file_is_exit_3(tmp_path, command):
    """The exit-code table: a directory given as an input is exit 3 (build said 2, a usage
    error, where the other network commands said 3)."""
    args = [a.replace("OUT", str(tmp_path / "out")) for a in command]
    r = run("network", args[0], str(tmp_path), *args[1:])
    assert r.exit_code == 3, r.stdout + r.stderr
    assert f"{tmp_path}: error: cannot read: Is a directory" in r.stdout + r.stderr
