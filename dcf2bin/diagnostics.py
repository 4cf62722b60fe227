"""Diagnostics as data (rule, severity, where, message) and the exit codes.

The one text form of a diagnostic (``format_text``) is here; every other output format is
rendered by report.py, which builds on this module. Nothing here prints.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass, field


class ExitCode(enum.IntEnum):
    """The one table of exit codes (docs/options.md, "Exit codes"; man pages), for every command."""
    OK = 0
    FINDINGS = 1      # the input has errors (compile: nothing written); a broken pipe after
                      # errors were reported
    USAGE = 2         # bad command line; an output that would overwrite an input; binary
                      # data to a terminal
    UNREADABLE = 3    # an input could not be read (missing, a directory, no permission;
                      # validate: a directory without DCF/EDS/bin files), or an output could
                      # not be written (full disk, closed standard output)
    INTERNAL = 70     # a bug in dcf2bin (EX_SOFTWARE); --debug shows the traceback
    # a caught signal ends the run with 128 + its number (130 SIGINT, 143 SIGTERM)


class Severity(str, enum.Enum):
    """How bad a finding is; errors stop a compile (exit 1), warnings and infos do not."""
    ERROR = "error"
    WARNING = "warning"
    INFO = "info"


@dataclass(frozen=True)
class Diagnostic:
    """One finding: ``format()`` gives ``file:line: severity: message [RULE]`` (a byte
    offset ``file:0x1C:`` for containers), as the command line prints it."""
    severity: Severity
    message: str
    file: str = ""
    line: int | None = None
    column: int | None = None
    offset: int | None = None     # byte offset, for binary inputs
    rule: str = ""
    hint: str = ""
    # a summary (``summary_finding``): how many findings of its rule in its file it
    # stands for, left out after the first ``LIMIT``; 0 for a finding of its own
    more: int = 0

    @property
    def weight(self) -> int:
        """How many findings this one counts for: 1, or a summary's ``more``."""
        return self.more or 1

    @property
    def location(self) -> str:
        """``file:line``, ``file:0xOFFSET`` or ``file`` (``location``)."""
        return location(self)

    def format(self) -> str:
        """The one text form, ``file:line: severity: message [RULE]`` (``format_text``)."""
        return format_text(self)


# -- the one text form of one diagnostic ------------------------------------------------------
# Here, beside the type, so that Diagnostic.format() needs nothing above it; report.py (every
# other output format) builds on these and re-exports them.

_COLOURS = {Severity.ERROR: "\x1b[31m", Severity.WARNING: "\x1b[33m", Severity.INFO: "\x1b[36m"}


def escape(text: str, *, controls: bool = True) -> str:
    """A file name (or a message naming one) as printable text, the same in every format.

    Python hands over the bytes of a name that is not UTF-8 as lone surrogates
    (surrogateescape); each becomes ``\\xNN`` for its byte, and so does a control
    character (a newline in a name would break a line-based report). Never raises."""
    if text.isprintable() and text.isascii():
        return text
    out = []
    for ch in text:
        o = ord(ch)
        if 0xDC80 <= o <= 0xDCFF:
            out.append(f"\\x{o - 0xDC00:02x}")
        elif 0xD800 <= o <= 0xDFFF:
            out.append(f"\\u{o:04x}")
        elif controls and (o < 0x20 or 0x7F <= o < 0xA0):
            out.append(f"\\x{o:02x}")
        else:
            out.append(ch)
    return "".join(out)


def location(d: Diagnostic) -> str:
    """``file:line`` (text files) or ``file:0xOFFSET`` (containers) or ``file``.

    The column is not part of the text form: compile and validate do not always know it
    for the same finding, and one finding must print the same everywhere (json, sarif and
    github carry the column where it is known)."""
    loc = escape(d.file) if d.file else "<input>"
    if d.line is not None:
        loc += f":{d.line}"
    elif d.offset is not None:
        loc += f":0x{d.offset:X}"
    return loc


def format_text(d: Diagnostic, colour: bool = False) -> str:
    """The one text form of a diagnostic: ``file:line: severity: message [RULE]``."""
    sev = d.severity.value
    if colour:
        sev = f"{_COLOURS[d.severity]}{sev}\x1b[0m"
    text = f"{location(d)}: {sev}: {escape(bounded(d.message))}"
    if d.rule:
        text += f" [{d.rule}]"
    return text


def shorten(text: str, n: int = 60) -> str:
    """A user's number or text as a message quotes it: whole when it has at most ``n``
    characters, else its first 40 and last 12 with the count between them
    (``0xFFFFFFFF...FFFF (4002 characters)``), so that a diagnostic stays one readable line
    whatever the input holds. Every message that shows a literal, a key or a name read
    from a file goes through this; a number is shown as it was written, never converted
    to decimal first (Python refuses to print an int of more than 4300 digits)."""
    if isinstance(text, int) and text.bit_length() > 256:   # hex: no limit, linear
        text = f"{'-' if text < 0 else ''}0x{abs(text):X}"
    text = str(text)
    return text if len(text) <= n else f"{text[:40]}...{text[-12:]} ({len(text)} characters)"


# The longest message any output format shows whole (issue 26): a message that quotes a
# user's text without ``shorten`` (a site that missed it) is still one bounded line.
MESSAGE_LIMIT = 2000


def bounded(message: str, n: int = MESSAGE_LIMIT) -> str:
    """A whole message as every output format renders it: whole when it has at most ``n``
    characters, else its first half and last quarter with the count between them, in the
    convention of ``shorten`` (``... (100071 characters)``). The safety net under
    ``shorten``: one length check for every message that needs none."""
    if len(message) <= n:
        return message
    return f"{message[:n // 2]}...{message[-(n // 4):]} ({len(message)} characters)"


@dataclass(slots=True)
class Where:
    """A place in an input file: every model element carries one."""
    file: str
    line: int | None = None

    def __str__(self) -> str:
        return f"{self.file}:{self.line}" if self.line is not None else self.file


class DcfError(Exception):
    """A problem in user input; carries the diagnostic that explains it."""

    def __init__(self, message: str, where: Where | None = None, *, rule: str = "",
                 offset: int | None = None, hint: str = ""):
        super().__init__(message)
        self.diagnostic = Diagnostic(Severity.ERROR, message, where.file if where else "",
                                     where.line if where else None, None, offset, rule, hint)

    def __str__(self) -> str:
        return self.diagnostic.format()


@dataclass
class Diagnostics:
    """A collector: code adds findings, the CLI decides what they mean for the exit code."""
    items: list[Diagnostic] = field(default_factory=list)

    def add(self, severity: Severity, message: str, where: Where | None = None, *,
            rule: str = "", column: int | None = None, offset: int | None = None,
            hint: str = "") -> None:
        self.items.append(Diagnostic(severity, message, where.file if where else "",
                                     where.line if where else None, column, offset, rule, hint))

    def error(self, message: str, where: Where | None = None, **kw) -> None:
        self.add(Severity.ERROR, message, where, **kw)

    def warning(self, message: str, where: Where | None = None, **kw) -> None:
        self.add(Severity.WARNING, message, where, **kw)

    def info(self, message: str, where: Where | None = None, **kw) -> None:
        self.add(Severity.INFO, message, where, **kw)

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.items if d.severity is Severity.ERROR]

    @property
    def has_errors(self) -> bool:
        return any(d.severity is Severity.ERROR for d in self.items)

    def extend(self, other: "Diagnostics") -> None:
        self.items.extend(other.items)

    def __iter__(self):
        return iter(self.items)

    def __len__(self) -> int:
        return len(self.items)


# validate and compile keep this many findings of one rule and severity in one file (every
# output format shows them: a CI job may want each); the others are counted in one summary
# finding (issue 26: 5 million unknown keys made 5 million findings, and a MemoryError)
LIMIT = 1000


def summary_finding(first: Diagnostic, n: int) -> Diagnostic:
    """The finding that stands for ``n`` findings of ``first``'s rule left out, at the line
    of the first of them: ``... and 4,999,000 more DCF050 findings like this``. One left
    out is ``first`` itself: a summary of one would say less in as much."""
    if n == 1 and not first.more:
        return first
    return Diagnostic(first.severity, f"... and {n:,} more {first.rule} findings like this",
                      first.file, first.line, first.column, first.offset, first.rule,
                      first.hint, n)


class Capped(Diagnostics):
    """A collector that keeps the first ``limit`` findings of each rule and severity in
    each file and counts the others (``summary_finding``, in the place of the first one
    left out): a finding left out costs a dict lookup, no object. Unlike ``Summarised``
    nothing is dropped as a repeat, and the summary counts in every total (``weight``)."""

    def __init__(self, limit: int = LIMIT):
        self.limit = limit
        self._items: list[Diagnostic | None] = []
        self._kept: dict = {}          # (file, rule, severity) -> findings kept
        self._more: dict = {}          # (file, rule, severity) -> [index, count, first]

    @property
    def items(self) -> list[Diagnostic]:
        for at, n, first in self._more.values():
            self._items[at] = summary_finding(first, n)
        return self._items

    @items.setter
    def items(self, value: list[Diagnostic]) -> None:
        self._items = value
        self._kept, self._more = {}, {}

    def add(self, severity: Severity, message: str, where: Where | None = None, *,
            rule: str = "", column: int | None = None, offset: int | None = None,
            hint: str = "") -> None:
        file, line = (where.file, where.line) if where else ("", None)
        group = (file, rule, severity)
        kept = self._kept.get(group, 0)
        if rule and kept >= self.limit:
            more = self._more.get(group)
            if more is None:
                first = Diagnostic(severity, message, file, line, column, offset, rule, hint)
                self._more[group] = [len(self._items), 1, first]
                self._items.append(None)   # the summary's place: filled by ``items``
            else:
                more[1] += 1
            return
        self._kept[group] = kept + 1
        self._items.append(Diagnostic(severity, message, file, line, column, offset, rule,
                                      hint))

    def extend(self, other) -> None:
        for d in other:
            self.add(d.severity, d.message, Where(d.file, d.line), rule=d.rule,
                     column=d.column, offset=d.offset, hint=d.hint)


class Summarised(Capped):
    """A collector for inputs that can repeat one mistake 100,000 times (a network file:
    issue 26): each finding is kept once (the same finding from ``defaults:`` or a
    template, reported for every node, is one), and of one rule and severity in one
    file the first ``limit``; the others are counted in one finding of that rule, at the
    line of the first one left out: ``... and 99,995 more NET007 findings like this``.
    Every output format shows that finding, so each says the count; an omitted finding
    costs a dict lookup instead of a Diagnostic, a line of text and a JSON object.
    ``Capped`` keeps and counts; this adds the repeats dropped and its own summary."""

    def __init__(self, limit: int = 5):
        super().__init__(limit)
        self._seen: set = set()            # the findings kept
        self._counted: set[int] = set()    # the hashes of those only counted

    @property
    def items(self) -> list[Diagnostic]:
        for at, n, first in self._more.values():
            # one left out is shown as it is: a summary of one would say less in as much
            self._items[at] = first if n == 1 else Diagnostic(
                first.severity, f"... and {n:,} more {first.rule} findings like this",
                first.file, first.line, rule=first.rule)
        return self._items

    @items.setter
    def items(self, value: list[Diagnostic]) -> None:
        self._items = value

    def add(self, severity: Severity, message: str, where: Where | None = None, *,
            rule: str = "", column: int | None = None, offset: int | None = None,
            hint: str = "") -> None:
        file, line = (where.file, where.line) if where else ("", None)
        key = (severity, message, file, line, column, offset, rule)
        if key in self._seen:
            return
        if rule and self._kept.get((file, rule, severity), 0) >= self.limit:
            # only counted: the finding is remembered by its hash (64 bits: 100,000 of
            # them would hold 50 MB of messages and tuples otherwise); two distinct ones
            # of one hash would count as one, once in 2^40 files of a million findings
            digest = hash(key)
            if digest in self._counted:
                return
            self._counted.add(digest)
        else:
            self._seen.add(key)
        super().add(severity, message, where, rule=rule, column=column, offset=offset,
                    hint=hint)


def summarise(diags, limit: int = LIMIT) -> list[Diagnostic]:
    """``diags`` with the first ``limit`` findings of each rule and severity in each file,
    in order, and the others counted in one summary finding at the place of the first one
    left out (``summary_finding``; summaries among them add their counts). The list
    itself when nothing is left out."""
    diags = list(diags)
    if len(diags) <= limit:
        return diags
    counts: dict = {}
    for d in diags:
        group = (d.file, d.rule, d.severity)
        counts[group] = counts.get(group, 0) + 1
    if max(counts.values()) <= limit:
        return diags
    kept: dict = {}
    more: dict = {}                    # group -> [index in out, count, first]
    out: list = []
    for d in diags:
        group = (d.file, d.rule, d.severity)
        n = kept.get(group, 0)
        if not d.rule or n < limit and not d.more:
            kept[group] = n + 1
            out.append(d)
            continue
        got = more.get(group)
        if got is None:
            more[group] = [len(out), d.weight, d]
            out.append(None)
        else:
            got[1] += d.weight
    for at, n, first in more.values():
        out[at] = summary_finding(first, n)
    return out


class DiagnosticWarning(UserWarning):
    """A warning (or info) finding, delivered through ``warnings.warn`` by the Python API
    functions that return a single value (``compile_file``, ``read_container``, ...);
    ``diagnostic`` holds the finding, ``str()`` is its one-line form."""

    def __init__(self, diagnostic: Diagnostic):
        super().__init__(diagnostic.format())
        self.diagnostic = diagnostic


__all__ = ["Capped", "Diagnostic", "DiagnosticWarning", "Diagnostics", "DcfError", "ExitCode",
           "LIMIT", "MESSAGE_LIMIT", "Severity", "Summarised", "Where", "bounded", "shorten",
           "summarise", "summary_finding"]
