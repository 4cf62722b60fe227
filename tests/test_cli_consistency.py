"""What a user trips over between commands (issue 10, items 8 and 16-19): one text form
with a cap per rule, one meaning of -q, one exit-code table, help and man pages that say
the rules themselves, samples that validate cleanly."""
from __future__ import annotations

import io
import json
import re

import click
import pytest
from click.testing import CliRunner
from conftest import ROOT, SAMPLES

from dcf2bin import __version__, report
from dcf2bin.cli import main
from dcf2bin.diagnostics import Diagnostic, ExitCode, Severity

FIX = ROOT / "tests" / "fixtures" / "lint"
BAD_TEXT = "[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=300\n"


def run(*args, input=None):
    return CliRunner().invoke(main, [str(a) for a in args], input=input,
                              catch_exceptions=False)


# -- item 8: at most 20 diagnostics per rule and file in text ----------------------------------

def _broken_lines(n: int) -> str:
    return "[2000]\nDataType=0x0005\nAccessType=rw\nParameterValue=1\n" + \
        "".join(f"junk line {i}\n" for i in range(n))


def test_compile_prints_20_per_rule_then_says_how_many_were_left_out(tmp_path):
    src = tmp_path / "junk.dcf"
    src.write_text(_broken_lines(30))
    r = run("compile", src, "-o", tmp_path / "junk.bin")
    assert r.exit_code == 1
    lines = r.stderr.splitlines()
    assert lines[:20] == [f"{src}:{5 + i}: error: line without '=': 'junk line {i}' [DCF002]"
                          for i in range(20)]
    assert lines[20:] == [
        (f"{src}: note: 10 more DCF002 diagnostics left out (text output shows 20 per rule "
         "and file)"),
        f"{src}: 30 errors, nothing written"]


def test_validate_caps_text_but_json_keeps_every_finding(tmp_path):
    src = tmp_path / "junk.dcf"
    src.write_text(_broken_lines(30))
    r = run("validate", "--select", "DCF002", src)
    assert r.exit_code == 1
    lines = r.stdout.splitlines()
    assert len(lines) == 22
    assert lines[20] == (f"{src}: note: 10 more DCF002 diagnostics left out (text output shows "
                         "20 per rule and file)")
    assert lines[21] == "30 errors, 0 warnings, 0 infos in 1 file"
    doc = json.loads(run("validate", "--select", "DCF002", "--format", "json", src).stdout)
    assert len(doc["diagnostics"]) == 30
    sarif = json.loads(run("validate", "--select", "DCF002", "--format", "sarif", src).stdout)
    assert len(sarif["runs"][0]["results"]) == 30


def test_the_cap_counts_per_rule_and_per_file():
    diags = [Diagnostic(Severity.ERROR, f"m{i}", f, i + 1, rule=r)
             for f in ("a.dcf", "b.dcf") for r in ("DCF001", "DCF002") for i in range(21)]
    out = io.StringIO()
    report.render_text(diags, out, colour=False)
    lines = out.getvalue().splitlines()
    assert len(lines) == 4 * 21
    assert [x for x in lines if ": note: " in x] == [
        f"{f}: note: 1 more {r} diagnostic left out (text output shows 20 per rule and file)"
        for f in ("a.dcf", "b.dcf") for r in ("DCF001", "DCF002")]
    assert report.text_lines(diags, cap=None) == [d.format() for d in diags]


# -- item 17: one text form, one meaning of -q --------------------------------------------------

def test_compile_and_validate_print_the_same_line_for_the_same_finding(tmp_path):
    src = tmp_path / "bad.dcf"
    src.write_text(BAD_TEXT)
    c = run("compile", src, "-o", tmp_path / "bad.bin")
    v = run("validate", src)
    line = (f"{src}:4: error: 0x2000sub0: value 300 out of range for UNSIGNED8 (0..255) "
            "[DCF200]")
    assert c.stderr.splitlines()[0] == line
    assert line in v.stdout.splitlines()


def test_a_finding_with_a_column_prints_file_line_in_both(tmp_path):
    src = FIX / "DCF202.fail.dcf"
    c = run("compile", src, "-o", tmp_path / "x.bin")
    v = run("validate", "--select", "DCF202", src)
    line = (f"{src}:92: error: cannot read DownloadFile 'missing.dat': No such file or "
            "directory [DCF202]")
    assert c.stderr.splitlines()[0] == line
    assert v.stdout.splitlines()[0] == line
    # the column is still in the machine formats
    doc = json.loads(run("validate", "--select", "DCF202", "--format", "json", src).stdout)
    assert (doc["diagnostics"][0]["line"], doc["diagnostics"][0]["column"]) == (92, 14)


_LINE = re.compile(r"(.*?:\d+): (error|warning|info): (.*) \[(\w+)\]$")


def _findings(text: str) -> dict:
    out: dict = {}
    for line in text.splitlines():
        m = _LINE.match(line)
        if m:
            message = m[3].replace(" (not written by compile)", "")
            out.setdefault((m[1], m[4]), set()).add(message)
    return out


@pytest.mark.parametrize("fixture", sorted(p.name for p in FIX.glob("*.fail.dcf")))
def test_every_line_compile_prints_validate_prints_in_the_same_words(tmp_path, fixture):
    """Same place, same rule: the same message (compile only adds its suffix)."""
    path = FIX / fixture
    c = _findings(run("compile", path, "-o", tmp_path / "x.bin").stderr)
    v = _findings(run("validate", path).stdout)
    for key, messages in c.items():
        assert key in v, key
        assert messages <= v[key], (key, messages, v[key])


def test_quiet_means_errors_only_in_every_command(tmp_path):
    warn = FIX / "DCF007.fail.dcf"        # one warning, compiles
    r = run("validate", "-q", warn)
    assert (r.exit_code, r.stdout) == (0, "")
    r = run("compile", "-q", warn, "-o", tmp_path / "x.bin")
    assert (r.exit_code, r.stderr) == (0, "")
    r = run("compile", warn, "-o", tmp_path / "x.bin")
    assert "warning" in r.stderr
    bad = tmp_path / "bad.dcf"
    bad.write_text(BAD_TEXT)
    r = run("validate", "-q", bad)
    assert r.exit_code == 1
    lines = r.stdout.splitlines()
    assert (f"{bad}:4: error: 0x2000sub0: value 300 out of range for UNSIGNED8 (0..255) "
            "[DCF200]") in lines
    assert len(lines) == 4 and all(": error: " in line for line in lines)   # no summary


# -- item 16: one exit-code table ---------------------------------------------------------------

@pytest.mark.parametrize("args", [
    ["compile", "{dir}"], ["dump", "{dir}"], ["bin2dcf", "{dir}", "-o", "{tmp}/x.dcf"],
    ["export", "--format", "lenze-st", "{dir}"],
    ["compile", str(SAMPLES / "bild8.dcf"), "--static-od", "{dir}", "-o", "{tmp}/x.bin"],
    ["compile", str(SAMPLES / "bild8.dcf"), "--append", "{dir}", "-o", "{tmp}/x.bin"],
    ["dump", str(SAMPLES / "bild8.bin"), "--eds", "{dir}"],
    ["simulate", "{dir}"],
    ["simulate", str(SAMPLES / "bild8.bin"), "--static-od", "{dir}"],
    ["download", "{dir}", "--node", "3", "--dry-run"],
    ["node", "{dir}"],
], ids=["compile", "dump", "bin2dcf", "export", "static-od", "append", "eds", "simulate",
        "simulate-static-od", "download", "node"])
def test_a_directory_as_an_input_file_is_exit_3(tmp_path, args):
    d = tmp_path / "folder.dcf"
    d.mkdir()
    r = run(*[a.format(dir=d, tmp=tmp_path) for a in args])
    assert r.exit_code == ExitCode.UNREADABLE
    assert r.stderr == f"{d}: error: cannot read: Is a directory [IO001]\n"


@pytest.mark.parametrize("option", ["--static-od", "--append"])
def test_a_missing_side_input_is_exit_3_like_the_main_input(tmp_path, option):
    missing = tmp_path / "missing.eds"
    r = run("compile", SAMPLES / "bild8.dcf", option, missing, "-o", tmp_path / "x.bin")
    assert r.exit_code == ExitCode.UNREADABLE
    assert r.stderr == f"{missing}: error: cannot read: No such file or directory [IO001]\n"
    assert not (tmp_path / "x.bin").exists()


def test_the_exit_code_table_is_the_same_in_code_docs_readme_and_man_pages():
    for page, heading in ((ROOT / "docs" / "options.md", "\n## Exit codes\n"),
                          (ROOT / "README.md", "\n## Exit codes\n")):
        table = page.read_text().split(heading, 1)[1].split("\n#", 1)[0]
        codes = [int(m) for m in re.findall(r"^\| (\d+) \|", table, re.MULTILINE)]
        assert codes == [int(c) for c in ExitCode], page.name
    man = (ROOT / "man" / "dcf2bin.1").read_text()
    for c in ExitCode:
        assert f"\n.B {int(c)}\n" in man, c
    for page in (ROOT / "man").glob("*.1"):     # every page lists the codes the same way
        text = page.read_text()
        assert ".SH EXIT STATUS\n.TP\n.B 0\n" in text, page.name
        assert "\n.B 3\n" in text and "\n.B 70\n" in text, page.name


# -- item 18: help and man pages say the rules themselves ---------------------------------------

INTERNAL_REFERENCE = re.compile(r"SPEC|§|\bD-[0-9]|\b[Ss]eeds?\b|[Ss]eed's")


def _all_commands():
    from dcf2bin.cli.bin2dcf import bin2dcf_main
    out = [([], main), ([], bin2dcf_main)]
    for name, cmd in sorted(main.commands.items()):
        out.append(([name], cmd))
        if isinstance(cmd, click.Group):
            out += [([name, sub], c) for sub, c in sorted(cmd.commands.items())]
    return out


@pytest.mark.parametrize("words, cmd", _all_commands(),
                         ids=["dcf2bin", "bin2dcf-program"] + [" ".join(w) for w, _ in _all_commands()[2:]])
def test_help_names_no_internal_document(words, cmd):
    root = cmd if not words else main        # bin2dcf is also a program of its own
    r = CliRunner().invoke(root, [*words, "--help"], catch_exceptions=False)
    assert r.exit_code == 0
    assert INTERNAL_REFERENCE.findall(r.stdout) == [], r.stdout


@pytest.mark.parametrize("page", sorted(p.name for p in (ROOT / "man").glob("*.1")))
def test_man_pages_name_no_internal_document_and_share_one_header(page):
    text = (ROOT / "man" / page).read_text()
    assert INTERNAL_REFERENCE.findall(text.replace("\\-", "-")) == []
    first = text.splitlines()[0]
    title = page[:-2].upper().replace("-", "\\-")
    assert re.fullmatch(rf'\.TH {re.escape(title)} 1 "\d{{4}}-\d{{2}}-\d{{2}}" '
                        rf'"dcf2bin {re.escape(__version__)}" "dcf2bin manual"', first), first
    dates = {p.read_text().split('"')[1] for p in (ROOT / "man").glob("*.1")}
    assert len(dates) == 1, dates


# docs/developing.md is the page for those who change dcf2bin, which follows SPEC.md: it
# says where the code cites the specification. Every page a user reads says the rule itself.
DEVELOPERS_PAGE = ROOT / "docs" / "developing.md"


@pytest.mark.parametrize("doc", sorted(p.relative_to(ROOT).as_posix() for p in
                                       [ROOT / "README.md", *(ROOT / "docs").glob("*.md")]
                                       if p != DEVELOPERS_PAGE))
def test_docs_name_no_internal_document(doc):
    assert INTERNAL_REFERENCE.findall((ROOT / doc).read_text()) == []


def test_readme_says_how_to_install_the_man_pages():
    readme = (ROOT / "README.md").read_text()
    assert "install -Dm644 man/*.1 -t ~/.local/share/man/man1/" in readme


# -- item 19: the samples are clean -------------------------------------------------------------

@pytest.mark.parametrize("sample", sorted(p.name for p in SAMPLES.iterdir()
                                          if p.suffix in (".dcf", ".bin")))
def test_every_sample_validates_strictly(sample):
    r = run("validate", "--strict", "--format", "json", SAMPLES / sample)
    doc = json.loads(r.stdout)
    assert [(d["rule"], d["message"]) for d in doc["diagnostics"]
            if d["severity"] != "info"] == []
    assert r.exit_code == 0
