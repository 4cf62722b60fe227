"""Building one entry from its INI section (a step of ``builder._Builder``).
"""
from __future__ import annotations

from dcf2bin import datatypes as dt, ini as ini_mod, values
from dcf2bin.diagnostics import Where, shorten
from dcf2bin.indexes import NV_FIRST, NV_LAST
from dcf2bin.model.objects import Entry
from dcf2bin.model.sections import _ACCESS, _DTYPES, _pdo_flag, _proto


class _EntrySteps:
    """Building one entry of ``_Builder``: its keys, inherited ObjFlags and PDOMapping, and
    its DataType.
    """

    def _entry(self, idx: int, sub: int, sec: ini_mod.Section, *, obj_flags: int = 0,
               obj_map: bool = False, sub0: bool = False,
               protos: dict[int, tuple] | None = None) -> Entry:
        """One sub-object. ``protos`` (one dict per object, whose ObjFlags and PDOMapping
        its sub-entries inherit) remembers the fields of an entry whose section shares the
        INI reader's template (``Section.rest``: the same text but for the values of
        ParameterName and Denotation), so that ``_object`` builds the other sub-entries
        of a network-variable array from them. Only an entry that raised no problem is
        remembered: every faulty one reports its own."""
        shape = sec.rest if protos is not None and sec.param_name is not None else None
        problems = len(self.dev.problems)
        e = self._entry_from(idx, sub, sec, obj_flags, obj_map, sub0)
        if shape is not None and len(self.dev.problems) == problems:
            protos[id(shape)] = _proto(e)
        return e

    def _entry_from(self, idx: int, sub: int, sec: ini_mod.Section, obj_flags: int,
                    obj_map: bool, sub0: bool) -> Entry:
        # the section's values: its template's (the fast reader's) with the names cut out
        # of it put back, without building the section's own dict of them
        rest = sec.rest
        get = (rest if rest is not None else sec.values).get   # '' counts as absent
        name = sec.param_name if rest is not None else None
        if name is None:
            name = get("parametername")
        den = sec.denotation if rest is not None else None
        if den is None:
            den = get("denotation")
        lazy = self.lazy_where    # Entry.where makes the Where from the section's line
        # positional, in field order
        e = Entry(idx, sub, name or "", None, None, False, obj_flags,
                  get("defaultvalue") or None, get("parametervalue") or None,
                  get("downloadfile") or None, get("lowlimit") or None,
                  get("highlimit") or None, den or None,
                  lazy if lazy is not None else Where(self.path, sec.line), None, False, sec)
        if get("objflags"):
            e.obj_flags = self._int_key(sec, "objflags", obj_flags, idx, sub) or 0
        pm = get("pdomapping")
        e.pdo_mapping = _pdo_flag(pm) if pm else obj_map
        text = get("datatype")
        if text:
            e.dtype = _DTYPES.get(text)
            if e.dtype is None:
                e.dtype = self._datatype(sec, text, idx, sub)
        elif sub0:
            e.dtype = dt.UNSIGNED8
        elif not (sub >= 1 and NV_FIRST <= idx <= NV_LAST):
            self.dev.error(f"[{shorten(sec.name)}] has no DataType", self.w(sec.line), idx, sub,
                           rule="DCF031")
        text = get("accesstype")
        if text:
            acc = _ACCESS.get(text) or text.strip().lower()
            if acc in dt.ACCESS_ATTR:
                e.access = acc
            else:
                self.dev.error(f"[{shorten(sec.name)}] unknown AccessType '{shorten(text)}'",
                               self.w(sec.line_of("accesstype")), idx, sub, rule="DCF032")
        elif sub0:
            e.access = "ro"
        elif not (sub >= 1 and NV_FIRST <= idx <= NV_LAST):
            self.dev.error(f"[{shorten(sec.name)}] has no AccessType", self.w(sec.line), idx, sub,
                           rule="DCF033")
        return e

    def _datatype(self, sec: ini_mod.Section, text: str, idx: int, sub: int):
        try:
            code = values.parse_int(values.split_numeric_comment(text)[0])
        except values.ValueProblem as exc:
            self.dev.error(f"[{shorten(sec.name)}] DataType: "
                           f"{exc}", self.w(sec.line_of("datatype")),
                           idx, sub, rule="DCF030")
            return None
        dtype = dt.BY_CODE.get(code)
        if dtype is None:
            self.dev.error(f"[{shorten(sec.name)}] unknown or unsupported DataType 0x{code:04X}",
                           self.w(sec.line_of("datatype")), idx, sub, rule="DCF030")
        elif len(_DTYPES) < 256:
            _DTYPES[text] = dtype
        return dtype
