"""Issue 19: the exit-code table (docs/options.md), command by command (70 is in
test_cli_vocabulary: --debug and the one-line internal error on every command).

0 success, 1 the input has errors (or is of a kind the command does not read), 2 usage
error, 3 an input could not be read (missing, a directory) or an output could not be
written (-o naming a directory)."""
from __future__ import annotations

import uuid

import pytest
from click.testing import CliRunner
from conftest import SAMPLES

from dcf2bin.cli import main
from dcf2bin.diagnostics import ExitCode

BAD_DCF = "[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=300\n"
CSV = "name,type,direction\nA,UNSIGNED8,input\n"
BAD_CSV = "name,type,direction\nA,NOSUCHTYPE,input\n"


def _args(template, tmp):
    out = []
    for a in template:
        a = a.replace("{S}", str(SAMPLES)).replace("{T}", str(tmp))
        if a == "{BUS}":
            out += ["-i", "virtual", "--channel", f"exit-{uuid.uuid4().hex[:8]}"]
        else:
            out.append(a)
    return out


# command -> {exit code: [argument lists]}; {T} is a folder holding bad.dcf, bad.bin,
# vars.csv, bad.csv and the empty folder adir; "-o {T}/adir" is an output that is a folder
TABLE = {
    "compile": {
        0: [["{S}/plc.dcf", "-o", "{T}/out.bin"]],
        1: [["{T}/bad.dcf", "-o", "{T}/out.bin"], ["{S}/plc.bin", "-o", "{T}/out.bin"]],
        2: [["{S}/plc.dcf", "--node-id", "200"], ["{S}/plc.dcf", "--entries", "some"]],
        3: [["{T}/missing.dcf"], ["{T}/adir"], ["{S}/plc.dcf", "-o", "{T}/adir"],
            ["{S}/plc.dcf", "-o", "-", "--static-od", "{T}/missing.eds"]],
    },
    "dump": {
        0: [["{S}/plc.bin"]],
        1: [["{T}/bad.bin"], ["{S}/plc.dcf"]],
        2: [["{S}/plc.bin", "-f", "yaml"]],
        3: [["{T}/missing.bin"], ["{T}/adir"], ["{S}/plc.bin", "-o", "{T}/adir"]],
    },
    "bin2dcf": {
        0: [["{S}/plc.bin", "-o", "{T}/out.dcf"]],
        1: [["{T}/bad.bin", "-o", "-"], ["{S}/plc.dcf", "-o", "-"]],
        2: [["{S}/plc.bin"]],                         # plc.dcf exists beside it
        3: [["{T}/missing.bin", "-o", "-"], ["{T}/adir", "-o", "-"],
            ["{S}/plc.bin", "-o", "{T}/adir"]],
    },
    "validate": {
        0: [["{S}/plc.dcf"], ["--select", "ALL", "{S}/plc.bin"]],
        1: [["{T}/bad.dcf"], ["{T}/bad.bin"]],
        2: [["--select", "NOPE1", "{S}/plc.dcf"], []],
        3: [["{T}/missing.dcf"], ["{T}/adir"], ["{S}/plc.dcf", "-o", "{T}/adir"]],
    },
    "export": {
        0: [["-f", "lenze-st", "-n", "3", "{S}/device.eds"]],
        1: [["-f", "lenze-st", "{T}/bad.dcf"], ["-f", "lenze-st", "{S}/plc.bin"]],
        2: [["{S}/device.eds"]],                      # no --format
        3: [["-f", "lenze-st", "{T}/missing.eds"], ["-f", "lenze-st", "{T}/adir"],
            ["-f", "lenze-st", "-n", "3", "{S}/device.eds", "-o", "{T}/adir"]],
    },
    "convert": {
        0: [["{S}/device.eds", "-o", "{T}/out.xdd"]],
        # (bad.dcf's value out of range is carried as written: validate says it of both)
        1: [["{T}/vars.csv", "-o", "{T}/out.xdd"], ["{S}/plc.bin", "-o", "{T}/out.xdd"]],
        2: [["{S}/device.eds"], ["{S}/device.eds", "-o", "{T}/out.txt"]],
        3: [["{T}/missing.eds", "-o", "{T}/out.xdd"], ["{T}/adir", "-o", "{T}/out.xdd"],
            ["{S}/device.eds", "-o", "{T}/adir", "-f", "xdd"]],
    },
    "tunnel": {
        0: [["1=2"]],
        2: [["1"], []],
        3: [["1=2", "-o", "{T}/adir"]],
    },
    "simulate": {
        0: [["{S}/plc.bin"], ["{S}/plc.dcf"]],
        1: [["{S}/plc.bin", "--pi-size", "4"], ["{T}/bad.dcf"], ["{T}/bad.bin"],
            ["{S}/plc.bin", "--static-od", "{S}/bild8.bin"]],
        2: [["{S}/plc.bin", "--pi-size", "-1"]],
        3: [["{T}/missing.bin"], ["{T}/adir"], ["{S}/plc.bin", "-o", "{T}/adir"],
            ["{S}/plc.bin", "--static-od", "{T}/missing.eds"]],
    },
    "map": {
        0: [["{S}/plc.dcf"], ["{S}/plc.bin"]],
        1: [["{T}/bad.dcf"], ["{T}/bad.bin"]],
        2: [["{S}/plc.dcf", "-f", "png"]],
        3: [["{T}/missing.dcf"], ["{T}/adir"], ["{S}/plc.dcf", "-o", "{T}/adir"]],
    },
    "allocate": {
        0: [["{T}/vars.csv"]],
        1: [["{T}/bad.csv"], ["{S}/plc.bin"]],
        2: [["{T}/vars.csv", "--nope"]],
        3: [["{T}/missing.csv"], ["{T}/adir"], ["{T}/vars.csv", "-o", "{T}/adir"]],
    },
    "download": {
        0: [["{S}/plc.dcf", "-n", "3", "--dry-run"]],
        1: [["{T}/bad.dcf", "-n", "3", "--dry-run"], ["{T}/bad.bin", "-n", "3", "--dry-run"]],
        2: [["{S}/plc.dcf"], ["{S}/plc.dcf", "-n", "128", "--dry-run"]],
        3: [["{T}/missing.dcf", "-n", "3", "--dry-run"], ["{T}/adir", "-n", "3", "--dry-run"],
            ["{S}/plc.dcf", "-n", "3", "-i", "no-such-interface"]],
    },
    "upload": {
        0: [["--help"]],
        1: [["-n", "3", "--eds", "{S}/device.eds", "{BUS}", "--timeout", "0.01", "--retries",
             "0", "-o", "{T}/out.dcf"],
            ["-n", "3", "--eds", "{T}/bad.bin", "-o", "{T}/out.dcf"]],
        2: [["--eds", "{S}/device.eds"], ["-n", "128", "--eds", "{S}/device.eds"]],
        3: [["-n", "3", "--eds", "{T}/missing.eds"], ["-n", "3", "--eds", "{T}/adir"],
            ["-n", "3", "--eds", "{S}/device.eds", "-o", "{T}/adir"],
            ["-n", "3", "--eds", "{S}/device.eds", "-i", "no-such-interface"]],
    },
    "diff": {
        0: [["{S}/plc.dcf", "{S}/plc.bin"]],
        1: [["{S}/device.eds", "{S}/device.dcf"]],                 # they differ
        2: [["{S}/plc.dcf"], ["{S}/plc.dcf", "{S}/plc.bin", "-f", "yaml"],
            ["{T}/adir", "{S}/plc.dcf"]],
        3: [["{T}/missing.dcf", "{S}/plc.dcf"], ["{T}/bad.bin", "{S}/plc.bin"],
            ["{T}/vars.csv", "{S}/plc.dcf"], ["{S}/plc.dcf", "{S}/plc.bin", "-o", "{T}/adir"],
            ["{S}/plc.dcf", "-n", "3", "-i", "no-such-interface"]],
    },
    "node": {
        0: [["{S}/device.eds", "-n", "3", "{BUS}", "--duration", "0"]],
        1: [["--container", "{S}/plc.bin", "-n", "3", "--static-od", "{S}/bild8.bin",
             "{BUS}", "--duration", "0"],
            ["--container", "{S}/device.dcf", "-n", "3", "{BUS}", "--duration", "0"]],
        2: [[], ["{S}/device.eds", "--container", "{S}/plc.bin"]],
        3: [["{T}/missing.eds", "{BUS}", "--duration", "0"],
            ["{T}/adir", "{BUS}", "--duration", "0"],
            ["--container", "{T}/missing.bin", "-n", "3", "{BUS}", "--duration", "0"]],
    },
}

CASES = [(cmd, code, args) for cmd, codes in TABLE.items() for code, arglists in codes.items()
         for args in arglists]


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "bad.dcf").write_text(BAD_DCF)
    (tmp_path / "bad.bin").write_bytes(b"\x30\x00\x00\x00" + b"\x01\x00" * 10)
    (tmp_path / "vars.csv").write_text(CSV)
    (tmp_path / "bad.csv").write_text(BAD_CSV)
    (tmp_path / "adir").mkdir()
    return tmp_path


@pytest.mark.parametrize("cmd,code,args", CASES,
                         ids=[f"{c}-{code}-{i}" for i, (c, code, _) in enumerate(CASES)])
def test_exit_code(folder, cmd, code, args):
    r = CliRunner().invoke(main, [cmd] + _args(args, folder), catch_exceptions=False)
    assert r.exit_code == code, (r.stdout, r.stderr)
    if code in (1, 3):
        # validate's findings and simulate's return code are their result, on stdout
        said = r.stderr + (r.stdout if cmd in ("validate", "simulate") else "")
        assert said.strip(), "an error without a line that says it"


def test_every_command_is_in_the_table():
    assert set(TABLE) == set(main.commands) - {"network", "lss"}
    for cmd, codes in TABLE.items():
        assert {0, 2, 3} <= set(codes), cmd
        if cmd != "tunnel":                # tunnel reads no input: its errors are usage
            assert 1 in codes, cmd


def test_a_directory_is_exit_3_with_one_line(folder):
    for cmd in ("compile", "dump", "map", "simulate", "allocate"):
        r = CliRunner().invoke(main, [cmd, str(folder / "adir")])
        assert (r.exit_code, r.stderr) == (
            ExitCode.UNREADABLE, f"{folder / 'adir'}: error: cannot read: Is a directory [IO001]\n"), cmd
    r = CliRunner().invoke(main, ["map", str(SAMPLES / "plc.dcf"), "-o", str(folder / "adir")])
    assert (r.exit_code, r.stderr) == (
        ExitCode.UNREADABLE, f"{folder / 'adir'}: error: cannot write: Is a directory\n")


def test_validate_an_empty_directory_counts_no_file(folder):
    r = CliRunner().invoke(main, ["validate", str(folder / "adir")])
    assert (r.exit_code, r.stdout) == (3, (
        f"{folder / 'adir'}: error: no *.dcf, *.eds, *.xdd, *.xdc, *.xpd or *.bin file in "
        "this directory [IO001]\n"
        "1 error, 0 warnings, 0 infos in 0 files\n"))


# -- default output names never replace a file (docs/options.md, "Output files") ------

def test_compile_default_output_never_replaces_a_file(tmp_path):
    src = tmp_path / "plc.dcf"
    src.write_bytes((SAMPLES / "plc.dcf").read_bytes())
    for out, extra in ((tmp_path / "plc.bin", []), (tmp_path / "plc.c", ["-f", "c"])):
        out.write_text("the user's own file\n")
        r = CliRunner().invoke(main, ["compile", str(src), *extra])
        assert (r.exit_code, r.stderr) == (2, (
            f"{out}: error: the file exists; name the output with -o to replace it, or give "
            "--force\n"))
        assert out.read_text() == "the user's own file\n"
        r = CliRunner().invoke(main, ["compile", str(src), *extra, "--force"])
        assert (r.exit_code, r.stderr) == (0, "")
        assert out.read_bytes() != b"the user's own file\n"
        out.write_text("the user's own file\n")
        r = CliRunner().invoke(main, ["compile", str(src), *extra, "-o", str(out)])
        assert r.exit_code == 0 and out.read_bytes() != b"the user's own file\n"
    (tmp_path / "plc.bin").unlink()
    r = CliRunner().invoke(main, ["compile", str(src)])
    assert r.exit_code == 0
    assert (tmp_path / "plc.bin").read_bytes() == (SAMPLES / "plc.bin").read_bytes()


def test_bin2dcf_force_replaces_the_default_output(tmp_path):
    (tmp_path / "plc.bin").write_bytes((SAMPLES / "plc.bin").read_bytes())
    (tmp_path / "plc.dcf").write_text("; the user's own DCF\n")
    r = CliRunner().invoke(main, ["bin2dcf", str(tmp_path / "plc.bin"), "--force"])
    assert r.exit_code == 0
    assert (tmp_path / "plc.dcf").read_text().startswith(
        f"; DCF written by dcf2bin bin2dcf from {tmp_path / 'plc.bin'} (434 bytes, 34 entries).")
