"""dcf2bin validate on the command line: inputs, selection, formats, exit codes."""
from __future__ import annotations

import json
import os

import jsonschema
import pytest
from click.testing import CliRunner

from conftest import ROOT, SAMPLES
from dcf2bin.cli import main
from dcf2bin.diagnostics import ExitCode
from dcf2bin.lint import registry
from dcf2bin.lint.report_schema import REPORT_SCHEMA, RULES_SCHEMA

FIX = ROOT / "tests" / "fixtures" / "lint"
CLEAN = FIX / "DCF200.pass.dcf"
BAD = FIX / "DCF200.fail.dcf"          # one error (line 92)
WARN = FIX / "DCF103.fail.dcf"         # one warning
CLEAN_BIN = FIX / "CNT013.pass.bin"
BAD_BIN = FIX / "CNT013.fail.bin"      # one warning


def run(*args, input=None, env=None):
    return CliRunner().invoke(main, ["validate", *map(str, args)], input=input, env=env,
                              catch_exceptions=False)


# -- exit codes ---------------------------------------------------------------------------------

def test_clean_file_exits_0_with_a_summary():
    r = run(CLEAN)
    assert r.exit_code == 0
    assert r.stdout == "0 errors, 0 warnings, 0 infos in 1 file\n"


def test_error_exits_1():
    r = run(BAD)
    assert r.exit_code == ExitCode.FINDINGS
    assert r.stdout.splitlines() == [
        f"{BAD}:92: error: 0x2000sub0 DefaultValue: value 300 out of range for UNSIGNED8 "
        "(0..255) [DCF200]",
        "1 error, 0 warnings, 0 infos in 1 file"]


def test_warnings_pass_unless_strict():
    assert run(WARN).exit_code == 0
    assert run("--strict", WARN).exit_code == ExitCode.FINDINGS
    assert run(BAD_BIN).exit_code == 0
    assert run("--strict", BAD_BIN).exit_code == ExitCode.FINDINGS


def test_unreadable_input_exits_3_and_others_are_still_checked(tmp_path):
    r = run(tmp_path / "missing.dcf", BAD)
    assert r.exit_code == ExitCode.UNREADABLE
    lines = r.stdout.splitlines()
    assert lines[0] == (f"{tmp_path / 'missing.dcf'}: error: cannot read: No such file or "
                        "directory [IO001]")
    assert "[DCF200]" in lines[1]


def test_usage_errors_exit_2():
    assert run().exit_code == ExitCode.USAGE
    r = run("--select", "XYZ", CLEAN)
    assert r.exit_code == ExitCode.USAGE
    assert "'XYZ' matches no rule id" in r.stderr
    assert run("--format", "xml", CLEAN).exit_code == ExitCode.USAGE


def test_a_crashing_rule_is_internal_error_70_and_debug_shows_the_traceback(monkeypatch):
    def boom(ctx):
        raise KeyError("bug")
        yield  # pragma: no cover
    rule = registry.RULES["DCF110"]
    monkeypatch.setitem(registry.RULES, "DCF110",
                        registry.Rule(rule.id, rule.name, rule.severity, rule.description,
                                      rule.hint, rule.kind, boom))
    r = run(BAD)
    assert r.exit_code == ExitCode.INTERNAL
    assert (f"{BAD}: error: internal error in rule DCF110 (subnumber-mismatch): KeyError: "
            "'bug' [INT001]") in r.stdout
    assert "[DCF200]" in r.stdout            # the other rules still ran
    assert "Traceback" not in r.stdout + r.stderr
    r = run("--debug", BAD)
    assert r.exit_code == ExitCode.INTERNAL
    assert "Traceback" in r.stderr and "KeyError: 'bug'" in r.stderr
    # --ignore cannot hide an internal error
    assert run("--ignore", "INT", BAD).exit_code == ExitCode.INTERNAL


# -- inputs -------------------------------------------------------------------------------------

def test_directories_are_searched_recursively_case_insensitively(tmp_path):
    (tmp_path / "a" / "b").mkdir(parents=True)
    (tmp_path / "a" / "b" / "X.EDS").write_bytes(BAD.read_bytes())
    (tmp_path / "a" / "y.Dcf").write_bytes(CLEAN.read_bytes())
    (tmp_path / "a" / "z.bin").write_bytes(BAD_BIN.read_bytes())
    (tmp_path / "a" / "notes.txt").write_text("not checked")
    (tmp_path / ".hidden").mkdir()
    (tmp_path / ".hidden" / "h.dcf").write_text("garbage")
    r = run("--format", "json", tmp_path)
    doc = json.loads(r.stdout)
    assert [(os.path.relpath(f["path"], tmp_path), f["kind"]) for f in doc["files"]] == [
        (os.path.join("a", "b", "X.EDS"), "dcf"), (os.path.join("a", "y.Dcf"), "dcf"),
        (os.path.join("a", "z.bin"), "container")]
    assert r.exit_code == 1


def test_stdin_dcf_and_container():
    r = run("-", input=BAD.read_bytes())
    assert r.exit_code == 1 and r.stdout.startswith("<stdin>:92: error:")
    r = run("--stdin-filename", "plc.dcf", "-", input=BAD.read_bytes())
    assert r.stdout.startswith("plc.dcf:92: error:")
    r = run("-", input=BAD_BIN.read_bytes())
    assert r.stdout.splitlines()[0] == (
        "<stdin>:0x35: warning: attribute 0x74 of entry 1 sets undefined bits 0x04 [CNT013]")


def test_select_and_ignore_by_id_prefix_and_name():
    r = run("--format", "json", "--select", "DCF1", WARN)
    assert {d["rule"] for d in json.loads(r.stdout)["diagnostics"]} == {"DCF103"}
    r = run("--format", "json", "--ignore", "object-not-listed", WARN)
    assert json.loads(r.stdout)["diagnostics"] == []
    r = run("--format", "json", "--select", "DCF2,DCF4", WARN)
    assert json.loads(r.stdout)["diagnostics"] == []
    assert run("--ignore", "DCF200", BAD).exit_code == 0


def test_profile_dis2_reports_the_offending_lines():
    r = run("--profile", "dis2", "--select", "DCF4", ROOT / "tests" / "fixtures" /
            "dis2_violations.dcf")
    assert r.exit_code == 1
    found = [(line.split(":")[1], line.rsplit(" ", 1)[1]) for line in r.stdout.splitlines()[:-1]]
    assert found == [("81", "[DCF450]"), ("141", "[DCF451]")]
    # without the profile the same file is clean for the PDO rules
    assert run("--select", "DCF4", ROOT / "tests" / "fixtures" /
               "dis2_violations.dcf").exit_code == 0


def test_samples_have_no_errors():
    inputs = sorted(SAMPLES.glob("*.bin")) + [SAMPLES / n for n in ("plc.dcf", "device.dcf")]
    r = run("--format", "json", *inputs)
    assert r.exit_code == 0
    assert json.loads(r.stdout)["summary"]["errors"] == 0


# -- formats ------------------------------------------------------------------------------------

def test_json_validates_against_its_schema(tmp_path):
    r = run("--format", "json", BAD, BAD_BIN, tmp_path / "missing.eds")
    doc = json.loads(r.stdout)
    jsonschema.validate(doc, REPORT_SCHEMA)
    assert doc["summary"] == {"files": 3, "errors": 2, "warnings": 1, "infos": 0,
                              "exit_code": 3}
    d = doc["diagnostics"][0]
    assert d == {"rule": "DCF200", "name": "bad-value", "severity": "error", "file": str(BAD),
                 "line": 92, "column": 14, "offset": None,
                 "message": "0x2000sub0 DefaultValue: value 300 out of range for UNSIGNED8 "
                            "(0..255)",
                 "hint": "write a value of the entry's DataType; values are never truncated"}
    assert doc["diagnostics"][1]["offset"] == 0x35 and doc["diagnostics"][1]["line"] is None


# The parts of the SARIF 2.1.0 schema that GitHub code scanning relies on.
SARIF_MIN = {
    "type": "object",
    "required": ["version", "runs"],
    "properties": {
        "version": {"const": "2.1.0"},
        "runs": {"type": "array", "minItems": 1, "items": {
            "type": "object", "required": ["tool", "results"],
            "properties": {
                "tool": {"type": "object", "required": ["driver"], "properties": {
                    "driver": {"type": "object", "required": ["name", "rules"], "properties": {
                        "name": {"type": "string"},
                        "rules": {"type": "array", "items": {
                            "type": "object", "required": ["id", "shortDescription"],
                            "properties": {"shortDescription": {
                                "type": "object", "required": ["text"]}}}}}}}},
                "results": {"type": "array", "items": {
                    "type": "object", "required": ["ruleId", "level", "message", "locations"],
                    "properties": {
                        "level": {"enum": ["none", "note", "warning", "error"]},
                        "message": {"type": "object", "required": ["text"]},
                        "ruleIndex": {"type": "integer", "minimum": 0},
                        "locations": {"type": "array", "minItems": 1, "items": {
                            "type": "object", "required": ["physicalLocation"],
                            "properties": {"physicalLocation": {
                                "type": "object", "required": ["artifactLocation"],
                                "properties": {
                                    "artifactLocation": {"type": "object",
                                                         "required": ["uri"]},
                                    "region": {"type": "object", "properties": {
                                        "startLine": {"type": "integer", "minimum": 1},
                                        "startColumn": {"type": "integer", "minimum": 1},
                                        "byteOffset": {"type": "integer",
                                                       "minimum": 0}}}}}}}}}}}}}}},
}


def test_sarif_has_the_required_fields_and_repository_relative_paths(monkeypatch):
    monkeypatch.chdir(ROOT)
    r = run("--format", "sarif", os.path.relpath(BAD, ROOT), os.path.relpath(BAD_BIN, ROOT))
    doc = json.loads(r.stdout)
    jsonschema.validate(doc, SARIF_MIN)
    run_ = doc["runs"][0]
    rules = run_["tool"]["driver"]["rules"]
    res = run_["results"]
    assert [x["ruleId"] for x in res] == ["DCF200", "CNT013"]
    assert rules[res[0]["ruleIndex"]]["id"] == "DCF200"
    loc = res[0]["locations"][0]["physicalLocation"]
    assert loc == {"artifactLocation": {"uri": "tests/fixtures/lint/DCF200.fail.dcf",
                                        "uriBaseId": "%SRCROOT%"},
                   "region": {"startLine": 92, "startColumn": 14}}
    assert res[1]["locations"][0]["physicalLocation"]["region"] == {"byteOffset": 0x35,
                                                                     "byteLength": 1}
    assert res[1]["level"] == "warning"
    assert run_["invocations"][0] == {"executionSuccessful": True, "exitCode": 1}


def test_github_annotations():
    r = run("--format", "github", BAD, BAD_BIN)
    assert r.stdout.splitlines() == [
        f"::error file={BAD},line=92,col=14,title=DCF200 bad-value::0x2000sub0 DefaultValue: "
        "value 300 out of range for UNSIGNED8 (0..255)",
        f"::warning file={BAD_BIN},title=CNT013 undefined-attribute-bits::attribute 0x74 of "
        "entry 1 sets undefined bits 0x04 (at byte 0x35)"]


def test_text_hints_quiet_and_output_file(tmp_path):
    r = run("--hints", "-q", BAD)
    assert r.stdout.splitlines()[1] == ("    hint: write a value of the entry's DataType; "
                                        "values are never truncated")
    assert len(r.stdout.splitlines()) == 2
    out = tmp_path / "report.sarif"
    r = run("--format", "sarif", "-o", out, BAD)
    assert r.exit_code == 1 and r.stdout == ""
    assert json.loads(out.read_text())["version"] == "2.1.0"


def test_no_colour_unless_a_terminal_and_never_with_no_color(monkeypatch):
    from dcf2bin import report

    class Tty:
        def isatty(self):
            return True
    monkeypatch.delenv("NO_COLOR", raising=False)
    assert report.use_colour(Tty())
    monkeypatch.setenv("NO_COLOR", "1")
    assert not report.use_colour(Tty())
    assert "\x1b[" not in run(BAD).stdout     # CliRunner's stdout is no terminal


def test_list_rules_text_and_json():
    r = run("--list-rules")
    assert r.exit_code == 0
    lines = r.stdout.splitlines()
    assert len(lines) == len(registry.all_rules()) >= 40
    assert lines[0].split()[:3] == ["DCF001", "error", "key-outside-section"]
    r = run("--list-rules", "--format", "json")
    doc = json.loads(r.stdout)
    jsonschema.validate(doc, RULES_SCHEMA)
    ids = [x["id"] for x in doc["rules"]]
    assert len(ids) == len(set(ids)) and "DCF450" in ids and "CNT020" in ids


def test_help_names_the_exit_codes():
    r = CliRunner().invoke(main, ["validate", "--help"])
    text = " ".join(r.stdout.split())
    assert "70 internal error" in text and "1 findings" in text and "--strict" in text


@pytest.mark.parametrize("fmt", ["text", "json", "sarif", "github"])
def test_a_directory_without_inputs_is_an_error_in_every_format(tmp_path, fmt):
    """A CI job pointed at the wrong folder must not pass: exit 3 and one IO001 line."""
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.txt").write_text("no DCF here")
    r = run("--format", fmt, empty)
    assert r.exit_code == ExitCode.UNREADABLE
    assert "IO001" in r.stdout
    if fmt == "text":
        assert r.stdout == (f"{empty}: error: no *.dcf, *.eds, *.xdd, *.xdc, *.xpd or *.bin file in this directory "
                            "[IO001]\n1 error, 0 warnings, 0 infos in 0 files\n")


# -- performance --------------------------------------------------------------------------------

def test_60000_variables_validate_without_errors():
    """A 60,000-variable PLC DCF validates without errors or crashed rules. (Its time is
    measured against compile by benchmarks/run.py, not asserted here: a timed unit test
    fails on a loaded machine and proves nothing on an idle one.)"""
    import importlib.util
    import sys

    from dcf2bin.lint import lint_bytes
    spec = importlib.util.spec_from_file_location("gen_dcf", ROOT / "benchmarks" / "gen_dcf.py")
    gen = importlib.util.module_from_spec(spec)
    sys.modules["gen_dcf"] = gen        # its dataclasses look themselves up there
    spec.loader.exec_module(gen)
    data = gen.generate(60000).encode("ascii")
    res = lint_bytes("big.dcf", data)
    assert res.tracebacks == []
    assert [d.format() for d in res.diagnostics if d.severity.value == "error"] == []
