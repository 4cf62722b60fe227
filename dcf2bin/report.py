"""Render diagnostics: one function per output format (text here; json, sarif
and github join it for ``validate``). Nothing here decides exit codes."""
from __future__ import annotations

import os
import sys
from typing import Iterable, TextIO

from dcf2bin.diagnostics import Diagnostic, Severity

_COLOURS = {Severity.ERROR: "\x1b[31m", Severity.WARNING: "\x1b[33m", Severity.INFO: "\x1b[36m"}


def use_colour(stream: TextIO) -> bool:
    if os.environ.get("NO_COLOR"):
        return False
    return hasattr(stream, "isatty") and stream.isatty()


def format_text(d: Diagnostic, colour: bool = False) -> str:
    sev = d.severity.value
    if colour:
        sev = f"{_COLOURS[d.severity]}{sev}\x1b[0m"
    text = f"{d.location}: {sev}: {d.message}"
    if d.rule:
        text += f" [{d.rule}]"
    return text


def render_text(diags: Iterable[Diagnostic], stream: TextIO | None = None,
                *, hints: bool = False) -> None:
    stream = stream or sys.stderr
    colour = use_colour(stream)
    for d in diags:
        stream.write(format_text(d, colour) + "\n")
        if hints and d.hint:
            stream.write(f"    hint: {d.hint}\n")


def summary(diags: Iterable[Diagnostic]) -> str:
    counts = {s: 0 for s in Severity}
    for d in diags:
        counts[d.severity] += 1
    parts = []
    for s in Severity:
        n = counts[s]
        parts.append(f"{n} {s.value}{'' if n == 1 else 's'}")
    return ", ".join(parts)
