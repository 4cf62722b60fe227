"""What the export formats share: the result type, the exported objects, value encoding and
one-line diagnostics. ``lenze`` and ``port`` build on it; ``export/__init__`` dispatches."""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin.diagnostics import DcfError, Diagnostic, Severity

FORMATS = ("lenze-st", "lenze-bin", "port-c")
FIRST_INDEX = 0x1000


@dataclass
class ExportResult:
    output: bytes | str | None              # None when errors stop the export
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.output is not None

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]


def model_diagnostics(dev) -> list[Diagnostic]:
    """The model's problems; errors about objects that are not exported become warnings."""
    out = []
    for p in dev.problems:
        d = p.diagnostic
        if d.severity is Severity.ERROR and p.index is not None and p.index < FIRST_INDEX:
            d = Diagnostic(Severity.WARNING, d.message + " (not exported)", d.file, d.line,
                           d.column, d.offset, d.rule, d.hint)
        out.append(d)
    return out


def exported_objects(dev) -> list:
    return [o for o in dev.sorted_objects() if o.index >= FIRST_INDEX]


def encode(dev, entry, errors: list[Diagnostic]) -> bytes | None:
    """The entry's value bytes, or None after appending the error."""
    if entry.dtype is None:
        return None  # the model already reported the missing/unknown DataType
    try:
        return dev.encode(entry)
    except DcfError as exc:
        errors.append(exc.diagnostic)
        return None


def warning(message: str, where, rule: str, hint: str = "") -> Diagnostic:
    return Diagnostic(Severity.WARNING, message, where.file if where else "",
                      where.line if where else None, None, None, rule, hint)


def error(message: str, where, rule: str, hint: str = "") -> Diagnostic:
    return Diagnostic(Severity.ERROR, message, where.file if where else "",
                      where.line if where else None, None, None, rule, hint)


def ascii_text(text: str) -> str:
    """A name made safe for a comment in generated source: ASCII, one line."""
    out = []
    for ch in text:
        if ch in "\r\n\t":
            out.append(" ")
        elif 32 <= ord(ch) < 127:
            out.append(ch)
        else:
            out.append("?")
    return "".join(out).strip()
