"""The LSS master (dcf2bin/bus/lss.py) and the software LSS slave (bus/lss_slave.py) on
python-can's virtual bus: several software nodes on one channel, each on a network of its
own, as separate devices are. Identities: samples/device.eds is 0xAB, 8, 0x00010002 (its
[DeviceInfo]); IoX4_8AI.eds 63, 3001003, 0x01390538 (its 0x1018)."""
from __future__ import annotations

import time

import pytest
from lss_helpers import AI, AI_ID, DRIVE_ID, Frames, drive_eds, lss_node, plain_node

from dcf2bin.bus import lss as L

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

IO8 = (0xAB, 8, 0x00010002)


def master(bench, **kw):
    return L.Master(bench.network(), **kw)


# -- answers that end the wait ----------------------------------------------------------------

def test_selective_switch_inquire_configure_and_reset(bench):
    node = lss_node(bench, 0x1001, node_id=7)
    m = master(bench, timeout=5)
    boot = Frames(m.net, 0x709)
    start = time.monotonic()
    assert m.select(L.Identity(*IO8, 0x1001))
    assert m.inquire_node_id() == 7
    assert [m.inquire(k) for k in range(4)] == [*IO8, 0x1001]
    assert m.configure_node_id(9) == L.Reply(L.CONFIGURE_NODE_ID, 0, 0)
    assert m.store() == L.Reply(L.STORE, 0, 0)
    # every answer ended its wait: far below one 5 s timeout for the eight of them
    assert time.monotonic() - start < 2.5
    assert (node.id, node.lss.pending, node.lss.stored) == (7, 9, 9)
    m.switch_global(configuration=False)
    m.net.send_message(0, bytes([0x82, 7]))            # NMT reset communication, node 7
    assert boot.wait(1) == [(0x709, b"\x00")]
    assert node.id == 9
    assert bench.sdo(9).upload(0x1018, 4) == (0x1001).to_bytes(4, "little")
    assert bench.sdo(9).upload(0x1018, 2) == (8).to_bytes(4, "little")   # from [DeviceInfo]


def test_selective_switch_of_another_identity_is_silence(bench):
    lss_node(bench, 0x1001, node_id=7)
    m = master(bench, timeout=0.2)
    assert not m.select(L.Identity(*IO8, 0x1002))
    assert m.inquire_node_id() is None                 # nobody is in configuration


def test_a_node_without_a_node_id_answers_lss_only_until_it_has_one(bench):
    node = lss_node(bench, 0x77, path=AI)
    m = master(bench, timeout=2)
    frames = Frames(m.net, 0x701, 0x705, 0x581)
    assert m.non_configured() == 1
    assert m.select(L.Identity(*AI_ID, 0x77))
    assert m.inquire_node_id() == 0xFF
    assert m.configure_node_id(5).ok
    assert frames.got == []                            # no boot-up, no heartbeat, no SDO
    m.switch_global(configuration=False)               # it takes node-ID 5 and boots
    assert frames.wait(1) == [(0x705, b"\x00")]
    assert bench.sdo(5).upload(0x1018, 4) == (0x77).to_bytes(4, "little")
    assert m.non_configured() == 0
    assert node.lss.stored == 0xFF                     # not stored: it was not asked to


def test_the_predefined_cob_ids_follow_the_new_node_id(bench):
    lss_node(bench, 0x77)                              # device.eds, $NODEID resolved with 1
    m = master(bench, timeout=2)
    assert m.select(L.Identity(*IO8, 0x77)) and m.configure_node_id(12).ok
    boot = Frames(m.net, 0x70C)
    m.switch_global(configuration=False)
    boot.wait(1)
    sdo = bench.sdo(12)
    assert sdo.upload(0x1800, 1)[:2] == (0x18C).to_bytes(2, "little")


NODE_ID_VALUE = """
[5F00]
ParameterName=A manufacturer's node-ID based value
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=$NODEID+0x100
"""


def _u32(sdo, index: int, sub: int) -> int:
    return int.from_bytes(sdo.upload(index, sub), "little")


def test_a_new_node_id_works_out_every_nodeid_value_and_keeps_the_configuration(
        bench, tmp_path):
    """At the reset communication that takes node-ID 9 (CiA 301): each value the EDS
    states as a $NODEID formula is worked out with 9, whatever its object (0x1200 and a
    manufacturer's 0x5F00 too: no list of the predefined connection set); a value written
    by SDO and stored ("save", 0x1010) comes back as written, one not stored is gone with
    the reset of the communication area; "load" (0x1011) forgets what was stored."""
    eds = drive_eds(tmp_path, NODE_ID_VALUE)
    lss_node(bench, 0x55, path=eds, node_id=3)
    with bench.sdo(3) as ch:
        ch.download(0x1014, 0, (0xF3).to_bytes(4, "little"))      # EMCY moved by hand
        ch.download(0x1010, 1, b"save")
        ch.download(0x1017, 0, (250).to_bytes(2, "little"))       # after the save
        assert [_u32(ch, 0x1014, 0), _u32(ch, 0x1017, 0), _u32(ch, 0x1200, 1),
                _u32(ch, 0x5F00, 0)] == [0xF3, 250, 0x603, 0x103]
    m = master(bench, timeout=2)
    assert m.select(L.Identity(*DRIVE_ID, 0x55)) and m.configure_node_id(9).ok
    assert m.store().ok
    m.switch_global(configuration=False)
    boot = Frames(m.net, 0x709)
    m.net.send_message(0, bytes([0x82, 3]))            # NMT reset communication, node 3
    assert boot.wait(1) == [(0x709, b"\x00")]
    with bench.sdo(9) as ch:
        assert [_u32(ch, index, sub) for index, sub in (
            (0x1200, 1), (0x1200, 2), (0x1400, 1), (0x1803, 1), (0x5F00, 0), (0x1014, 0),
            (0x1017, 0))] == [0x609, 0x589, 0x209, 0x80000489, 0x109, 0xF3, 0]
        ch.download(0x1011, 1, b"load")
    boot = Frames(m.net, 0x709)
    m.net.send_message(0, bytes([0x82, 9]))
    assert boot.wait(1) == [(0x709, b"\x00")]
    with bench.sdo(9) as ch:
        assert _u32(ch, 0x1014, 0) == 0x89                  # the file's, at node-ID 9


def test_a_nodeid_value_that_does_not_fit_at_the_new_node_id_has_no_value(tmp_path):
    """Never truncated: $NODEID+0x81 in an UNSIGNED8 is 0x84 at node-ID 3, and no value at
    127 (SDO then answers 0x060A0023), which the node says."""
    from dcf2bin.bus.node import from_file
    eds = drive_eds(tmp_path, NODE_ID_VALUE.replace("0x0006", "0x0005").replace(
        "0x100", "0x81"))
    node, errors = from_file(eds, 3)
    said = []
    node.on_event = said.append
    var = node.object_dictionary.get_variable(0x5F00)
    assert (errors, var.default) == ([], 0x84)
    node.take_node_id(127)
    assert var.default is None
    assert said == ["0x5F00 sub 0: '$NODEID+0x81' is no UNSIGNED8 at node-ID 127: no value"]
    node.take_node_id(5)
    assert var.default == 0x86


def test_refusals_carry_their_error_code(bench):
    lss_node(bench, 1, node_id=3, store_error=2)
    m = master(bench)
    assert m.select(L.Identity(*IO8, 1))
    reply = m.configure_node_id(0)
    assert (reply.ok, reply.text()) == (
        False, "configure node-ID: LSS error 1 (node-ID out of range)")
    assert m.configure_bit_timing(250_000).ok
    assert m.store().text() == "store configuration: LSS error 2 (storage media access error)"
    assert L.Reply(L.STORE, 255, 7).text() == (
        "store configuration: LSS error 255 (manufacturer-specific error 7)")
    assert L.Reply(L.CONFIGURE_BIT_TIMING, 9).text() == (
        "configure bit timing: LSS error 9 (an error code CiA 305 reserves)")


def test_bit_timing_is_kept_for_the_next_start(bench):
    node = lss_node(bench, 1, node_id=3)
    m = master(bench)
    assert m.select(L.Identity(*IO8, 1))
    assert m.configure_bit_timing(125_000).ok and m.store().ok
    assert (node.lss.timing, node.lss.stored_timing) == (4, 4)


def test_a_late_duplicate_is_not_the_next_answer(bench):
    """The slave sends every answer again 20 ms later: the second 0x5A arrives while the
    master waits for 0x5B, and is not taken for it (canopen's LssMaster takes the first
    frame of its queue and fails with "Response message is not for the request")."""
    lss_node(bench, 0x1001, node_id=7, twice=0.02)
    m = master(bench)
    assert m.select(L.Identity(*IO8, 0x1001))
    assert [m.inquire(k) for k in range(4)] == [*IO8, 0x1001]
    assert m.inquire_node_id() == 7


def test_a_node_that_does_not_answer_lss(bench):
    plain_node(bench, 4)
    m = master(bench, timeout=0.1, wait=0.02)
    assert m.non_configured() == 0
    assert not m.select(L.Identity(*IO8, 0))
    assert m.identify(0xAB, 8) == 0


def test_frames_and_steps():
    assert L.frame(L.FASTSCAN, 0x12345678, 31, 0, 1) == bytes.fromhex("5178563412 1F0001")
    assert L.frame(L.SWITCH_GLOBAL, None, 1) == bytes.fromhex("0401000000000000")
    assert L.fastscan_steps({}) == 133
    assert L.fastscan_steps({0: 1, 1: 2, 2: 3}) == 37
    assert L.fastscan_steps({0: 1, 1: 2, 3: 4}, frozenset({2})) == 4
    assert L.Identity(1, 2, 3, 4).text() == (
        "vendor-ID 0x00000001, product code 0x00000002, revision 0x00000003, "
        "serial 0x00000004")
