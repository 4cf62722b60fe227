"""Issue 26 item 4: a network file that repeats one thing 100,000 times costs what its size
costs, and says so in a few lines.

* a key near a known one is found by a few dict lookups (``yamlkeys.near_miss``), not by
  difflib against every known key (1.2 ms a key: 30,000 unknown keys took 39 s);
* the same mistake is reported five times per rule and file, then counted in one finding
  (``diagnostics.Summarised``), in every output format; a finding shared by the nodes
  through ``defaults:`` is reported once;
* the work has a bound: 250,000 expanded nodes, ``defaults:`` counted once per node.

The time itself is measured by benchmarks/hostile_shapes.py, not asserted here.
"""
from __future__ import annotations

import json

import pytest
from click.testing import CliRunner

from dcf2bin.cli import main
from dcf2bin.diagnostics import Severity, Summarised, Where
from dcf2bin.network import load_network
from dcf2bin.network.yamlkeys import MAP_KEYS, PDO_KEYS, SLAVE_KEYS, near_miss
from dcf2bin.network.yamltree import MAX_NODES


def found(net, tmp_path) -> list[str]:
    return [d.format().replace(str(tmp_path) + "/", "") for d in net.diagnostics]


# -- near misses ---------------------------------------------------------------------------------

@pytest.mark.parametrize("key,known,expected", [
    ("heartbeat_prodcuer", SLAVE_KEYS, "heartbeat_producer"),     # two swapped
    ("hearbeat_produer", SLAVE_KEYS, "heartbeat_producer"),       # two left out
    ("revison_number", SLAVE_KEYS, "revision_number"),            # one left out
    ("node_idd", SLAVE_KEYS, "node_id"),                          # one added
    ("node_ix", SLAVE_KEYS, "node_id"),                           # one replaced
    ("Node-ID", SLAVE_KEYS, "node_id"),                           # case, '-' for '_'
    ("cobid", PDO_KEYS, "cob_id"),
    ("mappings", PDO_KEYS, "mapping"),
    ("subindex", MAP_KEYS, "sub_index"),
    ("indx", MAP_KEYS, "index"),
    ("polling", SLAVE_KEYS, None),
    ("colour", SLAVE_KEYS, None),
    ("heartbeat_producer_1", SLAVE_KEYS, None),                   # three added
    ("no", SLAVE_KEYS, None),                                     # too short to guess
    ("x" * 100_000, SLAVE_KEYS, None),
])
def test_near_miss(key, known, expected):
    assert near_miss(key, known) == expected


# -- the same mistake, many times -------------------------------------------------------------

def test_summarised_keeps_five_of_a_rule_then_counts():
    diags = Summarised()
    for i in range(100_000):
        diags.info(f"key 'k{i}' is not used", Where("bus.yml", i + 3), rule="NET007")
        if i < 7:
            diags.error(f"bad {i}", Where("bus.yml", i + 3), rule="NET004")
    diags.error("a finding without a rule is never counted away", Where("bus.yml", 1))
    assert [d.format() for d in diags] == [
        "bus.yml:3: info: key 'k0' is not used [NET007]",
        "bus.yml:3: error: bad 0 [NET004]",
        "bus.yml:4: info: key 'k1' is not used [NET007]",
        "bus.yml:4: error: bad 1 [NET004]",
        "bus.yml:5: info: key 'k2' is not used [NET007]",
        "bus.yml:5: error: bad 2 [NET004]",
        "bus.yml:6: info: key 'k3' is not used [NET007]",
        "bus.yml:6: error: bad 3 [NET004]",
        "bus.yml:7: info: key 'k4' is not used [NET007]",
        "bus.yml:7: error: bad 4 [NET004]",
        "bus.yml:8: info: ... and 99,995 more NET007 findings like this [NET007]",
        "bus.yml:8: error: ... and 2 more NET004 findings like this [NET004]",
        "bus.yml:1: error: a finding without a rule is never counted away"]
    assert diags.has_errors and len(diags.errors) == 7


def test_summarised_keeps_a_repeated_finding_once_and_counts_per_file_and_severity():
    diags = Summarised(limit=1)
    for _ in range(3):
        diags.warning("the same", Where("a.yml", 2), rule="NET009")
    diags.warning("another", Where("a.yml", 3), rule="NET009")
    diags.warning("another file", Where("b.yml", 3), rule="NET009")
    diags.error("an error of that rule", Where("a.yml", 4), rule="NET009")
    assert [d.format() for d in diags] == [
        "a.yml:2: warning: the same [NET009]",
        "a.yml:3: warning: another [NET009]",       # one left out is shown as it is
        "b.yml:3: warning: another file [NET009]",
        "a.yml:4: error: an error of that rule [NET009]"]
    assert [d.severity for d in diags] == [Severity.WARNING] * 3 + [Severity.ERROR]


BUS = "master:\n  node_id: 1\nio:\n  dcf: io.eds\n  node_id: 5\n"


def test_a_network_file_reports_a_repeated_mistake_five_times(tmp_path):
    p = tmp_path / "bus.yml"
    p.write_text(BUS + "".join(f"  unknown_{i}: 1\n" for i in range(1000))
                 + "".join(f"  node_idd{'d' * i}: 1\n" for i in range(3)))
    net = load_network(str(p))
    assert found(net, tmp_path) == [
        *(f"bus.yml:{6 + i}: info: key 'unknown_{i}' is not used by dcf2bin; ignored "
          "[NET007]" for i in range(5)),
        # (node_iddd and node_idddd are two and three edits from node_id)
        "bus.yml:11: info: ... and 997 more NET007 findings like this [NET007]",
        "bus.yml:1006: warning: unknown key 'node_idd': did you mean 'node_id'? [NET006]"]


def test_defaults_finding_is_reported_once_not_once_per_node(tmp_path):
    p = tmp_path / "bus.yml"
    p.write_text("master:\n  node_id: 1\ndefaults:\n  dcf: io.eds\n  colour: blue\nnodes:\n"
                 + "".join(f"  s{n}: {{node_id: {n}}}\n" for n in range(2, 128)))
    net = load_network(str(p))
    assert found(net, tmp_path) == [
        "bus.yml:5: info: key 'colour' is not used by dcf2bin; ignored [NET007]"]


@pytest.mark.parametrize("fmt", ["json", "sarif"])
def test_check_json_and_sarif_say_the_count(tmp_path, fmt):
    p = tmp_path / "bus.yml"
    p.write_text("master:\n  node_id: 1\n  heartbeat_producer: x\n"
                 + "".join(f"  unknown_{i}: 1\n" for i in range(100)))
    r = CliRunner().invoke(main, ["network", "check", "--format", fmt, str(p)])
    assert r.exit_code == 1, r.output
    doc = json.loads(r.output)
    if fmt == "json":
        messages = [(d["rule"], d["line"], d["message"]) for d in doc["diagnostics"]]
    else:
        messages = [(x["ruleId"], x["locations"][0]["physicalLocation"]["region"]["startLine"],
                     x["message"]["text"]) for x in doc["runs"][0]["results"]]
    assert ("NET007", 9, "... and 95 more NET007 findings like this") in messages
    assert len([m for m in messages if m[0] == "NET007"]) == 6


# -- a bound on the work -------------------------------------------------------------------------

def test_defaults_merged_into_every_node_count_towards_the_bound(tmp_path):
    p = tmp_path / "bus.yml"
    items = MAX_NODES // 126 // 7 + 1           # an sdo item is 7 nodes
    p.write_text("master:\n  node_id: 1\ndefaults:\n  dcf: io.eds\n  sdo:\n"
                 + "    - {index: 0x2000, sub_index: 0, value: 1}\n" * items + "nodes:\n"
                 + "".join(f"  s{n}: {{node_id: {n}}}\n" for n in range(2, 128)))
    net = load_network(str(p))
    size = 1 + 2 + 2 + 7 * items           # the mapping, dcf: and its value, sdo: and its list
    assert found(net, tmp_path) == [
        f"bus.yml:3: error: the network expands to more than 250,000 nodes: its defaults: "
        f"({size:,}) are merged into each of its 126 nodes [NET003]"]
    assert net.slaves == []


def test_a_cpj_of_more_than_100_000_lines_is_not_read(tmp_path):
    from dcf2bin.network.cpj import MAX_LINES, read
    p = tmp_path / "net.cpj"
    p.write_text("[Topology]\nNetName=n\n" + "".join(f"Key{k}=1\n" for k in range(MAX_LINES)))
    net = read(str(p))
    assert found(net, tmp_path) == [
        "net.cpj:100001: error: the project has 100,003 lines, more than 100,000 (a network "
        "of 127 nodes takes about 520): not read [NET050]"]


def test_slaves_after_the_first_1024_are_not_read(tmp_path):
    p = tmp_path / "bus.yml"
    p.write_text("master:\n  node_id: 1\n" + "".join(
        f"s{k}:\n  node_id: {k % 126 + 2}\n  dcf: io.eds\n" for k in range(1100)))
    net = load_network(str(p))
    assert len(net.slaves) == 1024
    assert [m for m in found(net, tmp_path) if "NET004" in m] == [
        "bus.yml:3075: error: 1,100 slaves, but a CANopen network has 127 node-IDs: those "
        "after the first 1,024 are not read [NET004]"]
