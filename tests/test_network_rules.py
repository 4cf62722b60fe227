"""network check: one test per NET2xx rule of SPEC §10.4 (D-19).

The network is tests/fixtures/network/check/network.cpj: a CiA 405 PLC (node 1, the SYNC
producer, 10 ms), a CiA 401 I/O module (node 2) linked with it both ways, and a spare I/O
module (node 3) whose PDOs are off. It checks clean. Each test edits one value of one file
(the line numbers stay the same), checks that exactly the rule under test fires with its
exact text, and that a neighbour one edit away — a value at the boundary, or the PDO
disabled — does not.

Lines: a PDO from a file is named by its comm sub 1 value line (the ParameterValue of
[1800sub1] of io.dcf and io3.dcf is line 293, of [1400sub1] of plc.dcf line 208, of
[1802sub1] line 381, of [1401sub1] of io.dcf line 207, of [1400sub1] of io.dcf and io3.dcf
line 176); a heartbeat entry by its 0x1016 sub's value line (plc.dcf lines 139 and 148);
the SYNC window by its ParameterValue (plc.dcf line 101); a network-wide finding by
[Topology] (line 3).
"""
from __future__ import annotations

import pathlib
import shutil

import pytest

from dcf2bin.diagnostics import Where
from dcf2bin.network.check import check_network, run_rules
from dcf2bin.network.model import MASTER, RPDO, SLAVE, TPDO, Heartbeat, Mapped, Network, \
    Node, Pdo
from dcf2bin.network.rules import RULES

FIX = pathlib.Path(__file__).parent / "fixtures" / "network" / "check"


def edit(folder: pathlib.Path, fname: str, section: str, key: str, value: str) -> None:
    """Set ``key`` of ``[section]`` in ``fname`` to ``value`` (the line stays where it is)."""
    p = folder / fname
    lines = p.read_text().split("\n")
    i = lines.index(f"[{section}]") + 1
    while not lines[i].startswith(f"{key}="):
        assert not lines[i].startswith("["), f"[{section}] has no {key}"
        i += 1
    lines[i] = f"{key}={value}"
    p.write_text("\n".join(lines))


def check(tmp_path: pathlib.Path, *edits, **kw) -> list[str]:
    folder = tmp_path / "net"
    if not folder.exists():
        shutil.copytree(FIX, folder)
    for e in edits:
        edit(folder, *e)
    res = check_network(str(folder / "network.cpj"), **kw)
    return [d.format().replace(str(folder) + "/", "") for d in res.diagnostics]


def test_the_fixture_network_checks_clean(tmp_path):
    assert check(tmp_path) == []


# (rule, the edit that triggers it, the neighbour one edit away, exact findings)
CASES = [
    ("NET210", [("io3.dcf", "1800sub1", "ParameterValue", "0x182")],
     [("io3.dcf", "1800sub1", "ParameterValue", "0x80000182")],      # disabled: no producer
     ["io3.dcf:293: error: io3 (node 3) TPDO1 produces COB-ID 0x182, as io (node 2) TPDO1 "
      "at io.dcf:293 does [NET210]"]),
    ("NET211", [("io3.dcf", "1400sub1", "ParameterValue", "0x203")],
     [("io3.dcf", "1400sub1", "ParameterValue", "0x202")],           # listens to plc TPDO1
     ["io3.dcf:176: error: io3 (node 3) RPDO1 listens to COB-ID 0x203, which no TPDO of "
      "the network produces [NET211]"]),
    ("NET212", [("plc.dcf", "1802sub1", "ParameterValue", "0x381")],
     [("plc.dcf", "1802sub1", "ParameterValue", "0x80000381")],
     ["plc.dcf:381: info: plc (node 1) TPDO3 (COB-ID 0x381) is consumed by no RPDO of the "
      "network [NET212]"]),
    # io TPDO1 sends 0x6000sub1, 0x6000sub2 (UNSIGNED8), 0x6401sub1 (INTEGER16): 32 bits;
    # plc RPDO1 maps 0x2000sub1, 0x2000sub2, 0x2001 and, as its sub 4, 0x2000sub3
    ("NET220", [("plc.dcf", "1600sub0", "ParameterValue", "4")],    # 8+8+16+8 = 40 bits
     [("plc.dcf", "1600sub0", "ParameterValue", "3")],              # 32 bits
     ["plc.dcf:208: error: plc (node 1) RPDO1 maps 40 bits but its producer io (node 2) "
      "TPDO1 at io.dcf:293 sends 32: every PDO would arrive too short (EMCY 0x8210) "
      "[NET220]"]),
    ("NET221", [("plc.dcf", "1600sub0", "ParameterValue", "2")],    # 16 bits
     [("plc.dcf", "1600sub0", "ParameterValue", "3")],
     ["plc.dcf:208: warning: plc (node 1) RPDO1 maps 16 bits of the 32 its producer io "
      "(node 2) TPDO1 at io.dcf:293 sends [NET221]"]),
    # 0x2003 (16 bits) at bits 0…15 where the producer has two 8-bit fields; 0x2001 at
    # 16…31 matches 0x6401sub1
    ("NET222", [("plc.dcf", "1600sub0", "ParameterValue", "2"),
                ("plc.dcf", "1600sub1", "DefaultValue", "0x20030010"),
                ("plc.dcf", "1600sub2", "DefaultValue", "0x20010010")],
     [("plc.dcf", "1600sub0", "ParameterValue", "3"),               # as the producer
      ("plc.dcf", "1600sub1", "DefaultValue", "0x20000108"),
      ("plc.dcf", "1600sub2", "DefaultValue", "0x20000208")],
     ["plc.dcf:208: error: plc (node 1) RPDO1 maps 0x2003sub0 at bits 0…15, where its "
      "producer io (node 2) TPDO1 at io.dcf:293 has no field of 16 bits [NET222]"]),
    ("NET223", [("plc.dcf", "1600sub3", "DefaultValue", "0x20020010")],   # UNSIGNED16
     [("plc.dcf", "1600sub3", "DefaultValue", "0x20010010")],             # INTEGER16
     ["plc.dcf:208: warning: plc (node 1) RPDO1 maps 0x2002sub0 (UNSIGNED16) at bits "
      "16…31, where its producer io (node 2) TPDO1 at io.dcf:293 sends 0x6401sub1 "
      "(INTEGER16) [NET223]"]),
    # io RPDO1 (0x202) maps 0x6200sub1 and sub2; RPDO2 (0x302) maps 0x6200sub3
    ("NET224", [("io.dcf", "1601sub1", "ParameterValue", "0x62000108")],
     [("io.dcf", "1601sub1", "ParameterValue", "0x62000308")],
     ["io.dcf:207: warning: io (node 2) RPDO2 maps 0x6200sub1, as RPDO1 at io.dcf:176 "
      "does: the later frame overwrites it [NET224]"]),
    # the link io TPDO1 -> plc RPDO1 moved, both ends; each file's own DCF412 comes too
    ("NET230", [("io.dcf", "1800sub1", "ParameterValue", "0x102"),
                ("plc.dcf", "1400sub1", "ParameterValue", "0x102")],
     [("io.dcf", "1800sub1", "ParameterValue", "0x1A2"),
      ("plc.dcf", "1400sub1", "ParameterValue", "0x1A2")],
     ["plc.dcf:208: warning: RPDO 0x1400: CAN-ID 0x102 is reserved by CiA 301 [DCF412]",
      "io.dcf:293: warning: TPDO 0x1800: CAN-ID 0x102 is reserved by CiA 301 [DCF412]",
      "io.dcf:293: error: io (node 2) TPDO1 has COB-ID 0x102, an ID CiA 301 reserves for "
      "other services [NET230]"]),
    # the PLC's TIME COB-ID onto the link's ID; its neighbour on a free ID
    ("NET231", [("plc.dcf", "1012", "DefaultValue", "0x182")],
     [("plc.dcf", "1012", "DefaultValue", "0x183")],
     ["io.dcf:293: error: io (node 2) TPDO1 has COB-ID 0x182, the ID of the TIME of plc "
      "(node 1) [NET231]"]),
    ("NET240", [("plc.dcf", "1005", "ParameterValue", "0x00000080")],
     [("plc.dcf", "1005", "ParameterValue", "0x40000080")],
     ["io.dcf:293: error: io (node 2) TPDO1 is synchronous (transmission type 1) but no "
      "node of the network produces SYNC [NET240]"]),
    # io has 0x1006 = 10000 already: bit 30 of its 0x1005 makes it a second producer
    ("NET241", [("io.dcf", "1005", "ParameterValue", "0x40000080")],
     [("io.dcf", "1005", "ParameterValue", "0x00000080")],
     ["network.cpj:3: error: more than one node produces SYNC: plc (node 1) every 10000 "
      "µs, io (node 2) every 10000 µs [NET241]"]),
    ("NET242", [("plc.dcf", "1007", "ParameterValue", "10000")],
     [("plc.dcf", "1007", "ParameterValue", "9999")],
     ["plc.dcf:101: error: plc (node 1): the synchronous window of 10000 µs is not below "
      "the SYNC period of 10000 µs [NET242]"]),
    # io sends its heartbeat every 200 ms; the PLC waits 200 ms (0xC8), neighbour 201
    ("NET250", [("plc.dcf", "1016sub1", "ParameterValue", "0x000200C8")],
     [("plc.dcf", "1016sub1", "ParameterValue", "0x000200C9")],
     ["plc.dcf:139: error: plc (node 1) expects the heartbeat of io (node 2) within 200 ms, "
      "but it is sent every 200 ms [NET250]"]),
    ("NET251", [("io.dcf", "1017", "ParameterValue", "0")],
     [("io.dcf", "1017", "ParameterValue", "1")],
     ["plc.dcf:139: error: plc (node 1) monitors io (node 2), which produces no heartbeat "
      "(producer time 0) [NET251]"]),
    ("NET252", [("plc.dcf", "1016sub2", "ParameterValue", "0x000501F4")],
     [("plc.dcf", "1016sub2", "ParameterValue", "0x000001F4")],    # node 0: an unused entry
     ["plc.dcf:148: warning: plc (node 1) monitors node 5, which is not in the network "
      "[NET252]"]),
]


@pytest.mark.parametrize("code,edits,neighbour,expected", CASES, ids=[c[0] for c in CASES])
def test_rule(tmp_path, code, edits, neighbour, expected):
    assert check(tmp_path / "a", *edits) == expected
    assert check(tmp_path / "b", *edits, *neighbour) == []


def test_bus_load_above_max_load(tmp_path):
    # 3.625 % (tests/test_network_load.py has the arithmetic)
    assert check(tmp_path / "a", max_load=3.6) == [
        "network.cpj:3: warning: the estimated bus load is 3.6 % at 500 kbit/s, above 3.6 % "
        "[NET260]"]
    assert check(tmp_path / "b", max_load=3.7) == []


# -- rules a .cpj cannot reach: a network built by hand ------------------------------------

def _net(*nodes: Node) -> Network:
    return Network("bus.yml", nodes=list(nodes), master_where=Where("bus.yml", 1))


def _diags(network: Network) -> list[str]:
    return [d.format() for d in run_rules(network)]


def test_NET200_node_id_repeated():
    a = Node("plc", 1, MASTER, where=Where("bus.yml", 1))
    b = Node("drive", 2, SLAVE, where=Where("bus.yml", 5))
    c = Node("io", 2, SLAVE, where=Where("bus.yml", 9))
    assert _diags(_net(a, b, c)) == [
        "bus.yml:9: error: io has node-ID 2, as drive at bus.yml:5 has [NET200]"]
    c.node_id = 3
    assert _diags(_net(a, b, c)) == []


def test_NET201_node_id_range():
    a = Node("plc", 1, MASTER, where=Where("bus.yml", 1))
    b = Node("drive", 128, SLAVE, where=Where("bus.yml", 5))
    assert _diags(_net(a, b)) == [
        "bus.yml:5: error: drive: node-ID 128 is outside 1…127 [NET201]"]
    b.node_id = 127
    assert _diags(_net(a, b)) == []


def test_NET253_mandatory_not_monitored():
    a = Node("plc", 1, MASTER, where=Where("bus.yml", 1))
    b = Node("drive", 2, SLAVE, where=Where("bus.yml", 5), mandatory=True,
             heartbeat_producer=100)
    assert _diags(_net(a, b)) == [
        "bus.yml:5: warning: drive (node 2) is mandatory but the master does not monitor its "
        "heartbeat [NET253]"]
    a.heartbeat_consumers.append(Heartbeat(2, 300, Where("bus.yml", 1)))
    assert _diags(_net(a, b)) == []


def test_a_plc_mirror_is_named_by_the_slave_pdo_and_not_reported_twice():
    """D-19: a PLC mirror names the line of the slave PDO it mirrors; a synchronous slave
    PDO without SYNC is one error, not one more for its mirror."""
    at = Where("bus.yml", 12)
    slave = Pdo(2, TPDO, 1, 0x182, transmission=1, where=at,
                mapping=[Mapped(0x6000, 1, 8, 0x05)])
    mirror = Pdo(1, RPDO, 1, 0x182, transmission=1, mirror_of=slave,
                 mapping=[Mapped(0xA000, 1, 8, 0x05), Mapped(0xA000, 2, 8, 0x05)])
    a = Node("plc", 1, MASTER, where=Where("bus.yml", 1), pdos=[mirror])
    b = Node("io", 2, SLAVE, where=Where("bus.yml", 8), pdos=[slave])
    assert _diags(_net(a, b)) == [
        "bus.yml:12: error: plc (node 1) RPDO1 maps 16 bits but its producer io (node 2) "
        "TPDO1 at bus.yml:12 sends 8: every PDO would arrive too short (EMCY 0x8210) "
        "[NET220]",
        "bus.yml:12: error: io (node 2) TPDO1 is synchronous (transmission type 1) but no "
        "node of the network produces SYNC [NET240]"]


def test_every_rule_has_a_test():
    tested = {c[0] for c in CASES} | {"NET200", "NET201", "NET253", "NET260"}
    assert tested == set(RULES)


# -- the YAML path: bus.yml (a PLC, a CiA 402 drive, a CiA 401 I/O module) -------------------

def yaml_check(tmp_path: pathlib.Path, old: str = "", new: str = "", **kw) -> list[str]:
    """Check a copy of bus.yml (one text edit, same line count) next to the net fixtures."""
    folder = tmp_path / "check"
    shutil.copytree(FIX.parent, tmp_path, dirs_exist_ok=True)
    text = (FIX / "bus.yml").read_text()
    if old:
        assert text.count(old) == 1 and old.count("\n") == new.count("\n")
        text = text.replace(old, new)
    (folder / "bus.yml").write_text(text)
    res = check_network(str(folder / "bus.yml"), **kw)
    return [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics]


def test_the_yaml_network_checks_clean(tmp_path):
    assert yaml_check(tmp_path) == []


def test_NET200_in_yaml(tmp_path):
    # io on the drive's node-ID: the drive's TPDO1 COB-ID 0x182 is then io's too
    assert yaml_check(tmp_path / "a", "  node_id: 3\n", "  node_id: 2\n") == [
        "check/bus.yml:32: error: io has node-ID 2, as drive at check/bus.yml:10 has [NET200]",
        "IoX4_8AI.eds:419: error: io (node 2) TPDO1 produces COB-ID 0x182, as drive (node 2) "
        "TPDO1 at check/bus.yml:16 does [NET210]"]
    assert yaml_check(tmp_path / "b", "  node_id: 3\n", "  node_id: 4\n") == []


def test_NET253_in_yaml(tmp_path):
    # without a producer time the master has no 0x1016 entry for the drive
    assert yaml_check(tmp_path / "a", "  heartbeat_producer: 50\n", "  boot: true\n") == [
        "check/bus.yml:10: warning: drive (node 2) is mandatory but the master does not "
        "monitor its heartbeat [NET253]"]
    assert yaml_check(tmp_path / "b", "  mandatory: true\n", "  mandatory: false\n") == []


def test_NET242_in_yaml_names_the_master_line(tmp_path):
    old = "  heartbeat_producer: 100\n  sync_period: 10000\n"
    assert yaml_check(tmp_path / "a", old, "  sync_window: 10000\n  sync_period: 10000\n") \
        == ["check/bus.yml:5: error: master (node 1): the synchronous window of 10000 µs is "
            "not below the SYNC period of 10000 µs [NET242]"]
    assert yaml_check(tmp_path / "b", old, "  sync_window: 9999\n  sync_period: 10000\n") \
        == []


def test_docs_network_md_lists_every_check_rule():
    """docs/network.md "What check reports": one row per .cpj and NET2xx rule, as the
    tables in dcf2bin/network/cpj.py and rules.py have them."""
    from dcf2bin.network import cpj
    text = (pathlib.Path(__file__).parent.parent / "docs" / "network.md").read_text()
    rows = [line for line in text.splitlines() if line.startswith("| `NET")]
    assert rows == [f"| `{r.id}` | {r.severity.value} | `{r.name}` | {r.description} |"
                    for table in (cpj.RULES, RULES) for r in table.values()]


def test_NET224_not_for_one_value_sent_twice():
    """A PLC variable mirrored from one slave object that the slave maps in two TPDOs (D-17
    makes it one variable) is written by two PLC RPDOs with the same value: no NET224. A
    master without dcf (its mirrors name the slaves' own objects) is not checked."""
    t1 = Pdo(3, TPDO, 1, 0x183, mapping=[Mapped(0x2100, 0, 32, 0x07),
                                          Mapped(0x2101, 0, 32, 0x07)], event_timer=100)
    t5 = Pdo(3, TPDO, 5, 0x182, mapping=[Mapped(0x2101, 0, 32, 0x07)], event_timer=100)
    r1 = Pdo(1, RPDO, 1, 0x183, mirror_of=t1, mapping=[Mapped(0xA200, 1, 32, 0x07),
                                                       Mapped(0xA200, 2, 32, 0x07)])
    r2 = Pdo(1, RPDO, 2, 0x182, mirror_of=t5, mapping=[Mapped(0xA200, 2, 32, 0x07)])
    plc = Node("plc", 1, MASTER, where=Where("bus.yml", 1), pdos=[r1, r2], device=object())
    rtt = Node("rtt1", 3, SLAVE, where=Where("bus.yml", 9), pdos=[t1, t5])
    assert _diags(_net(plc, rtt)) == []
    # the same RPDOs fed by two different objects: the later frame overwrites the first
    t5.mapping = [Mapped(0x2100, 0, 32, 0x07)]
    assert _diags(_net(plc, rtt)) == [
        "bus.yml:1: warning: plc (node 1) RPDO2 maps 0xA200sub2, as RPDO1 at bus.yml:1 does: "
        "the later frame overwrites it [NET224]"]
    plc.device = None
    assert _diags(_net(plc, rtt)) == []


def test_NET260_names_the_frames_of_unknown_rate(tmp_path):
    # the PLC's TPDO mirroring the drive's RPDO1 is event-driven without timers: its rate
    # is unknown and counts as 0 (the total is the estimate's; test_network_load checks
    # the arithmetic)
    assert yaml_check(tmp_path / "a", max_load=0) == [
        "check/bus.yml:5: warning: the estimated bus load is 5.8 % at 500 kbit/s, above 0 % "
        "(1 frame of unknown rate counted as 0) [NET260]"]
    assert yaml_check(tmp_path / "b", max_load=5.9) == []


def test_rule_names_are_unique_beside_validates():
    """--select/--ignore take names: no network rule shares one with a validate rule."""
    from dcf2bin.network.check import rule_table
    table = rule_table()
    names = [r.name for r in table.values()]
    assert len(names) == len(set(names)) == len(table)


def test_validate_and_network_check_share_the_rule_options():
    """One decorator (cli.common.rule_options): --select/--ignore/--strict read and are
    worded alike in validate and network check."""
    from dcf2bin.cli.network.check import check_cmd
    from dcf2bin.cli.validate import validate_cmd

    def helps(cmd):
        return {p.name: (p.opts, p.help) for p in cmd.params
                if p.name in ("select_", "ignore", "strict")}
    assert helps(check_cmd) == helps(validate_cmd)
    assert helps(check_cmd)["select_"][1].startswith("Check only these rules: codes, code "
                                                     "prefixes (DCF4, CNT, NET2), names")
