"""``Device``: a device's objects and entries, its node-ID and problems; it encodes and
checks values through the ``encoding`` and ``checks`` mixins.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import ini as ini_mod
from dcf2bin.diagnostics import Diagnostic, Severity, Where
from dcf2bin.model.checks import _ValueChecks
from dcf2bin.model.encoding import _Encoding
from dcf2bin.model.objects import Entry, Obj, Problem


@dataclass
class Device(_Encoding, _ValueChecks):
    """A device's objects and entries as read from one DCF/EDS file (``builder.load``),
    its node-ID and the problems found; values stay text until ``encode``."""
    path: str
    encoding: str = "utf-8"
    objects: dict[int, Obj] = field(default_factory=dict)
    node_id: int | None = None
    node_id_where: Where | None = None
    node_id_from_cli: bool = False
    dummy_usage: set[int] = field(default_factory=set)
    problems: list[Problem] = field(default_factory=list)
    ini: ini_mod.IniFile | None = None
    allow_external_files: bool = False
    channels: list = field(default_factory=list)  # layout.Channel, parsed by layout
    # what the file's format says beyond the model's fields, by (index, subindex or None
    # for the object): a CiA 311 parameter's description, CANopenNode's CO_* properties
    # (dcf2bin.formats.xdd.document.XddFile); kept for the writers of other formats
    specifics: dict = field(default_factory=dict, repr=False)
    # (type code, value text) -> bytes: the encodings ``encode`` has made (a file repeats
    # few value texts per type, "0", "0x00"); select's hot loop reads it directly
    encoded: dict = field(default_factory=dict, repr=False)
    _warned: set = field(default_factory=set, repr=False)
    _verdicts: dict = field(default_factory=dict, repr=False)   # see text_problem

    # -- diagnostics -----------------------------------------------------------------
    def problem(self, severity: Severity, message: str, where: Where | None,
                index: int | None = None, sub: int | None = None, *, rule: str = "",
                hint: str = "") -> None:
        d = Diagnostic(severity, message, where.file if where else self.path,
                       where.line if where else None, None, None, rule, hint)
        self.problems.append(Problem(d, index, sub))

    def error(self, message, where, index=None, sub=None, **kw):
        self.problem(Severity.ERROR, message, where, index, sub, **kw)

    def warning(self, message, where, index=None, sub=None, **kw):
        self.problem(Severity.WARNING, message, where, index, sub, **kw)

    # -- access ------------------------------------------------------------------------
    def entry(self, index: int, sub: int) -> Entry | None:
        o = self.objects.get(index)
        return o.entries.get(sub) if o else None

    def sorted_objects(self) -> list[Obj]:
        return [self.objects[k] for k in sorted(self.objects)]

    def where(self, line: int | None = None) -> Where:
        return Where(self.path, line)

    # -- interop -----------------------------------------------------------------------
    def to_canopen(self):
        """This model as a ``canopen.objectdictionary.ObjectDictionary``.

        Values that cannot be encoded (bad value, missing node-ID) are left at the
        type's zero; use ``dcf2bin validate`` to see them.
        """
        from dcf2bin.interop import to_canopen
        return to_canopen(self)
