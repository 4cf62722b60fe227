"""Issue 28 item 1: a network node's dcf: may name CiA 311 XML (XDD/XDC), read through the
registry of formats as every command reads a description; every network command takes it,
and build writes the slave's configured DCF as CiA 306 text converted from it.

tests/fixtures/xdd/vendor_v10.xdc and vendor_v10.dcf say the same thing (test_xdd.py): a
network of a PLC and that drive is built, shown, checked, downloaded, scanned, given its
node-IDs and read back alike from either, but for the file names (and the lines of the
findings about the file, which are the XML's)."""
from __future__ import annotations

import re
import shutil

import pytest
from bus_helpers import run
from conftest import ROOT

pytest_plugins = ["bus_fixtures"]

XDD = ROOT / "tests" / "fixtures" / "xdd"
NET = ROOT / "tests" / "fixtures" / "network"

BUS = """master:
  node_id: 1
  name: plc
  dcf: plc.dcf
  heartbeat_producer: 100
  sync_period: 10000
axis:
  dcf: vendor_v10.{suffix}
  node_id: 5
  heartbeat_producer: 50
  revision_number: 0x00010002
  serial_number: 31400222
  tpdo:
    1:
      transmission: 1
      mapping:
        - {{index: 0x6041, sub_index: 0, name: axis_status}}
        - {{index: 0x6064, sub_index: 0, name: axis_position}}
  rpdo:
    1:
      mapping:
        - {{index: 0x6040, sub_index: 0, name: axis_control}}
  sdo:
    - {{index: 0x6083, sub_index: 0, value: 3000}}
    - {{index: 0x2401, sub_index: 0, value: 5}}
"""


def networks(tmp_path):
    """{suffix: its folder}: the same network, the drive read from the XDC in one folder,
    from the DCF in the other."""
    out = {}
    for suffix in ("xdc", "dcf"):
        folder = tmp_path / suffix
        folder.mkdir()
        shutil.copy(NET / "plc.dcf", folder)
        shutil.copy(XDD / f"vendor_v10.{suffix}", folder)
        (folder / "bus.yml").write_text(BUS.format(suffix=suffix))
        out[suffix] = folder
    return out


def same(text: str) -> str:
    """The text without the drive file's name and the lines in it."""
    return re.sub(r"vendor_v10\.(xdc|dcf)(:\d+)?", "F", text)


def in_folder(monkeypatch, folder, *args):
    monkeypatch.chdir(folder)
    return run(*[str(a) for a in args])


def test_the_command_the_reviewer_ran_reads_an_xdd_slave(tmp_path, monkeypatch):
    """Was: 'techno.xdd is CiA 311 XML (XDD/XDC), not DCF/EDS text; use dcf2bin compile
    to make a container of it' [NET011], exit 1, in check and build."""
    folder = tmp_path / "net"
    shutil.copytree(ROOT / "tests" / "golden" / "network" / "flat", folder)
    for name in ("plc.dcf", "IoX4_8AI.eds"):
        shutil.copy(NET / name, folder)
    r = in_folder(monkeypatch, folder, "convert", NET / "technosoft.eds", "-o", "techno.xdd",
                  "-q")
    assert r.exit_code == 0, r.stderr
    text = (folder / "bus.yml").read_text().replace("../../../fixtures/network/", "")
    (folder / "x.yml").write_text(text.replace("dcf: technosoft.eds", "dcf: techno.xdd"))
    r = run("network", "check", "x.yml")
    assert (r.exit_code, r.stdout) == (0, "0 errors, 0 warnings, 0 infos in 4 files\n")
    r = run("network", "build", "x.yml", "-o", "out", "-q")
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    assert sorted(p.name for p in (folder / "out").iterdir() if p.name[0] != ".") == [
        "drive.bin", "drive.dcf", "io.bin", "io.dcf", "plc.dcf"]


@pytest.mark.parametrize("args", [["check"], ["show"], ["show", "-f", "json"],
                                  ["show", "--writes"], ["download", "--dry-run"]])
def test_every_network_command_reads_the_xdc_as_the_dcf(tmp_path, monkeypatch, args):
    got = {}
    for suffix, folder in networks(tmp_path).items():
        r = in_folder(monkeypatch, folder, "network", args[0], "bus.yml", *args[1:])
        got[suffix] = (r.exit_code, same(r.stdout), same(r.stderr))
    assert got["xdc"][0] == 0
    if args == ["check"]:          # the findings about the file are in the order of its lines
        assert got["xdc"][1] == (
            "F: info: 0x1018sub4 is ro; its ParameterValue is not written [DCF213]\n"
            "F: info: 0x1000sub0 is const; its ParameterValue is not written [DCF213]\n"
            "0 errors, 0 warnings, 2 infos in 3 files\n")
        got = {k: (c, "".join(sorted(o.splitlines(True))), e) for k, (c, o, e) in got.items()}
    assert got["xdc"] == got["dcf"]


def test_check_names_the_xml_file_and_its_lines(tmp_path, monkeypatch):
    folder = networks(tmp_path)["xdc"]
    r = in_folder(monkeypatch, folder, "network", "check", "bus.yml")
    assert r.stdout.splitlines()[:2] == [
        "vendor_v10.xdc:31: info: 0x1018sub4 is ro; its ParameterValue is not written "
        "[DCF213]",
        "vendor_v10.xdc:92: info: 0x1000sub0 is const; its ParameterValue is not written "
        "[DCF213]"]


BUILT = {"plc": "3 files in out: plc.dcf and 1 slave for a PLC master, 2 links, 3 variables",
         "lely": "4 files in out: plc.dcf, plc.bin and 1 slave for a lely master, 2 links"}


@pytest.mark.parametrize("master", ["plc", "lely"])
def test_a_build_from_the_xdc_equals_the_build_from_the_dcf(tmp_path, monkeypatch, master):
    """Every output byte for byte, but the slave's DCF: from the XDC it is the XDC's
    sections as CiA 306 text with the configured values stated; it says what the DCF
    build's says (every entry, compiled to the same container)."""
    from dcf2bin.compiler import CompileOptions, compile_path
    folders = networks(tmp_path)
    for folder in folders.values():
        r = in_folder(monkeypatch, folder, "network", "build", "bus.yml", "-o", "out",
                      "--master", master)
        assert r.exit_code == 0, r.stderr
        assert r.stdout == ""
        assert r.stderr.splitlines()[-1] == f"network build: {BUILT[master]}"
    xdc, dcf = folders["xdc"] / "out", folders["dcf"] / "out"
    names = sorted(p.name for p in dcf.iterdir() if p.name[0] != ".")    # (not the lock)
    assert sorted(p.name for p in xdc.iterdir() if p.name[0] != ".") == names
    assert [n for n in names if (xdc / n).read_bytes() != (dcf / n).read_bytes()] == \
        ["axis.dcf"]
    containers = [compile_path(str(f / "axis.dcf"), CompileOptions()) for f in (xdc, dcf)]
    assert all(c.ok for c in containers)
    assert containers[0].data == containers[1].data
    monkeypatch.chdir(tmp_path)
    r = run("diff", "--all", "xdc/out/axis.dcf", "dcf/out/axis.dcf")
    assert (r.exit_code, r.stdout + r.stderr) == (
        0, "xdc/out/axis.dcf, dcf/out/axis.dcf: equal; 25 entries compared\n")
    said = [re.sub(r"^\w+/out/axis.dcf:\d+", "F", run("validate", f"{s}/out/axis.dcf").stdout,
                   flags=re.M) for s in ("xdc", "dcf")]
    assert said[0] == said[1]
    assert said[0].endswith("\n0 errors, 0 warnings, 3 infos in 1 file\n")
    text = (xdc / "axis.dcf").read_text()
    assert text.startswith("[FileInfo]\nFileName=vendor_v10.xdc\n")
    assert "\n[1017]\nParameterName=Producer heartbeat time\nObjectType=0x7\n" \
        "DataType=0x0006\nAccessType=rw\nDefaultValue=0\nParameterValue=0x0032\n" \
        "LowLimit=0\nHighLimit=0xFFFF\nPDOMapping=0\n" in text
    assert "\n[DeviceComissioning]\nNodeID=5\nNodeName=Axis X\nBaudrate=500\nNetNumber=1\n" \
        "NetworkName=Line 1\nCANopenManager=0\n\n" in text


def test_a_plc_master_in_xml(tmp_path, monkeypatch):
    """The PLC's file as an XDC: its variables are placed in the CiA 306 text converted
    from it, and plc.dcf says what the build from the PLC's DCF says."""
    folders = networks(tmp_path)
    folder = folders["dcf"]
    r = in_folder(monkeypatch, folder, "convert", "plc.dcf", "-o", "plc.xdc", "-q")
    assert r.exit_code == 0, r.stderr
    (folder / "x.yml").write_text(BUS.format(suffix="dcf").replace("dcf: plc.dcf",
                                                                   "dcf: plc.xdc"))
    for name, out in (("bus.yml", "a"), ("x.yml", "b")):
        r = run("network", "build", name, "-o", out, "-q")
        assert (r.exit_code, r.stderr) == (0, ""), name
    assert (folder / "a" / "axis.bin").read_bytes() == (folder / "b" / "axis.bin").read_bytes()
    r = run("diff", "--all", "a/plc.dcf", "b/plc.dcf")
    assert (r.exit_code, r.stdout + r.stderr) == (0, "a/plc.dcf, b/plc.dcf: equal; 1129 entries "
                                                   "compared\n")
    built = [run("compile", f"{out}/plc.dcf", "-o", "-").stdout_bytes for out in "ab"]
    assert built[0] == built[1] and len(built[0]) == 415


def test_a_container_is_refused_with_what_a_network_reads(tmp_path, monkeypatch):
    """NET011's advice fits the network: not 'use dcf2bin compile' (for an XDD) nor 'use
    dcf2bin dump' (for a container), but what a node's file may be."""
    folder = networks(tmp_path)["dcf"]
    r = in_folder(monkeypatch, folder, "compile", "vendor_v10.dcf", "-o", "axis.bin")
    assert r.exit_code == 0
    (folder / "bus.yml").write_text(BUS.format(suffix="dcf").replace("vendor_v10.dcf",
                                                                     "axis.bin"))
    r = run("network", "check", "bus.yml")
    assert (r.exit_code, r.stdout) == (1, (
        "bus.yml:8: error: axis.bin is a binary container, not DCF/EDS text; a network reads "
        "each node's EDS, DCF, XDD or XDC (dcf2bin bin2dcf turns a container into a DCF) "
        "[NET011]\n1 error, 0 warnings, 0 infos in 2 files\n"))


# -- on the bus: python-can's virtual bus, the drive a software node made from the XDC ----

def bus_args(bench):
    return ["-i", "virtual", "--channel", bench.channel, "--timeout", "2"]


@pytest.mark.parametrize("suffix", ["xdc", "dcf"])
def test_download_scan_and_upload_of_an_xdc_slave(bench, tmp_path, monkeypatch, suffix):
    from dcf2bin.bus.node import from_file
    node, errors = from_file(str(XDD / "vendor_v10.xdc"), 5)
    assert errors == []
    bench.add(node)
    folder = networks(tmp_path)[suffix]
    r = in_folder(monkeypatch, folder, "network", "download", "bus.yml", *bus_args(bench))
    assert (r.exit_code, r.stdout) == (0, (
        "node 5 (axis): identity checked, 15 entries written\n"
        "bus.yml: 1 configured, 0 failed, 0 skipped\n"
        "  configured  node 5 (axis)  15 entries\n")), r.stderr
    assert node.sdo[0x6083].raw == 3000 and node.sdo[0x1017].raw == 50
    r = run("network", "scan", "bus.yml", *bus_args(bench)[:-2], "--listen", "0",
            "--timeout", "0.5", "-q")
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    r = run("network", "upload", "bus.yml", "-o", "up", *bus_args(bench), "-q")
    assert r.exit_code == 0, r.stderr
    text = (folder / "up" / "axis.dcf").read_text()
    assert ("[6083]\nParameterName=Profile acceleration\nObjectType=0x7\nDataType=0x0007\n"
            "AccessType=rw\nDefaultValue=1000\nParameterValue=0x00000BB8\n") in text
    assert text.startswith(f"[FileInfo]\nFileName=vendor_v10.{suffix}\n") \
        if suffix == "xdc" else text.startswith("; dcf2bin test fixture")


@pytest.mark.parametrize("suffix", ["xdc", "dcf"])
def test_lss_gives_the_xdc_slave_its_node_id(bench, tmp_path, monkeypatch, suffix):
    from dcf2bin.bus.lss_slave import attach_lss
    from dcf2bin.bus.node import from_file
    node, errors = from_file(str(XDD / "vendor_v10.xdc"), 1)
    assert errors == []
    attach_lss(node, serial=31400222, unconfigured=True)
    bench.add(node)
    folder = networks(tmp_path)[suffix]
    r = in_folder(monkeypatch, folder, "network", "lss", "bus.yml", "-i", "virtual",
                  "--channel", bench.channel, "-f", "json")
    assert r.exit_code == 0, r.stderr
    import json
    got = json.loads(r.stdout)["nodes"]
    assert [(n["node_id"], n["status"], n["found_by"], n["identity"]) for n in got] == [
        (5, "assigned", "selective switch",
         {"vendor_id": "0x00000147", "product_code": "0x00000C4E",
          "revision_number": "0x00010002", "serial_number": "0x01DF211E"})]
    assert node.id == 5
