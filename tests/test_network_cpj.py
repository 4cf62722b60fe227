"""The CiA 306-3 nodelist project reader (network/cpj.py, NET050–NET059) and `network
check` on a .cpj from the command line."""
from __future__ import annotations

import json
import pathlib
import shutil

import pytest
from click.testing import CliRunner

from dcf2bin.cli.network.check import check_cmd
from dcf2bin.network import cpj
from dcf2bin.network.model import RPDO, TPDO

FIX = pathlib.Path(__file__).parent / "fixtures" / "network" / "check"


def project(tmp_path: pathlib.Path, text: str) -> str:
    folder = tmp_path / "p"
    if not folder.exists():
        shutil.copytree(FIX, folder)
    (folder / "network.cpj").write_text(text)
    return str(folder / "network.cpj")


def diags(network) -> list[str]:
    path = str(pathlib.Path(network.path).parent) + "/"
    return [d.format().replace(path, "") for d in network.diagnostics]


def test_the_fixture_project():
    net = cpj.read(str(FIX / "network.cpj"))
    assert net.kind == "cpj" and net.master is None and not net.diagnostics.items
    assert [(n.node_id, n.name, pathlib.Path(n.file).name) for n in net.nodes] == [
        (1, "plc", "plc.dcf"), (2, "io", "io.dcf"), (3, "io3", "io3.dcf")]
    assert net.master_where.line == 3 and net.options["netname"] == "Machine"
    io = net.node(2)
    assert [(p.label, hex(p.cob_id), p.transmission, p.exists) for p in io.pdos] == [
        ("RPDO1", "0x202", 255, True), ("RPDO2", "0x302", 255, True),
        ("TPDO1", "0x182", 1, True)]
    assert [(m.index, m.sub, m.bits, m.datatype) for m in io.pdo(TPDO, 1).mapping] == [
        (0x6000, 1, 8, 0x05), (0x6000, 2, 8, 0x05), (0x6401, 1, 16, 0x03)]
    assert io.pdo(RPDO, 1).where.line == 176          # [1400sub1] ParameterValue
    assert (io.heartbeat_producer, [(h.node_id, h.time_ms) for h in io.heartbeat_consumers]) \
        == (200, [(1, 300)])
    plc = net.node(1)
    assert (plc.sync_producer, plc.sync_period, plc.sync_cob_id, plc.emcy_cob_id,
            plc.time_cob_id) == (True, 10000, 0x80, 0x81, 0x100)
    assert [p.exists for p in net.node(3).pdos] == [False, False, False]


def test_a_second_network_and_its_absence(tmp_path):
    text = (FIX / "network.cpj").read_text() + (
        "\n[Topology2]\nNetName=Conveyor\nNodes=1\nNode5Present=1\nNode5Name=belt\n"
        "Node5DCFName=io.dcf\n")
    path = project(tmp_path, text)
    net = cpj.read(path, 2)
    assert [(n.node_id, n.name) for n in net.nodes] == [(5, "belt")]
    # io.dcf says NodeID=2: the project's 5 is used, with a warning
    assert diags(net) == ["network.cpj:25: warning: node 5: its DCF 'io.dcf' sets NodeID 2; "
                          "the project's node-ID 5 is used [NET059]"]
    assert net.node(5).pdo(TPDO, 1).cob_id == 0x182     # the DCF's value, as it is
    net = cpj.read(path, 3)
    assert diags(net) == ["network.cpj:1: error: the project has no [Topology3] section (it "
                          "has [Topology], [Topology2]) [NET051]"]


@pytest.mark.parametrize("text,expected", [
    ("[Topology]\nNodes=1\nNode1Present=1\nNode1DCFName=plc.dcf\nNode1Name=plc\n", []),
    ("; nothing\n[Other]\nA=1\n",
     ["network.cpj:1: error: the project has no [Topology] section [NET051]"]),
    ("[Topology]\nNodes=one\nNode1Present=1\nNode1DCFName=plc.dcf\n",
     ["network.cpj:2: error: [Topology] Nodes: invalid integer 'one' [NET052]"]),
    ("[Topology]\nNodes=1\nNode1Present=2\nNode2Present=1\nNode2DCFName=io.dcf\n",
     ["network.cpj:3: error: [Topology] Node1Present: '2' is neither 0 nor 1 [NET052]"]),
    ("[Topology]\nNodes=1\nNode0Present=1\nNode128Name=x\nNode1Present=1\n"
     "Node1DCFName=plc.dcf\n",
     ["network.cpj:3: error: [Topology] Node0Present: node-ID 0 is outside 1…127 [NET053]",
      "network.cpj:4: error: [Topology] Node128Name: node-ID 128 is outside 1…127 [NET053]"]),
    ("[Topology]\nNodes=1\nNode1Present=1\nNode1Name=plc\n",
     ["network.cpj:3: error: node 1 is present but has no Node1DCFName [NET054]"]),
    ("[Topology]\nNodes=1\nNode1Present=1\nNode1DCFName=missing.dcf\n",
     ["network.cpj:4: error: Node1DCFName: cannot read 'missing.dcf': No such file or "
      "directory [NET055]"]),
    ("[Topology]\nNodes=1\nNode1Present=1\nNode1DCFName=.\n",
     ["network.cpj:4: error: Node1DCFName: cannot read '.': Is a directory [NET055]"]),
    ("[Topology]\nNodes=2\nNode1Present=1\nNode1DCFName=plc.dcf\n",
     ["network.cpj:2: warning: [Topology] Nodes=2 but 1 node is present [NET056]"]),
    ("[Topology]\nNodes=0\nNode1Present=0\nNode1DCFName=plc.dcf\n",
     ["network.cpj:1: error: [Topology] marks no node present [NET057]"]),
    ("[Topology]\nNodes=1\nNode1Present=1\nNode1DCFName=plc.dcf\nNode1DCFname2=x\n",
     ["network.cpj:5: warning: [Topology] Node1DCFname2: not a key of a CiA 306-3 network "
      "[NET058]"]),
    ("[Topology]\nNodes=1\nNode1Present=1\nNode1DCFName=plc.dcf\nNode1Present=0\n",
     ["network.cpj:5: error: key 'node1present' repeated (first at line 3; the first is "
      "used) [NET050]"]),
])
def test_project_problems(tmp_path, text, expected):
    assert diags(cpj.read(project(tmp_path, text))) == expected


def test_cli_text_json_and_exit_codes(tmp_path):
    runner = CliRunner()
    path = str(FIX / "network.cpj")
    res = runner.invoke(check_cmd, [path])
    assert (res.exit_code, res.output) == (0, "0 errors, 0 warnings, 0 infos in 4 files\n")
    res = runner.invoke(check_cmd, [path, "--max-load", "1", "--strict"])
    assert res.exit_code == 1 and "[NET260]" in res.output
    res = runner.invoke(check_cmd, [path, "--max-load", "1", "--ignore", "bus-load",
                                    "--strict"])
    assert res.exit_code == 0
    res = runner.invoke(check_cmd, [path, "-f", "json", "--max-load", "1"])
    doc = json.loads(res.output)
    assert [(f["kind"], f["warnings"]) for f in doc["files"]] == [
        ("cpj", 1), ("dcf", 0), ("dcf", 0), ("dcf", 0)]
    assert [(d["rule"], d["name"], d["line"]) for d in doc["diagnostics"]] == [
        ("NET260", "bus-load", 3)]
    broken = project(tmp_path, "[Topology]\nNode1Present=1\nNode1DCFName=gone.dcf\n")
    res = runner.invoke(check_cmd, [broken])
    assert res.exit_code == 3 and "[NET055]" in res.output
    res = runner.invoke(check_cmd, [str(tmp_path / "nothing.cpj")])
    assert res.exit_code == 3 and "cannot read" in res.output
    res = runner.invoke(check_cmd, [path, "--select", "NOPE"])
    assert res.exit_code == 2
    res = runner.invoke(check_cmd, [path.replace(".cpj", ".yml"), "--net", "2"])
    assert res.exit_code == 2


def test_validate_findings_of_a_node_file_are_part_of_the_report(tmp_path):
    """An error of a node's file is reported as validate reports it; in an entry the network
    neither configures nor maps, it is a warning (as compile words it)."""
    folder = tmp_path / "p"
    shutil.copytree(FIX, folder)
    io = folder / "io.dcf"
    text = io.read_text()
    # 0x6200sub3 is mapped (io RPDO2); 0x6401sub1 too; [6000sub2] DefaultValue broken: mapped
    text = text.replace("[6401sub1]\nParameterName=Read analogue input 16-bit 1\n"
                        "ObjectType=0x7\nDataType=0x0003\nAccessType=ro\nDefaultValue=0",
                        "[6401sub1]\nParameterName=Read analogue input 16-bit 1\n"
                        "ObjectType=0x7\nDataType=0x0003\nAccessType=ro\nDefaultValue=40000")
    io.write_text(text)
    res = CliRunner().invoke(check_cmd, [str(folder / "network.cpj")])
    assert "/io.dcf:445: error: 0x6401sub1 DefaultValue: value 40000 out of range for " \
        "INTEGER16 (-32768..32767) [DCF200]\n" in res.output
    plc = folder / "plc.dcf"
    plc.write_text(plc.read_text().replace(
        "[2002]\nParameterName=Counter\nObjectType=0x7\nDataType=0x0006\nAccessType=rw\n"
        "DefaultValue=0", "[2002]\nParameterName=Counter\nObjectType=0x7\nDataType=0x0006\n"
        "AccessType=rw\nDefaultValue=70000"))
    res = CliRunner().invoke(check_cmd, [str(folder / "network.cpj")])
    line = [x for x in res.output.splitlines() if "plc.dcf" in x]
    assert len(line) == 1 and ": warning: " in line[0] and line[0].endswith(
        "(the network neither configures nor maps this entry) [DCF200]"), line


def test_build_then_a_cpj_naming_the_outputs_checks_clean(tmp_path):
    """network build of bus.yml, a .cpj project naming the files it wrote, network check of
    that project: the network as built checks clean, as the YAML it came from does."""
    from dcf2bin.network.build import build_network
    from dcf2bin.network.check import check_network
    shutil.copytree(FIX.parent, tmp_path / "net")
    yml = tmp_path / "net" / "check" / "bus.yml"
    assert check_network(str(yml)).diagnostics == []
    out = tmp_path / "out"
    res = build_network(str(yml), str(out))
    assert res.ok, [d.format() for d in res.diagnostics]
    assert sorted(p.name for p in out.iterdir()) == [
        ".dcf2bin-build.lock", "drive.bin", "drive.dcf", "io.bin", "io.dcf", "master.dcf"]
    (out / "machine.cpj").write_text(
        "[Topology]\nNetName=machine\nNodes=3\n"
        "Node1Present=1\nNode1Name=master\nNode1DCFName=master.dcf\n"
        "Node2Present=1\nNode2Name=drive\nNode2DCFName=drive.dcf\n"
        "Node3Present=1\nNode3Name=io\nNode3DCFName=io.dcf\n")
    res = check_network(str(out / "machine.cpj"))
    assert [d.format() for d in res.diagnostics] == []
    # the links are there: the drive's TPDO1 feeds the master, the master feeds its RPDO1
    net = res.network
    assert [(r.what, r.producer.name, [n.name for n, _ in r.consumers])
            for r in res.load.rows if r.what.startswith("TPDO")][:2] == [
        ("TPDO1", "drive", ["master"]), ("TPDO1", "io", ["master"])]
    assert net.node(1).pdo(RPDO, 1).exists


def test_json_and_sarif_reports_follow_validate_schemas(tmp_path):
    import jsonschema

    from dcf2bin.lint.report_schema import REPORT_SCHEMA, RULES_SCHEMA
    yml = tmp_path / "net" / "check" / "bus.yml"
    shutil.copytree(FIX.parent, tmp_path / "net")
    runner = CliRunner()
    for path in (str(FIX / "network.cpj"), str(yml)):
        res = runner.invoke(check_cmd, [path, "-f", "json", "--max-load", "1"])
        doc = json.loads(res.output)
        jsonschema.validate(doc, REPORT_SCHEMA)
        assert doc["summary"]["exit_code"] == res.exit_code == 0
        assert doc["files"][0]["kind"] == ("cpj" if path.endswith(".cpj") else "yaml")
        sarif = json.loads(runner.invoke(check_cmd, [path, "-f", "sarif"]).output)
        assert sarif["version"] == "2.1.0"
    rules = json.loads(runner.invoke(check_cmd, ["--list-rules", "-f", "json"]).output)
    jsonschema.validate(rules, RULES_SCHEMA)
    fams = {r["id"]: r["family"] for r in rules["rules"]}
    assert (fams["NET055"], fams["NET010"], fams["NET101"], fams["NET220"]) == (
        "network project (.cpj)", "network file", "network configuration",
        "network as a whole")
