"""network build (SPEC §10.2 D-17, §10.3 D-18): the golden networks byte for byte, the
hand-checked values, the built PLC compiling and simulating to 0x00, the concise DCFs
replayed, and one exact diagnostic per NET1xx code a user can cause."""
from __future__ import annotations

import json
import shutil

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin import model
from dcf2bin.api import compile_path
from dcf2bin.cli import main
from dcf2bin.network import build_network, configure, load_network
from dcf2bin.network.concise import read_concise
from dcf2bin.network.variables import default_name

FIXTURES = ROOT / "tests" / "fixtures" / "network"
GOLDEN = ROOT / "tests" / "golden" / "network"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


# -- the golden networks -----------------------------------------------------------------

@pytest.mark.parametrize("name", ["flat", "nodes"])
def test_golden_network_byte_for_byte(tmp_path, name):
    out = tmp_path / "out"
    r = run("network", "build", GOLDEN / name / "bus.yml", "-o", out, "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    expected = sorted(p.name for p in (GOLDEN / name / "out").iterdir())
    # and the folder's lock, which names the files the build wrote (tests/test_build_atomic.py)
    assert sorted(p.name for p in out.iterdir()) == [".dcf2bin-build.lock"] + expected
    for fname in expected:
        assert (out / fname).read_bytes() == (GOLDEN / name / "out" / fname).read_bytes(), fname


def _plc_values(path) -> dict[tuple[int, int], str]:
    dev = model.load(str(path))
    return {(e.index, e.sub): e.param for o in dev.objects.values()
            for e in o.entries.values() if e.param is not None}


def test_flat_golden_hand_checked_values():
    """tests/golden/network/README.md: each value worked out by hand from D-17."""
    v = _plc_values(GOLDEN / "flat" / "out" / "plc.dcf")
    assert v[(0x1F81, 2)] == "0x0000030D"   # 0x01 | boot 0x04 | mandatory 0x08 | 3 << 8
    assert v[(0x1F81, 5)] == "0x00000305"   # not mandatory
    assert v[(0x1016, 1)] == "0x00020096"   # node 2, 50 ms x 3.0 = 150 ms
    assert v[(0x1016, 2)] == "0x00050258"   # node 5, 200 ms x 3.0 = 600 ms
    assert (0x1F85, 5) not in v              # vendor_id: 0 turns the check off
    assert v[(0x1F86, 5)] == "0x002DCAAB"   # ProductNumber 3001003
    assert v[(0x1F80, 0)] == "0x00000003"   # 0x01 | start_all_nodes 0x02
    assert v[(0x1005, 0)] == "0x40000080"   # SYNC producer, the file's CAN-ID 0x80
    assert v[(0x1006, 0)] == "0x00002710"   # 10000 us
    assert v[(0x1400, 1)] == "0x00000182"   # mirrors the drive's TPDO1 (file COB-ID kept)
    assert v[(0x1600, 1)] == "0xA1000110"   # drive_status: 0xA100 sub 1, 16 bits
    assert v[(0x1600, 2)] == "0xA1C00220"   # drive_position: 0xA1C0 sub 2 (offset 4)


def test_nodes_golden_hand_checked_values():
    net = configure(load_network(str(GOLDEN / "nodes" / "bus.yml")))
    rtt1 = net.node(3)
    assert rtt1.pdo("tpdo", 5).cob_id == 0x182     # above PDO 4: lowest free, not 0x181
    assert rtt1.pdo("tpdo", 1).cob_id == 0x40000183
    v = _plc_values(GOLDEN / "nodes" / "out" / "master.dcf")
    assert v[(0x1016, 1)] == "0x0003012C"
    assert v[(0x1016, 2)] == "0x0004012C"
    assert v[(0x1400, 1)] == "0x40000183"   # bits 29-30 copied
    assert v[(0x1401, 1)] == "0x00000182"
    # each slave monitors the master: (1 << 16) | 200 ms x 3.0, in its first free sub
    assert [(w.index, w.sub, w.value) for w in rtt1.writes if w.index == 0x1016] == [
        (0x1016, 1, 0x00010258)]
    names = {(v.node_id, v.index): v.name for v in net.variables}
    assert names[(3, 0x2101)] == "rtt1_counter"
    assert names[(3, 0x2100)] == "rtt1_2100_0"


@pytest.mark.parametrize("name", ["flat", "nodes"])
def test_built_plc_compiles_and_simulates_to_0x00(name):
    plc = next(p for p in (GOLDEN / name / "out").iterdir()
               if p.suffix == ".dcf" and p.stem in ("plc", "master"))
    res = compile_path(str(plc))
    assert res.ok, [d.format() for d in res.diagnostics]
    r = run("simulate", plc, "-f", "json")
    assert r.exit_code == 0, r.output
    doc = json.loads(r.stdout)
    assert (doc["code"], doc["name"]) == ("0x00", "kCopSuccessful")


def test_concise_dcf_replays_the_write_list():
    res = build_network(str(GOLDEN / "flat" / "bus.yml"))
    assert res.ok
    drive = res.network.node(2)
    replay = read_concise(res.outputs["drive.bin"])
    assert replay == [(w.index, w.sub, w.data) for w in drive.writes]
    # D-18's order, worked out by hand for the drive of flat/bus.yml
    assert [(i, s, int.from_bytes(d, "little")) for i, s, d in replay] == [
        (0x1400, 1, 0x80000202), (0x1400, 2, 1),
        (0x1600, 0, 0), (0x1600, 1, 0x60400010), (0x1600, 2, 0x607A0020), (0x1600, 0, 2),
        (0x1400, 1, 0x202),
        (0x1401, 1, 0x80000302), (0x1402, 1, 0x80000402), (0x1403, 1, 0x80000502),
        (0x1800, 1, 0x80000182), (0x1800, 2, 1),
        (0x1A00, 0, 0), (0x1A00, 1, 0x60410010), (0x1A00, 2, 0x60640020), (0x1A00, 0, 2),
        (0x1800, 1, 0x182),
        (0x1801, 1, 0x80000282), (0x1802, 1, 0x80000382), (0x1803, 1, 0x80000482),
        (0x1017, 0, 50), (0x6060, 0, 8)]


def test_concise_dcf_is_the_index_segment_of_the_schema():
    from dcf2bin.container import BinContainer
    from dcf2bin.network.concise import concise_dcf
    net = configure(load_network(str(GOLDEN / "nodes" / "bus.yml")))
    for s in net.slaves:
        assert concise_dcf(s) == BinContainer(
            entries=[(w.index, w.sub, w.data) for w in s.writes]).index_bytes()


def test_slave_dcf_states_the_last_write_of_each_entry():
    res = build_network(str(GOLDEN / "flat" / "bus.yml"))
    drive = res.network.node(2)
    v = _plc_values(GOLDEN / "flat" / "out" / "drive.dcf")
    dev = model.load(str(GOLDEN / "flat" / "out" / "drive.dcf"))
    assert dev.node_id == 2
    last = {(w.index, w.sub): w for w in drive.writes}
    assert set(v) == set(last)
    for key, w in last.items():
        assert dev.effective_int(dev.entry(*key)) == w.value, key


def test_built_outputs_keep_every_other_line():
    """The PLC file's lines all stay, in order (only values and new lines are added)."""
    base = (FIXTURES / "plc.dcf").read_text().splitlines()
    built = (GOLDEN / "flat" / "out" / "plc.dcf").read_text().splitlines()
    it = iter(built)
    for line in base:
        if line == "NodeID=1" or line.startswith("SupportedObjects="):
            continue
        assert any(line == b for b in it), line


# -- the command line --------------------------------------------------------------------

def test_verbose_lists_links_and_variables(tmp_path):
    r = run("network", "build", GOLDEN / "flat" / "bus.yml", "-o", tmp_path, "-v")
    assert r.exit_code == 0
    lines = r.stderr.splitlines()
    assert "link RPDO1 COB-ID 0x182: drive TPDO1, 48 bits" in lines
    assert ("variable drive_status: 0xA100sub1, UNSIGNED16 input offset 0, from drive "
            "0x6041sub0") in lines
    assert lines[-1] == (f"network build: 5 files in {tmp_path}: plc.dcf and 2 slaves "
                         "for a PLC master, 4 links, 12 variables")


def test_plc_master_without_dcf_cannot_build(tmp_path):
    """--master plc asks for the PLC's file; without --master the file builds a lely
    master (tests/test_network_lely.py)."""
    r = run("network", "build", FIXTURES / "ros2_simple_bus.yml", "-o", tmp_path / "o", "-q",
            "--master", "plc")
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{FIXTURES}/ros2_simple_bus.yml:6: error: build needs the PLC's EDS or DCF: give "
        "it as 'dcf:' under 'master:' [NET119]",
        "network build: 1 error, nothing written"]
    assert not (tmp_path / "o").exists()


def test_unreadable_network_file_exit_3(tmp_path):
    r = run("network", "build", tmp_path / "none.yml", "-o", tmp_path / "o")
    assert r.exit_code == 3
    assert "none.yml: error: cannot read: No such file or directory" in r.stderr


def test_output_that_is_a_file_exit_3(tmp_path):
    (tmp_path / "f").write_text("x")
    r = run("network", "build", GOLDEN / "flat" / "bus.yml", "-o", tmp_path / "f")
    assert r.exit_code == 3


def test_an_output_never_overwrites_an_input(tmp_path):
    """A slave named like its own file, built into the file's folder, would overwrite
    it: refused (exit 2), the input unchanged."""
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    shutil.copy(FIXTURES / "IoX4_8AI.eds", tmp_path / "io.dcf")
    (tmp_path / "bus.yml").write_text(
        "master:\n  node_id: 1\n  dcf: plc.dcf\nio:\n  dcf: io.dcf\n  node_id: 5\n")
    before = (tmp_path / "io.dcf").read_bytes()
    r = run("network", "build", tmp_path / "bus.yml", "-o", tmp_path)
    assert r.exit_code == 2
    assert (tmp_path / "io.dcf").read_bytes() == before


# -- one exact diagnostic per code -------------------------------------------------------

HEAD = "master:\n  node_id: 1\n  dcf: plc.dcf\n  heartbeat_producer: 100\n"


def mini_eds(extra: str = "", vendor: str = "0x42", tpdo_map: str = "0x60000008",
             n_mapped: int = 1) -> str:
    """A small slave EDS: TPDO1/RPDO1, 0x1016 with two subs, and a few objects."""
    def var(sec, name, dtype, access, default, pdo=0):
        return (f"[{sec}]\nParameterName={name}\nObjectType=0x7\nDataType={dtype}\n"
                f"AccessType={access}\nDefaultValue={default}\nPDOMapping={pdo}\n\n")
    text = (f"[FileInfo]\nFileName=mini.eds\nEDSVersion=4.0\n\n[DeviceInfo]\n"
            f"VendorNumber={vendor}\nProductNumber=0x7\nNrOfRXPDO=1\nNrOfTXPDO=1\n\n"
            + var("1000", "Device type", "0x0007", "ro", "0x00000191")
            + var("1001", "Error register", "0x0005", "ro", "0")
            + "[1016]\nParameterName=Consumer heartbeat time\nObjectType=0x8\nSubNumber=3\n\n"
            + var("1016sub0", "n", "0x0005", "ro", "2")
            + var("1016sub1", "c1", "0x0007", "rw", "0x00070064")
            + var("1016sub2", "c2", "0x0007", "rw", "0x00080064")
            + var("1017", "Producer heartbeat time", "0x0006", "rw", "0")
            + "[1018]\nParameterName=Identity\nObjectType=0x9\nSubNumber=3\n\n"
            + var("1018sub0", "n", "0x0005", "ro", "2")
            + var("1018sub1", "Vendor-ID", "0x0007", "ro", "0x42")
            + var("1018sub2", "Product code", "0x0007", "ro", "0x7")
            + "[1400]\nParameterName=RPDO1\nObjectType=0x9\nSubNumber=3\n\n"
            + var("1400sub0", "n", "0x0005", "ro", "2")
            + var("1400sub1", "COB-ID", "0x0007", "rw", "$NODEID+0x200")
            + var("1400sub2", "Transmission", "0x0005", "rw", "255")
            + "[1600]\nParameterName=RPDO1 map\nObjectType=0x9\nSubNumber=3\n\n"
            + var("1600sub0", "n", "0x0005", "rw", "1")
            + var("1600sub1", "m1", "0x0007", "rw", "0x62000008")
            + var("1600sub2", "m2", "0x0007", "rw", "0")
            + "[1800]\nParameterName=TPDO1\nObjectType=0x9\nSubNumber=3\n\n"
            + var("1800sub0", "n", "0x0005", "ro", "2")
            + var("1800sub1", "COB-ID", "0x0007", "rw", "$NODEID+0x180")
            + var("1800sub2", "Transmission", "0x0005", "rw", "255")
            + "[1A00]\nParameterName=TPDO1 map\nObjectType=0x9\nSubNumber=3\n\n"
            + var("1A00sub0", "n", "0x0005", "rw", str(n_mapped))
            + var("1A00sub1", "m1", "0x0007", "rw", tpdo_map)
            + var("1A00sub2", "m2", "0x0007", "rw", "0")
            + var("6000", "in", "0x0005", "ro", "0", 1)
            + var("6200", "out", "0x0005", "rw", "0", 1)
            + var("2000", "real64", "0x0011", "ro", "0", 1)
            + var("2001", "rww", "0x0006", "rww", "0", 1)
            + extra)
    return text


def build(tmp_path, body: str, eds: str | None = None, plc: str | None = None):
    (tmp_path / "mini.eds").write_text(eds if eds is not None else mini_eds())
    if plc is None:
        shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    else:
        (tmp_path / "plc.dcf").write_text(plc)
    (tmp_path / "bus.yml").write_text(HEAD + body)
    res = build_network(str(tmp_path / "bus.yml"))
    # this file tests D-16..D-18; the rules of the network as a whole (NET2xx, which build
    # runs too) have their tests in tests/test_network_rules.py and are left out here
    # (mini.eds's 0x1016 monitors nodes 7 and 8 on purpose, for the free-sub tests)
    return [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
            if not d.rule.startswith("NET2")], res


SLAVE = "io:\n  dcf: mini.eds\n  node_id: 5\n"


def test_the_mini_slave_builds_clean(tmp_path):
    got, res = build(tmp_path, SLAVE)
    assert got == [] and res.ok
    assert [v.name for v in res.network.variables] == ["io_6000_0", "io_6200_0"]


@pytest.mark.parametrize("body,expected", [
    ("  tpdo:\n    9:\n      enabled: true\n",
     "bus.yml:9: error: io has no TPDO9 (its file lacks 0x1808) [NET101]"),
    ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x5FFF, sub_index: 0}\n",
     "bus.yml:11: error: io's file has no 0x5FFFsub0 to map [NET102]"),
    ("  rpdo:\n    1:\n      mapping:\n        - {index: 0x6000, sub_index: 0}\n",
     "bus.yml:11: error: 0x6000sub0 of io is ro: an RPDO maps writable objects that are "
     "not rwr [NET103]"),
    ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x2001, sub_index: 0}\n",
     "bus.yml:11: error: 0x2001sub0 of io is rww: a TPDO maps readable objects that are "
     "not rww [NET103]"),
    ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x2000, sub_index: 0}\n",
     "bus.yml:11: error: 0x2000sub0 of io is REAL64: the PLC has no network-variable "
     "range (CiA 405) for that type [NET104]"),
    ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x6000, sub_index: 0, name: 1st}\n",
     "bus.yml:11: error: name '1st' is not an IEC 61131-3 identifier (letters, digits and "
     "single '_', not a keyword) [NET106]"),
    ("  heartbeat_producer: 30000\n",
     "bus.yml:8: error: io's heartbeat time 30000 ms x 3 = 90000 ms is over 65535 ms "
     "[NET112]"),
    ("  sdo:\n    - {index: 0x1000, sub_index: 0, value: 1}\n",
     "bus.yml:9: error: 0x1000sub0 of io is ro: it cannot be written [NET114]"),
    ("  sdo:\n    - {index: 0x6200, sub_index: 0, value: 256}\n",
     "bus.yml:9: error: value for 0x6200sub0 (UNSIGNED8): value 256 out of range for "
     "UNSIGNED8 (0..255) [NET117]"),
    ("  sdo:\n    - {index: 0x6200, sub_index: 0, value: true}\n",
     "bus.yml:9: error: value true for 0x6200sub0 (UNSIGNED8): a boolean is accepted only "
     "for a BOOLEAN entry [NET117]"),
    ("  heartbeat_consumer: true\n",
     "bus.yml:8: error: io has no free 0x1016 sub for monitoring the master (2 subs, all in "
     "use) [NET115]"),
])
def test_one_error_each(tmp_path, body, expected):
    got, res = build(tmp_path, SLAVE + body)
    assert got == [expected]
    assert not res.ok and res.outputs == {}


def test_two_names_for_one_object_and_one_name_for_two(tmp_path):
    body = ("  tpdo:\n    1:\n      mapping:\n        - {index: 0x6000, sub_index: 0, "
            "name: level}\n        - {index: 0x6000, sub_index: 0, name: level2}\n"
            "  rpdo:\n    1:\n      mapping:\n"
            "        - {index: 0x6200, sub_index: 0, name: LEVEL}\n")
    got, _ = build(tmp_path, SLAVE + body)
    assert got == [
        "bus.yml:12: warning: io TPDO1 maps 0x6000sub0 twice (also at line 11): it sends it "
        "twice in every frame [NET122]",
        "bus.yml:12: error: 0x6000sub0 of io is named 'level2' here and 'level' at line 11 "
        "[NET107]",
        "bus.yml:16: error: name 'LEVEL' is given to two objects (also at bus.yml:11) "
        "[NET107]"]


def test_zero_entry_in_a_kept_mapping(tmp_path):
    """D-17: a kept PDO whose mapping names a zero entry is neither mirrored nor counted:
    a warning when the YAML does not list that PDO (a vendor file keeps it; the network
    builds), an error when it does. Validate's DCF404 about the same entry is not said
    again (one cause, one finding)."""
    got, res = build(tmp_path, SLAVE, eds=mini_eds(n_mapped=2))
    assert got == ["mini.eds:206: warning: io TPDO1 maps a zero entry (sub 0 counts 2 "
                   "objects): the PDO is kept as the file has it, and nothing links it "
                   "[NET105]"]
    assert res.ok and "io.bin" in res.outputs
    assert [p.mirror_of.label for p in res.network.master.pdos if p.mirror_of] == ["RPDO1"]
    got, res = build(tmp_path, SLAVE + "  tpdo:\n    1:\n      transmission: 1\n",
                     eds=mini_eds(n_mapped=2))
    assert got == ["mini.eds:206: error: io TPDO1 maps a zero entry (sub 0 counts 2 "
                   "objects); the network file lists this PDO: give its mapping, or "
                   "disable it [NET105]"]
    assert not res.ok


def test_identity_differs_from_0x1018(tmp_path):
    got, res = build(tmp_path, SLAVE, eds=mini_eds(vendor="0x43"))
    assert got == ["mini.eds:6: warning: io: [DeviceInfo] VendorNumber is 0x43 but its "
                   "0x1018sub1 is 0x42; the master will expect 0x43 [NET113]"]
    assert res.ok


def test_plc_without_an_nmt_object_warns(tmp_path):
    got, res = build(tmp_path, SLAVE + "  software_version: 3\n")
    assert got == ["bus.yml:8: warning: the PLC's file has no 0x1F55: the PLC cannot do "
                   "the software version check (io's software version); not written "
                   "[NET110]"]
    assert res.ok


def test_master_heartbeat_zero_warns(tmp_path):
    (tmp_path / "mini.eds").write_text(mini_eds())
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    (tmp_path / "bus.yml").write_text("master:\n  node_id: 1\n  dcf: plc.dcf\n"
                                      + SLAVE + "  heartbeat_consumer: true\n")
    res = build_network(str(tmp_path / "bus.yml"))
    assert [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
            if not d.rule.startswith("NET2")] == [
        "bus.yml:7: warning: io is to monitor the master, but the master produces no "
        "heartbeat (heartbeat_producer 0): nothing written [NET116]"]


def test_more_links_than_plc_pdos(tmp_path):
    body = "".join(f"io{k}:\n  dcf: mini.eds\n  node_id: {10 + k}\n" for k in range(9))
    got, _ = build(tmp_path, body)
    assert got == [
        "mini.eds:169: error: the PLC has no free RPDO for io8 TPDO1 (8 RPDOs in its file, "
        "all in use; 1 more link than it can take) [NET108]",
        "mini.eds:111: error: the PLC has no free TPDO for io8 RPDO1 (8 TPDOs in its file, "
        "all in use; 1 more link than it can take) [NET108]"]


def test_a_plc_short_of_pdos_is_one_finding_per_kind(tmp_path):
    """Issue 27: one cause, one finding -- 12 links the PLC cannot take are one NET108 per
    kind, not one per link, and never also NET211/NET212 for the PDOs it leaves unlinked
    (a PLC lacking PDOs printed 36 errors from one cause)."""
    body = "".join(f"io{k}:\n  dcf: mini.eds\n  node_id: {10 + k}\n" for k in range(12))
    (tmp_path / "mini.eds").write_text(mini_eds())
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    (tmp_path / "bus.yml").write_text(HEAD + body)
    res = build_network(str(tmp_path / "bus.yml"))
    assert [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics] == [
        "mini.eds:169: error: the PLC has no free RPDO for io8 TPDO1, io9 TPDO1, io10 TPDO1, "
        "io11 TPDO1 (8 RPDOs in its file, all in use; 4 more links than it can take) "
        "[NET108]",
        "mini.eds:111: error: the PLC has no free TPDO for io8 RPDO1, io9 RPDO1, io10 RPDO1, "
        "io11 RPDO1 (8 TPDOs in its file, all in use; 4 more links than it can take) "
        "[NET108]"] + [
        f"mini.eds:{line}: warning: io{k} (node {10 + k}) monitors node {n}, which is not "
        "in the network [NET252]" for k in range(12) for line, n in ((45, 7), (53, 8))]


def test_plc_with_dynamic_channels_is_refused(tmp_path):
    plc = (FIXTURES / "plc.dcf").read_text() + (
        "\n[DynamicChannels]\nNrOfSeg=1\nType1=0x0005\nDir1=ro\nRange1=0xA000-0xA03F\n"
        "PPOffset1=0\n")
    got, _ = build(tmp_path, SLAVE, plc=plc)
    assert got[0].startswith("plc.dcf:")
    assert got[0].endswith("error: the DCF has a [DynamicChannels] section: its segments "
                           "fix the layout, so variables cannot be allocated by the CiA 405 "
                           "ranges [NET118]")


def test_output_names(tmp_path):
    got, _ = build(tmp_path, "io/x:\n  dcf: mini.eds\n  node_id: 5\n")
    assert got == ["bus.yml:5: error: node name 'io/x' cannot be an output file name "
                   "[NET120]"]


def test_cob_id_assignment_order_and_explicit_ids(tmp_path):
    """Slaves by node-ID, TPDOs before RPDOs; n <= 4 takes its predefined ID when free;
    explicit IDs kept; enabled: false never assigned."""
    body = ("a:\n  dcf: mini.eds\n  node_id: 7\n  tpdo:\n    1:\n      cob_id: 0x186\n"
            "b:\n  dcf: mini.eds\n  node_id: 6\n  tpdo:\n    1:\n      cob_id: auto\n"
            "  rpdo:\n    1:\n      enabled: false\n      cob_id: auto\n")
    got, res = build(tmp_path, body)
    assert got == []
    net = res.network
    assert net.node(7).pdo("tpdo", 1).cob_id == 0x186
    # node 6's predefined TPDO1 ID is taken by node 7: the lowest free outside every
    # present node's predefined set (nodes 1, 6, 7) is 0x182
    assert net.node(6).pdo("tpdo", 1).cob_id == 0x182
    assert net.node(6).pdo("rpdo", 1).cob_id == 0x80000206


def test_default_names():
    assert default_name("io1", 0x6000, 1) == "io1_6000_1"
    assert default_name("io1", 0x6411, 0xA) == "io1_6411_A"
    assert default_name("my-io.2", 0x2000, 0x10) == "my_io_2_2000_10"


def test_0x1f22_takes_each_slaves_concise_dcf(tmp_path):
    """When the PLC's file has 0x1F22, sub <node> = the slave's concise DCF (its .bin)."""
    plc = (FIXTURES / "plc.dcf").read_text().replace(
        "[1F80]", "[1F22]\nParameterName=Concise DCF\nObjectType=0x8\nDataType=0x000F\n"
        "AccessType=rw\nPDOMapping=0\nCompactSubObj=127\n\n[1F80]")
    got, res = build(tmp_path, SLAVE + "  heartbeat_producer: 100\n", plc=plc)
    assert got == [] and res.ok
    blob = res.outputs["io.bin"]
    # count 1; 0x1017 sub 0, 2 bytes, 100
    assert blob == bytes.fromhex("01000000" "1710" "00" "02000000" "6400")
    v = _plc_values_of(res.outputs["master.dcf"], tmp_path)
    assert v[(0x1F22, 5)] == blob.hex().upper()
    out = tmp_path / "master.dcf"
    out.write_bytes(res.outputs["master.dcf"])
    r = compile_path(str(out))
    assert r.ok, [d.format() for d in r.diagnostics]


def _plc_values_of(data: bytes, tmp_path) -> dict[tuple[int, int], str]:
    p = tmp_path / "values.dcf"
    p.write_bytes(data)
    return _plc_values(p)


def test_help_imports_no_yaml():
    """dcf2bin --help and network --help stay light: the subcommands load when run."""
    import subprocess
    import sys
    code = ("import sys\nfrom click.testing import CliRunner\nfrom dcf2bin.cli import main\n"
            "r = CliRunner().invoke(main, ['network', '--help'])\n"
            "print(r.exit_code, 'build' in r.output, sorted({m.split('.')[0] for m in "
            "sys.modules} & {'yaml', 'canopen', 'construct', 'can'}))\n")
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True)
    assert out.stdout == "0 True []\n"


def test_lely_master_without_dcf_mirrors_the_links_in_memory():
    """A ros2_canopen file: no PLC file, so no naming or placement; the master still
    mirrors every link (for network check) and the slaves get their write lists."""
    net = configure(load_network(str(FIXTURES / "ros2_cia402_bus.yml")))
    assert not net.diagnostics.has_errors
    mirrors = [p for p in net.master.pdos if p.mirror_of is not None]
    # per drive: TPDO1-2 configured, RPDO1-2 configured and RPDO3-4 kept from its file
    assert len(mirrors) == 3 * 6
    for m in mirrors:
        src = m.mirror_of
        assert m.cob_id == src.cob_id & 0x7FFFFFFF
        assert [(e.bits, e.datatype) for e in m.mapping] == \
            [(e.bits, e.datatype) for e in src.mapping]
    d1 = net.node(2)
    assert [w.index for w in d1.writes][-4:] == [0x60C2, 0x60C2, 0x6081, 0x6083]
    assert d1.identity == {0x1F84: 0x00060192, 0x1F85: 0x1A3}


def test_rpdo_inhibit_and_event_timer_go_to_the_plc_not_the_slave(tmp_path):
    body = SLAVE + "  rpdo:\n    1:\n      inhibit_time: 50\n      event_timer: 20\n"
    got, res = build(tmp_path, body)
    assert got == []
    tpdo = res.network.master.pdo("tpdo", 1)
    assert (tpdo.inhibit_time, tpdo.event_timer, tpdo.cob_id) == (50, 20, 0x205)
    v = _plc_values_of(res.outputs["master.dcf"], tmp_path)
    assert (v[(0x1800, 3)], v[(0x1800, 5)]) == ("0x0032", "0x0014")
    io = res.network.node(5)
    assert [(w.index, w.sub) for w in io.writes if w.index == 0x1400] == [
        (0x1400, 1), (0x1400, 1)]          # COB-ID invalid, then valid: nothing else


def test_master_heartbeat_consumer_false_and_explicit_times(tmp_path):
    got, res = build(tmp_path, SLAVE + "  heartbeat_producer: 100\n")
    assert [h.time_ms for h in res.network.master.heartbeat_consumers] == [300]
    (tmp_path / "bus.yml").write_text(
        HEAD + "  heartbeat_consumer: false\n" + SLAVE + "  heartbeat_producer: 100\n")
    res = build_network(str(tmp_path / "bus.yml"))
    assert res.ok and res.network.master.heartbeat_consumers == []
    assert not any(w.index == 0x1016 for w in res.network.master.writes)
    (tmp_path / "bus.yml").write_text(
        HEAD + "  heartbeat_consumer: {io: 450}\n" + SLAVE + "  heartbeat_producer: 100\n")
    res = build_network(str(tmp_path / "bus.yml"))
    assert [(w.sub, w.value) for w in res.network.master.writes if w.index == 0x1016] == [
        (1, (5 << 16) | 450)]


def test_nmt_entry_beyond_the_plc_objects_subs(tmp_path):
    plc = (FIXTURES / "plc.dcf").read_text().replace(
        "ParameterName=NMT slave assignment\nObjectType=0x8\nDataType=0x0007\n"
        "AccessType=rw\nDefaultValue=0\nPDOMapping=0\nCompactSubObj=127",
        "ParameterName=NMT slave assignment\nObjectType=0x8\nDataType=0x0007\n"
        "AccessType=rw\nDefaultValue=0\nPDOMapping=0\nCompactSubObj=3")
    got, res = build(tmp_path, SLAVE, plc=plc)
    assert got == ["bus.yml:5: error: the PLC's file has no 0x1F81sub5 (slave assignment of "
                   "io): that sub-index is missing [NET111]"]


def test_heartbeat_times_are_rounded_down_from_the_decimal_multiplier():
    """D-16: every time multiplied by the multiplier is rounded down to whole ms — of the
    decimal product the YAML states (100 ms x 0.29 is 29 ms, though 100 * 0.29 is
    28.999999999999996 in binary floating point)."""
    from dcf2bin.network.slaveconfig import times
    assert times(100, 0.29) == 29
    assert times(100, 0.57) == 57
    assert times(7, 2.7) == 18            # 18.9: rounded down
    assert times(33, 1.5) == 49
    assert times(30000, 2.18) == 65400


def test_plc_0x1016_per_slave_multiplier_and_mapping(tmp_path):
    """0x1016 subs 1, 2, ... in node-ID order, (node-ID << 16) | time x the slave's own
    multiplier (else options'), rounded down; a {slave: ms} mapping gives the time."""
    def slave(name, nid, extra=""):
        return f"{name}:\n  dcf: mini.eds\n  node_id: {nid}\n" + extra
    body = (slave("c", 9, "  heartbeat_producer: 33\n  heartbeat_multiplier: 1.5\n")
            + slave("a", 3, "  heartbeat_producer: 7\n") + slave("b", 4)
            + slave("d", 10, "  heartbeat_producer: 100\n"))
    (tmp_path / "mini.eds").write_text(mini_eds())
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    (tmp_path / "bus.yml").write_text("options:\n  heartbeat_multiplier: 2.7\n" + HEAD + body)
    res = build_network(str(tmp_path / "bus.yml"))
    assert [(w.sub, w.value) for w in res.network.master.writes if w.index == 0x1016] == [
        (1, 0x00030012), (2, 0x00090031), (3, 0x000A010E)]   # 18, 49, 270 ms
    (tmp_path / "bus.yml").write_text(HEAD + "  heartbeat_consumer: {d: 500, a: 40}\n" + body)
    res = build_network(str(tmp_path / "bus.yml"))
    assert [(w.sub, w.value) for w in res.network.master.writes if w.index == 0x1016] == [
        (1, 0x00030028), (2, 0x00090031), (3, 0x000A01F4)]


def test_master_consumer_time_of_the_mapping_over_65535_is_an_error(tmp_path):
    """D-17: a consumer time over 65535 ms is an error, never truncated — also one the
    {slave: ms} mapping gives (70000 ms once became (5 << 16) | 70000 = 0x00051170)."""
    (tmp_path / "mini.eds").write_text(mini_eds())
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    (tmp_path / "bus.yml").write_text(HEAD + "  heartbeat_consumer: {io: 70000}\n" + SLAVE
                                      + "  heartbeat_producer: 100\n")
    res = build_network(str(tmp_path / "bus.yml"))
    errors = [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
              if d.severity.value == "error"]
    assert errors == ["bus.yml:5: error: heartbeat_consumer: 70000 is outside 0..65535 "
                      "[NET004]"]
    assert not any(w.index == 0x1016 and w.value == 0x00051170
                   for w in res.network.master.writes)


def test_master_mapping_names_a_slave_without_heartbeat(tmp_path):
    """D-19: monitoring a node whose producer time is 0 is an error — also when the
    master's {slave: ms} mapping asks for it (it was dropped without a word)."""
    (tmp_path / "mini.eds").write_text(mini_eds())
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    (tmp_path / "bus.yml").write_text(HEAD + "  heartbeat_consumer: {io: 500}\n" + SLAVE)
    res = build_network(str(tmp_path / "bus.yml"))
    errors = [d.format().replace(str(tmp_path) + "/", "") for d in res.diagnostics
              if d.severity.value == "error"]
    assert errors == ["bus.yml:5: error: master (node 1) monitors io (node 5), which "
                      "produces no heartbeat (producer time 0) [NET251]"]
