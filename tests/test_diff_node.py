"""dcf2bin diff FILE -n N: a file against a live node, on python-can's virtual bus with
dcf2bin's software nodes (docs/diff.md, "What it compares": a node)."""
from __future__ import annotations

from bus_helpers import bus_args, run, run_within
from conftest import ROOT

pytest_plugins = ["bus_fixtures"]

NET = ROOT / "tests" / "fixtures" / "network"
NONE = "SDO abort 0x060A0023: Resource not available"   # a software node: no value
VIRTUAL = ("python-can's virtual bus reaches only this process: a node run by another "
           "process cannot answer")


def test_a_node_holds_the_defaults_of_its_eds(bench):
    bench.device(3, "samples/device.eds")
    r = run("diff", "samples/device.eds", "-n", "3", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == ("samples/device.eds, node 3: equal; 30 entries compared, 1 of the "
                        "node's state left out (--all compares them)\n")


def test_the_dcf_against_the_node_before_and_after_download(bench):
    """Before: every configured value differs, and 0x2000 (a VISIBLE_STRING the EDS gives
    no value) is the abort the node answers. After `download`: only 0x2005, whose
    ObjFlags=1 keeps download from writing it."""
    bench.device(3, "samples/device.eds")
    r = run("diff", "samples/device.dcf", "-n", "3", *bus_args(bench.channel))
    assert r.exit_code == 1
    lines = r.stdout.splitlines()
    assert lines[:5] == ["--- samples/device.dcf", "+++ node 3",
                         "@@ 0x1016 Consumer heartbeat time @@",
                         "-0x1016sub1 Consumer heartbeat time1: 0x00010064",
                         "+0x1016sub1 Consumer heartbeat time1: 0x00000000"]
    assert lines[lines.index("@@ 0x2000 Location @@") + 1:][:2] == [
        '-0x2000sub0 Location: "Hall 3; rack #2"',
        "+0x2000sub0 Location: SDO abort 0x060A0023: Resource not available"]
    assert r.stderr == ("samples/device.dcf, node 3: 13 entries differ; 31 entries compared, "
                        "1 of the node's state left out (--all compares them)\n")
    assert run("download", "samples/device.dcf", "-n", "3", "-q",
               *bus_args(bench.channel)).exit_code == 0
    r = run("diff", "samples/device.dcf", "-n", "3", *bus_args(bench.channel))
    assert r.exit_code == 1
    assert r.stdout == ("--- samples/device.dcf\n+++ node 3\n"
                        "@@ 0x2005 Factory setting @@\n"
                        "-0x2005sub0 Factory setting: 0x0000000A\n"
                        "+0x2005sub0 Factory setting: 0x00000000\n")
    # the container asks only for what it writes: the node holds all of it
    r = run("diff", "samples/device.bin", "-n", "3", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == "samples/device.bin, node 3: equal; 13 entries compared\n"


def test_an_object_the_node_lacks_is_missing_on_the_node(bench, tmp_path):
    bench.device(3, "samples/device.eds")
    eds = tmp_path / "more.eds"
    eds.write_text((ROOT / "samples" / "device.eds").read_text() + (
        "\n[2100]\nParameterName=Extra\nObjectType=0x7\nDataType=0x0005\nAccessType=rw\n"
        "DefaultValue=5\n"))
    r = run("diff", str(eds), "-n", "3", *bus_args(bench.channel), "-q")
    assert r.exit_code == 1
    assert r.stdout == (f"--- {eds}\n+++ node 3\n"
                        f"@@ 0x2100 Extra: only in {eds} @@\n"
                        "-0x2100sub0 Extra: 5 (UNSIGNED8, rw, not mappable)\n")


def test_a_silent_node_ends_the_run_naming_the_entry(bench, faulty):
    node = bench.device(3, "samples/device.eds")

    class SilentAfter(faulty.Misbehaving):
        def __init__(self, node, answers):
            super().__init__(node)
            self.answers = answers

        def handle(self, request, serve, send):
            if self.answers > 0:
                self.answers -= 1
                serve()
    node.misbehaving = SilentAfter(node, 2)     # 0x1000, 0x1016 sub 0; not 0x1016 sub 1
    r = run_within(10, "diff", "samples/device.eds", "-n", "3", "-i", "virtual",
                   "--channel", bench.channel, "--timeout", "0.05", "--retries", "0")
    assert (r.exit_code, r.stdout) == (3, "")
    assert r.stderr == ("node 3: error: 0x1016 sub 1: node 3 did not answer (no SDO response "
                        f"within 0.05 s, 1 try; {VIRTUAL})\n")


def test_a_node_that_answers_twice_ends_the_run(bench, faulty):
    node = bench.device(3, "samples/device.eds")
    node.misbehaving = faulty.AnswersTwice(node)
    r = run_within(10, "diff", "samples/device.eds", "-n", "3", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout) == (3, "")
    assert r.stderr == ("node 3: error: 0x1016 sub 0: node 3 answered an SDO upload of 0x1000 "
                        "sub 0 twice\n")


def test_bytes_that_are_no_value_of_the_type_are_compared_as_answered(bench, faulty):
    """upload states no value of 4 bytes for an UNSIGNED8; diff shows what the node holds."""
    node = bench.device(3, "samples/device.eds")

    class Wide(faulty.Misbehaving):
        def handle(self, request, serve, send):
            if request[0] & 0xE0 == 0x40 and request[1:4] == bytes.fromhex("001802"):
                send(bytes([0x43]) + request[1:4] + bytes.fromhex("FF000000"))
            else:
                serve()
    Wide(node)
    r = run("diff", "samples/device.eds", "-n", "3", *bus_args(bench.channel), "-q")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1800 TPDO1 communication parameter @@",
        "-0x1800sub2 Transmission type: 255",
        "+0x1800sub2 Transmission type: FF000000 (4 bytes)"]


def test_a_node_that_restarts_while_it_is_read_ends_the_run(bench, faulty):
    node = bench.device(3, "samples/device.eds")

    class Restarts(faulty.Misbehaving):
        def handle(self, request, serve, send):
            serve()
            if request[1:4] == bytes.fromhex("171000"):
                from dcf2bin.bus.node import RESET_NODE
                self.node._reset(RESET_NODE)
    Restarts(node)
    r = run_within(10, "diff", "samples/device.eds", "-n", "3", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout) == (3, "")
    assert r.stderr == ("node 3: error: 0x1018 sub 0: node 3 restarted (its boot-up message "
                        "was heard)\n")


def test_a_build_states_the_identity_the_node_must_have(bench, tmp_path):
    """The built drive.dcf states serial number, revision and product code of the network
    file; a node made from it holds them (equal), one made from the plain EDS (which gives
    them no value: the software node answers an abort) differs in exactly those entries."""
    bus = tmp_path / "bus.yml"
    bus.write_text("master:\n  node_id: 1\n  sync_period: 10000\n"
                   f"drive:\n  dcf: {NET / 'technosoft.eds'}\n  node_id: 2\n"
                   "  product_code: 0x1234\n  revision_number: 0x00010002\n"
                   "  serial_number: 1234\n")
    r = run("network", "build", str(bus), "-o", str(tmp_path / "out"), "-q")
    assert r.exit_code == 0, r.stderr
    built = str(tmp_path / "out" / "drive.dcf")
    bench.device(2, built)
    r = run("diff", built, "-n", "2", *bus_args(bench.channel))
    assert (r.exit_code, r.stdout) == (0, ""), r.stdout
    bench.close()
    bench.device(2, str(NET / "technosoft.eds"))
    r = run("diff", built, "-n", "2", *bus_args(bench.channel), "-q")
    assert r.exit_code == 1
    assert r.stdout == (f"--- {built}\n+++ node 2\n"
                        "@@ 0x1018 Identity Object @@\n"
                        "-0x1018sub2 Product Code: 0x00001234\n"
                        f"+0x1018sub2 Product Code: {NONE}\n"
                        "-0x1018sub3 Revision number: 0x00010002\n"
                        f"+0x1018sub3 Revision number: {NONE}\n"
                        "-0x1018sub4 Serial number: 0x000004D2\n"
                        f"+0x1018sub4 Serial number: {NONE}\n")


def test_a_build_and_an_upload_of_the_same_node_agree(bench, tmp_path):
    """Issue 29: an EDS that gives its identity in [DeviceInfo] and [DeviceComissioning]
    only (0x1018 sub 2-4 without a value). The node made of it answers them from there,
    as a real device holds its identity, so the upload writes them; the build's DCF
    against the upload, and against the node, are equal -- one rule (model.identity):
    the build compared 0x1018 sub 2 as "0x00000000 (no value given)" against the upload's
    0x00001234 (exit 1) while the node said equal."""
    eds = tmp_path / "ts.eds"
    eds.write_text((NET / "technosoft.eds").read_text().replace(
        "VendorNumber=0x000001A3\n",
        "VendorNumber=0x000001A3\nProductNumber=0x1234\nRevisionNumber=0x00010002\n", 1)
        + "\n[DeviceComissioning]\nLSS_SerialNumber=1234\n")
    bus = tmp_path / "bus.yml"
    bus.write_text(f"master:\n  node_id: 1\n  sync_period: 10000\na:\n  dcf: {eds}\n"
                   "  node_id: 20\n")
    out, up = tmp_path / "out", tmp_path / "up"
    assert run("network", "build", str(bus), "-o", str(out), "-q").exit_code == 0
    bench.device(20, str(eds))
    args = bus_args(bench.channel)
    assert run("network", "download", str(bus), "-q", *args).exit_code == 0
    r = run("network", "upload", str(bus), "-o", str(up), "-q", *args)
    assert r.exit_code == 0, r.stderr
    r = run("diff", str(out), str(up), "-q")
    assert (r.exit_code, r.stdout) == (0, "")
    r = run("diff", str(out / "a.dcf"), "-n", "20", "-q", *args)
    assert (r.exit_code, r.stdout) == (0, "")
    # the identity is compared, not skipped: a node of another product code differs there
    bench.close()
    bench.device(20, str(tmp_path / "up" / "a.dcf"))
    bench.nodes[-1].sdo[0x1018][2].raw = 0x1235
    r = run("diff", str(out / "a.dcf"), "-n", "20", "-q", *args)
    assert (r.exit_code, r.stdout) == (1, f"--- {out}/a.dcf\n+++ node 20\n"
                                          "@@ 0x1018 Identity Object @@\n"
                                          "-0x1018sub2 Product Code: 0x00001234 (from "
                                          "[DeviceInfo] ProductNumber)\n"
                                          "+0x1018sub2 Product Code: 0x00001235\n")
