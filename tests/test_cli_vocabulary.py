"""Issue 19: one interface -- the same option, value syntax and help words in every command.

Walks every command and subcommand by click introspection (groups added later, such as
``network``, are walked too) and checks the shared vocabulary of cli/common.py."""
from __future__ import annotations

import click
import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES

from dcf2bin.cli import main
from dcf2bin.cli.bin2dcf import bin2dcf_main
from dcf2bin.cli.common import NODE_ID, SHARED_HELP, Integer, Option


def _commands(group=main, prefix=()):
    for name, cmd in sorted(group.commands.items()):
        path = prefix + (name,)
        if isinstance(cmd, click.Group):
            yield from _commands(cmd, path)
        else:
            yield " ".join(path), cmd
    if group is main:
        yield "bin2dcf (program)", bin2dcf_main


COMMANDS = dict(_commands())

# param name -> (the names shown in --help, the key of its first help sentence)
SHARED = {
    "node_id": (["-n", "--node-id"], "node_id"),
    "quiet": (["-q", "--quiet"], "quiet"),
    "verbose": (["-v", "--verbose"], "verbose"),
    "debug": (["--debug"], "debug"),
    "output": (["-o", "--output"], "output"),
    "fmt": (["-f", "--format"], "format"),
    "entries": (["--entries"], "entries"),
    "static_od": (["--static-od"], "static_od"),
    "force": (["--force"], "force"),
    "from_": (["--from"], "from_"),
}


# commands whose -o/--output is the folder of several outputs
FOLDER_OUTPUT = {("network build", "output"), ("network upload", "output")}


def _options(cmd):
    return [p for p in cmd.params if isinstance(p, click.Option) and p.name != "help"]


def _shown(p: click.Option) -> list[str]:
    return p.shown_names() if isinstance(p, Option) else p.opts + p.secondary_opts


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_shared_options_have_one_name_short_form_and_help(name):
    for p in _options(COMMANDS[name]):
        if p.name not in SHARED:
            continue
        names, key = SHARED[p.name]
        assert _shown(p) == names, (name, p.name)
        if (name, p.name) in FOLDER_OUTPUT:     # -o names a folder there, not a file
            assert p.help.startswith("Output folder"), (name, p.help)
            continue
        assert p.help.startswith(SHARED_HELP[key]), (name, p.name, p.help)


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_command_has_quiet_and_debug(name):
    params = {p.name for p in _options(COMMANDS[name])}
    assert {"quiet", "debug"} <= params, name
    if name not in ("download", "node", "network download"):   # they write to a bus
        assert "output" in params, name


@pytest.mark.parametrize("name", sorted(COMMANDS))
def test_every_integer_option_takes_the_dcf_integer_syntax(name):
    for p in _options(COMMANDS[name]):
        assert not isinstance(p.type, (click.types.IntParamType, click.IntRange)) \
            or isinstance(p.type, Integer), (name, p.name, p.type)
        if p.name in ("node_id", "manager"):
            assert p.type is NODE_ID and p.metavar in ("N", "M"), (name, p.name)


def test_a_short_or_long_name_means_one_thing_in_every_command():
    """-n is always the node-ID, -f always the format ...; --select is the one long name
    with two meanings, kept on purpose: rule codes in validate, the hidden old name of
    --entries in compile, simulate and map."""
    meaning: dict[str, set[str]] = {}
    for cmd in COMMANDS.values():
        for p in _options(cmd):
            for opt in p.opts + p.secondary_opts:
                meaning.setdefault(opt, set()).add(p.name)
    twice = {o: m for o, m in meaning.items() if len(m) > 1}
    assert twice == {"--select": {"select_", "entries"}}


def test_hidden_aliases_are_accepted_and_not_shown():
    runner = CliRunner()
    for name in ("compile", "simulate", "map", "download", "node", "export", "validate"):
        text = runner.invoke(main, [name, "--help"], terminal_width=200).stdout
        assert "--node-id" in text and "--node " not in text and "--node," not in text, name
    for name in ("compile", "simulate", "map"):
        text = runner.invoke(main, [name, "--help"], terminal_width=200).stdout
        assert "--entries" in text and "--select" not in text, name


def run(*args, **kw):
    return CliRunner().invoke(main, [str(a) for a in args], catch_exceptions=False, **kw)


@pytest.mark.parametrize("value", ["16", "0x10", "0X10", "020", " 16 "])
def test_node_id_in_any_dcf_integer_form(tmp_path, value):
    r = run("compile", SAMPLES / "plc.dcf", "-n", value, "-o", tmp_path / "x.bin")
    assert r.exit_code == 0, r.stderr
    assert (tmp_path / "x.bin").read_bytes() == \
        run("compile", SAMPLES / "plc.dcf", "--node-id", "16", "-o", "-").stdout_bytes


def test_the_issue_commands_take_hex():
    assert run("compile", SAMPLES / "plc.dcf", "--node-id", "0x10", "-o", "-").exit_code == 0
    assert run("download", SAMPLES / "plc.dcf", "-n", "0x03", "--dry-run").exit_code == 0
    r = run("simulate", SAMPLES / "plc.bin", "--pi-size", "0x10")
    assert r.exit_code == 0 and "target memory 16 bytes" in r.stdout, r.stdout
    assert run("simulate", SAMPLES / "plc.bin", "--pi-size", "0xF").exit_code == 1


@pytest.mark.parametrize("value,message", [
    ("0x80", "Invalid value for '-n' / '--node-id': 0x80 is not in the range 1<=x<=127"),
    ("0", "Invalid value for '-n' / '--node-id': 0 is not in the range 1<=x<=127"),
    ("08", "Invalid value for '-n' / '--node-id': '08' is not an integer (invalid octal "
           "literal '08'; decimal, 0x hex or 0 octal as in a DCF)"),
    ("$NODEID", "Invalid value for '-n' / '--node-id': '$NODEID' is not an integer "
                "($NODEID is not allowed here: '$NODEID'; decimal, 0x hex or 0 octal as in "
                "a DCF)"),
])
def test_a_bad_integer_is_a_usage_error_that_says_why(value, message):
    r = run("compile", SAMPLES / "plc.dcf", "--node-id", value, "-o", "-")
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == f"Error: {message}"


def test_old_names_still_run(tmp_path):
    """Scripts written before issue 19: download --node, compile --select all."""
    assert run("download", SAMPLES / "plc.dcf", "--node", "3", "--dry-run").exit_code == 0
    old = run("compile", SAMPLES / "device.dcf", "--select", "all", "-o", "-").stdout_bytes
    new = run("compile", SAMPLES / "device.dcf", "--entries", "all", "-o", "-").stdout_bytes
    assert old == new and old != run("compile", SAMPLES / "device.dcf", "-o", "-").stdout_bytes
    assert run("download", SAMPLES / "plc.dcf", "--node-id", "3", "--dry-run").exit_code == 0
    assert run("compile", SAMPLES / "plc.dcf", "--node", "3", "-o", "-").exit_code == 0


def test_validate_select_all_means_every_rule():
    for word in ("all", "ALL", "All"):
        r = run("validate", "--select", word, SAMPLES / "plc.dcf")
        assert r.exit_code == 0, r.stdout
        assert r.stdout == run("validate", SAMPLES / "plc.dcf").stdout
    assert run("validate", "--select", "ALL", "--ignore", "DCF213",
               SAMPLES / "plc.dcf").stdout == "0 errors, 0 warnings, 0 infos in 1 file\n"


def test_compile_has_f_and_debug_and_simulate_has_o(tmp_path):
    r = run("compile", SAMPLES / "plc.dcf", "-f", "c", "-o", tmp_path / "plc.c")
    assert r.exit_code == 0 and (tmp_path / "plc.c").read_text().startswith("/*")
    r = run("simulate", SAMPLES / "plc.bin", "-o", tmp_path / "report.txt")
    assert (r.exit_code, r.stdout) == (0, "")
    assert (tmp_path / "report.txt").read_text().startswith("0x00 kCopSuccessful")


def test_debug_on_every_command_shows_the_traceback(monkeypatch):
    import dcf2bin.filekind as filekind

    def boom(*a, **k):
        raise KeyError("bug")
    monkeypatch.setattr(filekind, "detect", boom)
    for args in (["compile", "samples/plc.dcf", "-o", "-"], ["dump", "samples/plc.bin"],
                 ["map", "samples/plc.dcf"], ["simulate", "samples/plc.bin"],
                 ["export", "-f", "lenze-st", "samples/device.eds"],
                 ["download", "samples/plc.dcf", "-n", "3", "--dry-run"]):
        r = CliRunner().invoke(main, args + ["--debug"])
        assert isinstance(r.exception, KeyError), args
        r = CliRunner().invoke(main, args)
        assert r.exit_code == 70, args
        assert r.stderr == ("dcf2bin: internal error: KeyError: 'bug' (run with --debug for "
                            "the traceback, and please report it)\n"), args


def test_quiet_on_allocate_and_tunnel(tmp_path):
    csv = tmp_path / "vars.csv"
    csv.write_text("name,type,direction\nA,UNSIGNED8,input\n")
    r = run("allocate", csv, "-v", "-q", "-o", tmp_path / "a.dcf")
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("allocate", csv, "-v", "-o", tmp_path / "a.dcf")
    assert r.stderr == "A: 0xA040sub1, input offset 0\n"
    r = run("tunnel", "1=2", "-o", tmp_path / "t.writes")
    assert r.stderr == "t.writes: 2 writes\n"
    r = run("tunnel", "1=2", "-q", "-o", tmp_path / "t.writes")
    assert (r.exit_code, r.stderr) == (0, "")


def test_readme_option_table_names_every_shared_option():
    text = (ROOT / "README.md").read_text()
    table = text[text.index("### Options every command shares"):]
    table = table[:table.index("\n### ", 5)]
    for names, _ in SHARED.values():
        assert f"`{', '.join(names)}" in table, names
    assert "`--select`" in table and "`--node`" in table


def test_readme_opens_with_the_two_commands_and_ci_runs_the_second_verbatim():
    """Both make a venv first (Debian and Ubuntu refuse pip outside one); .ci/run runs the
    second exactly as the README says it."""
    text = (ROOT / "README.md").read_text()
    head = text.split("\n")
    assert head[:2] == ["# dcf2bin", ""] and head[2] == "```sh" and head[5] == "```"
    first, second = head[3], head[4]
    venv = "python3 -m venv .venv && . .venv/bin/activate && "
    assert first.startswith(venv) and second.startswith(venv)
    assert first.endswith("dcf2bin compile -v samples/plc.dcf -o plc.bin && dcf2bin dump plc.bin")
    assert second.endswith("python3 -m pip install -q -e '.[test]' && python3 -m pytest -q")
    ci = (ROOT / ".ci" / "run").read_text().splitlines()
    assert second in ci


def _table_commands(cell: str) -> set[str]:
    """The README's "commands" cell as command names: "a, b", "every command",
    "every command but a, b and c", "network check/show/scan"."""
    every = {n for n in COMMANDS if n != "bin2dcf (program)"}
    if cell.startswith("every command"):
        but = cell.partition(" but ")[2]
        return every - _table_commands(but) if but else every
    names = set()
    for part in cell.replace(" and ", ", ").split(", "):
        head, _, subs = part.rpartition(" ")
        names |= {f"{head} {s}".strip() for s in subs.split("/")}
    return names


def test_readme_option_table_lists_the_commands_that_have_each_option():
    text = (ROOT / "README.md").read_text()
    table = text[text.index("### Options every command shares"):]
    table = table[:table.index("\n### ", 5)]
    rows = {}
    for line in table.splitlines():
        cells = [c.strip() for c in line.replace("\\|", "/").strip("|").split("|")]
        if line.startswith("| `") and len(cells) == 3:
            rows[cells[0].split("`")[1].split(", ")[-1].split(" ")[0]] = cells[2]
    by_option = {"--node-id": "node_id", "--output": "output", "--format": "fmt",
                 "--quiet": "quiet", "--verbose": "verbose", "--debug": "debug",
                 "--from": "from_", "--entries": "entries", "--static-od": "static_od",
                 "--force": "force"}
    assert set(by_option) <= set(rows)
    for opt, param in by_option.items():
        have = {n for n, cmd in COMMANDS.items() if n != "bin2dcf (program)"
                and any(p.name == param for p in _options(cmd))}
        assert _table_commands(rows[opt]) == have, opt
