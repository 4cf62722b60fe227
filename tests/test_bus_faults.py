"""A faulty bus (issue 26, items 9-12): `download`, `network download` and `network
scan` against software nodes that misbehave on purpose (bus_fixtures.py: a node that
toggles for ever, answers 3 bytes, answers for another entry, answers twice, restarts in
the middle of its download), each command run by the harness in a thread that must end
within the time its options give (bus_helpers.run_within), never by sleeping; and a node
from an EDS that gives its identity in [DeviceInfo] only."""
from __future__ import annotations

import pytest
from bus_helpers import VIRTUAL, run, run_within
from conftest import ROOT

from dcf2bin.bus.scan import worst_case

pytest_plugins = ["bus_fixtures"]
pytestmark = pytest.mark.usefixtures("at_root")

DCF = "samples/device.dcf"
# what a loaded machine may add to a command's own bound: loading the files, starting the
# bus, the threads taking turns (the bound itself comes from --timeout and --retries)
SLACK = 3.0
TIMEOUT, RETRIES = 0.2, 0


def bus(channel: str, *more: str) -> list[str]:
    return ["-i", "virtual", "--channel", channel, "--timeout", str(TIMEOUT),
            "--retries", str(RETRIES), *more]


def transfers(*sizes: int) -> float:
    """The most the SDO transfers of these sizes take with TIMEOUT and RETRIES: 1 + ceil(n/7)
    exchanges each (at least 2), each waited for (RETRIES + 1) x TIMEOUT."""
    return sum((1 + max(1, -(-n // 7))) * (RETRIES + 1) * TIMEOUT for n in sizes)


@pytest.fixture
def network_file(tmp_path):
    """A PLC and two slaves made from samples/device.eds (device type 0x000F0191,
    vendor-ID 0xAB); dev2 gets its TPDO1 and heartbeat written (7 writes), dev3 its
    heartbeat (1 write)."""
    path = tmp_path / "bus.yml"
    path.write_text(f"""master:
  node_id: 1
  name: plc
  dcf: {ROOT}/tests/fixtures/network/plc.dcf
dev2:
  dcf: {ROOT}/samples/device.eds
  node_id: 2
  product_code: 0
  heartbeat_producer: 200
  tpdo:
    1:
      transmission: 255
      mapping:
        - {{index: 0x2001, sub_index: 0, name: position}}
dev3:
  dcf: {ROOT}/samples/device.eds
  node_id: 3
  product_code: 0
  heartbeat_producer: 200
""")
    return str(path)


def net_download_bound(n_writes: int = 8) -> float:
    """Both slaves: two identity reads each and the writes (none over 4 bytes)."""
    return transfers(*[4] * 4, *[4] * n_writes) + SLACK


# -- 9: a node that toggles for ever --------------------------------------------------------

def test_scan_ends_in_its_bound_when_a_node_toggles_for_ever(bench, network_file, faulty):
    bench.device(3)
    liar = faulty.TogglesForever(bench.device(2), 0x1000, 0)
    r = run_within(worst_case(0, TIMEOUT, RETRIES) + SLACK, "network", "scan",
                           network_file, "--listen", "0", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{network_file}:5: error: node 2 (dev2) sent more than 4 bytes for an SDO upload of "
        "0x1000 sub 0 without ending it; the master expects 0x000F0191 (0x1F84)\n")
    assert liar.segments == 1           # the first segment was already more than 4 bytes
    rows = r.stdout.splitlines()[1:]
    assert rows[2].split() == ["2", "dev2", "answers", "bad", "answer", "0x000000AB",
                               "(none)", "(none)", "(none)"]
    assert rows[3].split()[:4] == ["3", "dev3", "answers", "0x000F0191"]


def test_network_download_ends_when_a_node_toggles_for_ever(bench, network_file, faulty):
    bench.device(3)
    faulty.TogglesForever(bench.device(2), 0x1000, 0, size=4)       # announces 4, sends on
    r = run_within(net_download_bound(), "network", "download", network_file,
                         "--keep-going", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{network_file}:5: error: node 2 (dev2): 0x1000 (device type) cannot be read: node 2 "
        "sent more than the 4 bytes it announced for an SDO upload of 0x1000 sub 0; the "
        "master expects 0x000F0191 (0x1F84): nothing written\n")
    assert r.stdout == (
        "node 2 (dev2): failed, nothing written\n"
        "node 3 (dev3): identity checked, 1 entry written\n"
        f"{network_file}: 1 configured, 1 failed, 0 skipped\n"
        "  failed      node 2 (dev2)  0x1000 (device type) cannot be read: node 2 sent more "
        "than the 4 bytes it announced for an SDO upload of 0x1000 sub 0; the master expects "
        "0x000F0191 (0x1F84): nothing written\n"
        "  configured  node 3 (dev3)  1 entry\n")


def test_download_verify_reads_no_more_than_max_upload(bench, faulty):
    # 0x2000 is a VISIBLE_STRING (15 bytes written): read back, the node never ends it
    liar = faulty.TogglesForever(bench.device(3), 0x2000, 0)
    r = run_within(transfers(*[4] * 15, 15, 64) + SLACK, "download", DCF, "-n", "3",
                         "--verify", "--max-upload", "64", *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{DCF}:178: error: node 3 sent more than 64 bytes for an SDO upload "
                        "of 0x2000 sub 0 without ending it while reading back\n")
    assert liar.segments == 10          # 70 bytes: the 10th segment went past 64


def test_an_upload_ends_at_its_deadline_whatever_the_node_sends(bench, faulty):
    from dcf2bin.bus import sdo
    faulty.TogglesForever(bench.device(3), 0x2000, 0)
    import time
    with sdo.Channel(bench.network(), 3, timeout=TIMEOUT, retries=RETRIES) as ch:
        with pytest.raises(sdo.SdoError) as e:
            ch.upload(0x2000, 0, deadline=time.monotonic())
    assert str(e.value) == "node 3 did not end an SDO upload of 0x2000 sub 0 within 0 s"


def test_transfer_bounds():
    from dcf2bin.bus import sdo
    assert [sdo.exchanges(n) for n in (0, 1, 4, 7, 8, 14, 15, 1 << 20)] == [
        2, 2, 2, 2, 3, 3, 4, 1 + 149797]
    assert sdo.bound(15, 0.5, 2) == pytest.approx(4 * 3 * 0.5)


# -- 10: a malformed answer, another entry's answer, an answer twice -------------------------

SHORT = ("node 2 answered a 3-byte frame to an SDO upload of 0x1018 sub 1")


def test_scan_names_a_3_byte_answer(bench, network_file, faulty):
    bench.device(3)
    faulty.ShortAnswer(bench.device(2), 0x1018, 1)
    r = run_within(worst_case(0, TIMEOUT, RETRIES) + SLACK, "network", "scan",
                         network_file, "--listen", "0", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (f"{network_file}:5: error: node 2 (dev2) answered a 3-byte frame to an "
                        "SDO upload of 0x1018 sub 1; the master expects 0x000000AB (0x1F85)\n")


def test_network_download_fails_that_node_and_names_every_node(bench, network_file, faulty):
    bench.device(3)
    faulty.ShortAnswer(bench.device(2), 0x1018, 1)
    r = run_within(net_download_bound(), "network", "download", network_file,
                         *bus(bench.channel))
    assert r.exit_code == 1                  # not 70: the node failed, dcf2bin did not
    problem = (f"0x1018 sub 1 (vendor-ID) cannot be read: {SHORT}; the master expects "
               "0x000000AB (0x1F85): nothing written")
    assert r.stderr == f"{network_file}:5: error: node 2 (dev2): {problem}\n"
    assert r.stdout == (
        "node 2 (dev2): failed, nothing written\n"
        f"{network_file}: 0 configured, 1 failed, 1 skipped\n"
        f"  failed      node 2 (dev2)  {problem}\n"
        "  skipped     node 3 (dev3)  not written: an earlier node failed (--keep-going goes "
        "on)\n")


def test_network_download_keep_going_configures_the_next_node(bench, network_file, faulty):
    bench.device(3)
    faulty.ShortAnswer(bench.device(2), 0x1018, 1)
    r = run_within(net_download_bound(), "network", "download", network_file,
                         "--keep-going", "--verify", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stdout.splitlines()[1:3] == ["node 3 (dev3): identity checked, 1 entry written, "
                                          "read back equal",
                                          f"{network_file}: 1 configured, 1 failed, 0 skipped"]


def test_an_answer_for_another_entry_is_named(bench, network_file, faulty):
    bench.device(3)
    faulty.WrongEntry(bench.device(2), 0x1018, 1, instead=(0x1018, 0))
    r = run_within(net_download_bound(), "network", "download", network_file,
                         "--keep-going", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{network_file}:5: error: node 2 (dev2): 0x1018 sub 1 (vendor-ID) cannot be read: "
        "node 2 answered an SDO upload of 0x1018 sub 1 with an upload answer for 0x1018 sub 0; "
        "the master expects 0x000000AB (0x1F85): nothing written\n")
    assert "did not answer" not in r.stdout + r.stderr


def test_scan_names_an_answer_for_another_entry(bench, network_file, faulty):
    bench.device(3)
    faulty.WrongEntry(bench.device(2), 0x1018, 1, instead=(0x1018, 0))
    r = run_within(worst_case(0, TIMEOUT, RETRIES) + SLACK, "network", "scan",
                         network_file, "--listen", "0", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{network_file}:5: error: node 2 (dev2) answered an SDO upload of 0x1018 sub 1 with "
        "an upload answer for 0x1018 sub 0; the master expects 0x000000AB (0x1F85)\n")


def test_download_names_an_answer_given_twice(bench, faulty):
    faulty.AnswersTwice(bench.device(3))
    r = run_within(transfers(*[4] * 15) + SLACK, "download", DCF, "-n", "3",
                         *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{DCF}:85: error: node 3 answered an SDO download of 0x1016 sub 1 "
                        "twice; 1 of 15 entries written before it\n")


def test_network_download_names_an_answer_given_twice(bench, network_file, faulty):
    bench.device(3)
    faulty.AnswersTwice(bench.device(2))
    r = run_within(net_download_bound(), "network", "download", network_file,
                         "--keep-going", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (
        f"{network_file}:5: error: node 2 (dev2): 0x1018 sub 1 (vendor-ID) cannot be read: "
        "node 2 answered an SDO upload of 0x1000 sub 0 twice; the master expects 0x000000AB "
        "(0x1F85): nothing written\n")
    assert r.stdout.splitlines()[0] == "node 2 (dev2): failed, nothing written"


def test_late_answers_to_a_request_sent_again_are_no_fault(bench, faulty):
    """A slow node: its answer to the first try comes after the retry went out, so it
    answers both tries; the second answer is passed over, not called a repeated one."""
    from dcf2bin.bus import sdo
    node = bench.device(3)

    class Slow(faulty.Misbehaving):
        def handle(self, request, serve, send):
            if len(self.requests) == 1:
                return                   # the first try: answered only with the second
            serve()
            if len(self.requests) == 2:
                serve()
    slow = Slow(node)
    with sdo.Channel(bench.network(), 3, timeout=0.05, retries=1) as ch:
        assert ch.upload(0x1000, 0) == bytes.fromhex("91010F00")
        assert ch.upload(0x1018, 1) == bytes.fromhex("AB000000")
    assert len(slow.requests) == 3


# -- 11: a node that restarts in the middle of its download ----------------------------------

def test_download_fails_a_node_that_restarts(bench, faulty):
    faulty.RestartsAfter(bench.device(3), 13)
    r = run_within(transfers(*[4] * 15) + SLACK, "download", DCF, "-n", "3",
                         *bus(bench.channel))
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr == (f"{DCF}:154: error: node 3 restarted during the download (after entry "
                        "13 of 15)\n")


def test_network_download_fails_a_node_that_restarts(bench, network_file, faulty):
    bench.device(3)
    faulty.RestartsAfter(bench.device(2), 5)
    r = run_within(net_download_bound(), "network", "download", network_file,
                         "--keep-going", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stderr == (f"{network_file}:11: error: node 2 (dev2): node 2 restarted during the "
                        "download (after entry 5 of 7)\n")
    assert r.stdout.splitlines()[0] == "node 2 (dev2): failed, 5 of 7 entries written"


def test_a_boot_up_before_the_writes_is_no_restart(bench, network_file, faulty):
    """A node that boots while its identity is read has lost nothing yet."""
    node = bench.device(2)
    bench.device(3)

    class BootsFirst(faulty.Misbehaving):
        def handle(self, request, serve, send):
            if not self.requests[1:]:
                node.boot()              # boot-up message, before the first answer
            serve()
    BootsFirst(node)
    r = run_within(net_download_bound(), "network", "download", network_file,
                         *bus(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")


# -- 12: the bench ------------------------------------------------------------------------------

EPOS = """[DeviceInfo]
VendorName=maxon motor ag
VendorNumber=0x000000FB
ProductName=EPOS2
ProductNumber=0x63010000
RevisionNumber=0x21210000

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[1000]
ParameterName=Device Type
ObjectType=0x7
DataType=0x0007
AccessType=ro

[1001]
ParameterName=Error Register
ObjectType=0x7
DataType=0x0005
AccessType=ro

[1018]
ParameterName=Identity Object
ObjectType=0x9
SubNumber=5
"""
EPOS += "".join(f"""
[1018sub{k}]
ParameterName={name}
ObjectType=0x7
DataType={"0x0005" if k == 0 else "0x0007"}
AccessType=ro
""" for k, name in enumerate(["Number of entries", "Vendor-ID", "Product code",
                              "Revision number", "Serial number"]))


@pytest.fixture
def epos(tmp_path):
    """An EDS like maxon's EPOS2: its identity in [DeviceInfo] only, no DefaultValue."""
    path = tmp_path / "epos2.eds"
    path.write_text(EPOS)
    return str(path)


def test_a_node_from_an_eds_answers_its_identity_from_device_info(bench, epos):
    from dcf2bin.bus import sdo
    from dcf2bin.bus.node import from_file
    node, errors = from_file(epos, 5)
    bench.add(node)
    with sdo.Channel(bench.network(), 5, timeout=2, retries=0) as ch:
        got = {(i, s): ch.upload(i, s, max_size=4) for i, s in
               [(0x1000, 0), (0x1001, 0), (0x1018, 0), (0x1018, 1), (0x1018, 2), (0x1018, 3)]}
        with pytest.raises(sdo.Aborted) as e:
            ch.upload(0x1018, 4)
    assert got == {(0x1000, 0): bytes(4), (0x1001, 0): b"\0", (0x1018, 0): b"\x04",
                   (0x1018, 1): bytes.fromhex("FB000000"),
                   (0x1018, 2): bytes.fromhex("00000163"),
                   (0x1018, 3): bytes.fromhex("00002121")}
    assert e.value.code == 0x060A0023          # the serial number: nowhere in the file
    assert [d.format() for d in node.warnings] == [
        f"{epos}:14: warning: 0x1000 (device type) has no value in the file, and every "
        "CANopen device answers it: the node answers 0x00000000, the device type of a "
        "device that follows no device profile [NOD002]"]


def test_node_warns_at_start_about_what_it_cannot_answer(channel, tmp_path):
    text = EPOS.replace("VendorNumber=0x000000FB\n", "").replace(
        "[1001]\nParameterName=Error Register\nObjectType=0x7\nDataType=0x0005\n"
        "AccessType=ro\n", "")
    eds = tmp_path / "bare.eds"
    eds.write_text(text)
    r = run("node", str(eds), "-n", "5", "-i", "virtual", "--channel", channel, "--duration",
            "0")
    assert r.exit_code == 0
    # each at its object's section (a missing one: the file), each with its code
    assert r.stderr.splitlines()[:3] == [
        f"{eds}: warning: the file has no 0x1001 (error register), which every CANopen device "
        "has: the node answers SDO abort 0x06020000 (object does not exist) [NOD001]",
        f"{eds}:13: warning: 0x1000 (device type) has no value in the file, and every "
        "CANopen device answers it: the node answers 0x00000000, the device type of a "
        "device that follows no device profile [NOD002]",
        f"{eds}:31: warning: 0x1018 sub 1 (vendor-ID) has no value in the file nor in "
        "[DeviceInfo] VendorNumber: the node answers SDO abort 0x060A0023 (resource not "
        "available) [NOD003]"]


def test_node_names_the_first_error_of_its_file(channel, tmp_path):
    eds = tmp_path / "bad.eds"
    eds.write_text(EPOS.replace("DataType=0x0005\nAccessType=ro\n",
                                "DataType=0x0005\nAccessType=rx\n", 1))    # [1001], line 24
    r = run("node", str(eds), "-n", "5", "-i", "virtual", "--channel", channel, "--duration",
            "0")
    assert r.exit_code == 0
    assert r.stderr.splitlines()[0] == (
        f"{eds}:24: warning: the file has 1 error, the first here (see 'dcf2bin validate'); "
        "the node has the objects that could be read [NOD004]")


def test_a_network_naming_such_an_eds_passes_its_identity_check(bench, epos, tmp_path):
    path = tmp_path / "epos.yml"
    path.write_text(f"master:\n  node_id: 1\n  name: plc\n  dcf: {ROOT}/tests/fixtures/"
                    f"network/plc.dcf\ndrive:\n  dcf: {epos}\n  node_id: 5\n")
    from dcf2bin.bus.node import from_file
    bench.add(from_file(epos, 5)[0])
    r = run_within(worst_case(0, TIMEOUT, RETRIES) + SLACK, "network", "scan",
                         str(path), "--listen", "0", *bus(bench.channel))
    assert (r.exit_code, r.stderr) == (0, "")
    assert r.stdout.splitlines()[3].split() == [
        "5", "drive", "answers", "0x00000000", "0x000000FB", "0x63010000",
        "0x21210000", "abort", "060A0023"]


def test_a_node_on_a_virtual_bus_of_another_process_is_said_to_be_unreachable(channel):
    r = run_within(transfers(4) + SLACK, "download", DCF, "-n", "3",
                         *bus(channel))
    assert r.stderr == (f"{DCF}:84: error: 0x1016sub1: node 3 did not answer (no SDO response "
                        f"within 0.2 s, 1 try{VIRTUAL}); 0 of 15 entries written before it\n")


def test_a_node_aborts_a_download_that_never_ends(bench):
    """`node`'s own bound: canopen's server would collect an endless segmented download
    for as long as the node runs; past max_download bytes (1 MiB) the node aborts it."""
    import queue
    node = bench.device(3)
    node.max_download = 64
    net = bench.network()
    answers: queue.SimpleQueue = queue.SimpleQueue()
    net.subscribe(0x583, lambda can_id, data, ts: answers.put(bytes(data)))
    net.send_message(0x603, bytes.fromhex("2100200000000000"))       # 0x2000, size not given
    assert answers.get(timeout=2) == bytes.fromhex("6000200000000000")
    toggle, sent = 0, 0
    while True:
        net.send_message(0x603, bytes([toggle]) + b"ENDLESS")
        sent += 1
        answer = answers.get(timeout=2)
        if answer[0] == 0x80:
            break
        assert answer == bytes([0x20 | toggle]) + bytes(7)
        toggle ^= 0x10
    assert (sent, answer) == (10, bytes.fromhex("8000200005000405"))


def test_scan_on_a_virtual_bus_says_what_it_reaches(bench, network_file):
    bench.device(3)                                  # dev2 (node 2) is missing
    r = run_within(worst_case(0, TIMEOUT, RETRIES) + SLACK, "network", "scan",
                         network_file, "--listen", "0", *bus(bench.channel))
    assert r.exit_code == 1
    assert r.stdout.splitlines()[-1] == ("(missing: python-can's virtual bus reaches only this "
                                         "process: a node run by another process cannot "
                                         "answer)")
    assert r.stderr.splitlines()[0] == (f"{network_file}:5: error: node 2 (dev2) is in the "
                                        "network but does not answer")
