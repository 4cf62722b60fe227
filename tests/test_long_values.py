"""A 100,000-character value, key or section name in any input (issue 26, item 3): every
message that quotes it is one readable line.

Each message quotes a user's text through ``diagnostics.shorten`` (a long one is cut in the
middle: ``'xxxx...xxxx (100000 characters)'``), and every output format bounds a whole
message (``diagnostics.bounded``, at most ``MESSAGE_LIMIT`` characters kept) in case a
message missed it. The generated inputs put a long string in the place of each value, key
and section name of a small DCF, a small EDS, a bus.yml and a .cpj in turn, and run the
commands in-process; before this work, 3 of them gave lines of 100,000 characters.
"""
from __future__ import annotations

import json
import re
import shutil

import pytest
from click.testing import CliRunner

from conftest import ROOT
from dcf2bin.cli import main
from dcf2bin.diagnostics import (MESSAGE_LIMIT, Diagnostic, Severity, bounded, format_text,
                                 shorten)
from dcf2bin.report import format_github, json_report, sarif_report, text_lines

LONG = 100_000
LINE_LIMIT = 2_500     # a bounded message, its file:line and its rule
# a line whose quoted texts all went through shorten() stays far below the safety net's cut
# (1,000 + 500 characters kept): the DCF/EDS inputs, which quote no file name, are held to
# this, so that a message that misses shorten() fails here although the net bounds it
SHORTENED = 1_000
CONTROL = re.compile(r"[\x00-\x08\x0a-\x1f\x7f]")
# the long texts, one per generated input in turn: letters, digits (an integer literal),
# a number with a comment, a $NODEID formula, control characters, a bad hex literal
FILLS = ["x" * LONG, "1" * LONG, "0x10 " + "c" * LONG, "$NODEID+" + "y" * LONG,
         "a\x01\x1b" * (LONG // 3), "0x" + "G" * LONG]
OBJECT_SECTION = re.compile(r"([0-9A-Fa-f]{4})(?:sub([0-9A-Fa-f]+))?")


def variants(text: str):
    """(what, text) for each key line (its value, then its key) and each section header
    (its name; an object section also with 100,000 digits of subindex) of an INI file."""
    lines = text.splitlines(True)
    k = 0
    for i, line in enumerate(lines):
        s = line.strip()
        if not s or s.startswith(";"):
            continue
        before, after = "".join(lines[:i]), "".join(lines[i + 1:])
        if s.startswith("["):
            name = s[1:s.find("]")]
            yield f"line {i + 1}: section name", f"{before}[{'S' * LONG}]\n{after}"
            m = OBJECT_SECTION.fullmatch(name)
            if m:
                sub = "0" * LONG + (m.group(2) or "1")
                yield f"line {i + 1}: subindex", f"{before}[{m.group(1)}sub{sub}]\n{after}"
        elif "=" in s:
            key, _, value = line.partition("=")
            fill = FILLS[k % len(FILLS)]
            k += 1
            yield f"line {i + 1}: value", f"{before}{key}={fill}\n{after}"
            yield f"line {i + 1}: key", f"{before}{'K' * LONG}={value}{after}"


def bad_lines(output: str, limit: int = LINE_LIMIT) -> list[str]:
    return [line[:120] + f"... ({len(line)} characters)" for line in output.splitlines()
            if len(line) > limit or CONTROL.search(line)]


def run(*args: str, limit: int = LINE_LIMIT):
    r = CliRunner().invoke(main, list(args), catch_exceptions=False)
    return r, bad_lines(r.stdout + r.stderr, limit)


@pytest.mark.parametrize("sample", ["samples/plc.dcf", "samples/device.eds"])
def test_long_values_keys_and_section_names_give_bounded_lines(sample, tmp_path):
    text = (ROOT / sample).read_text(encoding="latin-1")
    path = tmp_path / ("in" + (ROOT / sample).suffix)
    out = tmp_path / "out.bin"
    failures = []
    for n, (what, variant) in enumerate(variants(text)):
        path.write_text(variant, encoding="latin-1")
        commands = [("validate", str(path))]
        if n % 2 == 0:    # compile reads as validate does: every other input is enough
            commands.append(("compile", str(path), "-o", str(out)))
        for args in commands:
            r, bad = run(*args, limit=SHORTENED)
            if bad or r.exit_code not in (0, 1):
                failures.append(f"{args[0]} {what}: exit {r.exit_code}, {bad[:2]}")
    assert failures == []


@pytest.mark.parametrize("name", ["bus.yml", "network.cpj"])
def test_long_yaml_and_cpj_scalars_and_keys_give_bounded_lines(name, tmp_path):
    """Each scalar and key of a network file (each token of a line) in turn."""
    shutil.copytree(ROOT / "tests/fixtures/network", tmp_path / "net")
    path = tmp_path / "net" / "check" / name
    lines = path.read_text().splitlines(True)
    failures = []
    k = 0
    for i, line in enumerate(lines):
        if line.lstrip().startswith(("#", ";")):
            continue
        for m in re.finditer(r"[A-Za-z0-9_./$+-]+", line):
            fill = FILLS[k % len(FILLS)]
            k += 1
            new = line[:m.start()] + fill + line[m.end():]
            path.write_text("".join(lines[:i] + [new] + lines[i + 1:]), encoding="latin-1")
            r, bad = run("network", "check", str(path))
            if bad or r.exit_code not in (0, 1, 3):
                failures.append(f"line {i + 1} {m.group()!r}: exit {r.exit_code}, {bad[:2]}")
    assert k > 20
    assert failures == []


def test_long_access_type_is_cut_in_the_middle(tmp_path):
    path = tmp_path / "a.eds"
    path.write_text("[1000]\nParameterName=x\nObjectType=7\nDataType=7\nAccessType="
                    + "r" * 5000 + "\nDefaultValue=0\n")
    r, _ = run("validate", "--select", "DCF032", str(path))
    assert r.stdout == (f"{path}:5: error: [1000] unknown AccessType '{'r' * 40}..."
                        f"{'r' * 12} (5000 characters)' [DCF032]\n"
                        "1 error, 0 warnings, 0 infos in 1 file\n")


def test_long_section_name_of_a_repeated_key_is_cut(tmp_path):
    name = "S" * LONG
    path = tmp_path / "a.dcf"
    path.write_text(f"[{name}]\nKey{'k' * LONG}=1\nKey{'k' * LONG}=2\n")
    r, _ = run("validate", "--select", "DCF010", str(path))
    shown = shorten(name)
    assert r.stdout.splitlines()[0] == (
        f"{path}:3: error: key '{shorten('Key' + 'k' * LONG)}' repeated in [{shown}] "
        "(first at line 2) [DCF010]")


# -- the safety net: a message that quotes a text whole is still bounded ----------------------

HUGE = Diagnostic(Severity.ERROR, "value '" + "v" * LONG + "' is bad", "f.dcf", 7, rule="X001",
                  hint="h" * LONG)


def test_bounded_keeps_a_message_up_to_the_limit_whole():
    assert bounded("m" * MESSAGE_LIMIT) == "m" * MESSAGE_LIMIT
    assert bounded("") == ""


def test_bounded_cuts_a_longer_message_in_the_middle():
    text = "a" * 1000 + "b" * (LONG - 1500) + "c" * 500
    assert bounded(text) == f"{'a' * 1000}...{'c' * 500} ({LONG} characters)"


def test_every_format_bounds_a_message_that_quotes_a_value_whole():
    cut = bounded(HUGE.message)
    assert format_text(HUGE) == f"f.dcf:7: error: {cut} [X001]"
    lines = text_lines([HUGE], hints=True)
    assert lines == [f"f.dcf:7: error: {cut} [X001]", f"    hint: {bounded(HUGE.hint)}"]
    doc = json.loads(json_report([HUGE], [("f.dcf", "dcf")], {}, exit_code=1,
                                 tool_version="0"))
    assert doc["diagnostics"][0]["message"] == cut
    assert doc["diagnostics"][0]["hint"] == bounded(HUGE.hint)
    sarif = json.loads(sarif_report([HUGE], [], exit_code=1, tool_version="0"))
    assert sarif["runs"][0]["results"][0]["message"]["text"] == cut
    assert format_github(HUGE).endswith(f"::{cut}")
    assert max(len(line) for line in lines) < LINE_LIMIT


def test_long_option_value_is_cut_in_the_usage_error(tmp_path):
    path = tmp_path / "a.eds"
    path.write_text("[1000]\nParameterName=x\nObjectType=7\nDataType=7\nAccessType=ro\n")
    r = CliRunner().invoke(main, ["compile", "--entries", "x" * LONG, str(path)])
    assert r.exit_code == 2
    assert r.stderr.splitlines()[-1] == (
        f"Error: Invalid value for '--entries': '{shorten('x' * LONG)}' is not one of "
        "'auto', 'all'.")
