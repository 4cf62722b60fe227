"""Issue 26 items 7 and 8: one verdict in every network command.

build, show, download and scan read a network as check does (each node's file by its
kind, syntax and model, validate's rules that can report an error, the rules of the
network as a whole): the same errors, the same exit code; a node's file check cannot
read is never built. Issue 27: build takes --select/--ignore; show draws a network that
has errors, with them listed.
"""
from __future__ import annotations

import shutil

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin.cli import main

FIX = ROOT / "tests" / "fixtures" / "network"
GOLDEN = ROOT / "tests" / "golden" / "network" / "flat"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def network(tmp_path, drive_file: str = "technosoft.eds", extra: str = "") -> str:
    """The golden flat network (a PLC, a drive, an I/O module) in ``tmp_path``, the drive
    read from ``drive_file`` there."""
    for name in ("plc.dcf", "technosoft.eds", "IoX4_8AI.eds"):
        shutil.copy(FIX / name, tmp_path / name)
    text = (GOLDEN / "bus.yml").read_text().replace("../../../fixtures/network/", "")
    text = text.replace("dcf: technosoft.eds", f"dcf: {drive_file}")
    (tmp_path / "bus.yml").write_text(text + extra)
    return str(tmp_path / "bus.yml")


COMMANDS = [("check",), ("show",), ("show", "-f", "svg"), ("download", "--dry-run"),
            ("scan", "-i", "virtual", "--listen", "0", "--timeout", "0.01"),
            ("build", "-o", "OUT")]


def every_command(tmp_path, path: str):
    """(exit code, stdout, stderr) of each network command on ``path``."""
    out = []
    for command in COMMANDS:
        args = [a.replace("OUT", str(tmp_path / "out")) for a in command]
        r = run("network", args[0], path, *args[1:])
        out.append((r.exit_code, r.stdout, r.stderr))
    return out


def test_the_golden_network_is_clean_in_every_command(tmp_path):
    path = network(tmp_path)
    got = every_command(tmp_path, path)
    assert [code for code, _, _ in got[:5]] == [0, 0, 0, 0, 1]     # scan: nobody answers
    assert got[5][0] == 0 and (tmp_path / "out" / "plc.dcf").exists()


def test_random_bytes_as_a_node_file_are_never_built(tmp_path):
    """Issue 26 item 7: 3000 random bytes as the drive's EDS were built (exit 0, the bytes
    written as drive.dcf with [DeviceComissioning], an empty drive.bin) while check said
    DCF008: now every command says DCF008 and exits 1, and nothing is written."""
    path = network(tmp_path, "junk.eds")
    (tmp_path / "junk.eds").write_bytes(bytes(range(256)) * 12)
    line = (f"{tmp_path}/junk.eds:1: error: the file looks binary, not like EDS/DCF text "
            "(312 control bytes in its first 3072, the first at byte 0x0) [DCF008]")
    for command, (code, stdout, stderr) in zip(COMMANDS, every_command(tmp_path, path)):
        assert code == 1, command
        assert line in (stdout + stderr).splitlines(), command
        assert "Traceback" not in stdout + stderr
    assert not (tmp_path / "out").exists()


def test_the_network_file_as_a_node_file(tmp_path):
    """The network file named as a node's EDS is known by its content (issue 26 item 15):
    one finding naming what it is, not one DCF002 per line."""
    path = network(tmp_path, "bus.yml")
    for command, (code, stdout, stderr) in zip(COMMANDS, every_command(tmp_path, path)):
        assert code == 1, command
        text = stdout + stderr
        assert (f"{tmp_path}/bus.yml:15: error: {tmp_path}/bus.yml is not DCF/EDS text (it "
                "looks like a YAML network file: dcf2bin network check, show, build, download "
                "and scan read it) [NET011]") in text.splitlines()
        assert "DCF002" not in text
    assert not (tmp_path / "out").exists()


def test_a_container_as_a_node_file_is_refused_by_its_content(tmp_path):
    """A binary container named drive.eds: check linted it as a container and passed
    (exit 0), build wrote an empty drive.bin. Now one NET011 line, exit 1, everywhere."""
    path = network(tmp_path, "drive.eds")
    assert run("compile", ROOT / "samples" / "plc.dcf", "-o",
               tmp_path / "drive.eds").exit_code == 0
    line = (f"{path}:15: error: {tmp_path}/drive.eds is a binary container, not DCF/EDS "
            "text; a network reads each node's EDS, DCF, XDD or XDC (dcf2bin bin2dcf turns a "
            "container into a DCF) [NET011]")
    for command, (code, stdout, stderr) in zip(COMMANDS, every_command(tmp_path, path)):
        assert code == 1, command
        assert line in (stdout + stderr).splitlines(), command
    assert not (tmp_path / "out").exists()


# io's TPDO1 made to produce the drive's TPDO1 COB-ID: an error only the network rules find
CLASH = "    1:\n      event_timer: 100\n"


def clash(tmp_path) -> str:
    path = network(tmp_path)
    text = (tmp_path / "bus.yml").read_text().replace(
        CLASH, "    1:\n      event_timer: 100\n      cob_id: 0x182\n")
    (tmp_path / "bus.yml").write_text(text)
    return path


def test_an_error_of_the_network_rules_fails_every_command(tmp_path):
    """Issue 26 item 8: show exited 0 where check exited 1 on an error only the rules of
    the network as a whole find (NET210 here). Same line, exit 1, in every command."""
    path = clash(tmp_path)
    line = (f"{path}:52: error: io (node 5) TPDO1 produces COB-ID 0x182, as drive (node 2) "
            f"TPDO1 at {path}:20 does [NET210]")
    for command, (code, stdout, stderr) in zip(COMMANDS, every_command(tmp_path, path)):
        assert code == 1, command
        assert line in (stdout + stderr).splitlines(), command


def test_show_draws_a_network_with_errors(tmp_path):
    """Issue 27: show drew nothing ("nothing shown") for a network with errors: now it
    draws it as configured, the errors on standard error, and exits 1."""
    path = clash(tmp_path)
    r = run("network", "show", path, "-q")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[:5] == [
        f"{path}: 3 nodes, 3 PDO COB-IDs, estimated bus load 6.6 % of 500 kbit/s", "",
        "COB-ID  frame      producer     consumers             bytes  rate   load    content",
        "0x080   SYNC       plc          drive                 0      100/s  1.10 %",
        "0x182   TPDO1      drive TPDO1  plc RPDO1, plc RPDO2  6      100/s  2.30 %  "
        "drive_status, drive_position"]
    assert r.stderr.splitlines()[-1] == f"{path}: 1 error; shown as configured"
    r = run("network", "show", path, "-f", "svg")
    assert r.exit_code == 1 and "<svg xmlns=" in r.stdout


def test_validate_warnings_are_checks_alone(tmp_path):
    """The other commands lint each node's file with validate's rules that can report an
    error; the warnings and infos of validate's rules stay check's."""
    path = network(tmp_path)
    eds = tmp_path / "IoX4_8AI.eds"
    eds.write_bytes(eds.read_bytes().replace(b"[FileInfo]\r\n", b"[FileInfo]\r\nOwner=me\r\n"))
    check = run("network", "check", path)
    show = run("network", "show", path)
    assert check.exit_code == show.exit_code == 0
    assert (f"{tmp_path}/IoX4_8AI.eds:2: warning: key 'Owner' is not defined by CiA 306 "
            "for [FileInfo] [DCF050]") in check.stdout.splitlines()
    assert show.stderr == ""


def test_build_select_and_ignore(tmp_path):
    """Issue 27: build takes --select/--ignore as check does. A rule of the network as a
    whole can be left out (the files are built); an error of the configuration cannot."""
    path = clash(tmp_path)
    r = run("network", "build", path, "-o", tmp_path / "out", "-q")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[-1] == "network build: 1 error, nothing written"
    r = run("network", "build", path, "-o", tmp_path / "out", "-q", "--ignore", "NET210")
    assert (r.exit_code, r.stderr) == (0, "")
    assert (tmp_path / "out" / "io.bin").exists()
    r = run("network", "build", path, "-o", tmp_path / "o2", "--select", "nope")
    assert r.exit_code == 2
    assert "'nope' matches no rule code, code prefix or rule name" in r.stderr


def test_build_cannot_ignore_a_binding_error(tmp_path):
    path = network(tmp_path, "junk.eds")
    (tmp_path / "junk.eds").write_bytes(bytes(range(256)) * 12)
    r = run("network", "build", path, "-o", tmp_path / "out", "-q", "--ignore", "DCF,NET")
    assert r.exit_code == 1
    assert "[DCF008]" in r.stderr
    assert not (tmp_path / "out").exists()


def test_build_strict_stops_on_a_warning(tmp_path):
    path = network(tmp_path, extra="  software_version: 2\n")
    r = run("network", "build", path, "-o", tmp_path / "out", "--strict")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[-1] == ("network build: 0 errors, 1 warning (--strict), "
                                         "nothing written")
    assert not (tmp_path / "out").exists()


def test_build_of_a_cpj_says_build_reads_yaml(tmp_path):
    """Issue 26 item 8: `network build x.cpj` answered "YAML syntax [NET001]"."""
    cpj = FIX / "check" / "network.cpj"
    r = run("network", "build", cpj, "-o", tmp_path / "out")
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{cpj}: error: build reads a YAML network file (lely's dcfgen, ros2_canopen's "
        "bus.yml): a .cpj project has no master and nothing to build (network check, show, "
        "download and scan read it) [NET012]",
        "network build: 1 error, nothing written"]


@pytest.mark.parametrize("command", ["show", "download"])
def test_a_lint_error_in_a_node_file_fails_every_command(tmp_path, command):
    """An error only validate's rules find, in an entry the network uses (the drive's
    0x1A00 mapping of a PDO the network links maps 0x6041 with 8 bits: DCF407)."""
    path = network(tmp_path)
    eds = tmp_path / "technosoft.eds"
    eds.write_bytes(eds.read_bytes().replace(b"DefaultValue=0x60410010",
                                             b"DefaultValue=0x60410008", 1))
    c = run("network", "check", path)
    other = run("network", command, path, *(["--dry-run"] if command == "download" else []))
    assert c.exit_code == other.exit_code == 1
    errors = [line for line in c.stdout.splitlines() if ": error: " in line]
    assert errors and all(e in other.stderr.splitlines() for e in errors)


# -- --select/--ignore/--strict in every command; what stops which (issue 26 item 8) --------

SUBCOMMANDS = ("check", "show", "build", "download", "scan", "lss", "upload")


def test_every_network_command_takes_select_ignore_and_strict():
    from dcf2bin.cli import network as group
    from dcf2bin.cli.network import SUBCOMMANDS as ALL_OF_THEM
    assert set(ALL_OF_THEM) == set(SUBCOMMANDS)
    for name in SUBCOMMANDS:
        cmd = group.network_group.get_command(None, name)
        opts = {o for p in cmd.params for o in p.opts}
        assert {"--select", "--ignore", "--strict"} <= opts, name


def _no_sync(tmp_path) -> str:
    """The golden network with the master's SYNC gone: the drive's synchronous PDOs have
    no SYNC producer (NET240, an error of the PDO plan, twice)."""
    path = network(tmp_path)
    text = (tmp_path / "bus.yml").read_text().replace("  sync_period: 10000\n", "")
    (tmp_path / "bus.yml").write_text(text)
    return path


NET240 = "but no node of the network produces SYNC [NET240]"


def test_ignore_silences_a_pdo_plan_error_in_every_command(tmp_path):
    """The same way to silence a finding everywhere: with --ignore NET240 every command
    does what it does on a clean network (scan: nobody answers, exit 1 as there)."""
    path = _no_sync(tmp_path)
    plain = every_command(tmp_path, path)
    assert [code for code, _, _ in plain] == [1, 1, 1, 1, 1, 1]
    for command, (_, stdout, stderr) in zip(COMMANDS, plain):
        assert NET240 in stdout + stderr, command
    ignored = []
    for command in COMMANDS:
        args = [a.replace("OUT", str(tmp_path / "out")) for a in command]
        r = run("network", args[0], path, *args[1:], "--ignore", "NET240")
        ignored.append(r.exit_code)
        assert NET240 not in r.stdout + r.stderr, command
    assert ignored == [0, 0, 0, 0, 1, 0]
    assert (tmp_path / "out" / "drive.bin").exists()


def test_download_stops_on_a_pdo_plan_error_and_strict_on_a_warning(tmp_path):
    path = _no_sync(tmp_path)
    r = run("network", "download", path, "--dry-run", "-q")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines()[-1] == f"{path}: 2 errors, nothing sent"
    path = network(tmp_path, extra="  software_version: 2\n")        # a warning
    r = run("network", "download", path, "--dry-run", "-q", "--strict")
    assert (r.exit_code, r.stdout) == (1, "")
    assert r.stderr.splitlines()[-1] == \
        f"{path}: 0 errors, 1 warning (--strict), nothing sent"
    assert run("network", "download", path, "--dry-run", "-q").exit_code == 0
    r = run("network", "show", path, "-q", "--strict")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[-1] == \
        f"{path}: 0 errors, 1 warning (--strict); shown as configured"
    assert run("network", "show", path, "-q").exit_code == 0


def test_scan_and_upload_are_not_stopped_by_the_pdo_plan(tmp_path):
    """They do not depend on the PDOs: the network's errors are reported as check reports
    them, the work is done (nobody answers on this bus), and they exit 1 as check would."""
    path = _no_sync(tmp_path)
    r = run("network", "scan", path, "-i", "virtual", "--listen", "0", "--timeout", "0.01",
            "-q")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[3:] == [
        f"{path}: 2 errors, which network scan does not depend on: the bus is scanned, and "
        "the exit status is 1",
        f"{path}:13: error: node 2 (drive) is in the network but does not answer",
        f"{path}:45: error: node 5 (io) is in the network but does not answer"]
    r = run("network", "scan", path, "-i", "virtual", "--listen", "0", "--timeout", "0.01",
            "-q", "--ignore", "NET240")
    assert r.exit_code == 1 and "NET240" not in r.stderr and "does not depend" not in r.stderr
    r = run("network", "upload", path, "-o", tmp_path / "up", "-i", "virtual", "--timeout",
            "0.01", "--retries", "0", "-q")
    assert r.exit_code == 1
    assert (f"{path}: 2 errors, which network upload does not depend on: the slaves are read "
            "back, and the exit status is 1") in r.stderr.splitlines()
    assert "did not answer" in r.stderr and not (tmp_path / "up").exists()


def test_a_node_id_given_twice_stops_them_whatever_ignore_says(tmp_path):
    path = network(tmp_path)
    text = (tmp_path / "bus.yml").read_text().replace("  node_id: 5\n", "  node_id: 2\n")
    (tmp_path / "bus.yml").write_text(text)
    for command, outcome in (("scan", "nothing scanned"), ("lss", "nothing changed"),
                             ("upload", "nothing read"), ("download", "nothing sent")):
        more = ["-o", str(tmp_path / "up")] if command == "upload" else []
        r = run("network", command, path, *more, "-i", "virtual", "--ignore", "NET2", "-q")
        assert r.exit_code == 1, command
        assert "[NET200]" in r.stderr, command
        assert r.stderr.splitlines()[-1].endswith(f", {outcome}"), command


def test_an_unreadable_network_file_is_io001_in_every_command(tmp_path):
    """Issue 26: `network show z.yml` (z.yml a link to /dev/zero) printed the error without
    its code, check with it: the same finding, exit 3, in every command."""
    z = tmp_path / "z.yml"
    z.symlink_to("/dev/zero")
    line = f"{z}: error: cannot read: a device, not a regular file [IO001]"
    for command in SUBCOMMANDS:
        more = ["-o", str(tmp_path / "o")] if command in ("build", "upload") else []
        r = run("network", command, z, *more)
        assert r.exit_code == 3, command
        assert line in (r.stdout + r.stderr).splitlines(), command
    assert not (tmp_path / "o").exists()


def test_the_warnings_of_the_output_folder_have_codes(tmp_path):
    """'written by an earlier build, not an output of this network: kept' had no code:
    NET130, which --ignore leaves out as any other."""
    path = network(tmp_path)
    out = tmp_path / "out"
    assert run("network", "build", path, "-o", out, "-q").exit_code == 0
    text = (tmp_path / "bus.yml").read_text()
    (tmp_path / "bus.yml").write_text(text[:text.index("\nio:")] + "\n")
    r = run("network", "build", path, "-o", out)
    assert (r.exit_code, r.stderr.splitlines()[:2]) == (0, [
        f"{out}/io.bin: warning: written by an earlier build, not an output of this network: "
        "kept (remove it if it is no longer needed) [NET130]",
        f"{out}/io.dcf: warning: written by an earlier build, not an output of this network: "
        "kept (remove it if it is no longer needed) [NET130]"])
    r = run("network", "build", path, "-o", out, "--ignore", "NET130")
    assert (r.exit_code, r.stderr) == (0, f"network build: 3 files in {out}: plc.dcf and 1 "
                                          "slave for a PLC master, 2 links, 4 variables\n")


def test_a_node_file_named_dev_stdin_is_never_this_process_input(tmp_path):
    """`dcf: /dev/stdin` in a network file read the EDS piped into dcf2bin (exit 0): a name
    written in a file is a path like any other there, and standard input a FIFO."""
    import subprocess
    import sys
    path = network(tmp_path, "/dev/stdin")
    r = subprocess.run([sys.executable, "-m", "dcf2bin", "network", "check", path],
                       input=(FIX / "technosoft.eds").read_bytes(), capture_output=True,
                       timeout=60)
    assert (r.returncode, r.stdout.decode().splitlines()[0]) == (
        3, f"{path}:15: error: cannot read /dev/stdin: a FIFO, not a regular file [NET010]")


def test_a_device_description_as_the_network_file_says_what_it_is(tmp_path):
    """`network check ts.eds` answered `YAML syntax: did not find expected <document
    start> [NET001]`, `network build p.xpd` "mapping values are not allowed": the file's
    kind (as validate names a network file given to it), in one line, with the code of a
    network file that cannot be read, exit 3, nothing written -- in every command."""
    eds = tmp_path / "ts.eds"
    eds.write_text("[FileInfo]\nFileName=ts.eds\n\n[DeviceInfo]\nVendorNumber=0x1\n")
    xpd = tmp_path / "p.xpd"
    shutil.copy(ROOT / "tests" / "fixtures" / "convert" / "small.xdd", xpd)
    said = {eds: "DCF/EDS text", xpd: "CiA 311 XML (XDD/XDC)"}
    for path, kind in said.items():
        line = (f"{path}: error: {path} is {kind}, not a YAML network file or a CiA 306-3 "
                "network project; a network file names it as a node's dcf: (dcf2bin validate "
                "checks it, compile makes a container of it) [IO001]")
        for command in SUBCOMMANDS:
            more = ["-o", str(tmp_path / "o")] if command in ("build", "upload") else []
            r = run("network", command, path, *more)
            assert r.exit_code == 3, command
            got = [t for t in (r.stdout + r.stderr).splitlines() if "error:" in t]
            assert got == [line], command
    assert not (tmp_path / "o").exists()
