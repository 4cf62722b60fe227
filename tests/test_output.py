"""Output handling, the same for every command (issue 10, items 9-15): file modes,
symlinks, devices and FIFOs, full disks and closed or broken standard streams, signals
while writing, inputs that must never be overwritten, names that are not UTF-8."""
from __future__ import annotations

import json
import os
import signal
import stat
import subprocess
import sys
import threading
import time

import pytest
from click.testing import CliRunner
from conftest import SAMPLES

from dcf2bin.cli import main

BILD8 = SAMPLES / "bild8.dcf"
BILD8_BIN = SAMPLES / "bild8.bin"
BAD_TEXT = "[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=300\n"
ENV = {**os.environ, "NO_COLOR": "1"}
is_root = pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() != 0,
                             reason="creating device nodes needs root")


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


def dcf2bin(*args, **kw):
    """Run the real program (its own process, real file descriptors)."""
    kw.setdefault("env", ENV)
    kw.setdefault("check", False)
    return subprocess.run([sys.executable, "-m", "dcf2bin", *map(os.fsdecode, args)], **kw)


def temps(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".dcf2bin-"))


# One call per command that writes an output, all before '-o': each succeeds (exit 0).
def _commands(tmp_path):
    bad_free = tmp_path / "in.dcf"
    bad_free.write_bytes(BILD8.read_bytes())
    clean = tmp_path / "plc.dcf"
    clean.write_bytes((SAMPLES / "plc.dcf").read_bytes())
    return {
        "compile": ["compile", bad_free],
        "dump": ["dump", BILD8_BIN],
        "bin2dcf": ["bin2dcf", BILD8_BIN],
        "export": ["export", "--format", "lenze-st", bad_free],
        "validate": ["validate", clean],
        "tunnel": ["tunnel", "0x1A=1"],
        "simulate": ["simulate", BILD8_BIN],
        "download": ["download", SAMPLES / "device.dcf", "--node", "3", "--dry-run"],
    }


COMMANDS = ["compile", "dump", "bin2dcf", "export", "validate", "tunnel"]
# the commands whose result goes to standard output with no -o (simulate: a report)
STDOUT_ONLY = ["simulate", "download"]


# -- item 9: modes ------------------------------------------------------------------------------

@pytest.mark.parametrize("umask, mode", [(0o022, 0o644), (0o002, 0o664), (0o077, 0o600)],
                         ids=["022", "002", "077"])
def test_a_new_file_gets_the_mode_of_the_umask(tmp_path, umask, mode):
    old = os.umask(umask)
    try:
        r = run("compile", BILD8, "-o", tmp_path / "new.bin")
    finally:
        os.umask(old)
    assert r.exit_code == 0, r.stderr
    assert stat.S_IMODE(os.stat(tmp_path / "new.bin").st_mode) == mode


@pytest.mark.parametrize("name", COMMANDS)
def test_an_overwritten_file_keeps_its_mode(tmp_path, name):
    out = tmp_path / "out"
    out.write_bytes(b"old")
    os.chmod(out, 0o640)
    old = os.umask(0o077)
    try:
        r = run(*_commands(tmp_path)[name], "-o", out)
    finally:
        os.umask(old)
    assert r.exit_code == 0, r.stderr
    assert out.read_bytes() != b"old"
    assert stat.S_IMODE(os.stat(out).st_mode) == 0o640
    assert temps(tmp_path) == []


# -- item 10: symlinks, FIFOs, devices ----------------------------------------------------------

def test_a_symlink_is_followed_and_stays_a_link(tmp_path):
    real_dir = tmp_path / "real"
    real_dir.mkdir()
    target = real_dir / "target.bin"
    target.write_bytes(b"old")
    link = tmp_path / "link.bin"
    link.symlink_to(target)
    r = run("compile", BILD8, "-o", link)
    assert r.exit_code == 0, r.stderr
    assert link.is_symlink() and os.readlink(link) == str(target)
    assert target.read_bytes() == BILD8_BIN.read_bytes()
    # the temporary file was made beside the real target, and is gone
    assert temps(tmp_path) == [] and temps(real_dir) == []


def _release_reader(fifo, reader: threading.Thread, deadline: float = 10) -> None:
    """End a reader thread blocked on ``fifo`` without ever blocking the test: a writer
    is opened only without blocking (ENXIO when no reader has the FIFO open -- the reader
    has read its EOF and is about to end), and the thread is joined with a deadline. A
    blocking open here could wait for ever for a reader that is already gone."""
    end = time.monotonic() + deadline
    while reader.is_alive() and time.monotonic() < end:
        try:
            fd = os.open(fifo, os.O_WRONLY | os.O_NONBLOCK)
        except OSError:             # ENXIO: no reader (any more)
            pass
        else:
            os.close(fd)            # a reader waiting in open() now reads EOF
        reader.join(0.05)
    assert not reader.is_alive(), "the FIFO's reader never ended"


def test_a_fifo_is_written_directly(tmp_path):
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    got = []
    reader = threading.Thread(target=lambda: got.append(open(fifo, "rb").read()), daemon=True)
    reader.start()
    try:
        r = run("compile", BILD8, "-o", fifo)
    finally:
        _release_reader(fifo, reader)
    assert r.exit_code == 0, r.stderr
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    assert got == [BILD8_BIN.read_bytes()]
    assert temps(tmp_path) == []


@pytest.mark.skipif(not os.path.exists("/dev/stdout"), reason="needs /dev/stdout")
@pytest.mark.parametrize("into", ["pipe", "file"])
def test_dev_stdout_is_written_directly(tmp_path, into):
    """-o /dev/stdout names this process's standard output: a pipe or the file the shell
    opened, never a path to put a temporary file beside."""
    if into == "pipe":
        out = dcf2bin("compile", BILD8, "-o", "/dev/stdout", capture_output=True)
        got = out.stdout
    else:
        with open(tmp_path / "shell.bin", "wb") as f:
            out = dcf2bin("compile", BILD8, "-o", "/dev/stdout", stdout=f,
                          stderr=subprocess.PIPE)
        got = (tmp_path / "shell.bin").read_bytes()
    assert out.returncode == 0, out.stderr
    assert got == BILD8_BIN.read_bytes()
    assert temps(tmp_path) == []


@is_root
def test_a_character_device_is_written_directly(tmp_path):
    null = tmp_path / "null"
    os.mknod(null, stat.S_IFCHR | 0o666, os.makedev(1, 3))      # like /dev/null
    r = run("compile", BILD8, "-o", null)
    assert r.exit_code == 0, r.stderr
    assert stat.S_ISCHR(os.lstat(null).st_mode)


@is_root
def test_a_full_device_is_exit_3_and_stays_a_device(tmp_path):
    full = tmp_path / "full"
    os.mknod(full, stat.S_IFCHR | 0o666, os.makedev(1, 7))      # like /dev/full
    r = run("compile", BILD8, "-o", full)
    assert r.exit_code == 3
    assert r.stderr == f"{full}: error: cannot write: No space left on device\n"
    assert stat.S_ISCHR(os.lstat(full).st_mode)
    assert temps(tmp_path) == []


# -- item 11: a full or closed standard output --------------------------------------------------

@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("name", COMMANDS)
def test_stdout_on_a_full_device_is_exit_3_with_one_line(tmp_path, name):
    with open("/dev/full", "wb") as full:
        out = dcf2bin(*_commands(tmp_path)[name], "-o", "-", stdout=full,
                      stderr=subprocess.PIPE, text=True)
    assert out.returncode == 3, out.stderr
    assert out.stderr.splitlines()[-1] == "<stdout>: error: cannot write: No space left on device"
    assert "Traceback" not in out.stderr and "Exception ignored" not in out.stderr


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("name", STDOUT_ONLY)
def test_a_report_on_a_full_device_is_exit_3(tmp_path, name):
    with open("/dev/full", "wb") as full:
        out = dcf2bin(*_commands(tmp_path)[name], stdout=full, stderr=subprocess.PIPE,
                      text=True)
    assert out.returncode == 3, out.stderr
    assert out.stderr.splitlines()[-1] == "<stdout>: error: cannot write: No space left on device"


@pytest.mark.parametrize("name", STDOUT_ONLY)
def test_a_report_to_a_closed_stdout_is_exit_3(tmp_path, name):
    out = dcf2bin(*_commands(tmp_path)[name], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                  text=True, preexec_fn=lambda: os.close(1))
    assert out.returncode == 3, out.stderr
    assert out.stderr.splitlines()[-1] == ("<stdout>: error: cannot write: standard output "
                                           "is closed")


@pytest.mark.parametrize("name", COMMANDS)
def test_a_closed_stdout_is_exit_3_with_one_line(tmp_path, name):
    out = dcf2bin(*_commands(tmp_path)[name], "-o", "-", stdout=subprocess.DEVNULL,
                  stderr=subprocess.PIPE, text=True, preexec_fn=lambda: os.close(1))
    assert out.returncode == 3, out.stderr
    assert out.stderr.splitlines()[-1] == ("<stdout>: error: cannot write: standard output "
                                           "is closed")


# -- item 12: a broken pipe never hides a failure -----------------------------------------------

def _broken_pipe():
    """A pipe whose read end is already closed: every write gets EPIPE."""
    r, w = os.pipe()
    os.close(r)
    return w


def test_compile_errors_into_a_broken_pipe_still_exit_1(tmp_path):
    bad = tmp_path / "bad.dcf"
    bad.write_text(BAD_TEXT)
    w = _broken_pipe()
    try:          # compile bad.dcf 2>&1 | head -0
        out = dcf2bin("compile", bad, "-o", tmp_path / "bad.bin", stdout=w, stderr=w)
    finally:
        os.close(w)
    assert out.returncode == 1
    assert not (tmp_path / "bad.bin").exists()


def test_validate_findings_into_a_broken_pipe_exit_1_quietly(tmp_path):
    bad = tmp_path / "bad.dcf"
    bad.write_text(BAD_TEXT)
    w = _broken_pipe()
    try:
        out = dcf2bin("validate", bad, stdout=w, stderr=subprocess.PIPE, text=True)
    finally:
        os.close(w)
    assert (out.returncode, out.stderr) == (1, "")


@pytest.mark.parametrize("name", ["dump", "bin2dcf", "export", "tunnel"])
def test_a_successful_run_into_a_broken_pipe_exits_0_without_noise(tmp_path, name):
    w = _broken_pipe()
    try:
        out = dcf2bin(*_commands(tmp_path)[name], "-o", "-", stdout=w,
                      stderr=subprocess.PIPE, text=True)
    finally:
        os.close(w)
    assert (out.returncode, out.stderr) == (0, "")


# -- item 13: signals and fsync -----------------------------------------------------------------

_SLOW_RENAME = """
import os, signal, sys, time
# a test runner started in the background may hand down ignored signals: start as a shell would
signal.signal(signal.SIGINT, signal.default_int_handler)
signal.signal(signal.SIGTERM, signal.SIG_DFL)
signal.signal(signal.SIGHUP, signal.SIG_DFL)
marker = sys.argv[1]
def slow_replace(a, b):
    open(marker, "w").close()
    time.sleep(30)
os.replace = slow_replace
from dcf2bin.cli import main
main(sys.argv[2:], prog_name="dcf2bin")
"""


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT, signal.SIGHUP],
                         ids=["SIGTERM", "SIGINT", "SIGHUP"])
def test_a_signal_while_writing_leaves_no_temporary_file(tmp_path, sig):
    marker = tmp_path / "writing"
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    proc = subprocess.Popen([sys.executable, "-c", _SLOW_RENAME, str(marker), "compile",
                             str(BILD8), "-o", str(out_dir / "x.bin")],
                            env=ENV, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not marker.exists() and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.02)
        assert marker.exists(), "the write never started"
        assert len(temps(out_dir)) == 1          # the temporary file exists now
        proc.send_signal(sig)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 128 + sig, err
    assert temps(out_dir) == [] and not (out_dir / "x.bin").exists()
    assert "Traceback" not in err


def test_the_file_and_its_folder_are_fsynced_before_the_rename(tmp_path, monkeypatch):
    from dcf2bin.cli import common
    events = []
    real_fsync, real_replace = os.fsync, os.replace

    def fsync(fd):
        events.append(("fsync", stat.S_ISDIR(os.fstat(fd).st_mode)))
        real_fsync(fd)

    def replace(a, b):
        events.append(("rename", None))
        real_replace(a, b)
    monkeypatch.setattr(common.os, "fsync", fsync)
    monkeypatch.setattr(common.os, "replace", replace)
    r = run("compile", BILD8, "-o", tmp_path / "x.bin")
    assert r.exit_code == 0
    assert events == [("fsync", False), ("rename", None), ("fsync", True)]


# -- item 14: every input is protected ----------------------------------------------------------

def _writes(tmp_path):
    f = tmp_path / "x.writes"
    f.write_text("0x2200 0 UNSIGNED32 0x1A rw\n")
    return f


@pytest.mark.parametrize("case", ["append", "static-od", "eds", "hardlink", "validate-dir"])
def test_no_output_over_any_input(tmp_path, case):
    if case == "append":
        victim = _writes(tmp_path)
        args = ["compile", BILD8, "--append", victim, "-o", victim]
    elif case == "static-od":
        victim = tmp_path / "static.eds"
        victim.write_bytes((SAMPLES / "device.dcf").read_bytes())
        args = ["compile", BILD8, "--static-od", victim, "-o", victim]
    elif case == "eds":
        victim = tmp_path / "dev.eds"
        victim.write_bytes((SAMPLES / "device.dcf").read_bytes())
        args = ["bin2dcf", BILD8_BIN, "--eds", victim, "-o", victim]
    elif case == "validate-dir":      # a file found in a folder is an input too
        (tmp_path / "cfg").mkdir()
        victim = tmp_path / "cfg" / "plc.dcf"
        victim.write_bytes((SAMPLES / "plc.dcf").read_bytes())
        args = ["validate", tmp_path / "cfg", "-o", victim]
    else:
        victim = tmp_path / "in.dcf"
        victim.write_bytes(BILD8.read_bytes())
        os.link(victim, tmp_path / "same.bin")
        args = ["compile", victim, "-o", tmp_path / "same.bin"]
    before = victim.read_bytes()
    r = run(*args)
    assert r.exit_code == 2
    assert r.stderr.endswith("is the input file; refusing to overwrite it\n")
    assert victim.read_bytes() == before
    assert temps(tmp_path) == []


# -- item 15: names that are not UTF-8 ----------------------------------------------------------

@pytest.mark.skipif(sys.platform != "linux", reason="needs a file system that takes any bytes")
@pytest.mark.parametrize("fmt", ["text", "json", "sarif", "github"])
def test_a_name_that_is_not_utf8_is_escaped_alike_in_every_format(tmp_path, fmt):
    name = os.path.join(os.fsencode(tmp_path), b"caf\xe9.dcf")
    with open(name, "wb") as f:
        f.write(BAD_TEXT.encode())
    out = dcf2bin("validate", "--select", "DCF200", "--format", fmt, name,
                  capture_output=True, cwd=tmp_path)
    assert out.returncode == 1, out.stderr
    text = out.stdout.decode("utf-8")          # valid UTF-8, or this raises
    escaped = os.path.join(str(tmp_path), "caf\\xe9.dcf")
    if fmt == "text":
        assert text.splitlines()[0] == (f"{escaped}:4: error: 0x2000sub0: value 300 out of "
                                        "range for UNSIGNED8 (0..255) [DCF200]")
    elif fmt == "json":
        doc = json.loads(text)
        assert doc["files"][0]["path"] == escaped
        assert doc["diagnostics"][0]["file"] == escaped
    elif fmt == "sarif":
        loc = json.loads(text)["runs"][0]["results"][0]["locations"][0]["physicalLocation"]
        assert loc["artifactLocation"] == {"uri": "caf%E9.dcf", "uriBaseId": "%SRCROOT%"}
    else:
        assert text.startswith(f"::error file={escaped.replace(':', '%3A')},line=4,")
    # compile says the name the same way
    out = dcf2bin("compile", name, "-o", "-", capture_output=True)
    assert out.returncode == 1
    assert out.stderr.decode("utf-8").splitlines()[0] == (
        f"{escaped}:4: error: 0x2000sub0: value 300 out of range for UNSIGNED8 (0..255) "
        "[DCF200]")


def test_escape_never_raises():
    from dcf2bin.report import escape
    assert escape("a\udcffb") == "a\\xffb"
    assert escape("line\nbreak") == "line\\x0abreak"
    assert escape("\ud800") == "\\ud800"
    assert escape("grüße.dcf") == "grüße.dcf"


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("args", [["--help"], ["--version"], ["compile", "--help"]],
                         ids=["help", "version", "compile-help"])
def test_help_and_version_into_a_full_device_are_exit_3(args):
    with open("/dev/full", "wb") as full:
        out = dcf2bin(*args, stdout=full, stderr=subprocess.PIPE, text=True)
    assert (out.returncode, out.stderr) == (
        3, "<stdout>: error: cannot write: No space left on device\n")


@pytest.mark.parametrize("args", [["validate", "-"], ["compile", "-", "-o", "-"],
                                  ["dump", "-"]], ids=["validate", "compile", "dump"])
def test_a_closed_stdin_is_exit_3_with_one_line(args):
    out = dcf2bin(*args, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                  preexec_fn=lambda: os.close(0))
    assert (out.returncode, out.stderr) == (
        3, "<stdin>: error: cannot read: standard input is closed [IO001]\n")
