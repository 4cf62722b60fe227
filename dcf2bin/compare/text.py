"""The text form of a comparison, like ``diff -u`` for people: ``--- A`` / ``+++ B``, one
``@@ 0xINDEX name @@`` line per object that differs, then a ``-`` line (A) and a ``+``
line (B) per entry, each with the entry's name, its value (what a PDO mapping entry maps,
what a COB-ID says) and, where they differ or the entry is on one side only, its data
type, access and PDO mapping flag. Colour (ANSI) only when the caller says so: on a
terminal (``report.use_colour``).

    --- samples/device.eds
    +++ samples/device.dcf
    @@ 0x1017 Producer heartbeat time @@
    -0x1017sub0 Producer heartbeat time: 0
    +0x1017sub0 Producer heartbeat time: 100
"""
from __future__ import annotations

from dcf2bin.compare import show
from dcf2bin.compare.engine import ADDED, CHANGED, REMOVED, FileDiff, Result
from dcf2bin.diagnostics import escape

_BOLD, _RED, _GREEN, _CYAN, _RESET = "\x1b[1m", "\x1b[31m", "\x1b[32m", "\x1b[36m", "\x1b[0m"


def render(result: Result, *, colour: bool = False) -> str:
    """The differences of ``result`` as text; the empty string when there are none."""
    def paint(code: str, line: str) -> str:
        return f"{code}{line}{_RESET}" if colour else line
    lines: list[str] = []
    for name in result.only_a:
        lines.append(paint(_BOLD, f"Only in {escape(result.a)}: {escape(name)}"))
    for name in result.only_b:
        lines.append(paint(_BOLD, f"Only in {escape(result.b)}: {escape(name)}"))
    for f in result.files:
        if f.changes:
            lines += file_lines(f, paint)
    return "".join(line + "\n" for line in lines)


def file_lines(f: FileDiff, paint) -> list[str]:
    a, b = f.a, f.b
    out = [paint(_BOLD, f"--- {escape(a.label)}"), paint(_BOLD, f"+++ {escape(b.label)}")]
    index = None
    for c in f.changes:
        if c.key[0] != index:
            index = c.key[0]
            out.append(paint(_CYAN, _hunk(f, index)))
        if c.kind in (CHANGED, REMOVED):
            out.append(paint(_RED, "-" + entry_line(c.a, c.b, f, c)))
        if c.kind in (CHANGED, ADDED):
            out.append(paint(_GREEN, "+" + entry_line(c.b, c.a, f, c)))
    return out


def _hunk(f: FileDiff, index: int) -> str:
    name = show.object_name(index, f.a, f.b)
    head = f"0x{index:04X}" + (f" {escape(name)}" if name else "")
    if index in f.only_a:
        head += f": only in {escape(f.a.label)}"
    elif index in f.only_b:
        head += f": only in {escape(f.b.label)}"
    return f"@@ {head} @@"


def entry_line(item, other, f: FileDiff, c) -> str:
    """``0x1A00sub1 Mapped object 1: 0x60410010 = 0x6041sub0 Statusword, 16 bits``."""
    name = show.entry_name(item.index, item.sub, f.a, f.b)
    text = item.label + (f" {escape(name)}" if name else "") + ": "
    text += escape(show.value_text(item, other), controls=True)
    what = show.meaning(item, f.a, f.b)
    if what:
        text += f" = {escape(what)}"
    facts = show.facts(item, None if c.kind != CHANGED else
                       [x for x in c.facets if x != "value"])
    if facts and (c.kind != CHANGED or len(c.facets) > 1 or c.facets[0] != "value"):
        text += f" ({facts})"
    return text


def summary(result: Result) -> str:
    """One line for standard error: what was compared and how many differences."""
    entries = sum(len(f.changes) for f in result.files)
    compared = sum(f.compared for f in result.files)
    left: dict[str, int] = {}
    for f in result.files:
        for why, n in f.left_out.items():
            left[why] = left.get(why, 0) + n
    notes = [f"{_count(compared, 'entry', 'entries')} compared"]
    if left.get("state"):
        notes.append(f"{left['state']} of the node's state left out (--all compares them)")
    if left.get("ignored"):
        notes.append(f"{left['ignored']} ignored")
    if left.get("no_value"):
        n = left["no_value"]
        notes.append(f"{_count(n, 'value')} only one file states not compared")
    head = f"{escape(result.a)}, {escape(result.b)}: "
    if result.folders:
        differ = sum(1 for f in result.files if f.changes)
        bad = sum(1 for f in result.files if f.errors)
        n = len(result.files)
        words = [f"{differ} of {_count(n, 'file')} differ{'s' if n == 1 else ''}" if differ
                 else "no file differs as read" if bad else f"{_count(n, 'file')} equal"]
        if entries:
            words.append(_count(entries, "entry", "entries"))
        if bad:
            words.append(f"{_count(bad, 'file')} with errors")
        only = len(result.only_a) + len(result.only_b)
        if only:
            words.append(f"{_count(only, 'file')} only in one folder")
        if result.not_compared:
            words.append(f"{_count(len(result.not_compared), 'file')} of the build not "
                         "compared")
        head += ", ".join(words)
    else:
        errors = [f"{escape(side.label)} has {_count(f.errors_of(which), 'error')}"
                  for f in result.files for which, side in (("a", f.a), ("b", f.b))
                  if f.errors_of(which)]
        if entries:
            head += f"{_count(entries, 'entry differs', 'entries differ')}"
            if errors:
                head += f", and {' and '.join(errors)}"
        elif errors:
            head += f"no entry differs as read, but {' and '.join(errors)}"
        else:
            head += "equal"
    return f"{head}; {', '.join(notes)}"


def _count(n: int, word: str, plural: str | None = None) -> str:
    return f"{n} {word if n == 1 else plural or word + 's'}"
