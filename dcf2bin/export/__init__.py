"""Exports of a device's object dictionary for other systems (SPEC §7).

* ``lenze``: Lenze PLC Designer master OD (``CanOpenODEntry`` records), as IEC 61131-3
  structured text or packed little-endian binary;
* ``port``: a C source for the port CANopen Library (``LIST_ELEMENT_T`` / ``VALUE_DESC_T``).

Both export every entry of every object from 0x1000 up (objects below 0x1000 are data
type definitions), with the entry's value as SPEC §1 defines it (ParameterValue, else
DownloadFile, else DefaultValue, else the type's zero). Model errors that touch an exported
object stop the export; values that cannot be encoded are one-line ``file:line`` errors.
"""
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


def run(fmt: str, path: str, *, data: bytes | None = None, node_id: int | None = None,
        allow_external_files: bool = False, **options) -> ExportResult:
    """Load ``path`` (or ``data``) and export it in ``fmt`` (one of FORMATS)."""
    from dcf2bin import model
    dev = model.load(path, node_id=node_id, allow_external_files=allow_external_files,
                     data=data)
    return export_device(fmt, dev, **options)


def export_device(fmt: str, dev, **options) -> ExportResult:
    if fmt in ("lenze-st", "lenze-bin"):
        from dcf2bin.export import lenze
        return lenze.export(dev, binary=(fmt == "lenze-bin"), **options)
    if fmt == "port-c":
        from dcf2bin.export import port
        return port.export(dev, **options)
    raise ValueError(f"unknown export format '{fmt}' (known: {', '.join(FORMATS)})")
