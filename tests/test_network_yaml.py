"""The network file reader (SPEC §10.1, D-16): YAML as safe_load reads it, with lines.

Every finding is asserted exactly, as the command line prints it.
"""
from __future__ import annotations

import pytest

from conftest import ROOT
from dcf2bin.network import configure, load_network
from dcf2bin.network.codes import CODES
from dcf2bin.network.model import MASTER, RPDO, SLAVE, TPDO
from dcf2bin.network.yamltree import MAX_DEPTH

FIXTURES = ROOT / "tests" / "fixtures" / "network"


def load(tmp_path, text: str, name: str = "bus.yml"):
    p = tmp_path / name
    p.write_text(text)
    return load_network(str(p))


def found(net, tmp_path, severity=None) -> list[str]:
    out = []
    for d in net.diagnostics:
        if severity is None or d.severity.value == severity:
            out.append(d.format().replace(str(tmp_path) + "/", ""))
    return out


MINIMAL = "master:\n  node_id: 1\nio:\n  dcf: io.eds\n  node_id: 5\n"


def test_flat_layout_nodes_and_roles(tmp_path):
    net = load(tmp_path, MINIMAL)
    assert found(net, tmp_path) == []
    assert [(n.name, n.node_id, n.role) for n in net.nodes] == [
        ("master", 1, MASTER), ("io", 5, SLAVE)]
    assert net.nodes[1].file == str(tmp_path / "io.eds")
    assert net.nodes[1].where.line == 3
    assert net.layout == "flat"


def test_yaml_syntax_error_is_one_line(tmp_path):
    net = load(tmp_path, "master:\n  node_id: [1\nio: 2\n")
    assert found(net, tmp_path) == [
        "bus.yml:3: error: YAML syntax: while parsing a flow sequence: did not find "
        "expected ',' or ']' [NET001]"]
    assert net.nodes == []


def test_repeated_key_names_both_lines(tmp_path):
    net = load(tmp_path, MINIMAL + "  node_id: 6\n")
    assert found(net, tmp_path) == [
        "bus.yml:6: error: key 'node_id' repeated (first at line 5) [NET002]"]
    assert net.node(5) is not None          # the first one is kept


def test_alias_bomb_is_stopped(tmp_path):
    lines = ["a: &a [x, x, x, x, x, x, x, x, x, x]"]
    for i in range(1, 9):
        prev = chr(ord("a") + i - 1)
        cur = chr(ord("a") + i)
        lines.append(f"{cur}: &{cur} [" + ", ".join([f"*{prev}"] * 10) + "]")
    net = load(tmp_path, "\n".join(lines) + "\n")
    assert found(net, tmp_path) == [
        "bus.yml:6: error: the YAML expands to more than 250,000 nodes (a network has tens "
        "of thousands; aliases repeating aliases?) [NET003]"]


def test_recursive_alias(tmp_path):
    net = load(tmp_path, "master: &m\n  node_id: 1\n  self: *m\n")
    assert found(net, tmp_path) == [
        "bus.yml:3: error: a recursive alias (the node contains itself) [NET003]"]


@pytest.mark.parametrize("text", ["[" * 100_000, "- " * 100_000,
                                  "a:\n" + "".join(" " * i + "b:\n" for i in range(1, 80))])
def test_deep_nesting_is_refused_not_crashed(tmp_path, text):
    net = load(tmp_path, text)
    [msg] = found(net, tmp_path)
    assert msg.endswith(f"error: the YAML nests deeper than {MAX_DEPTH} levels [NET003]")


def test_undefined_alias_and_two_documents(tmp_path):
    assert found(load(tmp_path, "master: *nothing\n"), tmp_path) == [
        "bus.yml:1: error: alias *nothing names no anchor before it [NET001]"]
    assert found(load(tmp_path, MINIMAL + "---\n" + MINIMAL), tmp_path) == [
        "bus.yml:6: error: more than one YAML document in the network file [NET001]"]


def test_not_utf8_and_not_a_mapping(tmp_path):
    p = tmp_path / "bad.yml"
    p.write_bytes(b"master:\n  name: \xff\n")
    assert found(load_network(str(p)), tmp_path) == [
        "bad.yml:2: error: the network file is not UTF-8 text [NET001]"]
    assert found(load(tmp_path, "- 1\n- 2\n"), tmp_path) == [
        "bus.yml:1: error: the network file must be a mapping of 'options', 'master' and "
        "the slaves [NET001]"]


def test_no_master_no_slave_no_node_id_no_dcf(tmp_path):
    assert found(load(tmp_path, "io:\n  dcf: a.eds\n  node_id: 2\n"), tmp_path) == [
        "bus.yml:1: error: no 'master' in the network file [NET005]"]
    assert found(load(tmp_path, "master:\n  node_id: 1\n"), tmp_path) == [
        "bus.yml:1: error: no slave in the network file [NET005]"]
    assert found(load(tmp_path, "master:\n  node_id: 1\nio:\n  node_id: 2\n"), tmp_path) == [
        "bus.yml:3: error: io has no dcf (its EDS or DCF file) [NET005]"]
    assert found(load(tmp_path, "master:\n  node_id: 1\nio:\n  dcf: a.eds\n"), tmp_path) == [
        "bus.yml:3: error: io has no node_id [NET005]"]


def test_templates_placeholder_and_merge_keys(tmp_path):
    net = load(tmp_path, """\
.slave: &slave
  dcf: "@BUS_CONFIG_PATH@/eds/io.eds"
  heartbeat_producer: 100
master:
  node_id: 1
io1:
  <<: *slave
  node_id: 2
io2:
  <<: *slave
  node_id: 3
  heartbeat_producer: 0x20
""")
    assert found(net, tmp_path) == []
    io1, io2 = net.slaves
    assert io1.file == str(tmp_path / "eds" / "io.eds")
    assert (io1.config["heartbeat_producer"], io2.config["heartbeat_producer"]) == (100, 32)
    assert io1.config_where["dcf"].line == 2       # the line of the text, in the template


def test_ros2_layout_defaults_merged_node_wins_with_a_warning(tmp_path):
    net = load(tmp_path, """\
master:
  node_id: 1
defaults:
  dcf: drive.eds
  heartbeat_producer: 100
  driver: "ros2_canopen::Cia402Driver"
nodes:
  d1:
    node_id: 2
  d2:
    node_id: 3
    heartbeat_producer: 50
""")
    assert found(net, tmp_path) == [
        "bus.yml:6: info: key 'driver' is not used by dcf2bin; ignored [NET007]",
        "bus.yml:12: warning: 'heartbeat_producer' of d2 is also in defaults: (line 5); the "
        "node's value is taken (ros2_canopen's generator takes the one of defaults:) "
        "[NET009]"]
    d1, d2 = net.slaves
    assert net.layout == "nodes"
    assert (d1.config["heartbeat_producer"], d2.config["heartbeat_producer"]) == (100, 50)
    assert d1.file == d2.file == str(tmp_path / "drive.eds")


def test_eds_is_read_as_dcf_with_a_warning(tmp_path):
    net = load(tmp_path, "master:\n  node_id: 1\nio:\n  eds: io.eds\n  node_id: 5\n")
    assert found(net, tmp_path) == ["bus.yml:4: warning: 'eds' is read as 'dcf' [NET008]"]
    assert net.slaves[0].file == str(tmp_path / "io.eds")


def test_near_miss_warns_and_unknown_is_info(tmp_path):
    net = load(tmp_path, MINIMAL + "  heartbeat_prodcuer: 100\n  polling: true\n"
               "  colour: blue\n")
    assert found(net, tmp_path) == [
        "bus.yml:6: warning: unknown key 'heartbeat_prodcuer': did you mean "
        "'heartbeat_producer'? [NET006]",
        "bus.yml:7: info: key 'polling' is not used by dcf2bin; ignored [NET007]",
        "bus.yml:8: info: key 'colour' is not used by dcf2bin; ignored [NET007]"]


@pytest.mark.parametrize("value,expected", [
    ("0x1A", 26), ('"0x1A"', 26), ('"010"', 8), ("010", 8), ("0b1100", 12), ("12", 12)])
def test_integer_values(tmp_path, value, expected):
    net = load(tmp_path, MINIMAL + f"  heartbeat_producer: {value}\n")
    assert found(net, tmp_path) == []
    assert net.slaves[0].config["heartbeat_producer"] == expected


@pytest.mark.parametrize("value,message", [
    ('"$NODEID+0x180"', "heartbeat_producer: $NODEID is not allowed in the network file: "
                        "'$NODEID+0x180'"),
    ("true", "heartbeat_producer: expected an integer, found a boolean (True)"),
    ("1.5", "heartbeat_producer: expected an integer, found float 1.5"),
    ("70000", "heartbeat_producer: 70000 is outside 0..65535"),
    ('"ten"', "heartbeat_producer: invalid integer 'ten'"),
])
def test_bad_integers(tmp_path, value, message):
    net = load(tmp_path, MINIMAL + f"  heartbeat_producer: {value}\n")
    assert found(net, tmp_path) == [f"bus.yml:6: error: {message} [NET004]"]


@pytest.mark.parametrize("value,expected", [("true", True), ("False", False),
                                            ('"TRUE"', True), ("yes", True)])
def test_booleans(tmp_path, value, expected):
    net = load(tmp_path, MINIMAL + f"  mandatory: {value}\n")
    assert found(net, tmp_path) == []
    assert net.slaves[0].config["mandatory"] is expected


def test_bad_boolean(tmp_path):
    net = load(tmp_path, MINIMAL + "  boot: 1\n")
    assert found(net, tmp_path) == [
        "bus.yml:6: error: boot: expected true or false, found int 1 [NET004]"]


def test_pdos_mapping_and_sdo(tmp_path):
    net = load(tmp_path, MINIMAL + """\
  tpdo:
    1:
      cob_id: auto
      transmission: 0x01
      mapping:
        - {index: 0x6000, sub_index: 1, name: in1}
        - {index: "0x6401"}
    "3":
      enabled: false
  rpdo:
    2:
      cob_id: 0x305
  sdo:
    - {index: 0x2000, sub_index: 1, value: 1.5}
""")
    assert found(net, tmp_path) == []
    io = net.slaves[0]
    t1 = io.pdo_config[(TPDO, 1)]
    assert (t1.cob_id, t1.transmission, t1.where.line) == ("auto", 1, 7)
    assert [(m.index, m.sub, m.name, m.where.line) for m in t1.mapping] == [
        (0x6000, 1, "in1", 11), (0x6401, 0, None, 12)]
    assert io.pdo_config[(TPDO, 3)].enabled is False
    assert io.pdo_config[(RPDO, 2)].cob_id == 0x305
    [sdo] = io.sdo_config
    assert (sdo.index, sdo.sub, sdo.value, sdo.where.line) == (0x2000, 1, 1.5, 19)


@pytest.mark.parametrize("key,message", [
    ("0", "tpdo: PDO number '0' is not an integer 1..512"),
    ("513", "tpdo: PDO number '513' is not an integer 1..512"),
    ("one", "tpdo: PDO number 'one' is not an integer 1..512"),
])
def test_bad_pdo_numbers(tmp_path, key, message):
    net = load(tmp_path, MINIMAL + f"  tpdo:\n    {key}:\n      enabled: true\n")
    assert found(net, tmp_path) == [f"bus.yml:7: error: {message} [NET004]"]


def test_wrong_shapes(tmp_path):
    net = load(tmp_path, MINIMAL + "  tpdo: [1, 2]\n  sdo: {index: 1}\n")
    assert found(net, tmp_path) == [
        "bus.yml:6: error: 'tpdo' must be a mapping of PDO numbers, found a list [NET004]",
        "bus.yml:7: error: sdo must be a list of {index, sub_index, value}, found a mapping "
        "[NET004]"]


def test_master_keys(tmp_path):
    net = load(tmp_path, """\
master:
  node_id: 0x7F
  name: plc
  heartbeat_consumer: {io: 500}
  baudrate: 250
  start_nodes: "false"
io:
  dcf: io.eds
  node_id: 5
""")
    assert found(net, tmp_path) == []
    m = net.master
    assert (m.name, m.node_id, net.bitrate) == ("plc", 127, 250_000)
    assert m.config["start_nodes"] is False
    assert list(m.config["heartbeat_consumer"]) == ["io"]


def test_a_missing_slave_file_is_one_line(tmp_path):
    net = configure(load(tmp_path, MINIMAL))
    assert found(net, tmp_path) == [
        "bus.yml:4: error: cannot read io.eds: No such file or directory "
        "[NET010]"]
    (tmp_path / "d.eds").mkdir()
    net = configure(load(tmp_path, MINIMAL.replace("io.eds", "d.eds")))
    assert found(net, tmp_path) == [
        "bus.yml:4: error: cannot read d.eds: Is a directory [NET010]"]


@pytest.mark.parametrize("name", ["ros2_cia402_bus.yml", "ros2_simple_bus.yml",
                                  "ros2_robot_bus.yml"])
def test_real_ros2_canopen_layouts_load_and_configure(name):
    net = configure(load_network(str(FIXTURES / name)))
    assert [d.format() for d in net.diagnostics if d.severity.value != "info"] == []
    assert len(net.slaves) >= 2
    for s in net.slaves:
        assert any(p.exists for p in s.pdos)


def test_code_table_is_consistent():
    codes = [c for c, _, _ in CODES]
    assert codes == sorted(set(codes))
    assert all(c.startswith("NET0") or c.startswith("NET1") for c in codes)
    assert {sev for _, sev, _ in CODES} <= {"error", "warning", "info"}


def test_docs_list_every_code():
    """docs/network.md's code table is the code table of dcf2bin/network/codes.py."""
    text = (ROOT / "docs" / "network.md").read_text()
    rows = [line for line in text.splitlines() if line.startswith("| NET")]
    assert rows == [f"| {c} | {s} | {t} |" for c, s, t in CODES]


def test_man_page_lists_every_code():
    """man/dcf2bin-network.1's CODES section is the code table of network/codes.py."""
    text = (ROOT / "man" / "dcf2bin-network.1").read_text().replace("\\-", "-")
    section = text.split(".SH CODES\n")[1].split(".SH ")[0]
    rows = section.split(".TP\n")[1:]
    assert rows == [f".B {c}\n({s}) {t}\n" for c, s, t in CODES]


@pytest.mark.parametrize("value,message", [
    ("0x1FFFFFFFF", "cob_id: 8589934591 is outside 0..0xFFFFFFFF (auto or an integer)"),
    ("0x800", "cob_id: 0x800 has bits 11-28 set but not bit 29 (an 11-bit CAN-ID is at "
              "most 0x7FF; bit 29 marks a 29-bit one)"),
])
def test_bad_cob_ids_are_one_error_each(tmp_path, value, message):
    """A cob_id outside 32 bits, or an 11-bit COB-ID (bit 29 clear, CiA 301) with a CAN-ID
    above 0x7FF: one error at its line, and the value is not used further (0x800 was
    read as CAN-ID 0x000 and reported as NMT's ID)."""
    (tmp_path / "io.eds").write_text((ROOT / "tests/fixtures/network/IoX4_8AI.eds").read_text(
        encoding="latin-1"), encoding="latin-1")
    (tmp_path / "bus.yml").write_text("master:\n  node_id: 1\nio:\n  dcf: io.eds\n  node_id: 5\n"
                                      f"  tpdo:\n    1:\n      cob_id: {value}\n")
    from dcf2bin.network import check_network
    res = check_network(str(tmp_path / "bus.yml"))
    errors = [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
              if d.severity.value == "error"]
    assert errors == [f"bus.yml:8: error: {message} [NET004]"]


def test_a_tab_that_indents_is_named(tmp_path):
    """YAML indents with spaces only; libyaml's words for a tab ("found character that
    cannot start any token") get the reason added, at the tab's line."""
    net = load(tmp_path, "master:\n\tnode_id: 1\nio:\n  dcf: io.eds\n  node_id: 5\n")
    assert found(net, tmp_path) == [
        "bus.yml:2: error: YAML syntax: while scanning for the next token: found character "
        "that cannot start any token (a tab: YAML indents with spaces) [NET001]"]



def test_another_kind_of_file_is_named_not_parsed(tmp_path):
    """A concise DCF (not UTF-8: it was "not UTF-8 text") and a CSV list (it was "must be
    a mapping") given as the network file: what each is and which command reads it, in
    filekind's words for every command; a YAML file keeps its syntax error (above)."""
    p = tmp_path / "io.bin"
    p.write_bytes(bytes.fromhex("01000000" "0018" "01" "04000000" "81010080"))
    assert found(load_network(str(p)), tmp_path) == [
        "io.bin: error: io.bin is a concise DCF (CiA 302-3), not a YAML network file or a "
        "CiA 306-3 network project; use dcf2bin dump to read it (dcf2bin validate checks it, "
        "download writes it to a node, bin2dcf turns it into a DCF) [IO001]"]
    assert found(load(tmp_path, "name,type,direction\nlevel,UNSIGNED8,input\n", "v.csv"),
                 tmp_path) == [
        "v.csv: error: v.csv is not a YAML network file (it looks like CSV: dcf2bin allocate "
        "reads it) [IO001]"]
    # a flow-style network file in a file named .txt is YAML all the same
    net = load(tmp_path, "{master: {node_id: 1}, io: {dcf: io.eds, node_id: 5}}\n", "n.txt")
    assert found(net, tmp_path) == [] and [n.node_id for n in net.nodes] == [1, 5]


@pytest.mark.parametrize("value,shown", [("0x99999", "0x99999"), ("629145", "0x99999"),
                                         ("-1", "-0x1")])
def test_an_index_out_of_range_is_shown_in_hex(tmp_path, value, shown):
    """An object index is hex as users write it: 0x99999 was shown as 629145."""
    net = load(tmp_path, MINIMAL + "  tpdo:\n    1:\n      mapping:\n"
               f"        - {{index: {value}, sub_index: 0}}\n")
    assert found(net, tmp_path) == [
        f"bus.yml:9: error: index: {shown} is outside 0x0000..0xFFFF [NET004]"]
