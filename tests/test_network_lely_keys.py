"""Every key lely's dcfgen (dcf-tools 2.4.2) reads (its cli.py and master.dcf.em), as
dcf2bin reads it: for a lely master written where dcfgen writes it (D-21; values checked
here by hand, tests/test_network_lely_dcfgen.py compares keys.yml with dcfgen itself),
for a PLC master into the PLC's own objects where they apply (D-17, as 0x1006/0x1007),
else a warning (NET124) saying what dcfgen would do; every value range-checked at its
entry's type, a bad one an error at its line."""
from __future__ import annotations

import pytest

from conftest import ROOT
from dcf2bin.network import build_network, check_network, configure, load_network

FIXTURES = ROOT / "tests" / "fixtures" / "network"
KEYS = FIXTURES / "lely" / "keys.yml"
IO, CN, DRIVE = (FIXTURES / "IoX4_8AI.eds", FIXTURES / "canopennode.eds",
                 FIXTURES / "technosoft.eds")


def sections(text: str) -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for block in text.split("\n\n"):
        lines = block.strip().splitlines()
        out[lines[0]] = lines[1:]
    return out


def lines(diags, tmp_path, severity=None) -> list[str]:
    return [d.format().replace(str(tmp_path) + "/", "") for d in diags
            if severity is None or d.severity.value == severity]


def keys_build():
    res = build_network(str(KEYS))
    assert res.ok and res.mode == "lely", lines(res.diagnostics, "")
    return res


# -- a lely master ---------------------------------------------------------------------

def test_the_masters_own_keys():
    """keys.yml's master: its identity in [DeviceInfo], [DeviceComissioning] and 0x1018
    (the serial number as 1018sub4's value, not in master.bin), TIME produced on 0x100
    (0x1012 bit 30), EMCY inhibit 2 ms, SYNC counter overflow 10, NMT inhibit 3 ms, error
    behaviour: class 1 no state change, class 2 stopped."""
    s = sections(keys_build().outputs["master.dcf"].decode())
    assert "LSS_SerialNumber=0x0000ABCD" in s["[DeviceComissioning]"]
    assert s["[DeviceInfo]"][1:5] == ["VendorNumber=0x00000360", "ProductName=",
                                      "ProductNumber=0x00001234",
                                      "RevisionNumber=0x00010002"]
    assert [s[f"[1018sub{k}]"][-1] for k in range(1, 5)] == [
        "DefaultValue=0x00000360", "DefaultValue=0x00001234", "DefaultValue=0x00010002",
        "DefaultValue=0x0000ABCD"]
    assert s["[1012]"][-1] == "DefaultValue=0x40000100"
    assert s["[1015]"] == ["ParameterName=Inhibit time EMCY", "DataType=0x0006",
                           "AccessType=rw", "DefaultValue=20"]
    assert s["[1019]"] == ["ParameterName=Synchronous counter overflow value",
                           "DataType=0x0005", "AccessType=rw", "DefaultValue=10"]
    assert s["[1029Value]"] == ["NrOfEntries=2", "1=0x01", "2=0x02"]
    assert s["[102A]"] == ["ParameterName=NMT inhibit time", "DataType=0x0006",
                           "AccessType=rw", "DefaultValue=30"]


def test_without_the_keys_dcfgens_defaults_stay():
    s = sections(build_network(str(FIXTURES / "lely" / "flat.yml")).outputs[
        "master.dcf"].decode())
    assert "LSS_SerialNumber=0x00000000" in s["[DeviceComissioning]"]
    assert s["[1018sub4]"] == ["ParameterName=Serial number", "DataType=0x0007",
                               "AccessType=ro"]
    assert [s[f"[{i}]"][-1] for i in ("1012", "1015", "1019", "102A")] == [
        "DefaultValue=0x00000100", "DefaultValue=0", "DefaultValue=0", "DefaultValue=0"]
    assert s["[1029Value]"] == ["NrOfEntries=1", "1=0x00"]
    assert "[1F58]" not in s and "[1F8AValue]" in s
    assert s["[1F8AValue]"] == ["NrOfEntries=0"]


def test_the_slaves_keys_for_a_lely_master():
    """io: restore its defaults from 0x1011 sub 1 (0x1F8A, 0x1F81 bit 7), download
    firmware/io-2.1.bin (0x1F58, bit 6), its concise DCF under its own dcf_path; cn:
    restore from sub 4, its concise DCF where configuration_file says."""
    res = keys_build()
    s = sections(res.outputs["master.dcf"].decode())
    # 0x01 slave | 0x04 boot | 0x40 software update | 0x80 restore | retry factor 3 << 8
    assert s["[1F81Value]"] == ["NrOfEntries=2", "5=0x000003C5", "3=0x00000385"]
    assert s["[1F8AValue]"] == ["NrOfEntries=2", "5=0x01", "3=0x04"]
    assert s["[1F58]"] == ["SubNumber=128", "ParameterName=Program data", "ObjectType=0x08"]
    assert s["[1F58sub5]"] == ["ParameterName=Program data of node-ID 5", "DataType=0x000F",
                               "AccessType=ro", "UploadFile=firmware/io-2.1.bin"]
    assert s["[1F58sub3]"] == ["ParameterName=Program data of node-ID 3", "DataType=0x000F",
                               "AccessType=ro"]
    optional = s["[OptionalObjects]"]
    assert optional[optional.index("29=0x1F55") + 1] == "30=0x1F58"
    assert s["[1F22sub5]"][-1] == "UploadFile=/opt/io/io.bin"
    assert s["[1F22sub3]"][-1] == "UploadFile=/etc/robot/cn.bin"
    # the master's own writes: io's revision (0x1F87 sub 5), cn's serial number (0x1F88
    # sub 3, its LSS_SerialNumber) -- not its own serial number (0x1018 sub 4)
    assert res.outputs["master.bin"].hex() == (
        "02000000" "871f05" "04000000" "38053901" "881f03" "04000000" "01000000")


def test_the_slaves_writes():
    """io: heartbeat 200 ms, then error behaviour class 1 = 2 (stopped); cn: its TPDO1
    (COB-ID disabled, transmission 1, mapping, enabled), then 0x1012 = 0x80000100 (it
    consumes TIME)."""
    out = keys_build().outputs
    assert out["io.bin"].hex() == "02000000" "171000" "02000000" "c800" "291001" "01000000" "02"
    assert out["cn.bin"].hex() == (
        "07000000"
        "001801" "04000000" "830100c0"
        "001802" "01000000" "01"
        "001a00" "01000000" "00"
        "001a01" "04000000" "20000021"
        "001a00" "01000000" "01"
        "001801" "04000000" "83010040"
        "121000" "04000000" "00010080")


def test_sync_counter_and_time_of_a_lely_master_are_checked():
    """The lely master's 0x1019 makes its SYNC one byte long (the load estimate), and its
    TIME COB-ID (0x100 by default, as dcfgen writes it) is another service's ID for a
    PDO."""
    net = configure(load_network(str(KEYS)))
    assert (net.master.sync_counter, net.master.time_cob_id) == (10, 0x40000100)
    from dcf2bin.network.load import estimate
    assert [(r.what, r.bytes) for r in estimate(net).rows if r.what == "SYNC"] == [
        ("SYNC", 1)]
    flat = configure(load_network(str(FIXTURES / "lely" / "flat.yml")))
    assert (flat.master.sync_counter, flat.master.time_cob_id) == (0, 0x100)


def test_a_pdo_on_the_lely_masters_time_id(tmp_path):
    (tmp_path / "bus.yml").write_text(
        f"master:\n  node_id: 1\n  sync_period: 1000\ncn:\n  dcf: {CN}\n  node_id: 3\n"
        "  tpdo:\n    1:\n      cob_id: 0x100\n")
    res = check_network(str(tmp_path / "bus.yml"))
    assert [m for m in lines(res.diagnostics, tmp_path, "error") if "NET231" in m] == [
        "bus.yml:8: error: cn (node 3) TPDO1 has COB-ID 0x100, the ID of the TIME of master "
        "(node 1) [NET231]"]


# -- the values: each checked at its entry's type, an error at its line ------------------

@pytest.mark.parametrize("key,value,message", [
    ("sync_overflow", "256", "sync_overflow: 256 is outside 0..255"),
    ("sync_overflow", "1", "sync_overflow: 1 is not 0 or 2..240 (CiA 301 reserves 1 and "
                           "241..255)"),
    ("sync_overflow", "241", "sync_overflow: 241 is not 0 or 2..240 (CiA 301 reserves 1 "
                             "and 241..255)"),
    ("emcy_inhibit_time", "65536", "emcy_inhibit_time: 65536 is outside 0..65535"),
    ("nmt_inhibit_time", "-1", "nmt_inhibit_time: -1 is outside 0..65535"),
    ("time_cob_id", "0x800", "time_cob_id: 0x800 has bits 11-28 set but not bit 29 (an "
                             "11-bit CAN-ID is at most 0x7FF; bit 29 marks a 29-bit one)"),
    ("time_cob_id", "0x100000000", "time_cob_id: 4294967296 is outside 0..0xFFFFFFFF"),
    ("vendor_id", "-5", "vendor_id: -5 is outside 0..4294967295"),
    ("error_behavior", "3", "error_behavior: expected a mapping of 0x1029 sub-indexes to "
                            "values, found int 3"),
])
def test_a_bad_master_value_is_an_error_at_its_line(tmp_path, key, value, message):
    (tmp_path / "bus.yml").write_text(f"master:\n  node_id: 1\n  {key}: {value}\n"
                                      f"io:\n  dcf: {IO}\n  node_id: 5\n")
    net = load_network(str(tmp_path / "bus.yml"))
    assert lines(net.diagnostics, tmp_path) == [f"bus.yml:3: error: {message} [NET004]"]


@pytest.mark.parametrize("text,message", [
    ("{0: 1}", "error_behavior: sub-index 0 is outside 1..254"),
    ("{255: 1}", "error_behavior: sub-index 255 is outside 1..254"),
    ("{1: 0x100}", "error_behavior: 0x1029sub1: 256 is outside 0..255"),
    ("{x: 1}", "error_behavior: invalid integer 'x'"),
])
def test_a_bad_error_behavior_item_is_an_error_at_its_line(tmp_path, text, message):
    (tmp_path / "bus.yml").write_text(
        f"master:\n  node_id: 1\nio:\n  dcf: {IO}\n  node_id: 5\n  error_behavior:\n"
        f"    {text[1:-1]}\n")
    net = load_network(str(tmp_path / "bus.yml"))
    got = lines(net.diagnostics, tmp_path)
    assert [g.split(" [")[0] for g in got] == [f"bus.yml:7: error: {message}"]


@pytest.mark.parametrize("key,value,message", [
    ("restore_configuration", "256", "restore_configuration: 256 is outside 0..255"),
    ("software_file", '""', "software_file: expected a text, found ''"),
    ("configuration_file", "[a]", "configuration_file: expected a text, found a list"),
    ("dcf_path", "5", "dcf_path: expected a text, found int 5"),
])
def test_a_bad_slave_value_is_an_error_at_its_line(tmp_path, key, value, message):
    (tmp_path / "bus.yml").write_text(f"master:\n  node_id: 1\nio:\n  dcf: {IO}\n"
                                      f"  node_id: 5\n  {key}: {value}\n")
    net = load_network(str(tmp_path / "bus.yml"))
    assert lines(net.diagnostics, tmp_path) == [f"bus.yml:6: error: {message} [NET004]"]


@pytest.mark.parametrize("node,text,message", [
    ("io", "restore_configuration: 2", "io's file has no 0x1011sub2, where the master is "
                                       "to restore its defaults (restore_configuration)"),
    ("io", "error_behavior: {2: 1}", "io's file has no 0x1029sub2 (error behaviour of "
                                     "class 2): that sub-index is missing"),
    ("drive", "time_cob_id: 0x100", "drive's file has no 0x1012sub0 (COB-ID TIME): that "
                                    "object is missing"),
])
def test_a_write_the_slaves_file_cannot_take(tmp_path, node, text, message):
    """The slave must have the entry: its 0x1011 sub (the master writes "load" there),
    its 0x1029 sub, its 0x1012."""
    io, drive = (f"  {text}\n", "") if node == "io" else ("", f"  {text}\n")
    (tmp_path / "bus.yml").write_text(
        f"master:\n  node_id: 1\nio:\n  dcf: {IO}\n  node_id: 5\n{io}"
        f"drive:\n  dcf: {DRIVE}\n  node_id: 2\n{drive}")
    res = build_network(str(tmp_path / "bus.yml"))
    line = 6 if node == "io" else 9
    assert [m for m in lines(res.diagnostics, tmp_path, "error") if "NET1" in m] == [
        f"bus.yml:{line}: error: {message} [NET114]"]


def test_a_given_time_cob_id_is_written_even_when_the_file_has_it(tmp_path):
    """D-18: every value given is written -- cn's file has 0x1012 = 0x100 (dcfgen writes a
    time_cob_id only when it is not 0x100, the default it compares with instead of the
    file's value)."""
    (tmp_path / "bus.yml").write_text(
        f"master:\n  node_id: 1\ncn:\n  dcf: {CN}\n  node_id: 3\n  time_cob_id: 0x100\n")
    res = build_network(str(tmp_path / "bus.yml"))
    assert res.ok
    assert res.outputs["cn.bin"].hex() == "01000000" "121000" "04000000" "00010000"


# -- a PLC master ----------------------------------------------------------------------

PLC_OBJECTS = """
[1012]
ParameterName=COB-ID TIME
ObjectType=0x7
DataType=0x0007
AccessType=rw
DefaultValue=0x80000100

[1015]
ParameterName=Inhibit time EMCY
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0

[1019]
ParameterName=Synchronous counter overflow value
ObjectType=0x7
DataType=0x0005
AccessType=rw
DefaultValue=0

[1029]
ParameterName=Error behaviour
ObjectType=0x8
DataType=0x0005
AccessType=rw
DefaultValue=0
CompactSubObj=2

[102A]
ParameterName=NMT inhibit time
ObjectType=0x7
DataType=0x0006
AccessType=rw
DefaultValue=0

[1F8A]
ParameterName=Restore configuration
ObjectType=0x8
DataType=0x0005
AccessType=rw
DefaultValue=0
CompactSubObj=127
"""


def plc_network(tmp_path, with_objects: bool) -> str:
    """keys.yml with a PLC master: tests/fixtures/network/plc.dcf, with 0x1012, 0x1015,
    0x1019, 0x1029, 0x102A and 0x1F8A added when ``with_objects``."""
    plc = (FIXTURES / "plc.dcf").read_text()
    if with_objects:
        plc = plc.replace("SupportedObjects=45\n", "SupportedObjects=51\n").replace(
            "45=0x1F89\n", "45=0x1F89\n46=0x1012\n47=0x1015\n48=0x1019\n49=0x1029\n"
            "50=0x102A\n51=0x1F8A\n") + PLC_OBJECTS
    (tmp_path / "plc.dcf").write_text(plc)
    text = KEYS.read_text().replace('"../', f'"{FIXTURES}/').replace(
        "master:\n  node_id: 1\n", "master:\n  node_id: 1\n  dcf: plc.dcf\n")
    (tmp_path / "bus.yml").write_text(text)
    return str(tmp_path / "bus.yml")


# what a PLC master does not use: one warning per key (the master's identity: one)
NOT_USED = [
    "bus.yml:15: warning: vendor_id, product_code, revision_number, serial_number: lely's "
    "dcfgen writes them as a lely master's own identity (0x1018 sub 1-4, [DeviceInfo], "
    "LSS_SerialNumber); a PLC's identity is its own file's: not used [NET124]",
    "bus.yml:10: warning: dcf_path: lely's dcfgen names the concise DCFs under it in a "
    "lely master's 0x1F22 (UploadFile=); a PLC master holds the slaves' concise DCFs in its "
    "own 0x1F22: not used [NET124]",
    "bus.yml:41: warning: configuration_file: it names the slave's concise DCF in a lely "
    "master's 0x1F22 (UploadFile=; lely's dcfgen 2.4.2 reads it but does not use it); a "
    "PLC master holds the slaves' concise DCFs in its own 0x1F22: not used [NET124]",
    "bus.yml:33: warning: software_file: lely's dcfgen has a lely master download this "
    "program to the slave (0x1F58, 0x1F81 bit 6); dcf2bin does not configure a PLC's "
    "program download: not used [NET124]",
    "bus.yml:34: warning: dcf_path: lely's dcfgen names the concise DCFs under it in a "
    "lely master's 0x1F22 (UploadFile=); a PLC master holds the slaves' concise DCFs in its "
    "own 0x1F22: not used [NET124]",
]


def test_a_plc_takes_the_keys_into_its_own_objects(tmp_path):
    """The master's 0x1019, 0x1012, 0x1015, 0x102A and 0x1029 subs, the slaves' 0x1F8A
    sub <node> with 0x1F81 bit 7, as ParameterValue of the PLC's file; the slaves' writes
    as for a lely master."""
    res = build_network(plc_network(tmp_path, True))
    assert res.ok and res.mode == "plc"
    assert lines(res.diagnostics, tmp_path, "warning") == NOT_USED
    s = sections(res.outputs["master.dcf"].decode())
    values = {k: [v for v in s[f"[{k}]"] if v.startswith("ParameterValue")]
              for k in ("1012", "1015", "1019", "102A")}
    assert values == {"1012": ["ParameterValue=0x40000100"],
                      "1015": ["ParameterValue=0x0014"], "1019": ["ParameterValue=0x0A"],
                      "102A": ["ParameterValue=0x001E"]}
    assert s["[1029Value]"] == ["NrOfEntries=2", "1=0x01", "2=0x02"]
    assert s["[1F8AValue]"] == ["NrOfEntries=2", "3=0x04", "5=0x01"]
    # 0x01 | 0x04 boot | 0x80 restore | retry factor 3 << 8; no bit 6 (software_file)
    assert s["[1F81Value]"] == ["NrOfEntries=2", "3=0x00000385", "5=0x00000385"]
    lely = keys_build().outputs
    assert (res.outputs["io.bin"], res.outputs["cn.bin"]) == (lely["io.bin"], lely["cn.bin"])


def test_a_plc_without_the_objects_is_told(tmp_path):
    """plc.dcf has none of these objects: each is a warning that the PLC cannot do it
    (NET110; 0x1F8A once, for the first slave), and 0x1F81 asks for no restore."""
    res = build_network(plc_network(tmp_path, False))
    assert res.ok
    assert lines(res.diagnostics, tmp_path, "warning") == [
        "bus.yml:40: warning: the PLC's file has no 0x1F8A: the PLC cannot do the restore "
        "configuration (cn's restore configuration); not written [NET110]",
        "bus.yml:21: warning: the PLC's file has no 0x1019: the PLC cannot do the SYNC "
        "counter (synchronous counter overflow value); not written [NET110]",
        "bus.yml:22: warning: the PLC's file has no 0x1012: the PLC cannot do the TIME "
        "COB-ID (COB-ID TIME); not written [NET110]",
        "bus.yml:23: warning: the PLC's file has no 0x1015: the PLC cannot do the EMCY "
        "inhibit time (inhibit time EMCY (x 100 us)); not written [NET110]",
        "bus.yml:24: warning: the PLC's file has no 0x102A: the PLC cannot do the NMT "
        "inhibit time (NMT inhibit time (x 100 us)); not written [NET110]",
        "bus.yml:25: warning: the PLC's file has no 0x1029: the PLC cannot do the error "
        "behaviour (error behaviour of class 1); not written [NET110]",
    ] + NOT_USED
    s = sections(res.outputs["master.dcf"].decode())
    assert s["[1F81Value]"] == ["NrOfEntries=2", "3=0x00000305", "5=0x00000305"]


def test_a_key_that_is_not_used_is_a_warning_not_hidden_as_an_info(tmp_path):
    """--strict: a key of dcfgen's that a PLC master does not use stops the build (a
    warning, where an info would have passed unseen)."""
    from click.testing import CliRunner

    from dcf2bin.cli import main
    r = CliRunner().invoke(main, ["network", "build", plc_network(tmp_path, True), "-o",
                                  str(tmp_path / "out"), "--strict", "-q"])
    assert r.exit_code == 1
    assert r.stderr.splitlines()[-1] == "network build: 0 errors, 5 warnings (--strict), " \
        "nothing written"
