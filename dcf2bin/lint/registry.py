"""The rule registry of ``dcf2bin validate``.

Every rule has a stable id, a kebab-case name, a default severity, a one-line
description and a short hint. Two kinds exist:

* checks of this package: one small generator function per rule, registered with
  ``@rule(...)``; it receives a context (``DcfContext``, ``BinContext`` or
  ``ConciseContext``) and yields
  ``Finding``s;
* findings that the core (ini reader, model, layout, selection) already produces with
  a rule id: they are registered with ``core(...)`` so that they can be listed,
  selected and documented, but they have no function here (the checks are not
  duplicated).

This module imports no rule module: the rule modules import it (for ``@rule``, ``core``
and the severities) and the package ``__init__`` imports every rule module once, so the
table is full before anything in ``dcf2bin.lint`` is used.

Id families: DCF0xx syntax and file structure, DCF1xx object dictionary, DCF2xx
values, DCF3xx network variables and process image, DCF4xx PDOs, XDD0xx CiA 311 XML,
CNT0xx containers, CON0xx concise DCFs,
plus IO001/INT001 for unreadable inputs and internal errors (always on).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable, Iterable, Iterator

from dcf2bin.diagnostics import Severity, shorten

ERROR, WARNING, INFO = Severity.ERROR, Severity.WARNING, Severity.INFO

DCF, BIN, CONCISE, ANY = "dcf", "bin", "concise", "any"   # what a rule checks

FAMILIES = {
    "DCF0": "syntax and file structure",
    "DCF1": "object dictionary",
    "DCF2": "values",
    "DCF3": "network variables and process image",
    "DCF4": "PDOs",
    "XDD0": "CiA 311 XML (XDD/XDC)",
    "CNT0": "containers",
    "CON0": "concise DCFs",
    "TGT0": "target emulation (DynBuildOd)",
    "TGT1": "target emulation: what could not be checked",
    "IO0": "inputs",
    "INT0": "internal",
}


@dataclass(frozen=True)
class Finding:
    """What a check yields; the runner adds rule id, severity and file."""
    message: str
    line: int | None = None
    column: int | None = None
    offset: int | None = None
    hint: str = ""


@dataclass(frozen=True)
class Rule:
    id: str
    name: str
    severity: Severity
    description: str
    hint: str = ""
    kind: str = DCF
    check: Callable[..., Iterable[Finding]] | None = None   # None: produced by the core
    always: bool = False     # cannot be deselected (IO001, INT001)

    @property
    def family(self) -> str:
        for prefix, name in FAMILIES.items():
            if self.id.startswith(prefix):
                return name
        return "other"

    @property
    def source(self) -> str:
        return "core" if self.check is None else "lint"

    def as_dict(self) -> dict:
        return {"id": self.id, "name": self.name, "severity": self.severity.value,
                "family": self.family, "description": self.description, "hint": self.hint}


RULES: dict[str, Rule] = {}
_NAMES: set[str] = set()


def _add(r: Rule) -> Rule:
    if r.id in RULES:
        raise ValueError(f"rule id {r.id} registered twice")
    if r.name in _NAMES:
        raise ValueError(f"rule name {r.name} registered twice")
    RULES[r.id] = r
    _NAMES.add(r.name)
    return r


def rule(id: str, name: str, severity: Severity, description: str, *, hint: str = "",
         kind: str = DCF):
    """Register a check function under a stable rule id."""
    def deco(fn: Callable[..., Iterator[Finding]]):
        _add(Rule(id, name, severity, description, hint, kind, fn))
        return fn
    return deco


def core(id: str, name: str, severity: Severity, description: str, *, hint: str = "",
         kind: str = DCF, always: bool = False) -> Rule:
    """Register a rule whose findings come from the core (no check function here)."""
    return _add(Rule(id, name, severity, description, hint, kind, None, always))


def all_rules() -> list[Rule]:
    global _ORDER
    ids = tuple(RULES)
    if _ORDER[0] != ids:          # sorted once, not for every file (a rule added: again)
        _ORDER = (ids, sorted(ids, key=_sort_key))
    return [RULES[k] for k in _ORDER[1]]


_ORDER: tuple[tuple, list[str]] = ((), [])


@functools.lru_cache(maxsize=1024)
def _sort_key(rule_id: str):
    # DCF before CNT before IO/INT; numerically inside a family
    order = {"DCF": 0, "XDD": 0.5, "CNT": 1, "CON": 1.5, "TGT": 2, "IO": 3, "INT": 4}
    prefix = rule_id.rstrip("0123456789")
    if prefix.startswith("TGT"):     # TGT + a hex code: TGT0A1
        prefix = "TGT"
    return (order.get(prefix, 9), rule_id)


class SelectorError(ValueError):
    pass


def resolve(select: Iterable[str] | None, ignore: Iterable[str] | None) -> set[str]:
    """The ids of the active rules for ``--select``/``--ignore`` (ids, id prefixes or names;
    ``ALL``, any case, is every rule).

    Raises SelectorError for a selector that matches no rule.
    """

    def match(sel: str) -> set[str]:
        s = sel.strip()
        if not s:
            return set()
        up, low = s.upper(), s.lower()
        if up == "ALL":         # --select ALL: every rule (as ruff and flake8 spell it)
            return set(RULES)
        hits = {r.id for r in RULES.values() if r.id.startswith(up) or r.name == low}
        if not hits:
            raise SelectorError(f"'{shorten(s)}' matches no rule id, id prefix or rule name "
                                "(see --list-rules)")
        return hits

    def expand(items) -> list[str]:
        out = []
        for item in items or ():
            out.extend(p for p in item.split(","))
        return out

    sel = expand(select)
    active = set(RULES) if not sel else set().union(*(match(s) for s in sel))
    for s in expand(ignore):
        active -= match(s)
    active |= {r.id for r in RULES.values() if r.always}
    return active
