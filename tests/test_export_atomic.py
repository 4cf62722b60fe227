"""export -f canopennode writes OD.h and OD.c as one set (fileio.OutputSet, record=False):
both written and synced before the first is renamed, so that a full disk, SIGINT or
SIGTERM leaves both files as they were (never a new OD.h beside an old OD.c), a SIGKILL
between the two renames is undone by the next run, and a second writer waits for the
folder's lock. Without a record: once the set is complete the firmware's folder holds
OD.h, OD.c and nothing of the writer -- no .dcf2bin-build.lock -- while a network build's
lock file in that folder (its record of the files it wrote) stays as it was.

The tests of a failure, a signal, a SIGKILL and a waiting writer fail on the code before
this work, which wrote OD.h and then OD.c, each atomically, but not the two as a set; the
first two pass there too (it took no lock, so it left none) and pin that the set writer
leaves nothing of its own in a firmware's folder."""
from __future__ import annotations

import os
import signal
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin.cli import main
from test_build_atomic import child, full_disk, linux_only, network, snapshot

SAMPLE = ROOT / "tests" / "fixtures" / "canopennode" / "sample.eds"
ENV = {**os.environ, "NO_COLOR": "1"}
LOCK = ".dcf2bin-build.lock"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


def other_device(tmp_path):
    """sample.eds with 0x1017 named otherwise: its C name in OD.h and OD.c both differ."""
    text = SAMPLE.read_text()
    assert text.count("ParameterName=Producer heartbeat time") == 1
    path = tmp_path / "b.eds"
    path.write_text(text.replace("ParameterName=Producer heartbeat time",
                                 "ParameterName=Heartbeat producer time"))
    return path


@pytest.fixture
def exported(tmp_path):
    """sample.eds exported into od/; returns (od, another device's EDS, od's snapshot)."""
    od = tmp_path / "od"
    r = run("export", "-q", "-f", "canopennode", SAMPLE, "-o", od)
    assert (r.exit_code, r.stderr) == (0, "")
    b = other_device(tmp_path)
    before = snapshot(od)
    return od, b, before


def test_the_folder_holds_the_two_files_and_nothing_else(exported):
    od, b, before = exported
    assert sorted(before) == ["OD.c", "OD.h"]
    r = run("export", "-q", "-f", "canopennode", b, "-o", od)
    assert (r.exit_code, r.stderr) == (0, "")
    after = snapshot(od)
    assert sorted(after) == ["OD.c", "OD.h"]
    assert all(after[n][0] != before[n][0] for n in ("OD.c", "OD.h"))


def test_a_network_builds_lock_file_in_the_folder_stays_as_it_was(tmp_path):
    """Exported into a build's folder: the build's record (its lock file, which names the
    files it wrote) is left as it was, and the next build names no export file stale."""
    out = tmp_path / "out"
    bus = network(tmp_path)
    assert run("network", "build", bus, "-o", out, "-q").exit_code == 0
    record = (out / LOCK).read_bytes()
    r = run("export", "-q", "-f", "canopennode", SAMPLE, "-o", out)
    assert (r.exit_code, r.stderr) == (0, "")
    assert (out / LOCK).read_bytes() == record
    r = run("network", "build", bus, "-o", out)
    assert r.exit_code == 0 and "warning" not in r.stderr


@linux_only
@pytest.mark.parametrize("call", ["fsync", "write"])
def test_a_full_disk_at_the_second_file_leaves_both_as_they_were(exported, monkeypatch, call):
    od, b, before = exported
    full_disk(monkeypatch, call, 1)
    r = run("export", "-q", "-f", "canopennode", b, "-o", od)
    monkeypatch.undo()
    assert (r.exit_code, r.stderr) == (3, f"{od}/OD.c: error: cannot write: No space left on "
                                          "device\n")
    assert snapshot(od) == before


@linux_only
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_a_signal_after_the_first_rename_leaves_both_as_they_were(exported, sig):
    """OD.h renamed into place, then SIGINT or SIGTERM: exit 128 + N, and OD.h is the old
    one again (the same inode), beside the old OD.c."""
    od, b, before = exported
    proc = child("rename", 1, "pause", "export", "-q", "-f", "canopennode", b, "-o", od,
                 stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    try:
        assert proc.stdout.readline() == "paused\n"
        assert snapshot(od)["OD.h"][0] != before["OD.h"][0]     # the new OD.h, for now
        proc.send_signal(sig)
        _, err = proc.communicate("go\n", timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 128 + sig, err
    assert snapshot(od) == before


@linux_only
def test_sigkill_between_the_two_renames_is_undone_by_the_next_run(exported):
    od, b, before = exported
    proc = child("rename", 1, "kill", "export", "-q", "-f", "canopennode", b, "-o", od,
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    proc.communicate(timeout=60)
    assert proc.returncode == -signal.SIGKILL
    mixed = snapshot(od)
    assert mixed["OD.h"][0] != before["OD.h"][0] and mixed["OD.c"] == before["OD.c"]
    assert ".dcf2bin-build.journal" in mixed and LOCK in mixed
    r = run("export", "-f", "canopennode", SAMPLE, "-o", od)
    assert r.exit_code == 0, r.stderr
    assert r.stderr == (f"{od}: warning: a build stopped while renaming its files was rolled "
                        "back (1 file restored, 0 removed)\n")
    after = snapshot(od)
    assert sorted(after) == ["OD.c", "OD.h"]
    assert [after[n][0] for n in ("OD.c", "OD.h")] == [before[n][0] for n in ("OD.c", "OD.h")]


def test_a_writer_waiting_for_a_lock_file_that_is_removed_locks_the_new_one(exported):
    """Another writer holds the folder's lock; the export waits on that lock file. The
    other one removes it while it still holds it (as a set without a record does) and
    lets go: the export finds the path no longer names the file it locked, locks a new
    one, writes its set and removes that lock file too."""
    from dcf2bin.fileio import journal
    od, b, before = exported
    with journal.FolderLock(str(od)) as lock:
        proc = subprocess.Popen([sys.executable, "-m", "dcf2bin", "export", "-f",
                                 "canopennode", str(b), "-o", str(od)], env=ENV, text=True,
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        try:
            assert proc.stderr.readline() == f"export: waiting for another writer in {od}\n"
            assert {n: v for n, v in snapshot(od).items() if n != LOCK} == before
            lock.remove()
        except BaseException:
            proc.kill()
            proc.wait()
            raise
    _, err = proc.communicate(timeout=60)
    assert (proc.returncode, err) == (0, "")
    after = snapshot(od)
    assert sorted(after) == ["OD.c", "OD.h"]
    assert all(after[n][0] != before[n][0] for n in ("OD.c", "OD.h"))
