"""Render diagnostics: one function per output format. Nothing here decides exit codes.

* text   -- ``file:line: severity: message [RULE]`` (``format_text``, ``render_text``,
            ``text_report``): the one text form every command prints, at most ``CAP``
            per rule and file
* json   -- a versioned document with stable keys (``json_report``; schema
            ``dcf2bin/schemas/validate.json``, the rule list ``rules.json``)
* sarif  -- SARIF 2.1.0 for GitHub code scanning (``sarif_report``)
* github -- GitHub Actions workflow annotation lines (``github_report``)

The report functions take plain data: diagnostics, the inputs as (path, kind) pairs and
the rule table as dicts (``Rule.as_dict()``), so this module depends on nothing else.
"""
from __future__ import annotations

import os
import sys
from typing import Iterable, Sequence, TextIO
from urllib.parse import quote

# The one text form of one diagnostic lives with the data type (diagnostics.py), so that
# Diagnostic.format() needs no import from here; re-exported for the callers of report.*.
from dcf2bin.diagnostics import (Diagnostic, Severity, bounded, escape, format_text,  # noqa: F401
                                 location)

JSON_FORMAT = "dcf2bin-validate"
JSON_VERSION = 1
SARIF_SCHEMA = "https://json.schemastore.org/sarif-2.1.0.json"


def use_colour(stream: TextIO) -> bool:
    """Colour only on a terminal, and never when NO_COLOR is set (https://no-color.org)."""
    if os.environ.get("NO_COLOR"):
        return False
    return hasattr(stream, "isatty") and stream.isatty()


# -- names ------------------------------------------------------------------------------------

def _msg(text: str) -> str:
    """A message or hint as json, sarif and github show it: bounded as the text form's."""
    return escape(bounded(text), controls=False)


# -- text ---------------------------------------------------------------------------------------

# At most this many diagnostics of one rule in one file are printed in the text form; one
# line then says how many more were left out (json and sarif show every finding the command
# kept: the first diagnostics.LIMIT of a rule in a file, then one summary that counts the
# others, whose ``more`` every total here counts).
CAP = 20


def left_out(file: str, rule: str, n: int, cap: int = CAP) -> str:
    what = f"{rule} diagnostic" if rule else "diagnostic"
    return (f"{escape(file) if file else '<input>'}: note: {n} more {what}{'' if n == 1 else 's'}"
            f" left out (text output shows {cap} per rule and file)")


def text_lines(diags: Iterable[Diagnostic], *, colour: bool = False, hints: bool = False,
               cap: int | None = CAP) -> list[str]:
    """Lines of the text form, at most ``cap`` per rule and file (then one line saying how
    many were left out); with ``hints``, each hint once per rule and file, after the
    first finding that has it."""
    diags = list(diags)
    total: dict = {}
    for d in diags:     # a summary (``more``) counts the findings it stands for
        total[(d.file, d.rule)] = total.get((d.file, d.rule), 0) + d.weight
    seen: dict = {}
    hinted: set = set()
    out = []
    for d in diags:
        key = (d.file, d.rule)
        n = seen[key] = seen.get(key, 0) + 1
        if cap is not None and n > cap:
            continue
        out.append(format_text(d, colour))
        if hints and d.hint and (key, d.hint) not in hinted:
            hinted.add((key, d.hint))
            out.append(f"    hint: {escape(bounded(d.hint))}")
        if cap is not None and n == cap and total[key] > cap:
            out.append(left_out(d.file, d.rule, total[key] - cap, cap))
    return out


def render_text(diags: Iterable[Diagnostic], stream: TextIO | None = None,
                *, hints: bool = False, colour: bool | None = None,
                cap: int | None = CAP) -> None:
    stream = stream or sys.stderr
    if colour is None:
        colour = use_colour(stream)
    stream.write("".join(line + "\n" for line in text_lines(diags, colour=colour, hints=hints,
                                                             cap=cap)))


def summary(diags: Iterable[Diagnostic]) -> str:
    counts = {s: 0 for s in Severity}
    for d in diags:
        counts[d.severity] += d.weight
    parts = []
    for s in Severity:
        n = counts[s]
        parts.append(f"{n} {s.value}{'' if n == 1 else 's'}")
    return ", ".join(parts)


def text_report(diags: Sequence[Diagnostic], n_files: int, *, colour: bool = False,
                hints: bool = False, show_summary: bool = True,
                cap: int | None = CAP) -> str:
    """The text format of ``validate``: one line per finding (capped per rule and file),
    then a summary line that counts every finding."""
    out = text_lines(diags, colour=colour, hints=hints, cap=cap)
    if show_summary:
        out.append(f"{summary(diags)} in {n_files} file{'' if n_files == 1 else 's'}")
    return "".join(line + "\n" for line in out)


# -- json ---------------------------------------------------------------------------------------

def diagnostic_dict(d: Diagnostic, rules: dict[str, dict] | None = None) -> dict:
    name = (rules or {}).get(d.rule, {}).get("name", "")
    return {"rule": d.rule, "name": name, "severity": d.severity.value, "file": escape(d.file),
            "line": d.line, "column": d.column, "offset": d.offset, "message": _msg(d.message),
            "hint": _msg(d.hint)}


def json_report(diags: Sequence[Diagnostic], files: Sequence[tuple[str, str]],
                rules: dict[str, dict], *, exit_code: int, tool_version: str) -> str:
    """A versioned JSON document; every key is always present (null when unknown)."""
    per_file = {path: {"path": escape(path), "kind": kind, "errors": 0, "warnings": 0, "infos": 0}
                for path, kind in files}
    totals = {"errors": 0, "warnings": 0, "infos": 0}
    for d in diags:
        key = d.severity.value + "s"
        totals[key] += d.weight        # a summary counts the findings it stands for
        if d.file in per_file:
            per_file[d.file][key] += d.weight
    doc = {
        "format": JSON_FORMAT,
        "version": JSON_VERSION,
        "tool": {"name": "dcf2bin", "version": tool_version},
        "files": list(per_file.values()),
        "diagnostics": [diagnostic_dict(d, rules) for d in diags],
        "summary": {"files": len(files), **totals, "exit_code": int(exit_code)},
    }
    import json     # not for the text form, which every command prints
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def rules_json(rules: Sequence[dict]) -> str:
    import json
    return json.dumps({"format": "dcf2bin-rules", "version": JSON_VERSION, "rules": list(rules)},
                      indent=2, ensure_ascii=False) + "\n"


# -- sarif --------------------------------------------------------------------------------------

_SARIF_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "note"}


def artifact_uri(path: str, cwd: str | None = None) -> tuple[str, bool]:
    """(uri, relative?) for a SARIF artifactLocation: relative to the working directory
    (GitHub resolves it from the repository root) when the file lies below it."""
    cwd = cwd or os.getcwd()
    if path.startswith("<"):
        return quote(os.fsencode(path.strip("<>"))), True
    full = os.path.abspath(path)
    try:
        rel = os.path.relpath(full, cwd)
    except ValueError:   # another drive on Windows
        rel = None
    if rel is not None and not rel.startswith(".."):
        return quote(os.fsencode(rel.replace(os.sep, "/"))), True
    # a URI names the file's bytes: percent-encoded, so a name that is not UTF-8 works too
    return "file://" + quote(os.fsencode(full.replace(os.sep, "/"))), False


def sarif_report(diags: Sequence[Diagnostic], rules: Sequence[dict], *, exit_code: int,
                 tool_version: str, cwd: str | None = None) -> str:
    index = {r["id"]: i for i, r in enumerate(rules)}
    driver_rules = [{
        "id": r["id"],
        "name": r["name"],
        "shortDescription": {"text": r["description"]},
        "fullDescription": {"text": r["description"]},
        "help": {"text": r["hint"] or r["description"]},
        "defaultConfiguration": {"level": _SARIF_LEVEL[Severity(r["severity"])]},
        "properties": {"tags": [r["family"]]},
    } for r in rules]
    results = []
    for d in diags:
        uri, relative = artifact_uri(d.file, cwd)
        artifact = {"uri": uri}
        if relative:
            artifact["uriBaseId"] = "%SRCROOT%"
        phys: dict = {"artifactLocation": artifact}
        if d.line is not None:
            region = {"startLine": d.line}
            if d.column is not None:
                region["startColumn"] = d.column
            phys["region"] = region
        elif d.offset is not None:
            phys["region"] = {"byteOffset": d.offset, "byteLength": 1}
        elif d.rule.startswith("DCF"):
            phys["region"] = {"startLine": 1}   # a finding about the whole text file
        result = {"ruleId": d.rule, "level": _SARIF_LEVEL[d.severity],
                  "message": {"text": _msg(d.message)}, "locations": [{"physicalLocation": phys}]}
        if d.rule in index:
            result["ruleIndex"] = index[d.rule]
        results.append(result)
    doc = {
        "$schema": SARIF_SCHEMA,
        "version": "2.1.0",
        "runs": [{
            # no "informationUri" (optional in SARIF 2.1.0): dcf2bin has no public URL
            "tool": {"driver": {"name": "dcf2bin", "version": tool_version,
                                "rules": driver_rules}},
            "columnKind": "unicodeCodePoints",
            "results": results,
            "invocations": [{"executionSuccessful": int(exit_code) in (0, 1),
                             "exitCode": int(exit_code)}],
        }],
    }
    import json     # not for the text form, which every command prints
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


# -- github -------------------------------------------------------------------------------------

_GITHUB_LEVEL = {Severity.ERROR: "error", Severity.WARNING: "warning", Severity.INFO: "notice"}


def _gh_data(text: str) -> str:
    return text.replace("%", "%25").replace("\r", "%0D").replace("\n", "%0A")


def _gh_prop(text: str) -> str:
    return _gh_data(text).replace(":", "%3A").replace(",", "%2C")


def format_github(d: Diagnostic, rules: dict[str, dict] | None = None) -> str:
    """One workflow command: ``::error file=F,line=L,col=C,title=T::message``."""
    props = [f"file={_gh_prop(escape(d.file))}"]
    if d.line is not None:
        props.append(f"line={d.line}")
        if d.column is not None:
            props.append(f"col={d.column}")
    name = (rules or {}).get(d.rule, {}).get("name", "")
    title = f"{d.rule} {name}".strip() if d.rule else "dcf2bin"
    props.append(f"title={_gh_prop(title)}")
    message = _msg(d.message)
    if d.line is None and d.offset is not None:
        message += f" (at byte 0x{d.offset:X})"
    return f"::{_GITHUB_LEVEL[d.severity]} {','.join(props)}::{_gh_data(message)}"


def github_report(diags: Sequence[Diagnostic], rules: dict[str, dict] | None = None) -> str:
    return "".join(format_github(d, rules) + "\n" for d in diags)
