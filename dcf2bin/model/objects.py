"""The data of the model: ``Entry`` (one sub-object), ``Obj`` (one object) and ``Problem`` (a
diagnostic tagged with the object/entry it touches). Every one keeps its file:line.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt, ini as ini_mod
from dcf2bin.diagnostics import Diagnostic, Where
from dcf2bin.indexes import is_pdo_mapping


@dataclass(slots=True)
class Problem:
    """A diagnostic about the model, tagged with the object/entry it touches.

    ``compile`` turns an error into a warning when it touches nothing it writes.
    """
    diagnostic: Diagnostic
    index: int | None = None
    sub: int | None = None   # None: the whole object


class Entry:
    """One sub-object: its keys' values as text (encoded on demand), its type and access,
    and where it was written (``where``: the section, or the object's for a CompactSubObj
    sub-entry; ``lines``: key -> line where not the section's own).

    ``where`` of an entry read from its own section is made from the section's line when
    first asked for (a diagnostic, a map): the builder stores only the file's path, so a
    PLC file's 60,000 network variables carry no ``Where`` each until one is read (the
    same file:line either way). Compared by identity, like the dataclass it was."""
    __slots__ = ("index", "sub", "name", "dtype", "access", "pdo_mapping", "obj_flags",
                 "default", "param", "download_file", "low", "high", "denotation", "_where",
                 "lines", "implicit", "section")
    __match_args__ = ("index", "sub", "name", "dtype", "access", "pdo_mapping", "obj_flags",
                      "default", "param", "download_file", "low", "high", "denotation",
                      "where", "lines", "implicit", "section")

    def __init__(self, index: int, sub: int, name: str = "",
                 dtype: dt.DataType | None = None, access: str | None = None,
                 pdo_mapping: bool = False, obj_flags: int = 0, default: str | None = None,
                 param: str | None = None, download_file: str | None = None,
                 low: str | None = None, high: str | None = None,
                 denotation: str | None = None, where: Where | None = None,
                 lines: dict[str, int] | None = None, implicit: bool = False,
                 section: ini_mod.Section | None = None):
        self.index = index
        self.sub = sub
        self.name = name
        self.dtype = dtype
        self.access = access
        self.pdo_mapping = pdo_mapping
        self.obj_flags = obj_flags
        self.default = default
        self.param = param
        self.download_file = download_file
        self.low = low
        self.high = high
        self.denotation = denotation
        self._where = where        # a Where, None, or the file's path: see ``where``
        self.lines = lines         # key -> line, where not the section's own
        self.implicit = implicit   # created by the tool (sub 0, CompactPDO)
        self.section = section

    @property
    def where(self) -> Where | None:
        """The section (or the object's, for compact subs), as file:line."""
        w = self._where
        if w.__class__ is str:     # the builder's: the file, at the section's line
            sec = self.section
            w = self._where = Where(w, sec.line if sec is not None else None)
        return w

    @where.setter
    def where(self, value: Where | None) -> None:
        self._where = value

    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__match_args__)
        return f"Entry({fields})"

    @property
    def configured(self) -> bool:
        """SPEC §1: an entry is configured when it has a ParameterValue or a DownloadFile."""
        return self.param is not None or self.download_file is not None

    @property
    def value_text(self) -> str | None:
        """The text of the effective value (ParameterValue, else DefaultValue)."""
        return self.param if self.param is not None else self.default

    @property
    def has_value(self) -> bool:
        return self.param is not None or self.download_file is not None or self.default is not None

    def has_key(self, key: str) -> bool:
        return bool(self.lines and key in self.lines) or (
            self.section is not None and self.section.has(key))

    def key_where(self, key: str) -> Where:
        w = self.where or Where("")
        if self.lines and key in self.lines:
            return Where(w.file, self.lines[key])
        if self.section is not None and self.section.has(key):
            return Where(w.file, self.section.line_of(key))
        return w

    @property
    def value_where(self) -> Where:
        for key in ("parametervalue", "downloadfile", "defaultvalue"):
            if self.has_key(key):
                return self.key_where(key)
        return self.where or Where("")

    @property
    def label(self) -> str:
        return f"0x{self.index:04X}sub{self.sub:X}"


@dataclass(slots=True, eq=False)
class Obj:
    """One object: its name, ObjectType and entries by subindex, and where it was written."""
    index: int
    name: str = ""
    object_type: int = dt.OT_VAR
    entries: dict[int, Entry] = field(default_factory=dict)
    where: Where | None = None
    section: ini_mod.Section | None = None
    compact: int = 0           # CompactSubObj
    sub_number: int | None = None
    implicit: bool = False     # created from CompactPDO
    complex: bool = False      # ARRAY/RECORD

    def sorted_entries(self) -> list[Entry]:
        return [self.entries[k] for k in sorted(self.entries)]


def unstated_mapping_count(obj: Obj) -> tuple[Where, str] | None:
    """A PDO mapping object with sub-entries whose sub 0 gives no value (no sub 0 section,
    or one without DefaultValue/ParameterValue: Elmo EDS files write only HighLimit=8)
    does not say how many objects it maps; the model's sub 0 is then the highest subindex
    present (SPEC §1). Returns where to say so and the message (DCF419), else None.
    ``compile`` refuses to write a PDO block from such a count (docs/compile.md, choice 9)."""
    if not is_pdo_mapping(obj.index) or obj.implicit or obj.compact or len(obj.entries) < 2:
        return None
    e0 = obj.entries.get(0)
    if e0 is None:
        return None
    highest = max(obj.entries)
    if e0.implicit:
        what = f"PDO mapping 0x{obj.index:04X} has no sub 0"
    elif e0.section is not None and not any(
            e0.section.values.get(k) for k in ("parametervalue", "defaultvalue", "downloadfile")):
        what = f"{e0.label} has no DefaultValue or ParameterValue"
    else:
        return None
    return (e0.where or obj.where or Where(""),
            f"{what}: the number of mapped objects is not given (the highest subindex "
            f"present, {highest}, would be taken)")
