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
    # (index, sub) -> the builder's rules that would only repeat a finding of the reader:
    # DCF031 (no DataType) after XDD011/XDD010, DCF033 (no AccessType) after XDD010
    consequences: dict = field(default_factory=dict)

    def problem(self, severity: Severity, message: str, line: int | None,
                index: int | None = None, sub: int | None = None, *, rule: str,
                hint: str = "") -> None:
        self.problems.append((severity, message, line, index, sub, rule, hint))

    def finish(self, dev) -> None:
        """Give the Device what the sections could not: the findings (tagged with their
        object, so that compile weighs them as it weighs its own), first, and the
        specifics. What the builder says only because of a finding of the reader (no
        DataType after an unknown type) is left out: one cause, one line."""
        if self.consequences:
            dev.problems[:] = [p for p in dev.problems if p.diagnostic.rule not in
                               self.consequences.get((p.index, p.sub or 0), ())]
        mine = len(dev.problems)
        for severity, message, line, index, sub, rule, hint in self.problems:
            dev.problem(severity, message, Where(self.path, line), index, sub, rule=rule,
                        hint=hint)
        dev.problems[:] = dev.problems[mine:] + dev.problems[:mine]
        dev.specifics = self.specifics

    def follows(self, index: int, sub: int | None, *rules: str) -> None:
        """The builder's ``rules`` for this entry would repeat a finding of the reader."""
        self.consequences.setdefault((index, sub or 0), set()).update(rules)


class XmlSection(ini_mod.Section):
    """A section read from XML: its values by lower-case key, each key's name and line;
    ``keys`` (Key records) made when first asked for (a diagnostic), not for every key."""
    __slots__ = ("name", "line", "values", "_lines", "_keys")

    def __init__(self, name: str, line: int):
        self.name, self.line = name, line
        self.values: dict[str, str] = {}
        self._lines: dict[str, tuple[str, int]] = {}
        self._keys = None

    @property
    def keys(self) -> dict[str, ini_mod.Key]:
        if self._keys is None:
            self._keys = {low: ini_mod.Key(name, self.values[low], line)
                          for low, (name, line) in self._lines.items()}
        return self._keys

    def line_of(self, key: str) -> int:
        got = self._lines.get(key)
        return got[1] if got is not None else self.line


class SharedXmlSection(ini_mod._SharedSection):
    """A section read from XML whose values other than its names are a template shared by
    every section of the same shape (``rest``; the contract of ``ini.Section``: the
    ParameterName and Denotation keys stand in it with empty values, their values are
    ``param_name`` and ``denotation``, None where the section has no such key), so that
    the builder and the rules treat the many alike sub-objects of a CANopenEditor file as
    they treat a DCF's (``model.build_object``: one entry built per shape). ``linev``:
    the line of each key, in the template's order; ``values``, ``has``, ``get`` and
    ``key_names`` are the INI fast reader's (``ini._SharedSection``), ``keys`` and the
    name are worked out here when asked for. Made by ``direct.Straight``, without
    ``__init__``."""
    __slots__ = ("canon", "denotation", "linev", "_keys")

    @property
    def name(self) -> str:
        canon = self.canon
        if len(canon) == 4:
            return canon.upper()
        return canon[:4].upper() + "sub" + canon[7:].upper()

    @property
    def keys(self) -> dict[str, ini_mod.Key]:
        if self._keys is None:
            values = self.values
            self._keys = {low: ini_mod.Key(WRITTEN[low], values[low], line)
                          for low, line in zip(self.rest, self.linev)}
        return self._keys

    def line_of(self, key: str) -> int:
        for low, line in zip(self.rest, self.linev):
            if low == key:
                return line
        return self.line


# the keys of an object's section as CiA 306 writes them, by their lower-case names
WRITTEN = {k.lower(): k for k in (
    "ParameterName", "ObjectType", "SubNumber", "DataType", "AccessType", "DefaultValue",
    "ParameterValue", "LowLimit", "HighLimit", "PDOMapping", "ObjFlags", "Denotation")}


def section(name: str, line: int) -> XmlSection:
    return XmlSection(name, line)


_LOW: dict[str, str] = {}


def add(sec: XmlSection, name: str, value: str, line: int | None) -> None:
    low = _LOW.get(name)
    if low is None:
        low = name.lower()
        if len(_LOW) < 1024:
            _LOW[name] = low
    sec.values[low] = value
    sec._lines[low] = (name, line if line is not None else sec.line)
    sec._keys = None
