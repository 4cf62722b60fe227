"""network scan and network download on python-can's virtual bus, against canopen
LocalNodes made from samples/device.eds (device type 0x000F0191, vendor-ID 0xAB, no
0x1018 sub 2...4), with networks built by hand from the model (network_helpers)."""
from __future__ import annotations

import pytest
from bus_helpers import VIRTUAL
from network_helpers import network

from dcf2bin.bus import netconf
from dcf2bin.bus import scan as sc
from dcf2bin.network.model import Write

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

DEVICE_TYPE, VENDOR = 0x000F0191, 0xAB


def expected_of(net) -> list[sc.Expected]:
    return [sc.Expected(n.node_id, n.name, dict(n.identity), master=n.role == "master")
            for n in net.nodes]


# -- scan -----------------------------------------------------------------------------------

def test_scan_finds_missing_unexpected_and_wrong_vendor(bench):
    # the network: plc 16, io1 2, io2 3, io3 4; on the bus: 2 right, 3 with another vendor
    # (its file says 0xAB, the network 0xAC), 4 absent, 9 not in the network
    net = network(3)
    for n in net.slaves:
        n.identity = {0x1F84: DEVICE_TYPE, 0x1F85: VENDOR}
    net.node(3).identity[0x1F85] = 0xAC
    for nid in (2, 3, 9):
        bench.device(nid)
    result = sc.scan(bench.network(), listen=0.1, timeout=0.5)
    assert sorted(result.found) == [2, 3, 9]
    assert result.found[2].device_type == DEVICE_TYPE
    assert result.found[2].value(0x1018, 1) == VENDOR
    assert result.found[2].entries[(0x1018, 2)].code == 0x06090011   # no such sub-index
    findings = sc.compare(result, expected_of(net))
    assert [(f.kind, f.node_id) for f in findings] == [
        ("mismatch", 3), ("missing", 4), ("unexpected", 9)]
    assert findings[0].text == ("node 3 (io2): 0x1018 sub 1 (vendor-ID) is 0x000000AB, the "
                                "master expects 0x000000AC (0x1F85): it will not boot this node")
    assert (findings[0].expected, findings[0].actual, findings[0].entry) == (0xAC, 0xAB,
                                                                            (0x1018, 1))
    assert findings[1].text == "node 4 (io3) is in the network but does not answer"
    assert findings[2].text == ("node 9 answers but is not in the network, device type "
                                "0x000F0191")


def test_scan_master_is_never_missing_and_a_missing_sub_is_unread(bench):
    net = network(1)
    net.node(2).identity = {0x1F84: DEVICE_TYPE, 0x1F85: VENDOR, 0x1F86: 0x1234}
    bench.device(2)
    findings = sc.compare(sc.scan(bench.network(), listen=0, timeout=0.5), expected_of(net))
    assert [(f.kind, f.node_id, f.code) for f in findings] == [("unread", 2, 0x06090011)]
    assert findings[0].text.startswith(
        "node 2 (io1): 0x1018 sub 2 (product code) cannot be read: SDO abort 0x06090011: ")
    assert findings[0].text.endswith("; the master expects 0x00001234 (0x1F86)")


def test_scan_hears_a_node_that_boots_and_a_silent_one():
    found = {5: sc.Found(5, heard="operational")}
    findings = sc.compare(sc.Scan(found, 0.1), [sc.Expected(5, "io5", {0x1F85: 1})])
    assert [f.kind for f in findings] == ["silent"]
    assert findings[0].text == ("node 5 (io5) is heard (operational) but does not answer SDO "
                                "requests: its identity cannot be read")


def test_scan_worst_case_bound():
    assert sc.worst_case() == pytest.approx(1.7)
    assert sc.worst_case(0.5, 0.3, 1) == pytest.approx(0.6 + 4 * 0.6)
    assert sc.worst_case(2.0, 0.1, 0) == pytest.approx(2.4)


def test_scan_of_an_empty_bus_asks_once_and_reads_no_identity(bench, monkeypatch):
    # how long it takes is measured in benchmarks/network_scan.py; here: one round of 127
    # requests and, with nobody answering, no identity round
    rounds = []
    real = sc._Round.run

    def counted(self, timeout, retries):
        rounds.append((self.index, self.sub, len(self.ids)))
        return real(self, timeout, retries)
    monkeypatch.setattr(sc._Round, "run", counted)
    result = sc.scan(bench.network(), listen=0.05, timeout=0.1)
    assert result.found == {}
    assert rounds == [(0x1000, 0, 127)]


def test_scan_reads_the_identity_of_answering_nodes_only(bench, monkeypatch):
    rounds = []
    real = sc._Round.run

    def counted(self, timeout, retries):
        rounds.append((self.index, self.sub, self.ids))
        return real(self, timeout, retries)
    monkeypatch.setattr(sc._Round, "run", counted)
    bench.device(7)
    sc.scan(bench.network(), listen=0, timeout=0.5)
    assert rounds == [(0x1000, 0, list(range(1, 128)))] + [(0x1018, k, [7]) for k in (1, 2, 3, 4)]


# -- download -------------------------------------------------------------------------------

def _slaves(bench, net, ids=(2, 3)):
    nodes = {}
    for nid in ids:
        nodes[nid] = bench.device(nid)
    for n in net.slaves:
        n.identity = {0x1F84: DEVICE_TYPE, 0x1F85: VENDOR}
    return nodes


def test_download_configures_each_slave_in_node_id_order(bench):
    net = network(2)
    nodes = _slaves(bench, net)
    seen = []
    outcomes = netconf.configure_slaves(
        bench.network(), net, netconf.Options(timeout=2, retries=0, verify=True),
        source="bus.yml", progress=lambda o: seen.append((o.node_id, o.status)))
    assert seen == [(2, "configured"), (3, "configured")]
    assert [(o.written, o.total, o.verified, o.saved) for o in outcomes] == [
        (4, 4, True, False), (4, 4, True, False)]
    assert nodes[2].sdo[0x1800][1].raw == 0x182
    assert nodes[3].sdo[0x1800][1].raw == 0x183
    assert nodes[3].sdo[0x1017].raw == 100


def test_download_identity_mismatch_writes_nothing_to_that_node(bench):
    net = network(2)
    nodes = _slaves(bench, net)
    net.node(2).identity[0x1F85] = 0xAC
    writes = []
    nodes[2].add_write_callback(lambda **kw: writes.append(kw))
    outcomes = netconf.configure_slaves(bench.network(), net,
                                        netconf.Options(timeout=2, retries=0, keep_going=True),
                                        source="bus.yml")
    assert [o.status for o in outcomes] == ["failed", "configured"]
    assert writes == []
    assert [(p.message, p.where) for p in outcomes[0].problems] == [
        ("0x1018 sub 1 (vendor-ID) is 0x000000AB, the master expects 0x000000AC (0x1F85): "
         "nothing written", "bus.yml:10")]


def _aborting(net):
    """io1's second write goes to 0x1000 (read-only): the node aborts it."""
    io1 = net.node(2)
    io1.writes.insert(1, Write(0x1000, 0, 0x07, 1, b"\1\0\0\0", "Device type", "sdo",
                               io1.writes[0].where.__class__("bus.yml", 99)))


def test_download_abort_stops_everything_without_keep_going(bench):
    net = network(2)
    nodes = _slaves(bench, net)
    _aborting(net)
    writes = {2: [], 3: []}
    for nid in (2, 3):
        nodes[nid].add_write_callback(lambda index, subindex, od, data, nid=nid:
                                      writes[nid].append((index, subindex)))
    outcomes = netconf.configure_slaves(bench.network(), net,
                                        netconf.Options(timeout=2, retries=0),
                                        source="bus.yml")
    assert [o.status for o in outcomes] == ["failed", "skipped"]
    assert writes == {2: [(0x1800, 1)], 3: []}
    a = outcomes[0].aborts[0]
    assert (a.code, a.write.label, a.write.where) == (0x06010002, "0x1000sub0", "bus.yml:99")
    assert [p.message for p in outcomes[0].problems] == [
        "0x1000sub0 Device type (sdo): SDO abort 0x06010002: Attempt to write a read only "
        "object; 1 of 5 entries written before it"]


def test_download_keep_going_goes_on_after_an_abort(bench):
    net = network(2)
    nodes = _slaves(bench, net)
    _aborting(net)
    outcomes = netconf.configure_slaves(bench.network(), net,
                                        netconf.Options(timeout=2, retries=0, keep_going=True),
                                        source="bus.yml")
    assert [(o.status, o.written) for o in outcomes] == [("failed", 4), ("configured", 4)]
    assert nodes[2].sdo[0x1017].raw == 100           # io1: the writes after the abort too
    assert nodes[3].sdo[0x1800][1].raw == 0x183


def test_download_save_that_the_node_refuses_is_a_failure(bench):
    net = network(1)
    _slaves(bench, net, ids=(2,))
    outcomes = netconf.configure_slaves(bench.network(), net,
                                        netconf.Options(timeout=2, retries=0, save=True),
                                        source="bus.yml")
    # samples/device.eds has no 0x1010
    assert (outcomes[0].status, outcomes[0].written, outcomes[0].saved) == ("failed", 4, False)
    assert [(p.message, p.where) for p in outcomes[0].problems] == [
        ("storing the parameters: SDO abort 0x06020000: Object does not exist", "bus.yml:10")]


def test_download_a_silent_node_fails(bench):
    net = network(1)
    outcomes = netconf.configure_slaves(bench.network(), net,
                                        netconf.Options(timeout=0.05, retries=0),
                                        source="bus.yml")
    assert outcomes[0].status == "failed"
    assert outcomes[0].problems[0].message == (
        f"0x1000sub0: node 2 did not answer (no SDO response within 0.05 s, 1 try{VIRTUAL})")
