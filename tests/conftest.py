"""Shared fixtures. Corpus tests skip, with a reason, when ../shared is absent."""
from __future__ import annotations

import os
import pathlib

import pytest
from hypothesis import settings

# Property tests draw the same examples on every run (hypothesis derives them from each
# test's name), so that the suite, and CI, give the same answer for the same code: a red
# run is reproducible, never a draw. HYPOTHESIS_PROFILE=explore draws new examples each run
# to look for more; pin what it finds with @example.
settings.register_profile("repeatable", derandomize=True, database=None)
settings.register_profile("explore", derandomize=False)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "repeatable"))

ROOT = pathlib.Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
CORPUS = ROOT.parent / "shared" / "corpus" / "files"


def corpus_files(*suffixes: str) -> list[pathlib.Path]:
    if not CORPUS.is_dir():
        return []
    suffixes = suffixes or (".eds", ".dcf")
    return sorted(p for p in CORPUS.rglob("*") if p.is_file() and p.suffix.lower() in suffixes)


def corpus_params(*suffixes: str):
    """pytest params over the corpus, or one param that skips with the reason."""
    files = corpus_files(*suffixes)
    if not files:
        return [pytest.param(None, marks=pytest.mark.skip(
            reason=f"corpus not found at {CORPUS} (a fresh clone without ../shared)"))]
    return [pytest.param(p, id=str(p.relative_to(CORPUS))) for p in files]


_COMPILED: dict = {}


def compile_corpus_file(path: pathlib.Path):
    """Compile a corpus file once per test session (node-ID 1 when $NODEID needs one)."""
    if path not in _COMPILED:
        from dcf2bin.compiler import CompileOptions, compile_path
        res = compile_path(str(path), CompileOptions())
        if not res.ok and any(d.rule == "DCF201" for d in res.diagnostics):
            res = compile_path(str(path), CompileOptions(node_id=1))
        _COMPILED[path] = res
    return _COMPILED[path]


def compiling_corpus_params(*suffixes: str):
    """pytest params over the corpus files that compile (tests/test_corpus.py checks that
    the others fail cleanly), or one param that skips with the reason."""
    files = corpus_files(*suffixes)
    if not files:
        return corpus_params(*suffixes)
    ok = []
    for p in files:
        res = compile_corpus_file(p)
        if res.ok:
            ok.append(pytest.param(p, id=str(p.relative_to(CORPUS))))
    return ok


# Skips decided at collection, with their reason (the corpus lives outside the repository).
needs_corpus = pytest.mark.skipif(
    not CORPUS.is_dir(), reason=f"corpus not found at {CORPUS} (a fresh clone without ../shared)")


def corpus_pick_params(picks):
    """pytest params for named corpus files [(relative path, extra...)], each skipped with
    its reason when the file is absent."""
    out = []
    for rel, *rest in picks:
        path = CORPUS / rel
        marks = pytest.mark.skipif(not path.is_file(),
                                   reason=f"corpus file {rel} not found under {CORPUS}")
        out.append(pytest.param(path, *rest, id=rel, marks=marks))
    return out
