"""`dcf2bin dump` as git's textconv filter (README "diff", docs/diff.md "git"): a real
`git diff` in a temporary repository shows a container's changed entries, not "Binary
files differ"."""
from __future__ import annotations

import os
import shutil
import subprocess
import sys

import pytest

from conftest import ROOT, SAMPLES

GIT = shutil.which("git")
pytestmark = pytest.mark.skipif(GIT is None, reason="git is not installed")
FLAT = ROOT / "tests" / "golden" / "network" / "flat" / "out"


def git(repo, *args) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith("GIT_")}
    env.update(HOME=str(repo), GIT_CONFIG_NOSYSTEM="1", GIT_AUTHOR_NAME="t",
               GIT_AUTHOR_EMAIL="t@t", GIT_COMMITTER_NAME="t", GIT_COMMITTER_EMAIL="t@t")
    return subprocess.run([GIT, *args], cwd=repo, env=env, capture_output=True, text=True,
                          timeout=60)


@pytest.fixture
def repo(tmp_path):
    """A repository with the README's two lines: the attribute and the textconv command
    (this interpreter's dcf2bin, the same command as `dcf2bin dump - <`)."""
    assert git(tmp_path, "init", "-q").returncode == 0
    (tmp_path / ".gitattributes").write_text("*.bin diff=dcf2bin\n")
    dcf2bin = f"{sys.executable} -m dcf2bin"
    assert git(tmp_path, "config", "diff.dcf2bin.textconv",
               f"{dcf2bin} dump - <").returncode == 0
    return tmp_path


def commit(repo, name: str, data: bytes) -> None:
    (repo / name).write_bytes(data)
    assert git(repo, "add", ".").returncode == 0
    assert git(repo, "commit", "-qm", "x").returncode == 0


def test_git_diff_of_a_container_shows_the_changed_entries(repo):
    """samples/device.bin with 0x1017 (producer heartbeat time, 500) made 400: the entry's
    line and nothing but the entry's line, not the temporary file's name."""
    data = (SAMPLES / "device.bin").read_bytes()
    commit(repo, "device.bin", data)
    old = (500).to_bytes(2, "little")
    head = bytes.fromhex("171000") + (2).to_bytes(4, "little") + old
    assert data.count(head) == 1
    (repo / "device.bin").write_bytes(data.replace(head, head[:-2] + (400).to_bytes(2, "little")))
    r = git(repo, "diff")
    assert r.returncode == 0, r.stderr
    changed = [line for line in r.stdout.splitlines()
               if line[:1] in "+-" and not line.startswith(("+++", "---"))]
    assert len(changed) == 2 and "Binary files" not in r.stdout
    assert changed[0].split()[3:7] == ["0x1017", "0", "2", "F401"]     # 500
    assert changed[1].split()[3:7] == ["0x1017", "0", "2", "9001"]     # 400
    assert "git-blob" not in r.stdout


def test_git_diff_names_no_temporary_file_in_the_cached_diff_either(repo):
    commit(repo, "plc.bin", (SAMPLES / "plc.bin").read_bytes())
    (repo / "plc.bin").write_bytes((SAMPLES / "bild8.bin").read_bytes())
    assert git(repo, "add", "plc.bin").returncode == 0
    r = git(repo, "diff", "--cached")
    assert r.returncode == 0, r.stderr
    lines = r.stdout.splitlines()
    assert "-<stdin>: binary DCF segment container, 434 bytes, canonical layout" in lines
    assert "+<stdin>: binary DCF segment container, 127 bytes, canonical layout" in lines


@pytest.mark.skip(reason="dump reads no concise DCF before branch concise lands: then "
                         "git diff of network build's <slave>.bin shows its entries too")
def test_git_diff_of_a_concise_dcf_shows_the_changed_entries(repo):
    commit(repo, "drive.bin", (FLAT / "drive.bin").read_bytes())
    (repo / "drive.bin").write_bytes((FLAT / "io.bin").read_bytes())
    r = git(repo, "diff")
    assert r.returncode == 0, r.stderr
    assert "Binary files" not in r.stdout and "0x1017" in r.stdout
