"""Every corpus file either compiles or fails with one-line file:line errors; none crashes."""
from __future__ import annotations

import re

import pytest

from conftest import corpus_params
from dcf2bin.compiler import CompileOptions, compile_path
from dcf2bin.container import read
from dcf2bin.diagnostics import Severity

LINE = re.compile(r"^[^\n]+:\d+: (error|warning|info): [^\n]+$")
NO_LINE = re.compile(r"^[^\n]+: (error|warning|info): [^\n]+$")


@pytest.mark.parametrize("path", corpus_params())
def test_corpus_file_compiles_or_fails_cleanly(path):
    res = compile_path(str(path), CompileOptions())
    for d in res.diagnostics:
        text = d.format()
        assert "\n" not in text
        assert LINE.match(text) or (d.line is None and NO_LINE.match(text)), text
    if res.ok:
        back, warnings = read(res.data)
        assert warnings == []
        assert back.to_bytes() == res.data
    else:
        errors = [d for d in res.diagnostics if d.severity is Severity.ERROR]
        assert errors and all(d.file == str(path) for d in errors)
