"""dcf2bin download: a DCF's entries reach a canopen LocalNode by SDO on python-can's
virtual bus, in container order; aborts, silence and read-back differences are one line
each, naming the DCF line (or the container entry) they come from."""
from __future__ import annotations

import time

import pytest
from bus_helpers import TIMEOUT, VIRTUAL, bus_args, eventually, run
from conftest import SAMPLES

from dcf2bin.compiler import CompileOptions, compile_path

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

DCF = "samples/device.dcf"


def device_container():
    res = compile_path(str(SAMPLES / "device.dcf"), CompileOptions(node_id=3))
    assert res.ok
    return res.container


def final_values(c) -> dict[tuple[int, int], bytes]:
    out = {}
    for index, sub, data in c.entries:
        out[(index, sub)] = data
    return out


# -- the whole DCF reaches the node ---------------------------------------------------------

def test_download_reads_back_byte_for_byte(bench):
    node = bench.device()
    r = run("download", DCF, "-n", "3", *bus_args(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout == f"{DCF}: 15 entries written to node 3\n"
    sdo = bench.sdo(3)
    finals = final_values(device_container())
    assert len(finals) == 13
    for (index, sub), data in finals.items():
        assert sdo.upload(index, sub) == data, f"0x{index:04X}sub{sub}"
    # the device EDS said 0x1017 = 0 and the TPDO was off; the DCF's values are there now
    assert node.sdo[0x1017].raw == 500
    assert node.sdo[0x1800][1].raw == 0x183
    # ObjFlags bit 0: 0x2005 is not written (the EDS default stays)
    assert sdo.upload(0x2005, 0) == b"\0\0\0\0"


def test_download_writes_in_container_order(bench):
    node = bench.device()
    seen = []
    node.add_write_callback(lambda index, subindex, od, data: seen.append(
        (index, subindex, bytes(data))))
    r = run("download", DCF, "-n", "3", "-q", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout, r.stderr) == (0, "", "")
    assert seen == device_container().entries      # the PDO sequence of D-8 included


def test_download_container_and_json_forms(bench, tmp_path):
    bench.device()
    r = run("download", "samples/device.bin", "-n", "3", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout) == (0, "samples/device.bin: 15 entries written to node 3\n")
    json_path = tmp_path / "device.json"
    json_path.write_text(run("dump", "--format", "json", "samples/device.bin").stdout)
    r = run("download", str(json_path), "-n", "3", "--verify", *bus_args(bench.channel))
    assert r.exit_code == 0
    assert r.stdout == f"{json_path}: 15 entries written to node 3, read back equal\n"


# -- dry run --------------------------------------------------------------------------------

def test_dry_run_prints_the_writes_and_touches_no_bus():
    r = run("download", DCF, "-n", "3", "--dry-run", "-i", "no-such-interface")
    assert (r.exit_code, r.stderr) == (0, "")
    lines = r.stdout.splitlines()
    # every column lines up: the sources padded to the longest, the data last (issue 19)
    assert lines[:4] == [
        f"{DCF}: 15 SDO writes to node 3 (dry run, nothing sent)",
        "   #  entry       size  source                  data",
        f"   1  0x1016sub1     4  {DCF}:84   64 00 01 00",
        f"   2  0x1016sub2     4  {DCF}:85   C8 00 02 00",
    ]
    assert lines[5] == (f"   4  0x2000sub0    15  {DCF}:178  "
                        "48 61 6C 6C 20 33 3B 20 72 61 63 6B 20 23 32")
    # the CiA 301 PDO block: disable, mapping 0, entries, count, enable
    assert lines[10:] == [
        f"   9  0x1800sub1     4  {DCF}:133  83 01 00 80",
        f"  10  0x1800sub2     1  {DCF}:141  01",
        f"  11  0x1A00sub0     1  {DCF}:154  00",
        f"  12  0x1A00sub1     4  {DCF}:162  18 00 01 20",
        f"  13  0x1A00sub2     4  {DCF}:170  08 00 05 00",
        f"  14  0x1A00sub0     1  {DCF}:154  02",
        f"  15  0x1800sub1     4  {DCF}:133  83 01 00 00",
    ]
    assert {len(line.split("  samples")[0]) for line in lines[2:]} == {22}


def test_dry_run_of_a_container_names_byte_offsets():
    r = run("download", "samples/device.bin", "-n", "3", "--dry-run")
    assert r.stdout.splitlines()[2] == ("   1  0x1016sub1     4  samples/device.bin:0x2C  "
                                        "64 00 01 00")


def test_node_id_resolves_nodeid_values():
    r = run("download", DCF, "-n", "5", "--dry-run")
    assert r.stdout.splitlines()[-1] == f"  15  0x1800sub1     4  {DCF}:133  85 01 00 00"


# -- aborts ---------------------------------------------------------------------------------

def _abort_on(node, index: int, code: int = 0x06090030):
    from canopen import SdoAbortedError

    def refuse(**write):
        if write["index"] == index:
            raise SdoAbortedError(code)
    node.add_write_callback(refuse)


def test_abort_stops_the_run_with_one_line(bench):
    node = bench.device()
    _abort_on(node, 0x2002)
    r = run("download", DCF, "-n", "3", *bus_args(bench.channel))
    assert r.exit_code == 1
    assert r.stdout == ""
    assert r.stderr == (f"{DCF}:195: error: 0x2002sub0: SDO abort 0x06090030: Value range of "
                        "parameter exceeded; 5 of 15 entries written before it\n")
    sdo = bench.sdo(3)
    assert sdo.upload(0x2001, 0) == b"\x00\x00\x80"        # before it: written
    assert sdo.upload(0x2003, 0) == b"\x00\x00\x00\x00"    # after it: not


def test_keep_going_reports_every_abort_and_writes_the_rest(bench):
    node = bench.device()
    _abort_on(node, 0x2002)
    _abort_on(node, 0x2004, 0x06010002)
    r = run("download", DCF, "-n", "3", "--keep-going", *bus_args(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{DCF}:195: error: 0x2002sub0: SDO abort 0x06090030: Value range of parameter "
        "exceeded\n"
        f"{DCF}:211: error: 0x2004sub0: SDO abort 0x06010002: Attempt to write a read only "
        "object\n"
        f"{DCF}: 13 of 15 entries written, 2 SDO aborts\n")
    sdo = bench.sdo(3)
    assert sdo.upload(0x2003, 0) == bytes.fromhex("DEADBEEF")
    assert sdo.upload(0x1800, 1) == bytes.fromhex("83010000")


def test_abort_in_a_container_names_the_entry_offset(bench):
    node = bench.device()
    _abort_on(node, 0x2001, 0x0800_0000)
    r = run("download", "samples/device.bin", "-n", "3", *bus_args(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == ("samples/device.bin:0x61: error: 0x2001sub0: SDO abort 0x08000000: "
                        "General error; 4 of 15 entries written before it\n")


def test_unknown_abort_code_is_said_so(bench):
    node = bench.device()
    _abort_on(node, 0x1016, 0x12345678)
    r = run("download", DCF, "-n", "3", *bus_args(bench.channel))
    assert r.stderr == (f"{DCF}:84: error: 0x1016sub1: SDO abort 0x12345678: not an abort "
                        "code CiA 301 defines; 0 of 15 entries written before it\n")


# -- silence --------------------------------------------------------------------------------

def test_silent_node_is_a_timeout_error_after_the_retries(channel):
    start = time.monotonic()
    r = run("download", DCF, "-n", "3", "-i", "virtual", "--channel", channel,
            "--timeout", "0.05", "--retries", "2")
    assert time.monotonic() - start < 2.0
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{DCF}:84: error: 0x1016sub1: node 3 did not answer (no SDO response "
                        f"within 0.05 s, 3 tries{VIRTUAL}); 0 of 15 entries written before it\n")


def test_node_without_sdo_server_is_a_timeout_error(bench):
    node = bench.device()                               # boots and heartbeats, no SDO server
    node.network.unsubscribe(node.sdo.rx_cobid, node.sdo.on_request)
    try:
        r = run("download", DCF, "-n", "3", "-i", "virtual", "--channel", bench.channel,
                "--timeout", "0.05", "--retries", "1")
    finally:
        node.network.subscribe(node.sdo.rx_cobid, node.sdo.on_request)
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{DCF}:84: error: 0x1016sub1: node 3 did not answer (no SDO response "
                        f"within 0.05 s, 2 tries{VIRTUAL}); 0 of 15 entries written before it\n")


def test_keep_going_still_stops_at_a_silent_node(channel):
    r = run("download", DCF, "-n", "9", "--keep-going", "-i", "virtual", "--channel", channel,
            "--timeout", "0.05", "--retries", "0")
    assert r.exit_code == 1
    assert r.stderr == (f"{DCF}:84: error: 0x1016sub1: node 9 did not answer (no SDO response "
                        f"within 0.05 s, 1 try{VIRTUAL}); 0 of 15 entries written before it\n")


# -- verify ---------------------------------------------------------------------------------

def test_verify_catches_a_node_that_keeps_the_old_value(bench):
    node = bench.device()
    real_set = node.set_data

    def stubborn(index, subindex, data, check_writable=False):
        if index == 0x2003:
            node.get_data(index, subindex)        # accepts the write, keeps what it had
            return
        real_set(index, subindex, data, check_writable)
    node.set_data = stubborn
    r = run("download", DCF, "-n", "3", "--verify", *bus_args(bench.channel))
    assert r.exit_code == 1
    assert r.stdout == ""
    assert r.stderr == (
        f"{DCF}:203: error: 0x2003sub0: wrote DE AD BE EF, the node holds 00 00 00 00\n"
        f"{DCF}: 15 of 15 entries written, 1 difference on reading back\n")


def test_verify_reads_the_final_value_of_repeated_writes(bench):
    bench.device()
    r = run("download", DCF, "-n", "3", "--verify", *bus_args(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout == f"{DCF}: 15 entries written to node 3, read back equal\n"


# -- NMT and storing ------------------------------------------------------------------------

def _device_with_store(tmp_path):
    text = (SAMPLES / "device.eds").read_text()
    text += ("\n[1010]\nParameterName=Store parameters\nObjectType=0x8\nSubNumber=2\n\n"
             "[1010sub0]\nParameterName=Highest sub-index\nObjectType=0x7\nDataType=0x0005\n"
             "AccessType=ro\nDefaultValue=1\n\n[1010sub1]\nParameterName=Save all\n"
             "ObjectType=0x7\nDataType=0x0007\nAccessType=rw\nDefaultValue=1\n")
    path = tmp_path / "device-store.eds"
    path.write_text(text)
    return str(path)


def test_preop_save_and_reset_comm(bench, tmp_path):
    node = bench.device(path=_device_with_store(tmp_path))
    node.go_operational()
    states = []
    net = bench.network()
    net.subscribe(0, lambda can_id, data, ts: states.append(bytes(data)))
    boots = []
    net.subscribe(0x703, lambda can_id, data, ts: boots.append(bytes(data)))
    r = run("download", DCF, "-n", "3", "--preop", "--save", "--reset-comm", "--verify",
            *bus_args(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout == (f"{DCF}: 15 entries written to node 3, read back equal, saved, "
                        "communication reset\n")
    assert eventually(lambda: b"\x00" in boots)   # the reset's boot-up
    assert states == [b"\x80\x03", b"\x82\x03"]
    assert node.nmt.state == "PRE-OPERATIONAL"
    assert node.sdo[0x1017].raw == 500             # stored, so kept over the reset


def test_reset_comm_without_save_restores_the_communication_area(bench):
    node = bench.device()
    r = run("download", DCF, "-n", "3", "--reset-comm", *bus_args(bench.channel))
    assert r.exit_code == 0
    assert eventually(lambda: node.sdo[0x1017].raw == 0)    # 0x1000-0x1FFF: back to the EDS
    assert node.sdo[0x2003].raw == bytes.fromhex("DEADBEEF")  # the application area stays


def test_save_on_a_node_without_0x1010_is_one_line(bench):
    bench.device()
    r = run("download", DCF, "-n", "3", "--save", *bus_args(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (f"{DCF}: error: 0x1010sub1: storing the parameters: SDO abort "
                        "0x06020000: Object does not exist\n")


# -- concise DCF ----------------------------------------------------------------------------

def test_concise_dcf_delivers_the_index_segment(bench):
    import canopen.objectdictionary as od_mod

    from dcf2bin import dump
    od = od_mod.ObjectDictionary()
    arr = od_mod.ODArray("Concise DCF", 0x1F22)
    for sub in range(128):
        var = od_mod.ODVariable(f"sub{sub}", 0x1F22, sub)
        var.data_type = 0x05 if sub == 0 else 0x0F
        var.access_type = "ro" if sub == 0 else "rw"
        var.default = 127 if sub == 0 else b""
        arr.add_member(var)
    od.add_object(arr)
    from dcf2bin.bus.node import bench_node
    manager = bench.add(bench_node(1, od))
    r = run("download", "samples/device.bin", "-n", "3", "--concise-dcf-to", "1", "--verify",
            *bus_args(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout == "samples/device.bin: 1 entry written to node 1, read back equal\n"
    data = (SAMPLES / "device.bin").read_bytes()
    h = dump.header_of(dump.read_bytes(data, "device.bin")[0])
    segment = data[h["index_offset"]:h["index_offset"] + h["index_size"]]
    assert len(segment) == 170
    assert manager.data_store[0x1F22][3] == segment
    assert list(manager.data_store) == [0x1F22] and list(manager.data_store[0x1F22]) == [3]


def test_concise_dcf_dry_run():
    r = run("download", DCF, "-n", "3", "--concise-dcf-to", "1", "--dry-run")
    assert r.stdout.splitlines()[0] == f"{DCF}: 1 SDO write to node 1 (dry run, nothing sent)"
    assert r.stdout.splitlines()[2].startswith(
        f"   1  0x1F22sub3   170  {DCF}  0F 00 00 00 16 10 01")


# -- usage and inputs -----------------------------------------------------------------------

def test_interface_that_cannot_open_is_exit_3():
    r = run("download", DCF, "-n", "3", "-i", "no-such-interface", "--channel", "x")
    assert r.exit_code == 3
    assert r.stderr == ("dcf2bin: error: CAN interface 'no-such-interface': Unknown interface "
                        "type \"no-such-interface\"\n")


def _no_can_config(monkeypatch, home):
    for var in ("CAN_INTERFACE", "CAN_CHANNEL", "CAN_BITRATE", "CAN_CONFIG"):
        monkeypatch.delenv(var, raising=False)
    monkeypatch.setenv("HOME", str(home))


def test_python_can_configuration_file_when_no_bus_options(bench, monkeypatch, tmp_path):
    _no_can_config(monkeypatch, tmp_path)
    (tmp_path / ".canrc").write_text(f"[default]\ninterface = virtual\n"
                                     f"channel = {bench.channel}\n")
    bench.device()
    r = run("download", DCF, "-n", "3", "--timeout", TIMEOUT)
    assert (r.exit_code, r.stdout) == (0, f"{DCF}: 15 entries written to node 3\n")


def test_python_can_environment_when_no_bus_options(bench, monkeypatch, tmp_path):
    _no_can_config(monkeypatch, tmp_path)
    monkeypatch.setenv("CAN_INTERFACE", "virtual")
    monkeypatch.setenv("CAN_CHANNEL", bench.channel)
    bench.device()
    r = run("download", DCF, "-n", "3", "--timeout", TIMEOUT)
    assert (r.exit_code, r.stdout) == (0, f"{DCF}: 15 entries written to node 3\n")


def test_no_interface_at_all_is_exit_3(monkeypatch, tmp_path):
    _no_can_config(monkeypatch, tmp_path)
    monkeypatch.chdir(tmp_path)
    r = run("download", str(SAMPLES / "device.dcf"), "-n", "3")
    assert r.exit_code == 3
    assert r.stderr == ("dcf2bin: error: no CAN interface given: use --interface and --channel, "
                        "or a python-can configuration file\n")


def test_a_dcf_with_errors_sends_nothing(tmp_path):
    bad = tmp_path / "bad.dcf"
    bad.write_text("[2000]\nParameterName=x\nDataType=0x0005\nAccessType=rw\n"
                   "ParameterValue=300\n")
    r = run("download", str(bad), "-n", "3", "-i", "no-such-interface")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[-1] == f"{bad}: 1 error, nothing sent"
    assert "value 300 out of range for UNSIGNED8" in r.stderr


def test_unreadable_input_is_exit_3(tmp_path):
    r = run("download", str(tmp_path / "missing.dcf"), "-n", "3", "--dry-run")
    assert r.exit_code == 3
    missing = tmp_path / "missing.dcf"
    assert r.stderr == f"{missing}: error: cannot read: No such file or directory [IO001]\n"


def test_node_is_required():
    r = run("download", DCF, "--dry-run")
    assert r.exit_code == 2
    assert "Missing option '-n' / '--node-id'" in r.stderr


@pytest.mark.parametrize("n", ["0", "128"])
def test_node_id_range(n):
    assert run("download", DCF, "-n", n, "--dry-run").exit_code == 2


def test_verify_accepts_an_empty_value_the_node_cannot_upload(bench, tmp_path):
    """canopen's server answers an empty value with 'no data available' (0x08000024)."""
    text = (SAMPLES / "device.dcf").read_text().replace("ParameterValue=Hall 3; rack #2",
                                                        'ParameterValue=""')
    dcf = tmp_path / "empty.dcf"
    dcf.write_text(text)
    node = bench.device()
    r = run("download", str(dcf), "-n", "3", "--verify", *bus_args(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert node.data_store[0x2000][0] == b""


def test_json_from_stdin_names_the_json_lines(bench):
    from click.testing import CliRunner

    from dcf2bin.cli import main
    node = bench.device()
    _abort_on(node, 0x2002)
    text = run("dump", "--format", "json", "samples/device.bin").stdout
    r = CliRunner().invoke(main, ["download", "-", "--from", "json", "-n", "3",
                                  *bus_args(bench.channel)], input=text)
    assert r.exit_code == 1
    assert r.stderr == ("<stdin>:24: error: 0x2002sub0: SDO abort 0x06090030: Value range of "
                        "parameter exceeded; 5 of 15 entries written before it\n")
    assert text.splitlines()[23].startswith('    {"index": "0x2002", "subindex": 0,')


class _TtyStderr:
    """The stderr click's test runner installs, claiming to be a terminal."""

    def __getattr__(self, name):
        import sys
        return getattr(sys.stderr, name)

    def isatty(self):
        return True


def test_progress_bar_on_a_terminal_only(bench, monkeypatch):
    import types

    import dcf2bin.cli.download as cli_download
    bench.device()
    monkeypatch.setattr(cli_download, "sys", types.SimpleNamespace(stderr=_TtyStderr()))
    r = run("download", DCF, "-n", "3", *bus_args(bench.channel))
    assert r.exit_code == 0
    steps = r.stderr.split("\r")
    assert steps[1] == "node 3  [------------------------------------]    0%"
    assert steps[-1] == "node 3  [####################################]  100%\x1b[?25h\n"
    r = run("download", DCF, "-n", "3", "-q", *bus_args(bench.channel))
    assert (r.exit_code, r.stderr, r.stdout) == (0, "", "")
