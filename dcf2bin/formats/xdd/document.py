"""What the CiA 311 reader hands on: ``XddFile``, the file's data as the CiA 306 sections of
an ``ini.IniFile`` (every key at the line of the XML element it came from), with what the
sections cannot hold beside them -- the reader's findings tied to an object, the
specifics a writer needs to give the file back, the objects CANopenNode leaves out.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import ini as ini_mod
from dcf2bin.diagnostics import Severity, Where


@dataclass
class XddFile(ini_mod.IniFile):
    """A CiA 311 file read as sections (``format`` "xdd").

    ``specifics``: (index, subindex or None for the object) -> {name: value} of what CiA
    306 has no key for: the parameter's ``description``, the raw ``PDOmapping`` ("TPDO",
    "RPDO", "optional", "default"), CANopenNode's ``CO_*`` properties. ``disabled``: the
    sections of the objects marked ``CO_disabled`` (CANopenNode builds them into no object
    dictionary, and CANopenEditor writes them into no EDS), kept for a writer.
    ``problems``: findings tied to an object or entry, added to the Device by ``finish``.
    """
    specifics: dict = field(default_factory=dict)
    disabled: dict = field(default_factory=dict)
    problems: list = field(default_factory=list)
    untyped: set = field(default_factory=set)    # (index, sub) whose type XDD011 reported

    def problem(self, severity: Severity, message: str, line: int | None,
                index: int | None = None, sub: int | None = None, *, rule: str,
                hint: str = "") -> None:
        self.problems.append((severity, message, line, index, sub, rule, hint))

    def finish(self, dev) -> None:
        """Give the Device what the sections could not: the findings (tagged with their
        object, so that compile weighs them as it weighs its own) and the specifics. An
        entry whose type XDD011 reported is not reported again as having none (DCF031)."""
        if self.untyped:
            dev.problems[:] = [p for p in dev.problems if not (
                p.diagnostic.rule == "DCF031" and (p.index, p.sub or 0) in self.untyped)]
        for severity, message, line, index, sub, rule, hint in self.problems:
            dev.problem(severity, message, Where(self.path, line), index, sub, rule=rule,
                        hint=hint)
        dev.specifics = self.specifics


def section(name: str, line: int) -> ini_mod.Section:
    """An empty section as the exact INI reader makes them."""
    return ini_mod._WrittenSection(name, line)


def add(sec: ini_mod.Section, name: str, value: str, line: int | None) -> None:
    sec.add(ini_mod.Key(name, value, line if line is not None else sec.line))
