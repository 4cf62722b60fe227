"""`network show -f dbc` (issue 27 item 5): a network's PDOs as a CAN database.

The goldens in tests/fixtures/network_dbc/ are cantools' text, reviewed by hand against
the networks (`network show` of the same file lists the same COB-IDs, producers,
consumers, bytes and variables):

* show_bus.dbc -- tests/fixtures/network_show/bus.yml, the small golden network (PLC);
* lely_flat.dbc -- tests/fixtures/network/lely/flat.yml (a lely master, EDS PDOs);
* plc.dbc, lely.dbc -- network_dbc/plc.yml and lely.yml on sensor.eds: REAL32, REAL64,
  signed and BOOLEAN objects, dummy entries as gaps, an object mapped both ways, a
  29-bit COB-ID, event timers, a slave that listens to another slave.

The decoding test runs the network's slaves as software nodes on python-can's virtual
bus, configures them as `network download` does, sets objects, and decodes the frames
they send with the database cantools loads back from the file."""
from __future__ import annotations

import ast
import struct
import subprocess
import sys
import time

import pytest
from bus_helpers import run

from conftest import ROOT
from dcf2bin.network import dbc
from dcf2bin.network.check import ERRORS, examine

pytest_plugins = ["bus_fixtures"]


@pytest.fixture
def cantools():
    """cantools, which the test extra installs (the dbc extra); without it the tests that
    read a database skip, saying so, and the tests of its absence still run."""
    return pytest.importorskip("cantools", reason="cantools not installed (pip install "
                               "'.[dbc]' or '.[test]')")

HERE = ROOT / "tests" / "fixtures"
DBC = HERE / "network_dbc"
GOLDEN = {"show_bus.dbc": HERE / "network_show" / "bus.yml",
          "lely_flat.dbc": HERE / "network" / "lely" / "flat.yml",
          "plc.dbc": DBC / "plc.yml",
          "lely.dbc": DBC / "lely.yml"}


def network_of(path):
    res = examine(str(path), lint=ERRORS)
    assert not [d for d in res.diagnostics if d.severity.value == "error"]
    return res.network


# -- the file -------------------------------------------------------------------------------

@pytest.mark.parametrize("golden", sorted(GOLDEN))
def test_golden_dbc(golden, tmp_path, cantools):
    """The exact bytes, through the command (-o) and the library alike."""
    out = tmp_path / golden
    r = run("network", "show", str(GOLDEN[golden]), "-f", "dbc", "-o", str(out))
    assert r.exit_code == 0, r.stderr
    want = (DBC / golden).read_bytes()
    assert out.read_bytes() == want
    assert dbc.dump(network_of(GOLDEN[golden])) == want
    assert want.startswith(b'VERSION ""\r\n') and b"\n" not in want.replace(b"\r\n", b"")


def test_standard_output_is_the_same_bytes(cantools):
    r = run("network", "show", str(DBC / "plc.yml"), "-f", "dbc")
    assert r.exit_code == 0 and r.stderr == ""
    assert r.stdout_bytes == (DBC / "plc.dbc").read_bytes()


def test_cantools_reads_it_back(cantools):
    db = cantools.database.load_file(str(DBC / "plc.dbc"))       # strict: no overlap
    assert [(m.frame_id, m.name, m.length, m.is_extended_frame, m.senders, m.cycle_time)
            for m in db.messages] == [
        (0x185, "sensor_TPDO1", 8, False, ["sensor"], None),
        (0x205, "plc_TPDO1", 8, False, ["plc"], 50),
        (0x03AB0C05, "sensor_TPDO2", 6, True, ["sensor"], 100)]
    sig = {(m.name, s.name): (s.start, s.length, s.byte_order, s.is_signed, s.is_float,
                              s.receivers) for m in db.messages for s in m.signals}
    assert sig == {
        ("sensor_TPDO1", "temperature"): (0, 32, "little_endian", True, True, ["plc"]),
        ("sensor_TPDO1", "torque"): (32, 16, "little_endian", True, False, ["plc"]),
        ("sensor_TPDO1", "sensor_2003_0"): (48, 8, "little_endian", False, False, ["plc"]),
        ("sensor_TPDO1", "ready"): (56, 1, "little_endian", False, False, ["plc"]),
        # bit 57 is the dummy BOOLEAN: a gap (the DLC counts it)
        ("plc_TPDO1", "sensor_2004_0_out"): (0, 32, "little_endian", True, False,
                                             ["sensor"]),
        ("plc_TPDO1", "gain"): (32, 32, "little_endian", True, True, ["sensor"]),
        # bits 32-39 are the dummy UNSIGNED8
        ("sensor_TPDO2", "sensor_2004_0_in"): (0, 32, "little_endian", True, False,
                                               ["plc", "display"]),
        ("sensor_TPDO2", "sensor_2006_0"): (40, 8, "little_endian", True, False,
                                            ["plc", "display"])}
    assert [n.name for n in db.nodes] == ["plc", "sensor", "display"]
    assert db.buses[0].baudrate == 250000
    tpdo2 = db.get_message_by_name("sensor_TPDO2")
    assert tpdo2.comment == ("sensor TPDO2 (node-ID 5), COB-ID 0x03AB0C05, transmission type "
                             "255, event timer 100 ms; received by plc RPDO2, display RPDO1")
    assert tpdo2.get_signal_by_name("sensor_2004_0_in").comment == (
        "sensor: Setpoint (0x2004sub0, INTEGER32)")


def test_a_lely_master_names_signals_as_variables_and_takes_real64(cantools):
    db = cantools.database.load_file(str(DBC / "lely.dbc"))
    m = db.get_message_by_name("sensor_TPDO3")
    s = m.signals[0]
    assert (m.frame_id, m.length, s.name, s.length, s.is_float, s.comment) == (
        0x385, 8, "sensor_2007_0", 64, True, "sensor: Energy (0x2007sub0, REAL64)")
    assert db.buses[0].baudrate == 1_000_000          # the master's baudrate: 1000 (kbit/s)
    assert [n.name for n in db.nodes] == ["master", "sensor", "display"]


def test_no_bitrate_in_the_file_no_baudrate_in_the_database(cantools):
    """500 kbit/s is what the load estimate assumes, not a fact to write."""
    assert b"Baudrate" not in (DBC / "show_bus.dbc").read_bytes()
    db = cantools.database.load_file(str(DBC / "show_bus.dbc"))
    assert db.buses == [] or db.buses[0].baudrate is None


LONG = "temperature_of_the_second_sensor_in_kelvin"


def test_names_are_dbc_identifiers_unique_in_their_message(tmp_path, cantools):
    """Node names a YAML key may hold and DBC may not, one object twice in one PDO, a
    character cp1252 lacks, a name over DBC's 32 characters."""
    eds = (DBC / "sensor.eds").as_posix()
    path = tmp_path / "odd.yml"
    path.write_text(f"""master: {{node_id: 1}}
1st-sensor:
  dcf: {eds}
  node_id: 5
  tpdo:
    1:
      mapping:
        - {{index: 0x2001, name: "t\u2082 torque"}}
        - {{index: 0x2001}}
1st sensor:
  dcf: {eds}
  node_id: 6
  tpdo:
    1:
      mapping: [{{index: 0x2003}}, {{index: 0x2000, name: {LONG}}}]
Düse₂:
  dcf: {eds}
  node_id: 7
  tpdo:
    1:
      mapping: [{{index: 0x2003}}]
""", encoding="utf-8")
    res = examine(str(path), lint=ERRORS)
    # the object twice; a name: that is no IEC identifier is an error for a lely master
    # too (D-17, D-21), and dbc still makes a DBC identifier of what it is given
    assert [(d.rule, d.line) for d in res.diagnostics] == [("NET122", 9), ("NET106", 8)]
    data = dbc.dump(res.network)
    db = cantools.database.load_string(data.decode("cp1252"), "dbc")
    assert [n.name for n in db.nodes] == ["master", "_1st_sensor", "_1st_sensor_2", "D_se_"]
    assert [(m.name, m.senders, [s.name for s in m.signals]) for m in db.messages] == [
        ("_1st_sensor_TPDO1", ["_1st_sensor"], ["t__torque", "t__torque_2"]),
        ("_1st_sensor_2_TPDO1", ["_1st_sensor_2"], ["_1st_sensor_2003_0", LONG]),
        ("D_se__TPDO1", ["D_se_"], ["D_se_2003_0"])]
    assert b'CM_ BU_ _1st_sensor "node-ID 5";' in data
    # over 32 characters: cut, with the whole name beside it (Vector's long names)
    assert (b' SG_ ' + LONG[:32].encode() + b' : 8|32@1- ' in data
            and b'BA_ "SystemSignalLongSymbol" SG_ 390 ' + LONG[:32].encode() + b' "'
            + LONG.encode() + b'";' in data)
    # the comments keep the node's name: cp1252 has the u-umlaut (0xFC), not the
    # subscript two, written as '?'
    assert (b'CM_ BO_ 391 "D\xfcse? TPDO1 (node-ID 7), COB-ID 0x187, transmission type '
            b'255; received by master RPDO3";') in data


def test_deterministic(cantools):
    net = network_of(DBC / "plc.yml")
    assert dbc.dump(net) == dbc.dump(network_of(DBC / "plc.yml"))


def test_show_names_an_object_mapped_both_ways_for_each_direction():
    """The text's content column and the DBC take names from one place (show.carried):
    the TPDO carries the input variable, the PLC's TPDO the output."""
    r = run("network", "show", str(DBC / "plc.yml"))
    rows = [line for line in r.stdout.splitlines() if "TPDO" in line]
    assert rows[1].startswith("0x205       TPDO1      plc TPDO1     sensor RPDO1")
    assert rows[1].endswith("  sensor_2004_0_out, gain")
    assert rows[2].startswith("0x03AB0C05  TPDO2      sensor TPDO2  plc RPDO2, display RPDO1")
    assert rows[2].endswith("  sensor_2004_0_in, dummy 8 bits, sensor_2006_0")


# -- cantools is optional -------------------------------------------------------------------

MISSING = ("dcf2bin: error: dcf2bin network show -f dbc needs cantools: pip install "
           "cantools (or, from a checkout, pip install '.[dbc]')\n")


def test_without_cantools_one_line_and_exit_2(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "cantools", None)        # import cantools fails
    out = tmp_path / "n.dbc"
    r = run("network", "show", str(DBC / "plc.yml"), "-f", "dbc", "-o", str(out))
    assert (r.exit_code, r.stdout, r.stderr) == (2, "", MISSING)
    assert not out.exists()
    # said before the network is read: a network that does not exist changes nothing
    r = run("network", "show", str(tmp_path / "none.yml"), "-f", "dbc")
    assert (r.exit_code, r.stderr) == (2, MISSING)
    # the other formats do not need it
    assert run("network", "show", str(DBC / "plc.yml")).exit_code == 0


def test_help_does_not_import_cantools():
    code = ("import sys; from dcf2bin.cli import main\n"
            "for args in (['--help'], ['network', 'show', '--help']):\n"
            "    try:\n        main(args)\n    except SystemExit:\n        pass\n"
            "print(repr(sorted(m for m in sys.modules if m.startswith('cantools'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    assert ast.literal_eval(out.stdout.strip().splitlines()[-1]) == []


# -- a slave's frames on the virtual bus, decoded ------------------------------------------

def frames(bus, ids: set[int], timeout: float = 2.0) -> dict:
    """The first frame of each CAN-ID in ``ids`` (until all came or ``timeout``)."""
    got, end = {}, time.monotonic() + timeout
    while set(got) != ids and time.monotonic() < end:
        msg = bus.recv(0.05)
        if msg is not None and msg.arbitration_id in ids and msg.arbitration_id not in got:
            got[msg.arbitration_id] = msg
    return got


def configured_slaves(bench, network, files):
    from dcf2bin.bus import netconf
    nodes = {nid: bench.device(nid, path) for nid, path in files.items()}
    outcomes = netconf.configure_slaves(bench.network(), network,
                                        netconf.Options(timeout=2, retries=0),
                                        source=network.path)
    assert [o.status for o in outcomes] == ["configured"] * len(files)
    return nodes


def listening(bench):
    import can
    return can.Bus(interface="virtual", channel=bench.channel)


def test_a_slave_frame_decodes_into_the_values_set(bench, tmp_path, cantools):
    out = tmp_path / "plc.dbc"
    assert run("network", "show", str(DBC / "plc.yml"), "-f", "dbc", "-o",
               str(out)).exit_code == 0
    db = cantools.database.load_file(str(out))
    eds = str(DBC / "sensor.eds")
    nodes = configured_slaves(bench, network_of(DBC / "plc.yml"), {5: eds, 6: eds})
    sensor = nodes[5]
    sensor.set_data(0x2000, 0, struct.pack("<f", -12.25))     # REAL32
    sensor.set_data(0x2001, 0, struct.pack("<h", -1234))      # INTEGER16
    sensor.set_data(0x2002, 0, b"\x01")                       # BOOLEAN
    sensor.set_data(0x2003, 0, b"\xA5")                       # UNSIGNED8
    sensor.set_data(0x2004, 0, struct.pack("<i", -100000))    # INTEGER32
    sensor.set_data(0x2006, 0, struct.pack("<b", -7))         # INTEGER8
    bus = listening(bench)
    try:
        net = bench.network()
        net.send_message(0x000, [0x01, 0])       # NMT start all: TPDO2 (event timer) sends
        net.send_message(0x080, [])              # SYNC: TPDO1 (type 1) sends
        got = frames(bus, {0x185, 0x03AB0C05})
    finally:
        bus.shutdown()
    assert sorted(got) == [0x185, 0x03AB0C05]
    tpdo1, tpdo2 = got[0x185], got[0x03AB0C05]
    assert (tpdo1.is_extended_id, tpdo2.is_extended_id) == (False, True)
    assert (len(tpdo1.data), len(tpdo2.data)) == (8, 6)          # the messages' DLCs
    assert db.decode_message(tpdo1.arbitration_id, bytes(tpdo1.data)) == {
        "temperature": -12.25, "torque": -1234, "ready": 1, "sensor_2003_0": 0xA5}
    assert db.decode_message(tpdo2.arbitration_id, bytes(tpdo2.data)) == {
        "sensor_2004_0_in": -100000, "sensor_2006_0": -7}


def test_a_lely_networks_real64_frame_decodes(bench, cantools):
    db = cantools.database.load_file(str(DBC / "lely.dbc"))
    eds = str(DBC / "sensor.eds")
    nodes = configured_slaves(bench, network_of(DBC / "lely.yml"), {5: eds, 6: eds})
    nodes[5].set_data(0x2007, 0, struct.pack("<d", 1234.5678))    # REAL64
    bus = listening(bench)
    try:
        net = bench.network()
        net.send_message(0x000, [0x01, 5])
        for _ in range(10):                      # TPDO3: transmission type 10
            net.send_message(0x080, [])
        got = frames(bus, {0x385})
    finally:
        bus.shutdown()
    frame = got[0x385]
    assert db.decode_message(frame.arbitration_id, bytes(frame.data)) == {
        "sensor_2007_0": 1234.5678}


def test_an_rpdo_that_nobody_sends_is_a_message_without_sender(cantools):
    """(A .cpj project, or a master that could not take the link.) Here: plc.yml with the
    PLC's TPDOs taken away, so sensor's RPDO1 (0x205) listens to nobody: its objects are
    no variables, named by their mapping's name: or by the default rule."""
    net = network_of(DBC / "plc.yml")
    net.master.pdos = [p for p in net.master.pdos if p.kind != "tpdo"]
    net.node(5).pdo("rpdo", 1).mirrored_by = None
    data = dbc.dump(net)
    db = cantools.database.load_string(data.decode("cp1252"), "dbc")
    m = db.get_message_by_frame_id(0x205)
    assert (m.name, m.senders, m.length, [(s.name, s.receivers) for s in m.signals]) == (
        "sensor_RPDO1", [], 8, [("sensor_2004_0", ["sensor"]), ("gain", ["sensor"])])
    assert m.comment == ("sensor RPDO1 (node-ID 5), COB-ID 0x205: no node of the network "
                         "sends it")
    assert b"BO_ 517 sensor_RPDO1: 8 Vector__XXX\r\n" in data
