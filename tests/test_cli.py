"""The command line: exit codes, outputs, atomic writes, lazy imports."""
from __future__ import annotations

import ast
import os
import pathlib
import subprocess
import sys

import pytest
from click.testing import CliRunner

from conftest import SAMPLES
from dcf2bin import __version__
from dcf2bin.cli import main


def run(*args, input=None):
    return CliRunner().invoke(main, list(args), input=input, catch_exceptions=False)


def test_compile_default_output(tmp_path):
    src = tmp_path / "plc.dcf"
    src.write_bytes((SAMPLES / "plc.dcf").read_bytes())
    r = run("compile", str(src))
    assert r.exit_code == 0, r.output
    assert (tmp_path / "plc.bin").read_bytes() == (SAMPLES / "plc.bin").read_bytes()


def test_compile_to_stdout_and_verbose(tmp_path):
    r = run("compile", str(SAMPLES / "bild8.dcf"), "-o", "-", "-v")
    assert r.exit_code == 0
    assert r.stdout_bytes == (SAMPLES / "bild8.bin").read_bytes()
    assert r.stderr == (f"{SAMPLES / 'bild8.dcf'} -> -: 127 bytes, 6 entries, 4 network "
                        "variables, PI 6 bytes (in 0 @ 0, out 6 @ 0)\n")


def test_compile_stdin_needs_output():
    r = run("compile", "-", input=(SAMPLES / "bild8.dcf").read_bytes())
    assert r.exit_code == 2
    assert r.stderr == "dcf2bin: error: reading stdin needs -o OUTPUT (or -o - for stdout)\n"
    r = run("compile", "-", "-o", "-", input=(SAMPLES / "bild8.dcf").read_bytes())
    assert r.exit_code == 0 and r.stdout_bytes == (SAMPLES / "bild8.bin").read_bytes()


def test_error_exit_and_nothing_written(tmp_path):
    src = tmp_path / "bad.dcf"
    src.write_text("[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=300\n")
    out = tmp_path / "bad.bin"
    out.write_bytes(b"previous")
    r = run("compile", str(src), "-o", str(out))
    assert r.exit_code == 1
    assert r.stderr.splitlines() == [
        f"{src}:4: error: 0x2000sub0: value 300 out of range for UNSIGNED8 (0..255) [DCF200]",
        f"{src}: 1 error, nothing written"]
    assert out.read_bytes() == b"previous"
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".dcf2bin-")] == []


def test_missing_node_id_names_both_ways(tmp_path):
    src = tmp_path / "n.dcf"
    src.write_text("[2000]\nDataType=0x0007\nAccessType=rw\nParameterValue=$NODEID+0x180\n")
    r = run("compile", str(src), "-o", "-")
    assert r.exit_code == 1
    assert r.stderr.splitlines()[:2] == [
        f"{src}:4: error: value '$NODEID+0x180' of 0x2000sub0 uses $NODEID but no node-ID is "
        "known [DCF201]",
        "    hint: give --node-id N or set NodeID in [DeviceComissioning]"]
    r = run("compile", str(src), "-o", "-", "--node-id", "2")
    assert r.exit_code == 0 and r.stdout_bytes.endswith(b"\x82\x01\x00\x00\x70")


def test_never_overwrites_input(tmp_path):
    src = tmp_path / "x.bin"
    data = (SAMPLES / "bild8.dcf").read_bytes()
    src.write_bytes(data)
    r = run("compile", str(src), "--from", "dcf", "-o", str(src))
    assert r.exit_code == 2
    assert "is the input file; refusing to overwrite it" in r.stderr
    assert src.read_bytes() == data


def test_unreadable_input_exit_3(tmp_path):
    r = run("compile", str(tmp_path / "missing.dcf"))
    assert r.exit_code == 3
    assert r.stderr == f"{tmp_path / 'missing.dcf'}: error: cannot read: No such file or directory [IO001]\n"


def test_usage_error_exit_2():
    r = CliRunner().invoke(main, ["compile", str(SAMPLES / "bild8.dcf"), "--node-id", "200"])
    assert r.exit_code == 2


def test_internal_error_is_one_line(monkeypatch, tmp_path):
    import dcf2bin.compiler as compiler

    def boom(*a, **k):
        raise KeyError("bug")
    monkeypatch.setattr(compiler, "compile_path", boom)
    r = CliRunner().invoke(main, ["compile", str(SAMPLES / "bild8.dcf"), "-o", "-"])
    assert r.exit_code == 70
    assert r.stderr == ("dcf2bin: internal error: KeyError: 'bug' (run with --debug for the "
                        "traceback, and please report it)\n")
    r = CliRunner().invoke(main, ["--debug", "compile", str(SAMPLES / "bild8.dcf"), "-o", "-"])
    assert isinstance(r.exception, KeyError)


def test_version():
    r = run("--version")
    assert r.output == f"dcf2bin, version {__version__}\n"


@pytest.mark.parametrize("args", [["--help"], ["--version"], ["compile", "--help"]])
def test_help_and_version_do_not_import_heavy_modules(args):
    code = ("import sys; from dcf2bin.cli import main\n"
            "try:\n    main(%r)\nexcept SystemExit:\n    pass\n"
            "bad = sorted(m for m in sys.modules\n"
            "             if m.split('.')[0] in ('construct', 'canopen', 'can'))\n"
            "print(bad)" % (args,))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "NO_COLOR": "1"})
    assert out.stdout.strip().splitlines()[-1] == "[]"


def _imports(path: pathlib.Path) -> list[tuple[int, str]]:
    """(line, absolute module name) of every import in a module, at any depth."""
    package = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if path.name != "__init__.py":
        package = package.rpartition(".")[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[:len(package.split(".")) - node.level + 1] if node.level \
                else []
            found.append((node.lineno, ".".join(base + [node.module or ""]).strip(".")))
    return found


PACKAGE = pathlib.Path(__file__).resolve().parent.parent / "dcf2bin"


def test_click_stays_in_the_cli_package_and_the_libraries_never_import_it():
    """click only under dcf2bin/cli/; dynod, plc and bus are libraries the CLI uses,
    never the other way round (no import cycle through dcf2bin.cli)."""
    bad = []
    for path in sorted(PACKAGE.rglob("*.py")):
        part = path.relative_to(PACKAGE).parts[0]
        for line, name in _imports(path):
            top = name.split(".")
            if top[0] == "click" and part != "cli":
                bad.append(f"{path.name}:{line}: {name}")
            if top[:2] == ["dcf2bin", "cli"] and part in ("dynod", "plc", "bus"):
                bad.append(f"{part}/{path.name}:{line}: {name}")
    assert bad == []


def test_python_m_entry_point():
    out = subprocess.run([sys.executable, "-m", "dcf2bin", "--version"], capture_output=True,
                         text=True)
    assert out.returncode == 0 and out.stdout == f"dcf2bin, version {__version__}\n"


def test_append_extra_writes_after_all_groups(tmp_path):
    """compile --append: ordered writes after every D-8 group, no PI address for them."""
    extra = tmp_path / "x.writes"
    extra.write_text("0x2200 0 UNSIGNED32 0x1A rw ; select KO 0x001A\n"
                     "0x2214 0 UNSIGNED32 1 wo  ; KO := 1\n")
    out = tmp_path / "a.bin"
    r = run("compile", str(SAMPLES / "bild8.dcf"), "-o", str(out), "--append", str(extra))
    assert r.exit_code == 0, r.stderr
    golden = (SAMPLES / "bild8.bin").read_bytes()
    data = out.read_bytes()
    assert len(data) == len(golden) + 2 * 11 + 2
    from dcf2bin.container import read
    c, _ = read(data)
    assert c.entries[-2:] == [(0x2200, 0, bytes.fromhex("1a000000")),
                              (0x2214, 0, bytes.fromhex("01000000"))]
    assert c.attributes[-2:] == bytes([0x70, 0x50])
    assert c.addresses == [0, 1, 2, 4]
    bad = tmp_path / "y.writes"
    bad.write_text("0x2200 0 UNSIGNED8 0x1FF\n")
    r = run("compile", str(SAMPLES / "bild8.dcf"), "-o", str(out), "--append", str(bad))
    assert r.exit_code == 1
    assert r.stderr.splitlines()[0] == (f"{bad}:1: error: 0x2200sub0: value 0x1FF (= 511) out "
                                        "of range for UNSIGNED8 (0..255) [DCF200]")


def test_refuses_binary_to_a_terminal():
    import pty
    master, slave = pty.openpty()
    try:
        out = subprocess.run([sys.executable, "-m", "dcf2bin", "compile",
                              str(SAMPLES / "bild8.dcf"), "-o", "-"],
                             stdout=slave, stderr=subprocess.PIPE, text=True,
                             env={**os.environ, "NO_COLOR": "1"})
    finally:
        os.close(slave)
        os.close(master)
    assert out.returncode == 2
    assert out.stderr == ("dcf2bin: error: refusing to write binary data to a terminal; "
                          "use -o FILE or a pipe\n")
