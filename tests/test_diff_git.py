"""`dcf2bin dump --textconv` as git's textconv filter (docs/diff.md, "git"): the
form itself, exactly, and a real `git diff` in a temporary repository that shows the entries
of a container and of a concise DCF that changed -- those lines and no others -- instead of
"Binary files differ"."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES
from dcf2bin import concise
from dcf2bin.cli import main
from dcf2bin.dump import from_json_bytes, read_bytes, to_json
from test_dump import ODD

GIT = shutil.which("git")
FLAT = ROOT / "tests" / "golden" / "network" / "flat" / "out"
needs_git = pytest.mark.skipif(GIT is None, reason="git is not installed")


def textconv(*args) -> tuple[int, str, str]:
    r = CliRunner().invoke(main, ["dump", "--textconv", *map(str, args)])
    return r.exit_code, r.stdout, r.stderr


# -- the form -------------------------------------------------------------------------------

def test_a_container_is_one_line_per_entry_without_name_number_offset_or_padding():
    code, out, err = textconv(SAMPLES / "device.bin")
    assert (code, err) == (0, "")
    assert out.splitlines() == [
        "binary DCF segment container, 225 bytes, canonical layout",
        "index segment: 15 entries",
        "0x1016sub1: 4 bytes 64000100 = 0x00010064  attr 0x70 NUM|R|W",
        "0x1016sub2: 4 bytes C8000200 = 0x000200C8  attr 0x70 NUM|R|W",
        "0x1017sub0: 2 bytes F401 = 500  attr 0x70 NUM|R|W",
        '0x2000sub0: 15 bytes 48616C6C20333B207261636B202332 = "Hall 3; rack #2"  attr 0x68 '
        "VSTR|R|W",
        "0x2001sub0: 3 bytes 000080 = 0x800000  attr 0xF0 NUM|R|W|MAP",
        "0x2002sub0: 4 bytes 0000003F = 0x3F000000  attr 0x70 NUM|R|W",
        "0x2003sub0: 4 bytes DEADBEEF  attr 0x60 DOM|R|W",
        "0x2004sub0: 6 bytes FFFFFFFFFFFF = 0xFFFFFFFFFFFF  attr 0x70 NUM|R|W",
        "0x1800sub1: 4 bytes 83010080 = 0x80000183 = COB-ID 0x183, invalid  attr 0x70 NUM|R|W  "
        "write 1/2",
        "0x1800sub2: 1 byte 01 = 1  attr 0x70 NUM|R|W",
        "0x1A00sub0: 1 byte 00 = 0  attr 0x70 NUM|R|W  write 1/2",
        "0x1A00sub1: 4 bytes 18000120 = 0x20010018 = 2001sub0, 24 bits  attr 0x70 NUM|R|W",
        "0x1A00sub2: 4 bytes 08000500 = 0x00050008 = 0005sub0, 8 bits  attr 0x70 NUM|R|W",
        "0x1A00sub0: 1 byte 02 = 2  attr 0x70 NUM|R|W  write 2/2",
        "0x1800sub1: 4 bytes 83010000 = 0x00000183 = COB-ID 0x183  attr 0x70 NUM|R|W  write 2/2",
        "PI address segment: absent (0 network variables)",
        "PI parameter segment: absent"]


def test_the_same_bytes_under_another_name_are_the_same_text(tmp_path):
    copy = tmp_path / "git-blob-x" / "plc.bin"
    copy.parent.mkdir()
    copy.write_bytes((SAMPLES / "plc.bin").read_bytes())
    assert textconv(copy) == textconv(SAMPLES / "plc.bin")
    code, out, _ = textconv(SAMPLES / "plc.bin")
    assert code == 0 and "plc.bin" not in out
    assert out.splitlines()[-13:] == [
        "PI address segment: 9 addresses, 9 network variables",
        "address 0x0000 input 0  0xA040sub1  1 byte  UNSIGNED8",
        "address 0x0001 input 1  0xA040sub2  1 byte  UNSIGNED8",
        "address 0x0002 input 2  0xA040sub3  1 byte  UNSIGNED8",
        "address 0x0003 input 3  0xA040sub4  1 byte  UNSIGNED8",
        "address 0x0004 input 4  0xA0C0sub3  2 bytes  INTEGER16",
        "address 0x0006 input 6  0xA0C0sub4  2 bytes  INTEGER16",
        "address 0x0008 output 0  0xA4C0sub1  1 byte  UNSIGNED8",
        "address 0x0009 output 1  0xA4C0sub2  1 byte  UNSIGNED8",
        "address 0x000C output 4  0xA680sub2  4 bytes  UNSIGNED32",
        "PI parameter segment: complete size 16",
        "PI parameter segment: input area offset 0 size 8",
        "PI parameter segment: output area offset 8 size 8"]


def test_a_stored_layout_shows_its_header_and_every_stray_byte(tmp_path):
    """tests/test_dump.py's odd container: the header is no longer derived from the
    segments, so its fields are shown, each on its own line with the report's notes."""
    (tmp_path / "odd.bin").write_bytes(ODD)
    code, out, _ = textconv(tmp_path / "odd.bin", "-q")
    assert code == 0
    assert out == """\
binary DCF segment container, 78 bytes, stored layout (not canonical)
header: total size 78  ! header + segments = 67; 11 bytes belong to no segment
header: version 3  ! not the default 1
header: segment count 4  ! 3 segments are present
header: index segment offset 56 size 20
header: PI address segment offset 52 size 4  ! 2 addresses for 1 network variable
header: extended info segment offset 40 size 3  ! 3 attribute bytes for 2 entries
header: PI parameter segment offset 0 size 0
! segments are not in the header's order
index segment: 2 entries
0xA04Csub1: 1 byte 07 = 7  attr 0x36 NUM|R|0x06  write 1/2
0xA04Csub1: 1 byte 08 = 8  attr 0xF0 NUM|R|W|MAP  write 2/2
! 1 attribute byte without an entry: 30
PI address segment: 2 addresses, 1 network variable  ! they should match
address 0x0000  0xA04Csub1  1 byte  UNSIGNED8
address 0x0004  no network variable
PI parameter segment: absent
bytes in no segment at 0x2B: 9 bytes AABBCCDDEEFF00AA00
bytes in no segment at 0x4C: 2 bytes DEAD
"""


def test_a_concise_dcf_with_types_and_with_an_eds():
    code, out, _ = textconv(FLAT / "drive.bin")
    assert code == 0
    lines = out.splitlines()
    assert lines[:3] == [
        "concise DCF (CiA 302-3), 223 bytes, 22 entries",
        "0x1400sub1: UNSIGNED32  4 bytes 02020080 = 0x80000202 = COB-ID 0x202, invalid  "
        "write 1/2",
        "0x1400sub2: UNSIGNED8  1 byte 01 = 1"]
    assert lines[-2:] == ["0x1017sub0: UNSIGNED16  2 bytes 3200 = 50",
                          "0x6060sub0: UNSIGNED8?  1 byte 08 = 8"]
    code, out, _ = textconv("--eds", FLAT / "drive.dcf", FLAT / "drive.bin")
    assert code == 0
    lines = out.splitlines()
    assert lines[1] == ("0x1400sub1 COB-ID RPDO1: UNSIGNED32  4 bytes 02020080 = "
                        "0x80000202 = COB-ID 0x202, invalid  write 1/2")
    assert lines[-1] == "0x6060sub0 Modes of Operation: INTEGER8  1 byte 08 = 8"


def test_long_data_is_shown_whole():
    """A change in the tail of a long value must be a changed line."""
    data = bytes(range(40))
    c, _ = read_bytes((SAMPLES / "device.bin").read_bytes(), "device.bin")
    doc = to_json(c).replace("DEADBEEF", data.hex().upper())
    raw, diags = from_json_bytes(doc.encode(), "x.json")
    assert raw is not None, diags
    [line] = [x for x in _text(raw).splitlines() if x.startswith("0x2003sub0")]
    assert line == f"0x2003sub0: 40 bytes {data.hex().upper()}  attr 0x60 DOM|R|W"


def test_textconv_is_text_only():
    r = CliRunner().invoke(main, ["dump", "--textconv", "-f", "json", str(SAMPLES / "device.bin")])
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == ("Error: --textconv is a text form of its own: give it "
                                         "without -f json")


def _text(data: bytes) -> str:
    r = CliRunner().invoke(main, ["dump", "--textconv", "-"], input=data)
    assert r.exit_code == 0, r.stderr
    return r.stdout


# -- git diff ---------------------------------------------------------------------------------

def git(repo, *args) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}
    env.update(HOME=str(repo), GIT_CONFIG_NOSYSTEM="1", GIT_AUTHOR_NAME="t",
               GIT_AUTHOR_EMAIL="t@t", GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@t")
    return subprocess.run([GIT, *args], cwd=repo, env=env, capture_output=True, text=True,
                          timeout=60)


@pytest.fixture
def repo(tmp_path):
    """A repository with docs/diff.md's two lines: the attribute and the textconv command
    (this interpreter's dcf2bin, the same command as `dcf2bin dump --textconv`)."""
    assert git(tmp_path, "init", "-q").returncode == 0
    (tmp_path / ".gitattributes").write_text("*.bin diff=dcf2bin\n")
    dcf2bin = f"{sys.executable} -m dcf2bin"
    assert git(tmp_path, "config", "diff.dcf2bin.textconv",
               f"{dcf2bin} dump --textconv").returncode == 0
    return tmp_path


def commit(repo, name: str, data: bytes) -> None:
    (repo / name).write_bytes(data)
    assert git(repo, "add", ".").returncode == 0
    assert git(repo, "commit", "-qm", "x").returncode == 0


def changed(repo, *args) -> list[str]:
    """The -/+ lines of ``git diff`` (without its ---/+++ file lines)."""
    r = git(repo, "diff", *args)
    assert r.returncode == 0, r.stderr
    assert "Binary files" not in r.stdout and "git-blob" not in r.stdout
    return [line for line in r.stdout.splitlines()
            if line[:1] in "+-" and not line.startswith(("+++", "---"))]


@needs_git
def test_git_diff_of_a_container_shows_the_changed_entry_alone(repo):
    """samples/device.bin with 0x1017 (producer heartbeat time, 500) made 400."""
    data = (SAMPLES / "device.bin").read_bytes()
    commit(repo, "device.bin", data)
    head = bytes.fromhex("171000") + (2).to_bytes(4, "little") + (500).to_bytes(2, "little")
    assert data.count(head) == 1
    (repo / "device.bin").write_bytes(data.replace(head, head[:-2] + (400).to_bytes(2, "little")))
    assert changed(repo) == ["-0x1017sub0: 2 bytes F401 = 500  attr 0x70 NUM|R|W",
                             "+0x1017sub0: 2 bytes 9001 = 400  attr 0x70 NUM|R|W"]


@needs_git
def test_git_diff_of_a_grown_entry_shows_it_and_the_size_not_every_later_entry(repo):
    """0x2000's string made longer moves every later entry and the extended info segment:
    the entry's line and the size in the first line change, no other."""
    data = (SAMPLES / "device.bin").read_bytes()
    commit(repo, "device.bin", data)
    c, _ = read_bytes(data, "device.bin")
    longer = "Hall 3; rack #2, top".encode().hex().upper()
    doc = to_json(c).replace("48616C6C20333B207261636B202332", longer)
    raw, diags = from_json_bytes(doc.encode(), "x.json")
    assert raw is not None, diags
    (repo / "device.bin").write_bytes(raw)
    assert changed(repo) == [
        "-binary DCF segment container, 225 bytes, canonical layout",
        "+binary DCF segment container, 230 bytes, canonical layout",
        '-0x2000sub0: 15 bytes 48616C6C20333B207261636B202332 = "Hall 3; rack #2"  attr 0x68 '
        "VSTR|R|W",
        f'+0x2000sub0: 20 bytes {longer} = "Hall 3; rack #2, top"  attr 0x68 VSTR|R|W']


@needs_git
def test_git_diff_of_a_concise_dcf_shows_the_changed_entries(repo):
    """network build's <slave>.bin: its heartbeat (0x1017, 50 ms) made 100 ms."""
    entries = concise.parse((FLAT / "drive.bin").read_bytes())
    commit(repo, "drive.bin", concise.to_bytes(entries))
    edited = [(i, s, (100).to_bytes(2, "little") if (i, s) == (0x1017, 0) else d)
              for i, s, d in entries]
    (repo / "drive.bin").write_bytes(concise.to_bytes(edited))
    assert changed(repo) == ["-0x1017sub0: UNSIGNED16  2 bytes 3200 = 50",
                             "+0x1017sub0: UNSIGNED16  2 bytes 6400 = 100"]


@needs_git
def test_git_diff_of_another_slave_s_concise_dcf_reads_its_entries(repo):
    commit(repo, "drive.bin", (FLAT / "drive.bin").read_bytes())
    (repo / "drive.bin").write_bytes((FLAT / "io.bin").read_bytes())
    lines = changed(repo)
    assert "-0x6060sub0: UNSIGNED8?  1 byte 08 = 8" in lines
    assert "-0x1017sub0: UNSIGNED16  2 bytes 3200 = 50" in lines


@needs_git
def test_git_diff_names_no_temporary_file_in_the_cached_diff_either(repo):
    commit(repo, "plc.bin", (SAMPLES / "plc.bin").read_bytes())
    (repo / "plc.bin").write_bytes((SAMPLES / "bild8.bin").read_bytes())
    assert git(repo, "add", "plc.bin").returncode == 0
    lines = changed(repo, "--cached")
    assert "-binary DCF segment container, 434 bytes, canonical layout" in lines
    assert "+binary DCF segment container, 127 bytes, canonical layout" in lines


@needs_git
def test_git_diff_of_a_damaged_concise_dcf_shows_what_is_read_and_the_error(repo):
    """`head -c 50 drive.bin > drive.bin`: the filter turns the damaged file into its four
    whole entries and the error as a line of text, exit 0 -- a failing filter makes git
    abort the whole diff ("unable to read files to diff")."""
    data = (FLAT / "drive.bin").read_bytes()
    commit(repo, "drive.bin", data)
    (repo / "drive.bin").write_bytes(data[:50])
    lines = changed(repo)
    assert [x for x in lines if x.startswith("+")] == [
        "+concise DCF (CiA 302-3), 50 bytes, damaged: 4 whole entries",
        "+0x1400sub1: UNSIGNED32  4 bytes 02020080 = 0x80000202 = COB-ID 0x202, invalid",
        "+0x1600sub0: UNSIGNED8  1 byte 00 = 0",
        "+! 8 bytes after them not read",
        "+! error at 0x2D: entry 5 of 22 (0x1600sub2) claims 4 data bytes, 1 remain [CON002]"]
    # the first two lines written twice are no longer "write 1/2": their second writes
    # are past the damage
    assert lines[:2] == [
        "-concise DCF (CiA 302-3), 223 bytes, 22 entries",
        "-0x1400sub1: UNSIGNED32  4 bytes 02020080 = 0x80000202 = COB-ID 0x202, invalid  "
        "write 1/2"]
    assert len(lines) == 21 + 5          # 23 lines of 22 entries, 2 of them unchanged


def test_textconv_of_bytes_that_are_no_container_is_text_and_exit_0(tmp_path):
    """What can be read and the error, as lines of the text; a file that cannot be read at
    all (missing, a FIFO) still fails, exit 3."""
    cases = {
        "plc.bin": ((SAMPLES / "plc.bin").read_bytes()[:50],
                    "binary DCF segment container, 50 bytes, damaged\n"
                    "! error at 0x0: header says 434 bytes, the file has 50 (truncated) "
                    "[CNT002]\n"),
        "empty.bin": (b"",
                      "binary DCF segment container, 0 bytes, damaged\n"
                      "! error at 0x0: 0 bytes: too short for the 40-byte header [CNT001]\n"),
        "text.bin": ((SAMPLES / "plc.dcf").read_bytes(),
                     "! error: the file is DCF/EDS text, not a binary container or a concise "
                     "DCF (CiA 302-3); use dcf2bin compile to make a container of it (dcf2bin "
                     "validate checks it)\n"),
    }
    for name, (data, text) in cases.items():
        (tmp_path / name).write_bytes(data)
        assert textconv(tmp_path / name) == (0, text, ""), name
    os.mkfifo(tmp_path / "fifo.bin")
    code, out, err = textconv(tmp_path / "fifo.bin")
    assert (code, out) == (3, "")
    assert err == f"{tmp_path}/fifo.bin: error: cannot read: a FIFO, not a regular file [IO001]\n"
