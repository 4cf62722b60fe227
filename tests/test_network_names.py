"""Issue 27 "every real file builds" and "what passes silently today", on the small slave
of test_network_build (mini.eds: TPDO1 maps 0x6000, RPDO1 0x6200, rw 0x6200 mappable both
ways; 0x1016 monitors nodes 7 and 8):

* an object mapped both ways is two variables, ``_in`` and ``_out`` (SPEC §10.2, D-17),
  also when the PDOs come from the file; no other name changes;
* a slave's ``names:`` names the variables of PDOs the file configures;
* no false NET224 for objects of different slaves when the PLC cannot place its
  variables;
* ``mapping:`` empty (NET121) and one object twice in one PDO (NET122) are findings;
* a slave that does not monitor the master has its file's 0x1016 entry for the master
  cleared, as lely's dcfgen clears it.
"""
from __future__ import annotations

import pytest

from test_network_build import HEAD, SLAVE, build, mini_eds


def names(res) -> list[tuple[str, str, str]]:
    return [(v.name, v.direction, f"0x{v.index:04X}sub{v.sub:X}")
            for v in res.network.variables]


BOTH = ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x6200}\n"
        "  rpdo:\n    1:\n      mapping:\n        - {index: 0x6200}\n")


def test_an_object_mapped_both_ways_is_an_input_and_an_output(tmp_path):
    """3 of 12 real networks stopped here: a controlword in a TPDO and an RPDO gave two
    variables one default name (NET107 "name 'io_6200_0' is given to two objects")."""
    got, res = build(tmp_path, SLAVE + BOTH)
    assert got == [] and res.ok
    assert names(res) == [("io_6200_0_in", "input", "0x6200sub0"),
                          ("io_6200_0_out", "output", "0x6200sub0")]
    plc = res.outputs["master.dcf"].decode("latin-1")
    assert "ParameterName=io_6200_0_in" in plc and "ParameterName=io_6200_0_out" in plc


def test_only_objects_mapped_both_ways_get_the_suffix(tmp_path):
    body = SLAVE + ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x6200}\n"
                    "        - {index: 0x6000}\n"
                    "  rpdo:\n    1:\n      mapping:\n        - {index: 0x6200}\n")
    got, res = build(tmp_path, body)
    assert got == []
    assert names(res) == [("io_6200_0_in", "input", "0x6200sub0"),
                          ("io_6000_0", "input", "0x6000sub0"),
                          ("io_6200_0_out", "output", "0x6200sub0")]


def test_both_ways_from_the_file_and_named_by_names(tmp_path):
    """PDOs the file configures (no mapping: in the YAML to carry a name:): the default
    names get _in/_out, and names: names them (with _in/_out added)."""
    eds = mini_eds(tpdo_map="0x62000008")          # the file's TPDO1 maps 0x6200 too
    got, res = build(tmp_path, SLAVE, eds=eds)
    assert got == []
    assert names(res) == [("io_6200_0_in", "input", "0x6200sub0"),
                          ("io_6200_0_out", "output", "0x6200sub0")]
    got, res = build(tmp_path, SLAVE + "  names: {0x6200: lamp}\n", eds=eds)
    assert got == []
    assert names(res) == [("lamp_in", "input", "0x6200sub0"),
                          ("lamp_out", "output", "0x6200sub0")]


def test_names_key_forms(tmp_path):
    body = SLAVE + ('  names:\n    0x6000: level\n    "0x6200sub0": horn\n')
    got, res = build(tmp_path, body)
    assert got == []
    assert names(res) == [("level", "input", "0x6000sub0"), ("horn", "output", "0x6200sub0")]


@pytest.mark.parametrize("entry,expected", [
    ('    "6200x": a\n',
     "bus.yml:9: error: names: '6200x' is not an object (an index 0x0000..0xFFFF such as "
     '0x6040, or "0x6041sub0" with the sub-index in hex) [NET004]'),
    # the key as written, in hex (it said "names: '629145' is not an object")
    ('    0x99999: a\n',
     "bus.yml:9: error: names: 0x99999 is not an object (an index 0x0000..0xFFFF such as "
     '0x6040, or "0x6041sub0" with the sub-index in hex) [NET004]'),
    ('    true: a\n',
     "bus.yml:9: error: names: true is not an object (an index 0x0000..0xFFFF such as "
     '0x6040, or "0x6041sub0" with the sub-index in hex) [NET004]'),
    ("    0x6200: [a]\n",
     "bus.yml:9: error: names: 0x6200sub0: expected a text, found a list [NET004]"),
    ("    0x6200: 1st\n",
     "bus.yml:9: error: name '1st' is not an IEC 61131-3 identifier (letters, digits and "
     "single '_', not a keyword) [NET106]"),
    ("    0x6200: a\n    0x6200sub0: b\n",
     "bus.yml:10: error: names: 0x6200sub0 is named twice (first at line 9) [NET002]"),
    ("    0x6001: a\n",
     "bus.yml:9: warning: names: 0x6001sub0 of io is mapped by no PDO linked with the master: "
     "the name is not used [NET123]"),
    ("    0x6200: io_6000_0\n",
     "bus.yml:9: error: name 'io_6000_0' is given to two objects (also at mini.eds:198) "
     "[NET107]"),
])
@pytest.mark.parametrize("master", ["plc", "lely"])
def test_names_findings(tmp_path, entry, expected, master):
    """The same findings with and without a master dcf: (D-17, D-21): a lely master's
    variables are show's rows and dbc's signals, named by the same rules."""
    got, _ = build_as(tmp_path, master, SLAVE + "  names:\n" + entry)
    assert got == [expected]


# a lely master (no dcf:), its keys on as many lines as HEAD's, so that lines agree
LELY_HEAD = "master:\n  node_id: 1\n  # a lely master: no dcf\n  heartbeat_producer: 100\n"


def build_as(tmp_path, master: str, body: str):
    """``build`` of test_network_build with a PLC master (HEAD) or a lely master."""
    got, res = build(tmp_path, body)
    if master == "plc":
        return got, res
    (tmp_path / "bus.yml").write_text(LELY_HEAD + body)
    from dcf2bin.network import build_network
    res = build_network(str(tmp_path / "bus.yml"))
    assert res.network.master.device is None          # (the lely kind was built)
    return [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
            if not d.rule.startswith("NET2")], res


@pytest.mark.parametrize("master", ["plc", "lely"])
def test_a_mapping_name_and_names_disagree(tmp_path, master):
    body = SLAVE + ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x6000, name: level}\n"
                    "  names: {0x6000: height}\n")
    got, _ = build_as(tmp_path, master, body)
    assert got == ["bus.yml:12: error: 0x6000sub0 of io is named 'height' here and 'level' "
                   "at line 11 [NET107]"]


@pytest.mark.parametrize("master", ["plc", "lely"])
def test_a_mapping_name_is_checked(tmp_path, master):
    """A mapping entry's name: is an IEC identifier, and one name is one object, for a
    lely master too (a lely build wrote 0 errors and show listed a variable 'bad name')."""
    body = SLAVE + ('  tpdo:\n    1:\n      mapping:\n        - {index: 0x6000, name: "bad name"}\n'
                    "  rpdo:\n    1:\n      mapping:\n        - {index: 0x6200, name: horn}\n"
                    "  names: {0x6000: level}\n")
    got, res = build_as(tmp_path, master, body)
    assert got == [
        "bus.yml:11: error: name 'bad name' is not an IEC 61131-3 identifier (letters, digits "
        "and single '_', not a keyword) [NET106]",
        "bus.yml:16: error: 0x6000sub0 of io is named 'level' here and 'bad name' at line 11 "
        "[NET107]"]
    assert res.outputs == {}


def test_no_false_net224_when_the_plc_cannot_place_its_variables(tmp_path):
    """Two slaves mapping the same object, and a naming error that stops placement: the
    PLC mirrors then still name the slaves' own objects, and NET224 said "master RPDO2
    maps 0x6000sub0, as RPDO1 does" for objects of different slaves."""
    body = (SLAVE + "  tpdo:\n    1:\n      mapping:\n        - {index: 0x6000, name: 1st}\n"
            "io2:\n  dcf: mini.eds\n  node_id: 6\n")
    got, res = build(tmp_path, body)
    from dcf2bin.network.check import run_rules
    assert [d.rule for d in run_rules(res.network)
            if d.rule == "NET224"] == []
    assert got == ["bus.yml:11: error: name '1st' is not an IEC 61131-3 identifier (letters, "
                   "digits and single '_', not a keyword) [NET106]"]


@pytest.mark.parametrize("empty", ["", " []", " null"])
def test_an_empty_mapping_is_a_finding(tmp_path, empty):
    """mapping: empty wrote an enabled TPDO with no object, which disappeared from show and
    from the PLC without a word."""
    got, res = build(tmp_path, SLAVE + f"  tpdo:\n    1:\n      mapping:{empty}\n")
    assert got == ["bus.yml:10: warning: io TPDO1: mapping: is empty, so the PDO is enabled "
                   "with no object: it exists on the device but not in the network, and "
                   "nothing links it (map an object, or write enabled: false) [NET121]"]
    got, res = build(tmp_path, SLAVE + f"  tpdo:\n    1:\n      enabled: false\n"
                     f"      mapping:{empty}\n")
    assert got == []


def test_one_object_twice_in_one_pdo(tmp_path):
    body = SLAVE + ("  rpdo:\n    1:\n      mapping:\n        - {index: 0x6200}\n"
                    "        - {index: 0x6200, sub_index: 0}\n")
    got, res = build(tmp_path, body)
    assert got == ["bus.yml:12: warning: io RPDO1 maps 0x6200sub0 twice (also at line 11): "
                   "it writes it twice from every frame, the later value last [NET122]"]
    body = SLAVE + ("  rpdo:\n    1:\n      mapping:\n        - {index: 0x0005}\n"
                    "        - {index: 0x0005}\n")
    got, res = build(tmp_path, body)                 # a dummy entry only skips bits
    assert got == []


def heartbeat_eds(master_entry: str = "0x000100C8") -> str:
    """mini.eds whose 0x1016 sub 1 monitors node 1 (the master) for 200 ms."""
    return mini_eds().replace("DefaultValue=0x00070064", f"DefaultValue={master_entry}")


def test_a_slave_not_monitoring_the_master_gets_its_entry_cleared(tmp_path):
    """Issue 27: a slave whose heartbeat_consumer is false kept its file's 0x1016 entry
    that watches the master (dcfgen clears it; a slave watching a master that sends no
    heartbeat faults). As dcfgen: the sub that names the master with a nonzero time is
    written as (master node-ID << 16), time 0."""
    got, res = build(tmp_path, SLAVE, eds=heartbeat_eds())
    assert got == []
    io = res.network.node(5)
    assert [(w.index, w.sub, w.value, w.why) for w in io.writes if w.index == 0x1016] == [
        (0x1016, 1, 0x00010000, "consumer heartbeat time: stops monitoring the master "
         "(node 1; heartbeat_consumer is false)")]
    assert io.heartbeat_consumers[0].node_id == 8          # sub 2 still monitors node 8
    assert res.outputs["io.bin"][-11:] == bytes.fromhex("1610" "01" "04000000" "00000100")


def test_a_master_without_heartbeat_is_not_monitored(tmp_path):
    """heartbeat_consumer: true, but the master produces no heartbeat: NET116, and the
    file's entry for the master is cleared (dcfgen's rule: a master heartbeat of 0)."""
    build(tmp_path, SLAVE, eds=heartbeat_eds())
    (tmp_path / "bus.yml").write_text("master:\n  node_id: 1\n  dcf: plc.dcf\n" + SLAVE
                                      + "  heartbeat_consumer: true\n")
    from dcf2bin.network import build_network
    res = build_network(str(tmp_path / "bus.yml"))
    assert [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
            if d.rule == "NET116"] == [
        "bus.yml:7: warning: io is to monitor the master, but the master produces no "
        "heartbeat (heartbeat_producer 0): nothing written [NET116]"]
    io = res.network.node(5)
    assert [(w.sub, w.value, w.why) for w in io.writes if w.index == 0x1016] == [
        (1, 0x00010000, "consumer heartbeat time: stops monitoring the master (node 1; the "
         "master produces no heartbeat)")]


def test_a_slave_monitoring_the_master_keeps_its_sub(tmp_path):
    got, res = build(tmp_path, SLAVE + "  heartbeat_consumer: true\n", eds=heartbeat_eds())
    io = res.network.node(5)
    assert [(w.sub, w.value) for w in io.writes if w.index == 0x1016] == [
        (1, 0x0001012C)]        # the sub that names the master: 100 ms x 3.0
