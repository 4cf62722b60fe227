"""What a command run imports and leaves behind besides its work (issue 22, the whole
process): the group imports only the command that runs, a clean compile imports no
report renderer, and the cyclic GC stays off until a big command has returned."""
from __future__ import annotations

import ast
import gc
import os
import subprocess
import sys

import click
import pytest
from click.testing import CliRunner

from conftest import SAMPLES
from dcf2bin import compiler
from dcf2bin.cli import COMMANDS, main
from dcf2bin.cli.common import LazyGroup, without_cyclic_gc
from dcf2bin.cli.network import SUBCOMMANDS, network_group


def _modules_after(args: list[str]) -> dict:
    """Run ``main(args)`` in a fresh interpreter; -> its exit code and which modules of
    dcf2bin and of the report path it imported."""
    code = ("import sys; from dcf2bin.cli import main\n"
            "try:\n    main(%r)\nexcept SystemExit as e:\n    code = e.code\n"
            "mods = sorted(m for m in sys.modules if m.startswith(('dcf2bin', 'json')))\n"
            "print(repr({'code': code, 'modules': mods}))" % (args,))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         env={**os.environ, "NO_COLOR": "1"}, check=True)
    return ast.literal_eval(out.stdout.strip().splitlines()[-1])


def test_compile_imports_its_own_command_module_only(tmp_path):
    res = _modules_after(["compile", str(SAMPLES / "plc.dcf"), "-o", str(tmp_path / "p.bin")])
    assert res["code"] == 0
    assert (tmp_path / "p.bin").read_bytes() == (SAMPLES / "plc.bin").read_bytes()
    cli = [m for m in res["modules"] if m.startswith("dcf2bin.cli")]
    assert cli == ["dcf2bin.cli", "dcf2bin.cli.common", "dcf2bin.cli.compile"]
    # nothing to print: neither the renderer nor json
    assert "dcf2bin.report" not in res["modules"]
    assert "json" not in res["modules"]


def test_compile_with_a_warning_renders_it_without_json(tmp_path):
    src = tmp_path / "w.bin"               # a DCF under a container's name: a warning
    src.write_bytes((SAMPLES / "plc.dcf").read_bytes())
    res = _modules_after(["compile", str(src), "-o", str(tmp_path / "w.out")])
    assert res["code"] == 0
    assert "dcf2bin.report" in res["modules"]
    assert "json" not in res["modules"]


def test_help_imports_every_command_and_lists_them_all():
    res = _modules_after(["--help"])
    assert res["code"] == 0
    for target in COMMANDS.values():
        assert target.partition(":")[0] in res["modules"]
    r = CliRunner().invoke(main, ["--help"])
    listed = [line.split()[0] for line in r.output.split("Commands:\n")[1].splitlines()]
    assert listed == sorted(COMMANDS)


def test_the_table_names_every_command_module():
    """A command module added to the package but not to COMMANDS would never run."""
    here = os.path.dirname(sys.modules["dcf2bin.cli"].__file__)
    modules = {f[:-3] for f in os.listdir(here)
               if f.endswith(".py") and f not in ("__init__.py", "common.py")}
    modules |= {"network", "lss"}
    assert {t.partition(":")[0].rpartition(".")[2] for t in COMMANDS.values()} == modules


def test_lazy_group_lists_without_importing_and_loads_on_demand():
    calls = []

    @click.command("one")
    def one():
        calls.append("one")

    group = LazyGroup("g", lazy={"one": f"{__name__}:_ONE", "two": "no.such.module:cmd"})
    globals()["_ONE"] = one
    ctx = click.Context(group)
    assert group.list_commands(ctx) == ["one", "two"]
    assert group._commands == {}                  # listing imported nothing
    assert group.get_command(ctx, "one") is one
    assert group.get_command(ctx, "three") is None
    with pytest.raises(ModuleNotFoundError):
        group.get_command(ctx, "two")


def test_every_command_is_reachable_and_named_as_listed():
    ctx = click.Context(main)
    for name in main.list_commands(ctx):
        cmd = main.get_command(ctx, name)
        assert isinstance(cmd, click.Command) and cmd.name == name
    assert sorted(main.commands) == sorted(COMMANDS)
    assert list(network_group.commands) == list(SUBCOMMANDS)


def test_a_misspelt_command_still_gets_a_suggestion():
    r = CliRunner().invoke(main, ["comple"])
    assert r.exit_code == 2
    assert "No such command 'comple'. Did you mean 'compile'?" in r.output


@pytest.mark.parametrize("bad", [False, True])
def test_compile_keeps_the_gc_off_until_it_returns(tmp_path, monkeypatch, bad):
    seen = []
    real = compiler.compile_path

    def spy(*args, **kwargs):
        res = real(*args, **kwargs)
        seen.append(gc.isenabled())         # compile_path is done: still off
        return res
    monkeypatch.setattr(compiler, "compile_path", spy)
    src = tmp_path / "in.dcf"
    data = (SAMPLES / "plc.dcf").read_bytes()
    if bad:                                 # an error: the compile stops, nothing written
        data = data.replace(b"ParameterValue=1000\r", b"ParameterValue=zz\r", 1)
    src.write_bytes(data)
    assert gc.isenabled()
    r = CliRunner().invoke(main, ["compile", str(src), "-o", str(tmp_path / "out.bin")])
    assert r.exit_code == (1 if bad else 0), r.output
    assert seen == [False]
    assert gc.isenabled()                   # the caller's setting again
    assert (tmp_path / "out.bin").exists() is not bad


def test_without_cyclic_gc_restores_the_callers_setting():
    @without_cyclic_gc
    def work(fail: bool):
        assert not gc.isenabled()
        if fail:
            raise ValueError("x")
        return 7

    assert gc.isenabled()
    assert work(False) == 7 and gc.isenabled()
    with pytest.raises(ValueError):
        work(True)
    assert gc.isenabled()
    gc.disable()
    try:
        assert work(False) == 7 and not gc.isenabled()   # off before: stays off
    finally:
        gc.enable()
