"""dcf2bin diff of two folders (docs/diff.md, "Two folders"), and the identity a network
file gives a slave, stated in its built DCF so that a build and an upload agree (issue 29
item 3)."""
from __future__ import annotations

import json
import shutil

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin import schemas
from dcf2bin.cli import main

FLAT = ROOT / "tests" / "golden" / "network" / "flat" / "out"
NET = ROOT / "tests" / "fixtures" / "network"


def run(*args):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False)


@pytest.fixture
def build(tmp_path, monkeypatch):
    """A copy of the golden flat build as ``out`` in the current folder."""
    monkeypatch.chdir(tmp_path)
    shutil.copytree(FLAT, tmp_path / "out")
    return tmp_path / "out"


def edited(src, dst, old: str, new: str) -> None:
    text = src.read_text()
    assert text.count(old) == 1, old
    dst.write_text(text.replace(old, new))


def test_a_build_against_itself_is_equal(build):
    r = run("diff", "out", FLAT)
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == (f"out, {FLAT}: 5 files equal; 1557 entries compared, 151 of the "
                        "node's state left out (--all compares them)\n")


def test_a_build_against_an_edited_copy_is_exactly_the_changed_entry(build, tmp_path):
    shutil.copytree(build, tmp_path / "edit")
    edited(build / "drive.dcf", tmp_path / "edit" / "drive.dcf",
           "AccessType=rww\nPDOMapping=1\nLowLimit=-128\nHighLimit=127\nParameterValue=0x08",
           "AccessType=rww\nPDOMapping=1\nLowLimit=-128\nHighLimit=127\nParameterValue=0x07")
    r = run("diff", "out", "edit")
    assert r.exit_code == 1
    assert r.stdout == ("--- out/drive.dcf\n"
                        "+++ edit/drive.dcf\n"
                        "@@ 0x6060 Modes of Operation @@\n"
                        "-0x6060sub0 Modes of Operation: 8\n"
                        "+0x6060sub0 Modes of Operation: 7\n")
    assert r.stderr == ("out, edit: 1 of 5 files differ, 1 entry; 1557 entries compared, "
                        "151 of the node's state left out (--all compares them)\n")
    doc = json.loads(run("diff", "out", "edit", "-f", "json").stdout)
    check_schema(doc)
    assert [(f["a"]["file"], f["equal"]) for f in doc["files"]] == [
        ("out/drive.bin", True), ("out/drive.dcf", False), ("out/io.bin", True),
        ("out/io.dcf", True), ("out/plc.dcf", True)]


def test_a_file_only_in_one_folder_is_a_difference(build, tmp_path):
    shutil.copytree(build, tmp_path / "less")
    (tmp_path / "less" / "io.bin").unlink()
    (tmp_path / "less" / "notes.txt").write_text("not read")
    (tmp_path / "less" / ".dcf2bin-build.lock").write_text("not read")
    r = run("diff", "out", "less")
    assert r.exit_code == 1
    assert r.stdout == "Only in out: io.bin\n"
    assert r.stderr.startswith("out, less: 4 files equal, 1 file only in one folder; ")
    doc = json.loads(run("diff", "less", "out", "-f", "json").stdout)
    check_schema(doc)
    assert (doc["only_in_a"], doc["only_in_b"], doc["equal"]) == ([], ["io.bin"], False)


def test_an_upload_folder_is_compared_by_its_own_files(build, tmp_path):
    """An upload holds one <slave>.dcf per slave and no .bin: the build's concise DCFs and
    its master's DCF are not compared, and are no difference."""
    up = tmp_path / "up"
    up.mkdir()
    for name in ("drive.dcf", "io.dcf"):
        shutil.copy(build / name, up / name)
    r = run("diff", "out", "up")
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr == ("out, up: 2 files equal, 3 files of the build not compared; 404 "
                        "entries compared, 140 of the node's state left out (--all compares "
                        "them)\n")
    doc = json.loads(run("diff", "up", "out", "-f", "json").stdout)
    check_schema(doc)
    assert doc["not_compared"] == ["drive.bin", "io.bin", "plc.dcf"] and doc["equal"]
    shutil.copy(build / "io.dcf", up / "extra.dcf")       # a node the build does not know
    r = run("diff", "out", "up")
    assert (r.exit_code, r.stdout) == (1, "Only in up: extra.dcf\n")


def test_the_writers_lock_journal_and_temporaries_are_not_compared(tmp_path):
    """Two real builds of one network: each folder holds the all-or-nothing writer's
    .dcf2bin-build.lock (which lists the files written); a run stopped while writing
    leaves its journal and .dcf2bin-<run>-<i>.tmp/.old files. None is an input of the
    comparison, nor a file only in one folder."""
    bus = FLAT.parent / "bus.yml"
    for name in ("one", "two"):
        r = run("network", "build", bus, "-o", tmp_path / name, "-q")
        assert r.exit_code == 0, r.stderr
        assert (tmp_path / name / ".dcf2bin-build.lock").is_file()
    two = tmp_path / "two"
    (two / ".dcf2bin-build.journal").write_text("not read")
    (two / ".dcf2bin-1f2e-0.tmp").write_bytes((two / "drive.bin").read_bytes()[:-1])
    (two / ".dcf2bin-1f2e-1.old").write_text("[FileInfo]\n")
    (two / ".dcf2bin-5a5a5a5a5a5a.tmp").write_bytes(b"")
    r = run("diff", tmp_path / "one", two)
    assert (r.exit_code, r.stdout) == (0, "")
    assert r.stderr.startswith(f"{tmp_path / 'one'}, {two}: 5 files equal; ")
    doc = json.loads(run("diff", tmp_path / "one", two, "-f", "json").stdout)
    assert (doc["only_in_a"], doc["only_in_b"], doc["not_compared"]) == ([], [], [])
    assert [f["a"]["file"].rsplit("/", 1)[1] for f in doc["files"]] == [
        "drive.bin", "drive.dcf", "io.bin", "io.dcf", "plc.dcf"]


def test_a_name_that_is_no_regular_file_is_said_and_not_compared(build, tmp_path):
    """A FIFO, a folder or a link to nothing named like an input is not read (a FIFO
    would block the run): a warning says what it is, and a regular file of that name in
    the other folder is a file only in that folder."""
    import os
    shutil.copytree(build, tmp_path / "other")
    (tmp_path / "other" / "io.bin").unlink()
    os.mkfifo(tmp_path / "other" / "io.bin")
    os.mkfifo(tmp_path / "other" / "extra.dcf")
    (tmp_path / "other" / "sub.eds").mkdir()
    (tmp_path / "other" / "gone.xdc").symlink_to(tmp_path / "nowhere")
    r = run("diff", "out", "other")
    assert (r.exit_code, r.stdout) == (1, "Only in out: io.bin\n")
    assert r.stderr.splitlines() == [
        "other/extra.dcf: warning: a FIFO, not a regular file: not compared",
        "other/gone.xdc: warning: a symbolic link to nothing, not a regular file: not "
        "compared",
        "other/io.bin: warning: a FIFO, not a regular file: not compared",
        "other/sub.eds: warning: a folder, not a regular file: not compared",
        "out, other: 4 files equal, 1 file only in one folder; 1552 entries compared, 151 "
        "of the node's state left out (--all compares them)"]


def test_folders_that_cannot_be_read_are_exit_3(build, tmp_path):
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "drive.dcf").write_bytes(b"\x00" * 100)
    r = run("diff", "out", "bad")
    assert r.exit_code == 3
    assert r.stderr.splitlines()[0].startswith("bad/drive.dcf:")


# -- the identity in a slave's built DCF ---------------------------------------------------

IDENTITY = """\
  vendor_id: 0x1A3
  product_code: 0x1234
  revision_number: 0x00010002
  serial_number: 1234
"""


def network(tmp_path, master: str, identity: str = IDENTITY):
    path = tmp_path / "bus.yml"
    path.write_text(f"master:\n  node_id: 1\n  sync_period: 10000\n{master}"
                    f"drive:\n  dcf: {NET / 'technosoft.eds'}\n  node_id: 2\n{identity}"
                    f"io:\n  dcf: {NET / 'IoX4_8AI.eds'}\n  node_id: 5\n"
                    "  serial_number: 0\n")
    return path


@pytest.mark.parametrize("master", [f"  name: plc\n  dcf: {NET / 'plc.dcf'}\n", ""],
                         ids=["plc", "lely"])
def test_the_network_files_identity_is_in_the_slaves_dcf(tmp_path, master):
    r = run("network", "build", network(tmp_path, master), "-o", tmp_path / "out", "-q")
    assert r.exit_code == 0, r.stderr
    text = (tmp_path / "out" / "drive.dcf").read_text()
    for sub, name, value in ((1, "Vendor ID", "0x000001A3"), (2, "Product Code", "0x00001234"),
                             (3, "Revision number", "0x00010002"),
                             (4, "Serial number", "0x000004D2")):
        section = text[text.index(f"[1018sub{sub}]"):]
        section = section[:section.index("\n\n")]
        assert section.splitlines()[1] == f"ParameterName={name}"
        assert section.splitlines()[-1] == f"ParameterValue={value}", section
    # serial_number: 0 checks nothing and states nothing; io's file keeps its own identity
    io = (tmp_path / "out" / "io.dcf").read_text()
    assert "ParameterValue" not in io[io.index("[1018sub1]"):io.index("[1018sub4]") + 120]
    # compile does not write the read-only identity; validate says so as an info
    r = run("compile", tmp_path / "out" / "drive.dcf", "-o", "-", "-q")
    assert r.exit_code == 0
    r = run("diff", tmp_path / "out" / "drive.bin", tmp_path / "out" / "drive.dcf")
    assert (r.exit_code, r.stdout) == (0, "")
    r = run("validate", "--select", "DCF213", tmp_path / "out" / "drive.dcf")
    assert r.stdout.count("[DCF213]") == 4


def test_a_node_with_another_serial_number_differs_there(tmp_path):
    """The build's drive.dcf against a DCF read back from a node with serial 1235:
    exactly 0x1018 sub 4."""
    r = run("network", "build", network(tmp_path, ""), "-o", tmp_path / "out", "-q")
    assert r.exit_code == 0, r.stderr
    (tmp_path / "up").mkdir()
    edited(tmp_path / "out" / "drive.dcf", tmp_path / "up" / "drive.dcf",
           "ParameterValue=0x000004D2", "ParameterValue=0x000004D3")
    r = run("diff", tmp_path / "out", tmp_path / "up", "-q")
    assert r.exit_code == 1
    assert r.stdout.splitlines()[2:] == [
        "@@ 0x1018 Identity Object @@",
        "-0x1018sub4 Serial number: 0x000004D2",
        "+0x1018sub4 Serial number: 0x000004D3"]


def test_an_identity_entry_the_file_lacks_is_not_stated(tmp_path):
    """samples/device.eds has 0x1018 sub 1 only: serial_number goes to the master's check,
    not into the slave's DCF (which has no entry to hold it)."""
    path = tmp_path / "bus.yml"
    path.write_text(f"master:\n  node_id: 1\ndev:\n  dcf: {ROOT / 'samples' / 'device.eds'}\n"
                    "  node_id: 3\n  serial_number: 77\n  vendor_id: 0xAB\n")
    r = run("network", "build", path, "-o", tmp_path / "out", "-q")
    assert r.exit_code == 0, r.stderr
    text = (tmp_path / "out" / "dev.dcf").read_text()
    assert "[1018sub4]" not in text and "ParameterValue=0x000000AB" in text


def check_schema(doc: dict) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    jsonschema.validate(doc, schemas.load("diff"))
