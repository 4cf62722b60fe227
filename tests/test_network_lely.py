"""`network build` of a lely master (SPEC §10.2a, D-21): values checked by hand against
the SPEC on tests/fixtures/network/lely/flat.yml (this repository's own EDS files), the
choice of master, and the command's output. The comparison with dcfgen itself is
tests/test_network_lely_dcfgen.py."""
from __future__ import annotations

import pathlib

from click.testing import CliRunner

from dcf2bin.cli import main
from dcf2bin.network import build_network, configure, load_network

HERE = pathlib.Path(__file__).resolve().parent
LELY = HERE / "fixtures" / "network" / "lely"
FIXTURES = HERE / "fixtures" / "network"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def sections(text: str) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for block in text.split("\n\n"):
        lines = block.strip().splitlines()
        out[lines[0]] = lines[1:]
    return out


def flat():
    res = build_network(str(LELY / "flat.yml"))
    assert res.ok and res.mode == "lely"
    return res


def test_outputs_are_dcfgens_files_and_each_slaves_dcf():
    """master.dcf, master.bin (the master checks io's revision), one .bin per slave, as
    dcfgen writes them; then, unlike dcfgen, one .dcf per slave (node-ID order), so that
    `diff` compares an upload of the node with its build (issue 29)."""
    assert list(flat().outputs) == ["master.dcf", "master.bin", "io.bin", "drive.bin",
                                    "drive.dcf", "io.dcf"]


def test_slaves_in_the_files_order_not_by_node_id():
    """io (node 5) comes first in flat.yml: its TPDOs are the master's RPDOs 1-4, its
    heartbeat the master's 0x1016 sub 1 (200 ms x 2.5), drive's (100 ms x 2.5) sub 2."""
    s = sections(flat().outputs["master.dcf"].decode())
    assert s["[5800]"][-1] == "DefaultValue=0x00000105"      # TPDO1 of node 5
    assert s["[5804]"][-1] == "DefaultValue=0x00000102"      # TPDO1 of node 2
    assert s["[1016Value]"] == ["NrOfEntries=2", "1=0x000501F4", "2=0x000200FA"]
    assert s["[1F81Value]"] == ["NrOfEntries=2", "5=0x00000305", "2=0x0000050D"]


def test_received_objects_mapped_to_0x2000_records():
    """Master RPDO1 (io TPDO1) maps 0x2000 sub 1-4; drive's TPDO2 maps 0x6041 again,
    which the master takes from 0x2004 sub 1 (drive's TPDO1, master RPDO5)."""
    s = sections(flat().outputs["master.dcf"].decode())
    assert s["[1600Value]"] == ["NrOfEntries=4", "1=0x20000110", "2=0x20000208",
                                "3=0x20000310", "4=0x20000408"]
    assert s["[1605Value]"] == ["NrOfEntries=2", "1=0x20040110", "2=0x20050120"]
    assert s["[2000sub1]"] == ["ParameterName=io: AI0_Input_PV", "DataType=0x0003",
                               "AccessType=rww", "PDOMapping=1"]
    assert s["[2005]"] == ["SubNumber=2", "ParameterName=Mapped application objects for "
                           "RPDO 6", "ObjectType=0x09"]
    assert s["[5A05Value]"] == ["NrOfEntries=2", "1=0x60410010", "2=0x606C0020"]


def test_disabled_pdo_is_not_mirrored():
    """drive's RPDO2 (enabled: false) is not a master TPDO: the master feeds its RPDO1
    (predefined COB-ID 0x202, its transmission type) and RPDO3-4 (kept from its EDS)."""
    s = sections(flat().outputs["master.dcf"].decode())
    assert "NrOfTxPDO=3" in s["[DeviceInfo]"]
    assert s["[1800sub1]"][-1] == "DefaultValue=0x00000202"
    assert s["[1800sub2]"][-1] == "DefaultValue=0x01"
    assert [s[f"[5C0{k}]"][-1] for k in range(3)] == [
        "DefaultValue=0x00000102", "DefaultValue=0x00000302", "DefaultValue=0x00000402"]
    assert s["[1801sub1]"][-1] == "DefaultValue=0x00000402"    # RPDO3: $NODEID+0x400
    assert "[1803]" not in s


def test_concise_dcfs_and_upload_files():
    res = flat()
    # io: heartbeat 200 ms, then the sdo REAL32 1.5 as 1.5 (0x3FC00000)
    assert res.outputs["io.bin"].hex() == (
        "02000000" "171000" "02000000" "c800" "266101" "04000000" "0000c03f")
    # the master's own write: 0x1F87 sub 5 = io's revision (its [DeviceInfo])
    assert res.outputs["master.bin"].hex() == "01000000" "871f05" "04000000" "38053901"
    s = sections(res.outputs["master.dcf"].decode())
    assert s["[1F22sub5]"][-1] == "UploadFile=@BUS_CONFIG_PATH@/io.bin"
    assert s["[1F22sub2]"][-1] == "UploadFile=@BUS_CONFIG_PATH@/drive.bin"
    assert s["[1F22sub3]"] == ["ParameterName=Node-ID 3", "DataType=0x000F",
                               "AccessType=ro"]


def test_check_numbers_the_master_pdos_as_build():
    """configure (network check, show) numbers a lely master's PDOs in dcfgen's order."""
    net = configure(load_network(str(LELY / "flat.yml")))
    rpdos = [(p.number, p.mirror_of.node_id, p.mirror_of.number)
             for p in net.master.pdos if p.kind == "rpdo"]
    assert rpdos == [(1, 5, 1), (2, 5, 2), (3, 5, 3), (4, 5, 4), (5, 2, 1), (6, 2, 2)]


def test_nodes_layout_sorts_the_names():
    net = load_network(str(LELY / "nodes.yml"))
    from dcf2bin.network.lely.order import dcfgen_order
    assert [n.name for n in dcfgen_order(net)] == ["base", "elbow", "wrist"]


def test_command_says_lely_master(tmp_path):
    r = run("network", "build", LELY / "flat.yml", "-o", tmp_path, "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("network", "build", LELY / "flat.yml", "-o", tmp_path)
    assert r.exit_code == 0
    assert r.stderr.splitlines()[-1] == (
        f"network build: 6 files in {tmp_path}: master.dcf, master.bin and 2 slaves for a "
        "lely master, 9 links")
    # and the folder's lock, which names the files the build wrote (tests/test_build_atomic.py)
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        ".dcf2bin-build.lock", "drive.bin", "drive.dcf", "io.bin", "io.dcf", "master.bin",
        "master.dcf"]


def test_master_lely_on_a_plc_file(tmp_path):
    """--master lely builds a lely master from a file whose master has dcf:, and says it
    does not read that file."""
    r = run("network", "build", LELY / "plc.yml", "-o", tmp_path, "--master", "lely")
    assert r.exit_code == 0
    lines = r.stderr.splitlines()
    assert (f"{LELY}/plc.yml:6: info: the master's dcf: is not read: a lely master is "
            "built [NET007]") in lines
    assert lines[-1] == (f"network build: 6 files in {tmp_path}: master.dcf, master.bin and "
                         "2 slaves for a lely master, 7 links")
    assert (tmp_path / "drive.dcf").exists()        # the slave's DCF, for diff (issue 29)


def test_master_plc_needs_dcf(tmp_path):
    r = run("network", "build", LELY / "flat.yml", "-o", tmp_path / "o", "-q",
            "--master", "plc")
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{LELY}/flat.yml:9: error: build needs the PLC's EDS or DCF: give it as 'dcf:' "
        "under 'master:' [NET119]",
        "network build: 1 error, nothing written"]
    assert not (tmp_path / "o").exists()


def test_plc_file_builds_a_plc_master(tmp_path):
    r = run("network", "build", LELY / "plc.yml", "-o", tmp_path)
    assert r.exit_code == 0
    assert r.stderr.splitlines()[-1].startswith(
        f"network build: 5 files in {tmp_path}: master.dcf and 2 slaves for a PLC master, ")


def test_ros2_simple_file_builds():
    """A ros2_canopen file (no master dcf:) that build refused before (NET119) builds."""
    res = build_network(str(FIXTURES / "ros2_simple_bus.yml"))
    assert res.ok and res.mode == "lely"
    assert list(res.outputs) == ["master.dcf", "master.bin", "proxy_device_1.bin",
                                 "proxy_device_2.bin", "proxy_device_1.dcf",
                                 "proxy_device_2.dcf"]


def test_show_names_the_lely_masters_application_objects(tmp_path):
    """show headed a lely master's table "PLC variables:" (there is no PLC): its rows are
    the records 0x2000/0x2200 that master.dcf maps the slaves' data into (D-21), each
    variable at the sub where it first came (drive's 0x6041, mapped in two TPDOs, at
    0x2004sub1 as [1605Value] maps it); a PLC master keeps its heading and columns."""
    out = run("network", "show", LELY / "flat.yml").output.split("\n\n")
    table = next(b for b in out if b.startswith("Mapped"))
    lines = table.splitlines()
    assert lines[:3] == [
        "Mapped application objects of the lely master (0x2000/0x2200):",
        "variable      dir  type        node       object      master entry",
        "io_7130_1     in   INTEGER16   io (5)     0x7130sub1  0x2000sub1"]
    assert lines[-7:] == [
        "drive_6041_0  in   UNSIGNED16  drive (2)  0x6041sub0  0x2004sub1",
        "drive_6064_0  in   INTEGER32   drive (2)  0x6064sub0  0x2004sub2",
        "drive_606C_0  in   INTEGER32   drive (2)  0x606Csub0  0x2005sub1",
        "drive_6040_0  out  UNSIGNED16  drive (2)  0x6040sub0  0x2200sub1",
        "drive_6060_0  out  INTEGER8    drive (2)  0x6060sub0  0x2200sub2",
        "drive_607A_0  out  INTEGER32   drive (2)  0x607Asub0  0x2201sub1",
        "drive_60FF_0  out  INTEGER32   drive (2)  0x60FFsub0  0x2202sub1"]
    assert not any("PLC" in b for b in out)
    page = run("network", "show", LELY / "flat.yml", "-f", "html").output
    assert ("<h2>Mapped application objects of the lely master (0x2000/0x2200)</h2>" in page
            and "PLC" not in page)
    plc = run("network", "show", LELY / "plc.yml").output.split("\n\n")
    assert [b.splitlines()[:2] for b in plc if "PLC variables" in b] == [[
        "PLC variables:",
        "variable        dir  type        node       object      PLC entry    offset"]]


def test_check_and_show_take_master_as_build_does(tmp_path):
    """--master lely on a file whose master has dcf: (plc.yml): check says what build says
    of it (the master's dcf: not read) and exits as build does, and show draws the lely
    master's table; without --master both follow dcf: (a PLC). --master plc on a file
    without dcf: is build's NET119 in check too (one verdict)."""
    r = run("network", "check", LELY / "plc.yml", "--master", "lely")
    assert r.exit_code == 0
    assert (f"{LELY}/plc.yml:6: info: the master's dcf: is not read: a lely master is built "
            "[NET007]") in r.stdout.splitlines()
    assert "NET007" not in run("network", "check", LELY / "plc.yml").stdout
    shown = run("network", "show", LELY / "plc.yml", "--master", "lely").output
    assert "Mapped application objects of the lely master (0x2000/0x2200):" in shown
    assert "PLC variables:" in run("network", "show", LELY / "plc.yml").output
    r = run("network", "check", LELY / "flat.yml", "--master", "plc")
    assert r.exit_code == 1
    assert (f"{LELY}/flat.yml:9: error: build needs the PLC's EDS or DCF: give it as 'dcf:' "
            "under 'master:' [NET119]") in r.stdout.splitlines()
