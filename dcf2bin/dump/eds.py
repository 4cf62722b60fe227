"""Names and exact types from an EDS given with ``--eds`` (``EdsInfo``, ``load_eds``).
"""
from __future__ import annotations

from dataclasses import dataclass

from dcf2bin.diagnostics import Diagnostic, Severity


@dataclass
class EdsInfo:
    """Names and exact types from an EDS (``--eds``); see ``load_eds``."""
    entries: dict          # (index, sub) -> model.Entry
    objects: dict          # index -> model.Obj

    def name(self, index: int, sub: int) -> str:
        e = self.entries.get((index, sub))
        if e is not None and e.name:
            return e.name
        o = self.objects.get(index)
        return o.name if o is not None and sub == 0 and o.name else ""

    def dtype(self, index: int, sub: int):
        e = self.entries.get((index, sub))
        return e.dtype if e is not None else None


def load_eds(path: str, data: bytes | None = None) -> tuple[EdsInfo, object, int]:
    """Load an EDS (or any description, ``formats.load``) -> (EdsInfo, Device, number of
    errors in it)."""
    from dcf2bin import formats
    dev = formats.load(path, data=data)
    entries = {}
    for idx, obj in dev.objects.items():
        for sub, e in obj.entries.items():
            entries[(idx, sub)] = e
    errors = sum(1 for p in dev.problems if p.diagnostic.severity is Severity.ERROR)
    return EdsInfo(entries, dev.objects), dev, errors


def eds_warnings(path: str, errors: int) -> list[Diagnostic]:
    """The warning for an ``--eds`` with ``errors`` errors in it (none for none)."""
    if not errors:
        return []
    return [Diagnostic(Severity.WARNING, f"the EDS has {errors} error"
                       f"{'s' if errors != 1 else ''} (see 'dcf2bin validate'); types and "
                       "names are taken where they could be read", path)]
