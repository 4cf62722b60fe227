"""dcf2bin.fileio, the one place every command reads and writes (issue 26): the bounded
reader (items 1-2: a device or a FIFO as any input ends at once, exit 3), outputs
checked before slow work, ``-o ''`` a usage error, messages that start with the file
name, ``--timeout`` saying what a time is (item 18), and the all-or-nothing writer's own
cases (tests/test_build_atomic.py has the command's)."""
from __future__ import annotations

import errno
import json
import os
import shutil
import subprocess
import sys
import threading

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES
from dcf2bin.cli import main
from dcf2bin import fileio

try:
    import resource
except ImportError:  # not on Windows
    resource = None

NET = ROOT / "tests" / "fixtures" / "network" / "check"
posix_only = pytest.mark.skipif(not hasattr(os, "mkfifo") or not os.path.exists("/dev/zero"),
                                reason="needs os.mkfifo and /dev/zero (POSIX)")


def run(*args, **kw):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False, **kw)


# -- the bounded reader ------------------------------------------------------------------------

@posix_only
def test_a_device_or_a_fifo_is_refused_before_a_byte_is_read(tmp_path):
    os.symlink("/dev/zero", tmp_path / "z.yml")
    os.mkfifo(tmp_path / "n.yml")
    (tmp_path / "d.yml").mkdir()
    for name, exc, text in (("z.yml", fileio.NotARegularFile, "a device, not a regular file"),
                            ("n.yml", fileio.NotARegularFile, "a FIFO, not a regular file"),
                            ("d.yml", IsADirectoryError, "Is a directory")):
        with pytest.raises(exc) as got:
            fileio.read_file(str(tmp_path / name))
        assert (got.value.strerror, got.value.filename) == (text, str(tmp_path / name))


def test_a_file_over_the_limit_is_refused(tmp_path):
    big = tmp_path / "big.dcf"
    with open(big, "wb") as f:
        f.truncate(fileio.MAX_INPUT + 1)            # sparse: costs no disk
    with pytest.raises(fileio.InputTooLarge) as got:
        fileio.read_file(str(big))
    assert got.value.strerror == "larger than 64 MiB (the input limit)"
    assert fileio.read_file(str(big), limit=fileio.MAX_INPUT + 1)[-1:] == b"\0"
    small = tmp_path / "small"
    small.write_bytes(b"12345")
    assert fileio.read_file(str(small), limit=5) == b"12345"
    with pytest.raises(fileio.InputTooLarge):
        fileio.read_file(str(small), limit=4)


def test_a_stream_is_bounded_too():
    import io
    assert fileio.read_stream(io.BytesIO(b"abc"), "<stdin>", limit=3) == b"abc"
    with pytest.raises(fileio.InputTooLarge) as got:
        fileio.read_stream(io.BytesIO(b"abcd"), "<stdin>", limit=3)
    assert (got.value.strerror, got.value.filename) == ("larger than 3 bytes (the input limit)",
                                                        "<stdin>")


@pytest.mark.skipif(not os.path.isdir("/proc/self/fd"), reason="needs /proc/self/fd")
def test_a_descriptor_path_is_read_from_the_open_descriptor(tmp_path):
    """/dev/fd/N of a pipe whose writer is gone (a shell's <(...) after its command
    ended): read from the descriptor itself, never opened again (a FIFO's open would
    wait for a writer that never comes)."""
    r, w = os.pipe()
    os.write(w, b"[FileInfo]\n")
    os.close(w)
    try:
        assert fileio.read_file(f"/dev/fd/{r}") == b"[FileInfo]\n"
    finally:
        os.close(r)
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    fd = os.open(fifo, os.O_RDWR)             # a FIFO this process holds open
    os.write(fd, b"x" * 10)
    try:
        with pytest.raises(fileio.InputTooLarge):
            fileio.read_file(f"/proc/self/fd/{fd}", limit=9)
    finally:
        os.close(fd)
    # a name inside a file (DownloadFile) never reads this process's descriptors
    with pytest.raises(OSError):
        fileio.read_file("/dev/fd/0", descriptors=False, limit=1)


# A child that runs each network subcommand on each hostile network file, in one process
# bounded in time and memory: before, a FIFO hung show/build/download/scan/check and
# /dev/zero ate memory until MemoryError (exit 70).
_MATRIX = r"""
import json, sys
from click.testing import CliRunner
from dcf2bin.cli import main
out = []
for args in json.loads(sys.argv[1]):
    r = CliRunner().invoke(main, args)
    out.append([args, r.exit_code, r.stdout, r.stderr])
print(json.dumps(out))
"""

_SUBCOMMANDS = [["show"], ["build", "-o", "out"], ["download", "--dry-run"],
                ["scan", "-i", "virtual"], ["check"]]


def bounded(calls: list[list[str]], cwd) -> list:
    """Run each command line in one child process (click's runner), bounded in time and
    memory, so that a read that never ends fails the test, not the test run; each
    call's [args, exit code, stdout, stderr]."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NO_COLOR": "1"}
    limit = (lambda: resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))) \
        if resource else None
    proc = subprocess.run([sys.executable, "-c", _MATRIX, json.dumps(calls)], cwd=cwd,
                          env=env, capture_output=True, text=True, timeout=120,
                          preexec_fn=limit)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


@posix_only
def test_every_network_subcommand_ends_at_once_on_a_device_or_a_fifo(tmp_path):
    os.symlink("/dev/zero", tmp_path / "z.yml")
    os.mkfifo(tmp_path / "n.yml")
    calls = [["network", cmd[0], name, *cmd[1:]] for cmd in _SUBCOMMANDS
             for name in ("z.yml", "n.yml")]
    why = {"z.yml": "a device, not a regular file", "n.yml": "a FIFO, not a regular file"}
    for args, code, stdout, stderr in bounded(calls, tmp_path):
        name = args[2]
        line = f"{name}: error: cannot read: {why[name]}"
        if args[1] == "check":        # the report is check's result: on standard output
            assert (code, stdout, stderr) == (
                3, f"{line} [IO001]\n1 error, 0 warnings, 0 infos in 1 file\n", ""), args
        else:                         # the same finding, IO001, as the other findings
            assert (code, stdout, stderr) == (3, "", f"{line} [IO001]\n    hint: check the "
                                              "path and its permissions\n"), args
    assert not (tmp_path / "out").exists()


@posix_only
def test_other_inputs_read_through_the_same_reader(tmp_path):
    """The main input of other commands, --static-od, and a .cpj project's node file."""
    os.symlink("/dev/zero", tmp_path / "z.dcf")
    shutil.copytree(NET, tmp_path / "net")
    os.unlink(tmp_path / "net" / "io.dcf")
    os.symlink("/dev/zero", tmp_path / "net" / "io.dcf")
    calls = [["compile", "z.dcf", "-o", "-"], ["validate", "z.dcf"], ["dump", "z.dcf"],
             ["map", "z.dcf"], ["compile", str(SAMPLES / "plc.dcf"), "--static-od", "z.dcf",
                                "-o", "-"],
             ["network", "show", "net/network.cpj"]]
    for args, code, stdout, stderr in bounded(calls, tmp_path):
        assert code == 3, args
        assert "cannot read" in stdout + stderr, args
        assert "a device, not a regular file" in stdout + stderr, args


# -- outputs: checked first, an empty name, messages that start with the file ----------------

def test_scan_checks_its_output_before_opening_the_bus(tmp_path, monkeypatch):
    import dcf2bin.cli.network.scan as scan
    opened = []
    monkeypatch.setattr(scan, "open_bus", lambda *a: opened.append(a))
    r = run("network", "scan", NET / "bus.yml", "-i", "virtual", "-o",
            tmp_path / "missing" / "x.txt")
    assert opened == []
    assert (r.exit_code, r.stderr) == (
        3, f"{tmp_path}/missing/x.txt: error: cannot write: No such file or directory\n")


def test_scan_refuses_an_output_over_its_network_file(tmp_path, monkeypatch):
    import dcf2bin.cli.network.scan as scan
    monkeypatch.setattr(scan, "open_bus", lambda *a: pytest.fail("the bus was opened"))
    shutil.copytree(NET, tmp_path / "net")
    bus = tmp_path / "net" / "bus.yml"
    r = run("network", "scan", bus, "-i", "virtual", "-o", bus)
    assert (r.exit_code, r.stderr) == (
        2, f"{bus}: error: the output is the input file; refusing to overwrite it\n")


@pytest.mark.parametrize("cmd", ["download", "network download"])
def test_download_checks_standard_output_before_the_bus(cmd):
    """With standard output closed, the summary could not be written: said at once
    (before, after the whole download)."""
    args = ([str(SAMPLES / "plc.dcf"), "-n", "3"] if cmd == "download"
            else [str(NET / "bus.yml")])
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NO_COLOR": "1"}
    proc = subprocess.run([sys.executable, "-m", "dcf2bin", *cmd.split(), *args, "-i",
                           "socketcan", "--channel", "no-such-can9"], stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True, env=env, timeout=60,
                          preexec_fn=lambda: os.close(1))
    assert (proc.returncode, proc.stderr) == (
        3, "<stdout>: error: cannot write: standard output is closed\n")


@pytest.mark.parametrize("args", [
    ["compile", str(SAMPLES / "plc.dcf")], ["dump", str(SAMPLES / "plc.bin")],
    ["validate", str(SAMPLES / "plc.dcf")], ["tunnel", "1=2"],
    ["network", "show", str(NET / "bus.yml")], ["network", "check", str(NET / "bus.yml")],
    ["network", "scan", str(NET / "bus.yml"), "-i", "virtual"],
])
def test_an_empty_output_name_is_a_usage_error(args):
    r = run(*args, "-o", "")
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == ("Error: Invalid value for '-o' / '--output': an empty "
                                         "name is not a file (use '-' for standard output)")


def test_the_input_file_message_starts_with_the_file(tmp_path):
    src = tmp_path / "plc.dcf"
    shutil.copy(SAMPLES / "plc.dcf", src)
    r = run("compile", src, "--from", "dcf", "-o", src)
    assert (r.exit_code, r.stderr) == (
        2, f"{src}: error: the output is the input file; refusing to overwrite it\n")


# -- --timeout: what a time is ------------------------------------------------------------------

@pytest.mark.parametrize("value, message", [
    ("0x1", "'0x1' is not a time in seconds (a decimal number such as 0.5 or 2)"),
    ("inf", "'inf' is not a time in seconds (a decimal number such as 0.5 or 2)"),
    ("nan", "'nan' is not a time in seconds (a decimal number such as 0.5 or 2)"),
    ("0", "0 is not in the range 0.001<=x<=86400 seconds"),
    ("1e9", "1e9 is not in the range 0.001<=x<=86400 seconds"),
    # the value as messages quote one: never unbounded (issue 26 item 3)
    ("1" * 1000, f"'{'1' * 40}...{'1' * 12} (1000 characters)' is not a time in seconds (a "
                 "decimal number such as 0.5 or 2)"),
    ("9" * 5000, f"'{'9' * 40}...{'9' * 12} (5000 characters)' is not a time in seconds (a "
                 "decimal number such as 0.5 or 2)"),
])
@pytest.mark.parametrize("cmd", ["download", "network download", "network scan"])
def test_a_bad_time_says_what_a_time_is(cmd, value, message):
    target = [str(SAMPLES / "plc.dcf"), "-n", "3"] if cmd == "download" else \
        [str(NET / "bus.yml")]
    r = run(*cmd.split(), *target, "--timeout", value, "--dry-run" if "scan" not in cmd
            else "--retries=0")
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == f"Error: Invalid value for '--timeout': {message}"


def test_every_timeout_option_is_a_time():
    from dcf2bin.cli.common import Seconds
    from test_cli_vocabulary import COMMANDS
    found = [(name, p.name) for name, cmd in COMMANDS.items() for p in cmd.params
             if p.name in ("timeout", "listen")]
    assert found and all(isinstance(p.type, Seconds) for name, cmd in COMMANDS.items()
                         for p in cmd.params if p.name in ("timeout", "listen")), found
    assert Seconds(0.001).convert(" 0.25 ", None, None) == 0.25
    assert Seconds(0.001).convert("2", None, None) == 2.0
    assert Seconds(0.001).convert("1.5e-3", None, None) == 0.0015


# -- the all-or-nothing writer, on its own ------------------------------------------------------

def _set(folder, **files):
    return fileio.OutputSet(str(folder), [(n.replace("_", "."), d) for n, d in files.items()])


def test_a_set_replaces_its_files_and_keeps_their_modes(tmp_path):
    (tmp_path / "a.bin").write_bytes(b"old")
    os.chmod(tmp_path / "a.bin", 0o640)
    report = _set(tmp_path, a_bin=b"A", b_dcf=b"B").write()
    assert report.written == [f"{tmp_path}/a.bin", f"{tmp_path}/b.dcf"]
    assert (tmp_path / "a.bin").read_bytes() == b"A" and (tmp_path / "b.dcf").read_bytes() == b"B"
    assert oct(os.stat(tmp_path / "a.bin").st_mode & 0o777) == oct(0o640)
    assert sorted(p.name for p in tmp_path.iterdir()) == [".dcf2bin-build.lock", "a.bin",
                                                          "b.dcf"]


def test_a_failed_rename_puts_every_file_back(tmp_path, monkeypatch):
    """The third rename fails: the two files already renamed get their old files back
    (the same inodes), the new one is removed, no temporary file is left."""
    for name in ("a", "b"):
        (tmp_path / name).write_bytes(b"old " + name.encode())
    inodes = {n: os.stat(tmp_path / n).st_ino for n in ("a", "b")}
    real, done = os.replace, []

    def replace(src, dst, **kw):
        if os.path.basename(src).endswith(".tmp") and ".dcf2bin-build" not in src:
            if len(done) == 2:
                raise OSError(errno.EIO, "Input/output error")
            done.append(dst)
        return real(src, dst, **kw)
    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(OSError) as got:
        fileio.OutputSet(str(tmp_path), [("a", b"A"), ("b", b"B"), ("c", b"C")]).write()
    monkeypatch.undo()
    assert (got.value.strerror, got.value.filename) == ("Input/output error",
                                                        f"{tmp_path}/c")
    assert sorted(p.name for p in tmp_path.iterdir()) == [".dcf2bin-build.lock", "a", "b"]
    assert {n: ((tmp_path / n).read_bytes(), os.stat(tmp_path / n).st_ino) for n in "ab"} == {
        "a": (b"old a", inodes["a"]), "b": (b"old b", inodes["b"])}


def test_without_hard_links_the_old_files_are_moved_aside_and_back(tmp_path, monkeypatch):
    """Where the file system has no hard links, an old file is renamed aside just before
    its replacement, and renamed back when the set fails."""
    def no_link(*a, **k):
        raise OSError(errno.EPERM, "Operation not permitted")
    monkeypatch.setattr(os, "link", no_link)
    fileio.OutputSet(str(tmp_path), [("a", b"A1"), ("b", b"B1")]).write()
    assert (tmp_path / "a").read_bytes() == b"A1"
    inodes = {n: os.stat(tmp_path / n).st_ino for n in "ab"}
    real_replace, failed = os.replace, []

    def replace(src, dst, **kw):
        real_replace(src, dst, **kw)
        if os.path.basename(dst) == "b" and not failed:
            failed.append(dst)                  # b's new file is in place, then an error
            raise OSError(errno.EIO, "Input/output error")
    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(OSError):
        fileio.OutputSet(str(tmp_path), [("a", b"A2"), ("b", b"B2")]).write()
    monkeypatch.undo()
    assert {n: ((tmp_path / n).read_bytes(), os.stat(tmp_path / n).st_ino) for n in "ab"} == {
        "a": (b"A1", inodes["a"]), "b": (b"B1", inodes["b"])}
    assert sorted(p.name for p in tmp_path.iterdir()) == [".dcf2bin-build.lock", "a", "b"]


def test_a_symlink_at_an_outputs_name_is_followed(tmp_path):
    real = tmp_path / "elsewhere"
    real.mkdir()
    (real / "a.bin").write_bytes(b"old")
    out = tmp_path / "out"
    out.mkdir()
    os.symlink(real / "a.bin", out / "a.bin")
    fileio.OutputSet(str(out), [("a.bin", b"new")]).write()
    assert os.path.islink(out / "a.bin") and (real / "a.bin").read_bytes() == b"new"
    assert sorted(p.name for p in real.iterdir()) == ["a.bin"]


@posix_only
def test_a_fifo_at_an_outputs_name_is_refused(tmp_path):
    os.mkfifo(tmp_path / "a.bin")
    with pytest.raises(OSError) as got:
        fileio.OutputSet(str(tmp_path), [("a.bin", b"x")]).check()
    assert (got.value.strerror, got.value.filename) == ("a FIFO, not a regular file",
                                                        f"{tmp_path}/a.bin")


def test_an_input_by_a_hard_link_is_refused(tmp_path):
    (tmp_path / "in.dcf").write_bytes(b"x")
    os.link(tmp_path / "in.dcf", tmp_path / "out.dcf")
    with pytest.raises(fileio.OutputIsInput):
        fileio.OutputSet(str(tmp_path), [("out.dcf", b"y")], inputs=[str(tmp_path / "in.dcf")]).check()
    assert (tmp_path / "in.dcf").read_bytes() == b"x"


@pytest.mark.parametrize("name", ["", ".", "..", "a/b", ".dcf2bin-build.lock", "a\0b"])
def test_a_name_that_is_not_a_plain_file_name_is_a_programming_error(tmp_path, name):
    with pytest.raises(ValueError):
        fileio.OutputSet(str(tmp_path), [(name, b"")])


def test_a_folder_made_for_a_set_that_fails_is_removed(tmp_path, monkeypatch):
    def full(fd):
        raise OSError(errno.ENOSPC, "No space left on device")
    monkeypatch.setattr(os, "fsync", full)
    with pytest.raises(OSError):
        fileio.OutputSet(str(tmp_path / "new" / "deeper"), [("a", b"A")]).write()
    monkeypatch.undo()
    assert list(tmp_path.iterdir()) == []


def test_a_waiting_writer_is_told_once(tmp_path):
    import fcntl
    fileio.OutputSet(str(tmp_path), [("a", b"1")]).write()
    fd = os.open(tmp_path / ".dcf2bin-build.lock", os.O_RDWR)
    fcntl.flock(fd, fcntl.LOCK_EX)
    waited = threading.Event()

    def on_wait():
        waited.set()
    done = []
    t = threading.Thread(target=lambda: done.append(
        fileio.OutputSet(str(tmp_path), [("a", b"2")], on_wait=on_wait).write()))
    t.start()
    try:
        assert waited.wait(30)
        assert (tmp_path / "a").read_bytes() == b"1"
    finally:
        os.close(fd)
        t.join(30)
    assert done and (tmp_path / "a").read_bytes() == b"2"
