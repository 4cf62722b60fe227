"""network build writes its files all or none (issue 26, item 6): every output checked
before the first byte, every file a synced temporary file renamed only when all are
complete, a failure, SIGINT or SIGTERM leaving the folder as it was (the earlier build's
files the same inodes, the same bytes), a SIGKILL between two renames undone by the next
run, a second build waiting for the folder's lock, and the files of a slave that left
the network named, never deleted.

Each test fails on the code before this work: there, the files were written one after
the other, each atomically, but the set was not."""
from __future__ import annotations

import errno
import fcntl
import os
import shutil
import signal
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin.cli import main

FIXTURES = ROOT / "tests" / "fixtures" / "network"
GOLDEN = ROOT / "tests" / "golden" / "network" / "flat"
ENV = {**os.environ, "NO_COLOR": "1"}
LOCK = ".dcf2bin-build.lock"
OUTPUTS = ["drive.bin", "drive.dcf", "io.bin", "io.dcf", "plc.dcf"]
linux_only = pytest.mark.skipif(not os.path.isdir("/proc/self/fd"),
                                reason="the child finds its files through /proc/self/fd")


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def network(tmp_path, io_heartbeat: int = 200, with_io: bool = True):
    """The golden flat network with its files beside it: A (io heartbeat 200 ms), B (300:
    io.bin, io.dcf and plc.dcf differ from A's), or without the io slave."""
    net = tmp_path / "net"
    net.mkdir(exist_ok=True)
    for name in ("plc.dcf", "technosoft.eds", "IoX4_8AI.eds"):
        shutil.copy(FIXTURES / name, net / name)
    text = (GOLDEN / "bus.yml").read_text().replace("../../../fixtures/network/", "")
    text = text.replace("heartbeat_producer: 200", f"heartbeat_producer: {io_heartbeat}")
    if not with_io:
        text = text[:text.index("\nio:\n")] + "\n"
    (net / "bus.yml").write_text(text)
    return net / "bus.yml"


def snapshot(folder) -> dict:
    """Each file of ``folder``: its bytes, inode and mtime (what "untouched" means)."""
    out = {}
    for p in sorted(folder.iterdir()):
        st = p.stat()
        out[p.name] = (p.read_bytes() if p.is_file() else "<dir>", st.st_ino, st.st_mtime_ns)
    return out


def leftovers(folder) -> list[str]:
    return sorted(p.name for p in folder.iterdir() if p.name.startswith(".dcf2bin-")
                  and p.name != LOCK)


@pytest.fixture
def built(tmp_path):
    """Network A built into out/; returns (out, B's bus.yml, A's snapshot)."""
    out = tmp_path / "out"
    r = run("network", "build", network(tmp_path), "-o", out, "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    before = snapshot(out)
    b_dir = tmp_path / "b"
    b_dir.mkdir()
    b = network(b_dir, io_heartbeat=300)
    assert (b_dir / "net" / "bus.yml").read_text() != (tmp_path / "net" / "bus.yml").read_text()
    return out, b, before


def nothing_written(out) -> str:
    return f"network build: nothing written (the files in {out} are as they were)"


# -- every output checked before the first byte --------------------------------------------

def test_an_output_that_is_a_slaves_input_writes_nothing(tmp_path):
    """A slave whose file is io.dcf, built into that file's folder: exit 2 naming the
    file, and not one output written (before, plc's master.dcf and io.bin were)."""
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    shutil.copy(FIXTURES / "IoX4_8AI.eds", tmp_path / "io.dcf")
    (tmp_path / "bus.yml").write_text(
        "master:\n  node_id: 1\n  dcf: plc.dcf\nio:\n  dcf: io.dcf\n  node_id: 5\n")
    before = snapshot(tmp_path)
    r = run("network", "build", tmp_path / "bus.yml", "-o", tmp_path, "-q")
    assert snapshot(tmp_path) == before
    assert r.exit_code == 2
    assert r.stderr.splitlines() == [
        f"{tmp_path}/io.dcf: error: the output is the input file; refusing to overwrite it",
        nothing_written(tmp_path)]


def test_a_directory_at_one_outputs_name_writes_nothing(built):
    out, b, before = built
    (out / "io.bin").unlink()
    (out / "io.bin").mkdir()
    before = snapshot(out)
    r = run("network", "build", b, "-o", out, "-q")
    assert snapshot(out) == before and leftovers(out) == []
    assert r.exit_code == 3
    assert r.stderr.splitlines() == [f"{out}/io.bin: error: cannot write: Is a directory",
                                     nothing_written(out)]


def test_a_directory_in_a_new_folder_leaves_no_folder_or_lock(tmp_path):
    out = tmp_path / "new"
    out.mkdir()
    (out / "io.dcf").mkdir()              # the last of the five
    r = run("network", "build", network(tmp_path), "-o", out, "-q")
    assert r.exit_code == 3
    assert sorted(p.name for p in out.iterdir()) == ["io.dcf"]


@pytest.mark.parametrize("args", [["-o", ""], ["--output="]])
def test_an_empty_output_folder_is_a_usage_error(tmp_path, args):
    r = run("network", "build", network(tmp_path), *args)
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == ("Error: Invalid value for '-o' / '--output': an empty "
                                         "name is not a folder (use '.' for this one)")


def test_a_read_only_folder_writes_nothing(built, monkeypatch):
    out, b, before = built
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        # root may write into a read-only folder: the kernel's answer to anyone else is
        # given here, by access() and by every file created in it
        real_open, real_access = os.open, os.access

        def inside(path) -> bool:
            return os.path.abspath(path) == str(out) or \
                os.path.dirname(os.path.abspath(path)) == str(out)

        def refusing_open(path, flags, *args, **kwargs):
            if flags & os.O_CREAT and inside(path):
                raise PermissionError(errno.EACCES, "Permission denied", path)
            return real_open(path, flags, *args, **kwargs)

        def refusing_access(path, mode, *args, **kwargs):
            if mode & os.W_OK and inside(path):
                return False
            return real_access(path, mode, *args, **kwargs)
        monkeypatch.setattr(os, "open", refusing_open)
        monkeypatch.setattr(os, "access", refusing_access)
    os.chmod(out, 0o500)
    try:
        r = run("network", "build", b, "-o", out, "-q")
    finally:
        os.chmod(out, 0o755)
        monkeypatch.undo()
    assert r.exit_code == 3
    assert r.stderr.splitlines() == [f"{out}: error: cannot write: Permission denied",
                                     nothing_written(out)]
    assert snapshot(out) == before


# -- a full disk ------------------------------------------------------------------------------

def _temp_name(fd: int) -> str | None:
    """The name of the output temporary file ``fd`` writes, else None (the journal, the
    lock, a folder)."""
    try:
        name = os.path.basename(os.readlink(f"/proc/self/fd/{fd}"))
    except OSError:
        return None
    if name.startswith(".dcf2bin-") and not name.startswith(".dcf2bin-build"):
        return name
    return None


def full_disk(monkeypatch, call: str, at: int) -> None:
    """``os.<call>`` ("write" or "fsync") fails with ENOSPC on the output temporary file
    written ``at``-th (0 first), as a full disk does."""
    real = getattr(os, call)
    seen: list[str] = []

    def full(fd, *args):
        name = _temp_name(fd)
        if name is not None and name not in seen:
            seen.append(name)
        if name is not None and seen.index(name) == at:
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(fd, *args)
    monkeypatch.setattr(os, call, full)


@linux_only
@pytest.mark.parametrize("call", ["fsync", "write"])
def test_a_full_disk_at_the_third_file_leaves_the_earlier_build(built, monkeypatch, call):
    """ENOSPC while the third file is written (os.write) or synced (os.fsync, where a
    file system with delayed allocation reports it): exit 3 naming that output, the
    earlier build's five files as they were, no temporary file left."""
    out, b, before = built
    full_disk(monkeypatch, call, 2)
    r = run("network", "build", b, "-o", out, "-q")
    monkeypatch.undo()
    assert snapshot(out) == before and leftovers(out) == []
    assert r.exit_code == 3, r.stderr
    assert r.stderr.splitlines() == [
        f"{out}/drive.dcf: error: cannot write: No space left on device", nothing_written(out)]


# -- signals ----------------------------------------------------------------------------------

# Runs dcf2bin with one system call wrapped: after the AT-th output file is synced
# ("write") or renamed into place ("rename"), it says "paused" and waits for a line on its
# standard input (the test sends its signal first), or SIGKILLs itself ("kill").
_CHILD = r"""
import os, signal, sys
# a test runner started in the background may hand down ignored signals: start as a shell would
signal.signal(signal.SIGINT, signal.default_int_handler)
signal.signal(signal.SIGTERM, signal.SIG_DFL)
signal.signal(signal.SIGHUP, signal.SIG_DFL)
mode, at, action = sys.argv[1], int(sys.argv[2]), sys.argv[3]
real_fsync, real_replace = os.fsync, os.replace
count = [0]

def stop():
    if action == "kill":
        os.kill(os.getpid(), signal.SIGKILL)
    sys.stdout.write("paused\n")
    sys.stdout.flush()
    sys.stdin.readline()

def output_temp(fd):
    try:
        name = os.path.basename(os.readlink(f"/proc/self/fd/{fd}"))
    except OSError:
        return False
    return name.startswith(".dcf2bin-") and not name.startswith(".dcf2bin-build")

def fsync(fd):
    real_fsync(fd)
    if mode == "write" and output_temp(fd):
        count[0] += 1
        if count[0] == at:
            stop()

def replace(src, dst, **kw):
    real_replace(src, dst, **kw)
    if mode == "rename" and not os.path.basename(dst).startswith(".dcf2bin-"):
        count[0] += 1
        if count[0] == at:
            stop()

os.fsync, os.replace = fsync, replace
from dcf2bin.cli import main
main(sys.argv[4:], prog_name="dcf2bin")
"""


def child(mode: str, at: int, action: str, *args, **kw) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", _CHILD, mode, str(at), action,
                             *map(str, args)], env=ENV, text=True, **kw)


@linux_only
@pytest.mark.parametrize("mode", ["write", "rename"])
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_while_writing_leaves_the_earlier_build(built, mode, sig):
    """SIGINT or SIGTERM after the second file is written, or after the second is renamed
    into place: exit 128 + N, and the folder is the earlier build's, file for file."""
    out, b, before = built
    proc = child(mode, 2, "pause", "network", "build", b, "-o", out, "-q",
                 stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        assert proc.stdout.readline() == "paused\n"
        proc.send_signal(sig)
        _, err = proc.communicate("go\n", timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert snapshot(out) == before and leftovers(out) == []
    assert proc.returncode == 128 + sig, err
    said = "dcf2bin: interrupted" if sig == signal.SIGINT else \
        "dcf2bin: stopped by signal SIGTERM"
    assert err.splitlines() == [said]


@linux_only
@pytest.mark.parametrize("then", ["recover", "build"])
def test_sigkill_between_two_renames_is_undone_by_the_next_run(built, then):
    """SIGKILL right after the second rename: two of B's files are in place, three are
    A's. The next run in the folder rolls that set back first (the earlier build's files
    again, the same inodes, no temporary file), then builds."""
    out, b, before = built
    proc = child("rename", 2, "kill", "network", "build", b, "-o", out, "-q",
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    mixed = snapshot(out)
    changed = [n for n in OUTPUTS if mixed[n] != before[n]]
    assert len(changed) == 2 and ".dcf2bin-build.journal" in mixed
    if then == "recover":
        from dcf2bin.fileio import journal
        with journal.FolderLock(str(out)) as lock:
            said = journal.recover(str(out), lock)
        assert said == ("a build stopped while renaming its files was rolled back (2 files "
                        "restored, 0 removed)")
        assert snapshot(out) == before and leftovers(out) == []
        return
    r = run("network", "build", b, "-o", out)
    assert r.exit_code == 0, r.stderr
    assert r.stderr.splitlines()[0] == (
        f"{out}: warning: a build stopped while renaming its files was rolled back (2 files "
        "restored, 0 removed) [NET131]")
    assert leftovers(out) == []
    got = snapshot(out)
    assert [n for n in OUTPUTS if got[n][0] != before[n][0]] == ["io.bin", "io.dcf", "plc.dcf"]


@linux_only
def test_sigkill_while_writing_leaves_temporaries_the_next_run_removes(built):
    """SIGKILL after the second temporary file is synced: nothing is replaced yet; the
    next run removes the temporary files the journal names, then builds."""
    out, b, before = built
    proc = child("write", 2, "kill", "network", "build", b, "-o", out, "-q",
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    left = snapshot(out)
    assert [n for n in OUTPUTS if left[n] != before[n]] == [] and len(leftovers(out)) == 3
    r = run("network", "build", b, "-o", out)
    assert r.exit_code == 0, r.stderr
    assert r.stderr.splitlines()[0] == (
        f"{out}: warning: a build stopped while writing its files was cleared away (its "
        "temporary files removed; no file had been replaced) [NET131]")
    assert leftovers(out) == []


# -- a concurrent build ------------------------------------------------------------------------

def test_a_second_build_waits_for_the_folders_lock(built):
    """While another writer holds the folder's lock, a build says so and waits, touching
    nothing; it writes its set once the lock is free."""
    out, b, before = built
    fd = os.open(out / LOCK, os.O_RDWR)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        proc = subprocess.Popen([sys.executable, "-m", "dcf2bin", "network", "build", str(b),
                                 "-o", str(out)], env=ENV, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            line = proc.stderr.readline()
            assert line == f"network build: waiting for another build writing in {out}\n"
            assert snapshot(out) == before and leftovers(out) == []
        finally:
            os.close(fd)                   # the other writer is done
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    got = snapshot(out)
    assert [n for n in OUTPUTS if got[n][0] != before[n][0]] == ["io.bin", "io.dcf", "plc.dcf"]


# -- a slave that left the network ---------------------------------------------------------------

def test_files_of_a_removed_slave_are_named_and_kept(built, tmp_path):
    out, _, before = built
    (out / "notes.txt").write_text("the user's own file\n")
    c_dir = tmp_path / "c"
    c_dir.mkdir()
    c = network(c_dir, with_io=False)
    stale = [f"{out}/io.bin: warning: written by an earlier build, not an output of this "
             "network: kept (remove it if it is no longer needed) [NET130]",
             f"{out}/io.dcf: warning: written by an earlier build, not an output of this "
             "network: kept (remove it if it is no longer needed) [NET130]"]
    r = run("network", "build", c, "-o", out)
    assert r.exit_code == 0, r.stderr
    assert r.stderr.splitlines() == stale + [
        f"network build: 3 files in {out}: plc.dcf and 1 slave for a PLC master, 2 links, 4 variables"]
    got = snapshot(out)
    assert got["io.bin"] == before["io.bin"] and got["io.dcf"] == before["io.dcf"]
    assert (out / "notes.txt").read_text() == "the user's own file\n"
    # said again by the next build, until they are removed; a file the user replaced is
    # the user's: not named
    r = run("network", "build", c, "-o", out, "-q")
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("network", "build", c, "-o", out)
    assert r.stderr.splitlines()[:2] == stale
    (out / "io.dcf").unlink()
    (out / "io.dcf").write_text("the user's own io.dcf\n")
    r = run("network", "build", c, "-o", out)
    assert r.stderr.splitlines()[:-1] == stale[:1]


def test_the_api_writes_all_or_none_and_names_its_inputs(tmp_path):
    """build_network(path, outdir) is the same writer: an output over an input raises
    OutputIsInput (a ValueError) before anything is written."""
    from dcf2bin.api import build_network
    from dcf2bin.fileio import OutputIsInput
    shutil.copy(FIXTURES / "plc.dcf", tmp_path / "plc.dcf")
    shutil.copy(FIXTURES / "IoX4_8AI.eds", tmp_path / "io.dcf")
    (tmp_path / "bus.yml").write_text(
        "master:\n  node_id: 1\n  dcf: plc.dcf\nio:\n  dcf: io.dcf\n  node_id: 5\n")
    before = snapshot(tmp_path)
    with pytest.raises(OutputIsInput) as exc:
        build_network(tmp_path / "bus.yml", tmp_path)
    assert exc.value.path == f"{tmp_path}/io.dcf" and isinstance(exc.value, ValueError)
    assert snapshot(tmp_path) == before
