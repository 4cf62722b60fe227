"""validate over the real-world corpus: no internal error, every finding well-formed, and
the rule hits per file equal the reviewed golden summary.

Regenerate the golden file after a reviewed change of the rules:

    DCF2BIN_UPDATE_GOLDEN=1 python -m pytest tests/test_lint_corpus.py
"""
from __future__ import annotations

import collections
import os

import pytest

from conftest import (CORPUS, ROOT, needs_corpus, compile_corpus_file, compiling_corpus_params,
                      corpus_files, corpus_params)
from dcf2bin.lint import RULES, Options, all_rules, lint_bytes, run

GOLDEN = ROOT / "tests" / "golden" / "corpus_lint_summary.txt"
SUFFIXES = (".eds", ".dcf", ".bin")


@pytest.mark.parametrize("path", corpus_params(*SUFFIXES))
def test_no_internal_error_and_well_formed_findings(path):
    res = run([str(path)], Options())
    assert res.tracebacks == []
    all_rules()
    n_lines = path.read_bytes().count(b"\n") + 1
    for d in res.diagnostics:
        assert d.rule in RULES and d.rule != "INT001", d.format()
        assert d.file == str(path)
        assert "\n" not in d.message and d.message
        assert d.hint, d.rule
        assert d.line is None or 1 <= d.line <= n_lines, d.format()
        assert d.severity is RULES[d.rule].severity, d.format()


@pytest.mark.parametrize("path", compiling_corpus_params(".eds", ".dcf"))
def test_what_compile_writes_validates_clean(path):
    res = compile_corpus_file(path)
    found = lint_bytes("out.bin", res.data).diagnostics
    assert [d.format() for d in found] == []


def summary() -> str:
    lines = ["# dcf2bin validate over ../shared/corpus/files: rule hits per file (reviewed).",
             "# Regenerate: DCF2BIN_UPDATE_GOLDEN=1 python -m pytest tests/test_lint_corpus.py"]
    for path in corpus_files(*SUFFIXES):
        res = run([str(path)], Options())
        counts = collections.Counter(d.rule for d in res.diagnostics)
        hits = " ".join(f"{rule}x{counts[rule]}" for rule in sorted(counts)) or "clean"
        lines.append(f"{path.relative_to(CORPUS).as_posix()}: {hits}")
    return "\n".join(lines) + "\n"


@needs_corpus
def test_rule_hits_per_file_match_the_golden_summary():
    text = summary()
    if os.environ.get("DCF2BIN_UPDATE_GOLDEN"):
        GOLDEN.write_text(text)
    assert text == GOLDEN.read_text(), "rule hits changed: review, then regenerate (see top)"
