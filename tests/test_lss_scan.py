"""LSS where silence is the answer: fastscan (confirming the parts known, scanning the
rest, several nodes answering one step, a node answering twice), the census of the nodes
without a node-ID (lss scan) and identify remote slave halving the unknown ranges -- on
python-can's virtual bus with software LSS slaves (identities as in tests/test_lss.py)."""
from __future__ import annotations

import pytest
from lss_helpers import AI, AI_ID, lss_node, plain_node

from dcf2bin.bus import lss as L

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

IO8 = (0xAB, 8, 0x00010002)


def master(bench, **kw):
    return L.Master(bench.network(), **kw)


def test_fastscan_confirms_what_is_known_and_scans_the_rest(bench):
    """Three nodes answer every step they all match; the lowest serial is found, with the
    default wait, in 1 + 3 + 33 steps; it stays in configuration, out of the next scan."""
    for serial in (0x1003, 0x1001, 0x1002):
        lss_node(bench, serial)
    m = master(bench)
    assert m.wait == 0.05
    known = dict(enumerate(IO8))
    assert m.fastscan(known) == (True, {**known, 3: 0x1001})
    assert m.steps == 37
    assert m.inquire(3) == 0x1001                      # the one node in configuration
    assert m.matches(known) is True                    # two more match what is known
    assert m.steps == 41
    assert m.matches({**known, 3: 0x1001}) is False    # not the one in configuration


def test_fastscan_leaves_out_an_unknown_revision(bench):
    lss_node(bench, 0x1001)
    lss_node(bench, 0x55, path=AI)
    m = master(bench, wait=0.02)
    assert m.fastscan({0: 0x3F, 1: 0x2DCAAB, 3: 0x55}, frozenset({2})) == (
        True, {0: 0x3F, 1: 0x2DCAAB, 3: 0x55})
    assert m.steps == 4
    assert m.inquire(2) == AI_ID[2]


def test_fastscan_of_parts_nobody_has(bench):
    lss_node(bench, 0x1001)
    m = master(bench, wait=0.02)
    assert m.fastscan({0: 0xAB, 1: 9}) == (True, None)
    assert m.steps == 3                                # reset, vendor-ID, product code


def test_fastscan_passes_by_nodes_with_a_node_id(bench):
    lss_node(bench, 0x1001, node_id=4)
    m = master(bench, wait=0.02)
    assert m.fastscan() == (False, None)
    assert m.matches({0: 0xAB}) is False


def test_a_late_duplicate_within_the_wait_is_counted_once(bench):
    """Two nodes, one of them answering every step twice: the scan is the same."""
    lss_node(bench, 0x1002, twice=0.005)
    lss_node(bench, 0x1001)
    m = master(bench, wait=0.03)
    known = dict(enumerate(IO8))
    assert m.fastscan(known) == (True, {**known, 3: 0x1001})
    assert m.matches(known) is True                    # the second one


def test_census_lists_every_node_without_a_node_id(bench):
    lss_node(bench, 0x1002)
    lss_node(bench, 0x66, path=AI)
    lss_node(bench, 0x1001, node_id=9)                 # has a node-ID: not listed
    m = master(bench, wait=0.02)
    census = L.unconfigured(m)
    assert census == L.Census([L.Identity(*AI_ID, 0x66), L.Identity(*IO8, 0x1002)], 3, True)
    assert m.steps == 2 * 133 + 1 + 2                  # two full scans, the last reset, checks
    assert L.census_bound(3, 0.02) == pytest.approx(3 * 134 * 0.02)


def test_a_node_slower_than_the_wait_is_not_seen(bench):
    lss_node(bench, 0x1001, delay=0.04)
    m = master(bench, wait=0.02)
    assert L.unconfigured(m) == L.Census([], 1, True)


def test_identify_remote_slave_halves_the_unknown_ranges(bench):
    """Two nodes that share the factory node-ID 1: SDO cannot tell them apart, identify
    remote slave can."""
    lss_node(bench, 0x2002, node_id=1)
    lss_node(bench, 0x2001, node_id=1)
    plain_node(bench, 2, path=AI)
    m = master(bench, wait=0.02)
    assert m.identify(0xAB, 8) == 2
    assert m.identify(0xAB, 8, serials=(0x2002, 0x2002)) == 1
    assert m.identify(0xAB, 8, revisions=(0, 0x10001)) == 0
    assert m.search(0xAB, 8, revisions=(IO8[2], IO8[2]), limit=5) == [
        (IO8[2], 0x2001), (IO8[2], 0x2002)]
    before = m.steps
    assert m.search(0xAB, 8, revisions=(IO8[2], IO8[2]), serials=(0x2002, 0x2002)) == [
        (IO8[2], 0x2002)]
    assert m.steps - before == 2                       # the revision, then the serial
    assert m.search(0x3F, 0x2DCAAB) == []              # no LSS there


