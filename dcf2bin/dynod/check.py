"""compile checks what it writes (SPEC §8.1, D-11): the emulation run on a container just
built from a DCF, with the DCF's own objects minus the creation group as the static OD,
and its result as diagnostics at the DCF line of the offending value.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostic, Severity, Where
from dcf2bin.dynod import codes as C
from dcf2bin.dynod.emulate import Outcome, TargetOptions, emulate
from dcf2bin.dynod.static import StaticOD


def value_text(data: bytes | None) -> str:
    """An entry's data as an engineer reads it: a little-endian number up to 8 bytes."""
    if data is None:
        return "?"
    if not data:
        return "(empty)"
    if len(data) <= 8:
        return f"0x{int.from_bytes(data, 'little'):0{2 * len(data)}X}"
    return data[:16].hex().upper() + ("..." if len(data) > 16 else "") + f" ({len(data)} bytes)"


def message(out: Outcome) -> str:
    """``0x1A00sub1 = 0xA4C00110: <reason>; would make DynBuildOd return 0x78 kCopPdoErrorMapp``"""
    head = f"{out.label} = {value_text(out.value)}: " if out.index is not None else ""
    return f"{head}{out.reason}; would make DynBuildOd return 0x{out.code:02X} {out.name}"


class Sources:
    """1-based entry position -> the DCF place that produced it (computed on demand: only a
    failing entry needs it). Entries after the selection's come from --append files."""

    def __init__(self, dev, entries: list, extra: list | None = None):
        self.dev = dev
        self.entries = entries
        self.n = len(entries)
        self.extra = extra or []

    def get(self, pos: int) -> Where | None:
        if 1 <= pos <= self.n:
            index, sub, _ = self.entries[pos - 1]
            e = self.dev.entry(index, sub)
            return None if e is None else e.value_where
        k = pos - self.n - 1
        if 0 <= k < len(self.extra):
            return getattr(self.extra[k], "where", None)
        return None

    __call__ = get


def run(dev, sel, container, options: TargetOptions, extra=None) -> Outcome:
    """Emulate a container compiled from ``dev`` with selection ``sel``."""
    static = StaticOD.from_device(dev, sel.created)
    return emulate(container, options, static, Sources(dev, sel.entries, extra))


def diagnostics(out: Outcome, path: str, severity: Severity = Severity.ERROR) -> list[Diagnostic]:
    """The emulation's verdict as one diagnostic (none on success)."""
    if out.ok:
        return []
    file, line = path, None
    if out.where:
        head, _, tail = out.where.rpartition(":")
        if head and tail.isdigit():
            file, line = head, int(tail)
        else:
            file = out.where
    return [Diagnostic(severity, message(out), file, line, rule=C.rule_id(out.code),
                       hint="the target's DynBuildOd() would refuse this container; "
                            "see dcf2bin-simulate(1)")]


__all__ = ["Sources", "diagnostics", "message", "run", "value_text"]
