"""Hostile DCF/EDS input (issue 10, items 1-8): every case ends in one clean ``file:line``
diagnostic, in bounded time and memory.

The pathological cases run ``dcf2bin`` in a subprocess with a generous ``timeout=`` and an
address-space limit, so that a case that would hang, or grow without bound, fails the
test instead of the test run. No test asserts a timing.
"""
from __future__ import annotations

import os
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin.cli import main
from dcf2bin.lint import Options, lint_bytes
from helpers import compile_text, messages

try:
    import resource
except ImportError:  # not on Windows
    resource = None

MEMORY_LIMIT = 1 << 30      # address space of a bounded run: 1 GiB
# seconds: far above what any case needs (lower it to see the old code fail sooner)
TIMEOUT = int(os.environ.get("DCF2BIN_TEST_TIMEOUT", "120"))


def _limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def bounded(*args: str, cwd=None) -> subprocess.CompletedProcess:
    """``python -m dcf2bin ARGS`` in a subprocess, with a time and a memory limit."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "NO_COLOR": "1"}
    env.pop("DCF2BIN_DEBUG", None)
    out = subprocess.run([sys.executable, "-m", "dcf2bin", *args], capture_output=True,
                         text=True, env=env, timeout=TIMEOUT, cwd=cwd,
                         preexec_fn=_limit_memory if resource else None)
    out.stderr = no_hints(out.stderr)
    return out


class _Result:
    def __init__(self, r):
        self.exit_code, self.stdout, self.stdout_bytes = r.exit_code, r.stdout, r.stdout_bytes
        self.stderr_with_hints = r.stderr
        self.stderr = no_hints(r.stderr)


def no_hints(text: str) -> str:
    """The diagnostic lines of compile's stderr (its hint lines are checked on their own)."""
    return "".join(x for x in text.splitlines(True) if not x.startswith("    hint: "))


def run(*args):
    return _Result(CliRunner().invoke(main, list(args), catch_exceptions=False))


def lint(data: bytes, name: str = "t.dcf", **opts) -> list[str]:
    return [d.format() for d in lint_bytes(name, data, Options(**opts)).diagnostics]


def errors_of(lines: list[str]) -> list[str]:
    return [x for x in lines if ": error: " in x]


# -- 1. a count in the file never drives a loop beyond what the file holds -------------------

def test_nrofseg_beyond_the_described_segments_is_one_error():
    res = compile_text("[DynamicChannels]\nNrOfSeg=2000\nType1=0x0005\nDir1=rw\n"
                       "Range1=0xA900-0xA93F\nType2=0x0005\n")
    assert messages(res) == [
        "test.dcf:2: error: [DynamicChannels] NrOfSeg=2000 but the section describes "
        "2 segments [DCF312]",
        "test.dcf:1: error: [DynamicChannels] segment 2 lacks Dir2, Range2 [DCF312]"]


@pytest.mark.parametrize("count", ["1000000", "0xFFFFFFFF"])
def test_nrofseg_huge_ends_at_once(tmp_path, count):
    src = tmp_path / "seg.dcf"
    src.write_bytes(f"[DynamicChannels]\nNrOfSeg={count}\n".encode())
    out = bounded("compile", "-q", str(src), "-o", str(tmp_path / "seg.bin"))
    shown = int(count, 0)
    assert (out.returncode, out.stderr) == (1, (
        f"{src}:2: error: [DynamicChannels] NrOfSeg={shown} but the section describes "
        f"0 segments [DCF312]\n"
        f"{src}: 1 error, nothing written\n"))
    out = bounded("validate", "-q", "--select", "DCF3", str(src))
    assert (out.returncode, out.stdout) == (1, (
        f"{src}:2: error: [DynamicChannels] NrOfSeg={shown} but the section describes "
        f"0 segments [DCF312]\n"))


def _segments(n: int) -> str:
    return "[DynamicChannels]\nNrOfSeg=%d\n" % n + "".join(
        f"Type{k}=0x0005\nDir{k}=rw\nRange{k}=0xA900-0xA900\n" for k in range(1, n + 1))


def test_overlapping_segments_are_named_once_each():
    res = compile_text(_segments(4))
    assert messages(res) == [
        f"test.dcf:{3 * k + 2}: error: [DynamicChannels] Range{k} overlaps Range1 (line 5) "
        "[DCF315]" for k in (2, 3, 4)]


def test_thousands_of_overlapping_segments_end(tmp_path):
    # every pair would be 4.5 million errors; one per segment is 2,999
    src = tmp_path / "segs.dcf"
    src.write_bytes(_segments(3000).encode())
    out = bounded("compile", "-q", str(src), "-o", str(tmp_path / "segs.bin"))
    assert out.returncode == 1
    assert out.stderr.endswith(f"{src}: 2999 errors, nothing written\n")


# -- 2. [Comments] Lines= ---------------------------------------------------------------------

@pytest.mark.parametrize("count", ["30000000", "99999999999999999999"])
def test_comment_lines_count_is_not_a_list_size(tmp_path, count):
    src = tmp_path / "c.dcf"
    src.write_bytes(f"[Comments]\nLines={count}\nLine1=one\n".encode())
    out = bounded("validate", "--select", "DCF059", str(src))
    assert (out.returncode, out.stdout, out.stderr) == (0, (
        f"{src}:2: warning: [Comments] Lines={count} but the Line<k> keys are 1 "
        "[DCF059]\n0 errors, 1 warning, 0 infos in 1 file\n"), "")


# -- 3. integer literals of any length -------------------------------------------------------

BIG = "0x" + "F" * 4400


def test_huge_default_value_is_a_value_error():
    text = (f"[2000]\nParameterName=x\nDataType=0x0007\nAccessType=rw\nDefaultValue={BIG}\n"
            f"ParameterValue={BIG}\n")
    assert messages(compile_text(text)) == [
        "test.dcf:6: error: 0x2000sub0: integer literal too long (4400 digits, at most 64) "
        "[DCF200]"]
    assert errors_of(lint(text.encode(), "test.dcf", active={"DCF200"})) == [
        "test.dcf:5: error: 0x2000sub0 DefaultValue: integer literal too long (4400 digits, "
        "at most 64) [DCF200]",
        "test.dcf:6: error: 0x2000sub0: integer literal too long (4400 digits, at most 64) "
        "[DCF200]"]


@pytest.mark.parametrize("key,extra", [("SubNumber", ""),
                                       ("CompactSubObj", "DataType=0x0007\nAccessType=rw\n")])
def test_huge_structural_number_is_one_error(key, extra):
    text = f"[2000]\nParameterName=x\nObjectType=0x8\n{extra}{key}={BIG}\n"
    line = 4 + extra.count("\n")
    assert errors_of(lint(text.encode(), "t.dcf", active={"DCF020", "DCF021", "DCF110",
                                                         "DCF111", "INT001"})) == [
        f"t.dcf:{line}: error: [2000] {key}: integer literal too long (4400 digits, at most 64) "
        "[DCF020]"]
    assert messages(compile_text(text, "t.dcf"), "warning")[0] == (
        f"t.dcf:{line}: warning: [2000] {key}: integer literal too long (4400 digits, at most 64) "
        "(not written by compile) [DCF020]")


@pytest.mark.parametrize("text", ["1" * 5000, "0x" + "0" * 5000 + "1", "0" * 70, "-" + "7" * 65],
                         ids=["decimal", "hex", "octal", "signed"])
def test_every_integer_literal_longer_than_64_digits_is_refused(text):
    from dcf2bin.values import ValueProblem, parse_int
    with pytest.raises(ValueProblem,
                       match=r"^integer literal too long \(\d+ digits, at most 64\)$"):
        parse_int(text)


def test_a_long_value_is_cut_in_the_message():
    text = "[2000]\nParameterName=x\nObjectType=0x9\nSubNumber=" + "x" * 100_000 + "\n"
    assert errors_of(lint(text.encode(), "t.dcf", active={"DCF020"})) == [
        "t.dcf:4: error: [2000] SubNumber: invalid integer '" + "x" * 40 + "..." + "x" * 12
        + " (100000 characters)' [DCF020]"]


def test_64_digit_literals_still_read():
    from dcf2bin.values import parse_int
    assert parse_int("0x" + "0" * 63 + "1") == 1
    assert parse_int("0" * 64) == 0


# -- 4. a NUL byte in DownloadFile= ----------------------------------------------------------

DOMAIN_ENTRY = ("[2000]\nParameterName=D\nObjectType=0x7\nDataType=0x000F\nAccessType=rw\n"
                "DownloadFile={}\n")


def test_nul_in_download_file_is_a_diagnostic_everywhere(tmp_path):
    src = tmp_path / "nul.dcf"
    src.write_bytes(DOMAIN_ENTRY.format("a\x00b").encode())
    message = f"{src}:6: error: DownloadFile 'a\\x00b' contains a NUL byte [DCF202]\n"
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "nul.bin"))
    assert (r.exit_code, r.stderr) == (1, message + f"{src}: 1 error, nothing written\n")
    r = run("validate", "-q", "--select", "DCF202", str(src))
    assert (r.exit_code, r.stdout) == (1, message)
    r = run("export", "-q", "--format", "port-c", str(src), "-o", str(tmp_path / "nul.c"))
    assert (r.exit_code, r.stderr) == (1, message + f"{src}: 1 error, nothing written\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["nul.dcf"]


# -- 5. linear time; a CR-only file ----------------------------------------------------------

def _device(extra: str) -> str:
    return ("[2000]\nParameterName=x\nObjectType=0x7\nDataType=0x0008\nAccessType=rw\n"
            + extra)


@pytest.mark.parametrize("name,text", [
    # a long line full of '=' (the numeric-comment pre-filter of DCF057/DCF203)
    ("equals", _device("DefaultValue=1\nX=" + "=" * 200_000 + "\n")),
    # a REAL32 value of many digits that is not a number
    ("digits", _device("ParameterValue=" + "1" * 100_000 + "x\n")),
    # a numeric comment search over a long run of blanks
    ("blanks", _device("ParameterValue=1" + " " * 100_000 + "x ;\n")),
    # a [DynamicChannels] Range of many '-'
    ("dashes", "[DynamicChannels]\nNrOfSeg=1\nType1=0x0005\nDir1=rw\nRange1="
               + "-" * 100_000 + " x\n"),
], ids=lambda v: v if len(v) < 10 else "")
def test_long_lines_take_linear_time(tmp_path, name, text):
    src = tmp_path / f"{name}.dcf"
    src.write_bytes(text.encode())
    out = bounded("validate", "-q", str(src))
    assert out.returncode == 1 and "INT001" not in out.stdout and out.stderr == ""
    out = bounded("compile", "-q", str(src), "-o", str(tmp_path / "x.bin"))
    assert out.returncode in (0, 1) and "internal error" not in out.stderr


CR_ONLY = "[2000]\rParameterName=x\rDataType=0x0005\rAccessType=rw\rParameterValue=1\r"


def test_cr_only_file_is_one_error_in_compile_and_validate(tmp_path):
    src = tmp_path / "mac.dcf"
    src.write_bytes(CR_ONLY.encode())
    error = (f"{src}:1: error: the lines end in CR alone (classic Mac OS); only LF and CRLF "
             "end lines in an EDS/DCF [DCF008]\n")
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "mac.bin"))
    assert (r.exit_code, r.stderr) == (1, error + f"{src}: 1 error, nothing written\n")
    r = run("validate", "-q", str(src))
    assert (r.exit_code, r.stdout) == (1, error)
    r = run("compile", str(src), "-o", str(tmp_path / "mac.bin"))
    assert r.stderr_with_hints.splitlines()[1] == "    hint: convert the line ends to LF or CRLF"


def test_big_cr_only_file_ends(tmp_path):
    src = tmp_path / "big.dcf"
    src.write_bytes((CR_ONLY * 100_000).encode())      # 6 MB on one "line"
    out = bounded("validate", "-q", str(src))
    assert (out.returncode, out.stdout) == (1, (
        f"{src}:1: error: the lines end in CR alone (classic Mac OS); only LF and CRLF end "
        "lines in an EDS/DCF [DCF008]\n"))


def test_lone_cr_inside_an_lf_file_is_still_read():
    res = compile_text("[2000]\nParameterName=a\rb\nDataType=0x0005\nAccessType=rw\n"
                       "ParameterValue=1\n")
    assert res.ok and res.container.entries == [(0x2000, 0, b"\x01")]


# -- 6. an empty file; nothing configured ----------------------------------------------------

@pytest.mark.parametrize("data,what", [(b"", "is empty"), (b"\n  \n", "is empty"),
                                       (b"; only a comment\n", "has no sections")],
                         ids=["empty", "blank", "comment"])
def test_no_sections_is_an_error_in_compile_and_validate(tmp_path, data, what):
    src = tmp_path / "e.dcf"
    src.write_bytes(data)
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "e.bin"))
    assert (r.exit_code, r.stderr) == (1, f"{src}: error: the file {what} [DCF056]\n"
                                          f"{src}: 1 error, nothing written\n")
    assert not (tmp_path / "e.bin").exists()
    r = run("validate", "-q", str(src))
    assert (r.exit_code, r.stdout) == (1, f"{src}: error: the file {what} [DCF056]\n")


EDS = ("[FileInfo]\nFileName=x.eds\n[2000]\nParameterName=A\nObjectType=0x7\n"
       "DataType=0x0005\nAccessType=rw\nDefaultValue=3\n")


def test_an_empty_or_binary_static_od_is_an_error(tmp_path):
    src = tmp_path / "x.dcf"
    src.write_bytes(EDS.encode() + b"ParameterValue=4\n")
    static = tmp_path / "static.eds"
    for data, message in ((b"", "the file is empty"),
                          (b"\x00" * 64, "the file looks binary, not like EDS/DCF text (64 "
                                          "control bytes in its first 64, the first at byte "
                                          "0x0)")):
        static.write_bytes(data)
        r = run("compile", "-q", "--static-od", str(static), str(src), "-o", "-")
        line = "" if data == b"" else ":1"
        assert (r.exit_code, r.stderr) == (1, f"{static}{line}: error: static OD: {message} "
                                              f"[{'DCF056' if line == '' else 'DCF008'}]\n"
                                              f"{static}: 1 error in the static OD, "
                                              "nothing written\n")


def test_nothing_configured_compiles_with_a_warning(tmp_path):
    src = tmp_path / "x.eds"
    src.write_bytes(EDS.encode())
    r = run("compile", str(src), "-o", str(tmp_path / "x.bin"))
    assert (r.exit_code, r.stderr_with_hints) == (0, (
        f"{src}: warning: nothing is configured (no ParameterValue or DownloadFile, no network "
        "variable): the container holds no entries [DCF009]\n"
        "    hint: --entries all also writes every DefaultValue (the device's defaults)\n"))
    r = run("compile", "--entries", "all", str(src), "-o", str(tmp_path / "x.bin"))
    assert (r.exit_code, r.stderr) == (0, "")


def test_select_all_with_no_value_still_warns():
    res = compile_text("[2000]\nParameterName=A\nDataType=0x0005\nAccessType=rw\n",
                       select="all")
    assert res.ok and messages(res, "warning") == [
        "test.dcf: warning: no entry has a value: the container holds no entries [DCF009]"]


# -- 7. DownloadFile: symlinks, FIFOs, devices, size -----------------------------------------

def _domain_dcf(folder, name: str):
    folder.mkdir(exist_ok=True)
    src = folder / "d.dcf"
    src.write_bytes(DOMAIN_ENTRY.format(name).encode())
    return src


@pytest.mark.skipif(not hasattr(os, "symlink") or sys.platform == "win32",
                    reason="needs POSIX symbolic links")
def test_symlink_out_of_the_folder_is_refused(tmp_path):
    secret = tmp_path / "secret"
    secret.write_bytes(b"password")
    src = _domain_dcf(tmp_path / "dcf", "link")
    os.symlink(secret, tmp_path / "dcf" / "link")
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "d.bin"))
    assert (r.exit_code, r.stderr) == (1, (
        f"{src}:6: error: DownloadFile 'link' leads through a symbolic link out of the DCF's "
        f"folder [DCF202]\n{src}: 1 error, nothing written\n"))
    r = run("compile", "-q", "--allow-external-files", str(src), "-o", "-")
    assert r.exit_code == 0 and b"\x00\x20\x00\x08\x00\x00\x00password" in r.stdout_bytes


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs os.mkfifo (POSIX)")
def test_fifo_is_refused_without_blocking(tmp_path):
    src = _domain_dcf(tmp_path / "dcf", "pipe")
    os.mkfifo(tmp_path / "dcf" / "pipe")
    for cmd in (["compile", "-q", str(src), "-o", str(tmp_path / "d.bin")],
                ["export", "-q", "--format", "port-c", str(src), "-o", str(tmp_path / "d.c")]):
        out = bounded(*cmd)
        assert (out.returncode, out.stderr) == (1, (
            f"{src}:6: error: DownloadFile 'pipe' is not a regular file [DCF202]\n"
            f"{src}: 1 error, nothing written\n"))
    out = bounded("validate", "-q", "--hints", "--select", "DCF202", str(src))
    assert (out.returncode, out.stdout) == (
        1, f"{src}:6: error: DownloadFile 'pipe' is not a regular file [DCF202]\n"
           "    hint: name a regular file, not a device, pipe or directory\n")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs os.mkfifo (POSIX)")
def test_validate_walks_past_a_fifo_in_a_folder(tmp_path):
    os.mkfifo(tmp_path / "pipe.dcf")
    (tmp_path / "empty.eds").write_bytes(b"")
    out = bounded("validate", "-q", str(tmp_path))
    assert (out.returncode, out.stdout) == (1, f"{tmp_path / 'empty.eds'}: error: the file is "
                                               "empty [DCF056]\n")


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_device_is_refused(tmp_path):
    src = _domain_dcf(tmp_path / "dcf", "/dev/zero")
    out = bounded("compile", "-q", "--allow-external-files", str(src), "-o",
                  str(tmp_path / "d.bin"))
    assert (out.returncode, out.stderr) == (1, (
        f"{src}:6: error: DownloadFile '/dev/zero' is not a regular file [DCF202]\n"
        f"{src}: 1 error, nothing written\n"))


def test_download_file_over_16_mib_is_refused(tmp_path):
    src = _domain_dcf(tmp_path / "dcf", "big.bin")
    with open(tmp_path / "dcf" / "big.bin", "wb") as f:
        f.truncate((16 << 20) + 1)          # sparse: costs no disk
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "d.bin"))
    assert (r.exit_code, r.stderr) == (1, (
        f"{src}:6: error: DownloadFile 'big.bin' is larger than 16 MiB [DCF202]\n"
        f"{src}: 1 error, nothing written\n"))


def test_directory_is_refused(tmp_path):
    src = _domain_dcf(tmp_path / "dcf", "sub")
    (tmp_path / "dcf" / "sub").mkdir()
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "d.bin"))
    assert r.exit_code == 1
    assert r.stderr.splitlines()[0] in (
        f"{src}:6: error: DownloadFile 'sub' is not a regular file [DCF202]",
        f"{src}:6: error: cannot read DownloadFile 'sub': Is a directory [DCF202]")


def test_download_file_inside_the_folder_is_read(tmp_path):
    src = _domain_dcf(tmp_path / "dcf", "data.bin")
    (tmp_path / "dcf" / "data.bin").write_bytes(b"\x01\x02\x03")
    r = run("compile", "-q", str(src), "-o", "-")
    assert r.exit_code == 0 and r.stdout_bytes[40:40 + 4 + 7 + 3] == (
        b"\x01\x00\x00\x00" + b"\x00\x20\x00\x03\x00\x00\x00" + b"\x01\x02\x03")


# -- 8. UTF-16 and binary input: one error, not thousands ------------------------------------

TEXT = "[FileInfo]\r\nFileName=x.dcf\r\n[2000]\r\nParameterName=A\r\n" * 50


@pytest.mark.parametrize("data,message", [
    (TEXT.encode("utf-16"), "the file looks like UTF-16 text (it starts with a UTF-16 byte "
                            "order mark); an EDS/DCF is UTF-8 or Latin-1"),
    (TEXT.encode("utf-16-le"), "the file looks like UTF-16 text (every other byte is 0); an "
                               "EDS/DCF is UTF-8 or Latin-1"),
    (TEXT.encode("utf-16-be"), "the file looks like UTF-16 text (every other byte is 0); an "
                               "EDS/DCF is UTF-8 or Latin-1"),
], ids=["bom", "le", "be"])
def test_utf16_is_one_error(tmp_path, data, message):
    src = tmp_path / "u.dcf"
    src.write_bytes(data)
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "u.bin"))
    assert (r.exit_code, r.stderr) == (1, f"{src}:1: error: {message} [DCF008]\n"
                                          f"{src}: 1 error, nothing written\n")
    r = run("validate", "-q", str(src))
    assert (r.exit_code, r.stdout) == (1, f"{src}:1: error: {message} [DCF008]\n")


def test_binary_is_one_error_naming_the_line_of_its_first_control_byte(tmp_path):
    src = tmp_path / "b.dcf"
    src.write_bytes(b"[FileInfo]\nFileName=\n" + bytes(range(256)) * 400)   # 100 KiB
    message = (f"{src}:3: error: the file looks binary, not like EDS/DCF text (832 control "
               "bytes in its first 8192, the first at byte 0x15) [DCF008]\n")
    r = run("compile", "-q", str(src), "-o", str(tmp_path / "b.bin"))
    assert (r.exit_code, r.stderr) == (1, message + f"{src}: 1 error, nothing written\n")
    r = run("validate", "-q", str(src))
    assert (r.exit_code, r.stdout) == (1, message)


def test_a_container_named_dcf_is_checked_as_a_container(tmp_path):
    """Issue 19: the content decides (one rule for every command); the name that says
    otherwise is one IO002 warning."""
    src = tmp_path / "plc.dcf"
    src.write_bytes((ROOT / "samples" / "plc.bin").read_bytes())
    r = run("validate", "--hints", str(src))
    assert (r.exit_code, r.stdout.splitlines()) == (0, [
        f"{src}: warning: {src} is a binary container, not DCF/EDS text as its name says; "
        "checked as a binary container [IO002]",
        "    hint: rename the file to the suffix of its kind (.dcf/.eds text, .bin container)",
        "0 errors, 1 warning, 0 infos in 1 file"])
    assert run("validate", "--strict", "-q", str(src)).exit_code == 1


def test_a_few_stray_control_bytes_are_still_text():
    res = compile_text("[2000]\nParameterName=a\x01b\nDataType=0x0005\nAccessType=rw\n"
                       "ParameterValue=1\n")
    assert res.ok
