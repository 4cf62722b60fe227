"""Every rule has a minimal failing and a passing fixture; validating each gives exactly
the (rule, line) -- or (rule, byte offset) -- list its markers state.

The fixtures live in tests/fixtures/lint/ and are written by generate.py there (see its
docstring for the marker syntax); a test checks the committed files are up to date.
"""
from __future__ import annotations

import importlib.util
import pathlib

import pytest

from conftest import ROOT
from dcf2bin.lint import Options, all_rules, run

FIXTURES = ROOT / "tests" / "fixtures" / "lint"

# Rules without a fixture pair, and why.
EXEMPT = {
    "DCF099": "a safety net for core problems without a rule id; none is known to exist",
    "CNT099": "a safety net: every reader rejection has a finer CNT rule",
    "DCF009": "compile only (validate never reports it): tests/test_hostile_input.py",
    "DCF014": "65,537 keys in one section are a 600 KB file: tests/test_read_bounds.py",
    "DCF015": "1,048,577 sections are an 11 MB file: tests/test_read_bounds.py (with the "
              "bound lowered)",
    "IO001": "needs an unreadable path: tests/test_lint_cli.py",
    "IO002": "a fixture's name is its kind; a misnamed file is in tests/test_filekind.py",
    "CON001": "fewer than 4 bytes are no concise DCF by content (a .bin is then a container, "
              "CNT001); read as one only when forced (download --from concise): "
              "tests/test_concise.py, tests/test_concise_commands.py",
    "INT001": "needs a crashing rule: tests/test_lint_cli.py monkeypatches one",
    "TGT0A0": "needs --pi-size, which container fixtures cannot give, and on a DCF the layout "
              "check (DCF305) stops compile first: tests/test_simulate.py",
}
# CiA 311 XML: the fixtures here are CiA 306 text; each XDD rule's failing case (exact text)
# is in tests/test_xdd.py or tests/test_xdd_corpus.py, and tests/fixtures/xdd/vendor_v10.xdc
# is the passing one (validate: no XDD finding)
EXEMPT.update(dict.fromkeys(
    ("XDD001", "XDD002", "XDD003", "XDD004", "XDD010", "XDD011", "XDD012", "XDD013", "XDD014",
     "XDD020"), "CiA 311 XML: tests/test_xdd.py, tests/test_xdd_corpus.py"))
# simulate's warnings (an unknown static OD): validate reports only the emulation's verdict;
# their cases are in tests/test_dynod.py and tests/test_simulate.py
EXEMPT.update(dict.fromkeys(("TGT101", "TGT102", "TGT103", "TGT104"),
                            "a warning of simulate only: tests/test_dynod.py"))


def _generator():
    spec = importlib.util.spec_from_file_location("lint_fixture_generator",
                                                  FIXTURES / "generate.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _dcf_expectations(text: str) -> tuple[list[tuple[str, int | None]], dict]:
    expected: list[tuple[str, int | None]] = []
    pending: list[str] = []
    options: dict = {}
    for lineno, line in enumerate(text.split("\n"), 1):
        s = line.strip()
        if s.startswith(";!file"):
            expected += [(r, None) for r in s[len(";!file"):].split()]
        elif s.startswith(";!"):
            pending += s[2:].split()
        elif s.startswith("; options:"):
            words = s[len("; options:"):].split()
            for key, value in zip(words[::2], words[1::2]):
                options[key.lstrip("-").replace("-", "_")] = int(value) if value.isdigit() \
                    else value
        elif s and s[0] not in ";#":
            expected += [(r, lineno) for r in pending]
            pending = []
    assert not pending, f"markers {pending} before the end of the file"
    return sorted(expected, key=str), options


def _fixtures(suffix: str) -> list:
    return [pytest.param(p, id=p.name) for p in sorted(FIXTURES.glob(f"*{suffix}"))]


@pytest.mark.parametrize("path", _fixtures(".dcf"))
def test_dcf_fixture(path: pathlib.Path):
    expected, options = _dcf_expectations(path.read_text(encoding="utf-8"))
    res = run([str(path)], Options(**options))
    got = sorted(((d.rule, d.line) for d in res.diagnostics), key=str)
    assert got == expected, "\n".join(d.format() for d in res.diagnostics)
    if path.name.endswith(".pass.dcf"):
        assert got == []
    else:
        rule = path.name.split(".")[0]
        assert rule in {r for r, _ in got}, f"{path.name} does not trigger {rule}"


@pytest.mark.parametrize("path", _fixtures(".bin"))
def test_container_fixture(path: pathlib.Path):
    expect = path.with_name(path.name + ".expect")
    expected = []
    if expect.exists():
        for line in expect.read_text().splitlines():
            rule, offset = line.split()
            expected.append((rule, int(offset, 16)))
    res = run([str(path)], Options())
    got = sorted((d.rule, d.offset) for d in res.diagnostics)
    assert got == sorted(expected), "\n".join(d.format() for d in res.diagnostics)
    if path.name.endswith(".fail.bin"):
        assert path.name.split(".")[0] in {r for r, _ in got}


def test_every_rule_has_a_failing_and_a_passing_fixture():
    names = {p.name for p in FIXTURES.iterdir()}
    missing = []
    for r in all_rules():
        if r.id in EXEMPT:
            continue
        # CNT rules check containers, CON rules concise DCFs (.bin too); TGT rules (kind
        # "any") may have either pair
        exts = ("bin",) if r.id.startswith(("CNT", "CON")) else ("dcf", "bin") \
            if r.kind == "any" else ("dcf",)
        for kind in ("fail", "pass"):
            if not any(f"{r.id}.{kind}.{ext}" in names for ext in exts):
                missing.append(f"{r.id}.{kind}.{exts[0]}")
    assert missing == []
    assert set(EXEMPT) <= {r.id for r in all_rules()}


def test_fixtures_are_what_generate_py_writes(tmp_path):
    wanted = _generator().files()
    on_disk = {p.name: p.read_bytes() for p in FIXTURES.iterdir()
               if p.is_file() and p.name != "generate.py"}
    assert sorted(on_disk) == sorted(wanted), "run: python tests/fixtures/lint/generate.py"
    stale = [n for n, data in wanted.items() if on_disk[n] != data]
    assert stale == [], "run: python tests/fixtures/lint/generate.py"
