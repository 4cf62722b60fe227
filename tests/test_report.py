"""The renderers of dcf2bin/report.py: one function per format, plain data in."""
from __future__ import annotations

import io
import json
import os

import jsonschema

from dcf2bin import report
from dcf2bin.diagnostics import Diagnostic, Severity
from dcf2bin.lint import all_rules
from dcf2bin.lint.report_schema import REPORT_SCHEMA

E = Diagnostic(Severity.ERROR, "value 300 out of range", "a.dcf", 12, 14, None, "DCF200",
               "fix it")
W = Diagnostic(Severity.WARNING, "undefined bits", "b.bin", None, None, 0x35, "CNT013", "")
I = Diagnostic(Severity.INFO, "vendor section", "a.dcf", 3, None, None, "DCF051", "")
F = Diagnostic(Severity.ERROR, "mandatory object 0x1000 is missing", "a.dcf", rule="DCF101")


def _rules():
    return {r.id: r.as_dict() for r in all_rules()}


def test_text_lines_and_summary():
    assert report.format_text(E) == "a.dcf:12: error: value 300 out of range [DCF200]"
    assert report.format_text(W) == "b.bin:0x35: warning: undefined bits [CNT013]"
    assert report.format_text(F) == "a.dcf: error: mandatory object 0x1000 is missing [DCF101]"
    assert report.format_text(E, colour=True) == (
        "a.dcf:12: \x1b[31merror\x1b[0m: value 300 out of range [DCF200]")
    assert report.text_report([E, W, I], 2, hints=True) == (
        "a.dcf:12: error: value 300 out of range [DCF200]\n"
        "    hint: fix it\n"
        "b.bin:0x35: warning: undefined bits [CNT013]\n"
        "a.dcf:3: info: vendor section [DCF051]\n"
        "1 error, 1 warning, 1 info in 2 files\n")
    assert report.text_report([], 1) == "0 errors, 0 warnings, 0 infos in 1 file\n"
    assert report.text_report([E], 1, show_summary=False).count("\n") == 1


def test_render_text_still_writes_compile_diagnostics():
    out = io.StringIO()
    report.render_text([E], out, hints=True)
    assert out.getvalue() == ("a.dcf:12: error: value 300 out of range [DCF200]\n"
                              "    hint: fix it\n")


def test_json_document_keys_are_stable():
    text = report.json_report([E, W, F], [("a.dcf", "dcf"), ("b.bin", "container")], _rules(),
                              exit_code=1, tool_version="9.9")
    doc = json.loads(text)
    jsonschema.validate(doc, REPORT_SCHEMA)
    assert list(doc) == ["format", "version", "tool", "files", "diagnostics", "summary"]
    assert doc["files"] == [
        {"path": "a.dcf", "kind": "dcf", "errors": 2, "warnings": 0, "infos": 0},
        {"path": "b.bin", "kind": "container", "errors": 0, "warnings": 1, "infos": 0}]
    assert doc["diagnostics"][1] == {
        "rule": "CNT013", "name": "undefined-attribute-bits", "severity": "warning",
        "file": "b.bin", "line": None, "column": None, "offset": 0x35,
        "message": "undefined bits", "hint": ""}
    assert doc["summary"] == {"files": 2, "errors": 2, "warnings": 1, "infos": 0,
                              "exit_code": 1}


def test_sarif_levels_regions_and_uris(tmp_path):
    rules = [r.as_dict() for r in all_rules()]
    inside = os.path.join(str(tmp_path), "dir", "x y.dcf")
    d_inside = Diagnostic(Severity.INFO, "m", inside, 1, None, None, "DCF051")
    doc = json.loads(report.sarif_report([E, W, I, F, d_inside], rules, exit_code=70,
                                         tool_version="9.9", cwd=str(tmp_path)))
    res = doc["runs"][0]["results"]
    assert [r["level"] for r in res] == ["error", "warning", "note", "error", "note"]
    assert res[3]["locations"][0]["physicalLocation"]["region"] == {"startLine": 1}
    assert res[4]["locations"][0]["physicalLocation"]["artifactLocation"] == {
        "uri": "dir/x%20y.dcf", "uriBaseId": "%SRCROOT%"}
    assert doc["runs"][0]["invocations"][0]["executionSuccessful"] is False
    driver = doc["runs"][0]["tool"]["driver"]
    # informationUri is optional, and dcf2bin has no public URL to give: none is invented
    assert sorted(driver) == ["name", "rules", "version"]
    assert driver["rules"][res[0]["ruleIndex"]]["defaultConfiguration"] == {"level": "error"}
    assert driver["rules"][res[2]["ruleIndex"]]["defaultConfiguration"] == {"level": "note"}


def test_artifact_uri_outside_the_working_directory(tmp_path):
    uri, relative = report.artifact_uri("/elsewhere/a.dcf", str(tmp_path))
    assert (uri, relative) == ("file:///elsewhere/a.dcf", False)
    assert report.artifact_uri("<stdin>", str(tmp_path)) == ("stdin", True)


def test_github_escapes_properties_and_data():
    d = Diagnostic(Severity.WARNING, "50% of\nit", "dir,1/a:b.dcf", 3, None, None, "DCF050")
    assert report.format_github(d, _rules()) == (
        "::warning file=dir%2C1/a%3Ab.dcf,line=3,title=DCF050 unknown-key::50%25 of%0Ait")
    assert report.format_github(I) == "::notice file=a.dcf,line=3,title=DCF051::vendor section"
    assert report.github_report([]) == ""


def test_a_hint_is_printed_once_per_rule_and_file():
    def d(file, line, rule="DCF201", hint="give --node-id N"):
        return Diagnostic(Severity.ERROR, f"m{line}", file, line, None, None, rule, hint)
    lines = report.text_lines([d("a.dcf", 1), d("a.dcf", 2), d("b.dcf", 3), d("a.dcf", 4),
                               d("a.dcf", 5, "DCF200", "other"), d("a.dcf", 6, hint="new")],
                              hints=True)
    assert lines == [
        "a.dcf:1: error: m1 [DCF201]", "    hint: give --node-id N",
        "a.dcf:2: error: m2 [DCF201]",
        "b.dcf:3: error: m3 [DCF201]", "    hint: give --node-id N",
        "a.dcf:4: error: m4 [DCF201]",
        "a.dcf:5: error: m5 [DCF200]", "    hint: other",
        "a.dcf:6: error: m6 [DCF201]", "    hint: new"]
