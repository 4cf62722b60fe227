"""Building one object from its INI sections (a step of ``builder._Builder``).
"""
from __future__ import annotations

from dcf2bin import datatypes as dt, ini as ini_mod, values
from dcf2bin.diagnostics import Where, shorten
from dcf2bin.indexes import is_network_variable_index
from dcf2bin.model.objects import Entry, Obj
from dcf2bin.model.sections import _pdo_flag, _proto


class _ObjectStep:
    """Building one object of ``_Builder``: its section, sub-sections, CompactSubObj
    expansion, sub-index 0 and the auxiliary [xxxxName]/[xxxxValue] sections.
    """

    def _object(self, idx: int, sec: ini_mod.Section, subsecs: dict[int, ini_mod.Section],
                aux: dict[tuple[int, str], ini_mod.Section]) -> None:
        obj = self._object_head(idx, sec, subsecs)
        obj_flags = self._int_key(sec, "objflags", 0, idx) or 0
        obj_map = _pdo_flag(sec.get("pdomapping"))
        if not obj.complex:
            if is_network_variable_index(idx):
                self.dev.error(f"[{shorten(sec.name)}] is a VAR; objects in 0xA000-0xAFFF must "
                               "be ARRAYs",
                               self.w(sec.line), idx, rule="DCF300")
            e = self._entry(idx, 0, sec, obj_flags=obj_flags, obj_map=obj_map)
            obj.entries[0] = e
            return
        if obj.compact:
            self._compact_entries(obj, sec, subsecs, aux, obj_flags, obj_map)
        else:
            vsec = aux.get((idx, "value"))
            if vsec is not None:
                self.dev.warning(f"[{shorten(vsec.name)}] without CompactSubObj in "
                                 f"[{shorten(sec.name)}] is "
                                 "ignored", self.w(vsec.line), idx, rule="DCF027")
        self._sub_entries(obj, subsecs, obj_flags, obj_map)
        self._sub0(obj)

    def _object_head(self, idx: int, sec: ini_mod.Section,
                     subsecs: dict[int, ini_mod.Section]) -> Obj:
        """The object itself: name, ObjectType, SubNumber, CompactSubObj; added to the
        device."""
        dev = self.dev
        obj = Obj(idx, sec.get("parametername") or "", where=self.w(sec.line), section=sec)
        ot = self._int_key(sec, "objecttype", None, idx)
        obj.sub_number = self._int_key(sec, "subnumber", None, idx)
        obj.compact = self._int_key(sec, "compactsubobj", 0, idx) or 0
        if obj.compact and not 1 <= obj.compact <= 0xFE:
            dev.error(f"CompactSubObj={obj.compact} is outside 1..254", self.w(
                sec.line_of("compactsubobj")), idx, rule="DCF021")
            obj.compact = 0
        has_subs = bool(subsecs) or bool(obj.sub_number) or obj.compact > 0
        if ot is not None and ot not in dt.OBJECT_TYPES:
            dev.error(f"[{shorten(sec.name)}] unknown ObjectType "
                      f"0x{ot:X}", self.w(sec.line_of("objecttype")),
                      idx, rule="DCF022")
            ot = None
        if ot in (dt.OT_ARRAY, dt.OT_RECORD):
            obj.complex = True
        elif has_subs:
            obj.complex = True
            if ot is not None:
                dev.warning(f"[{shorten(sec.name)}] has ObjectType 0x{ot:X} but sub-objects; "
                            "treated as ARRAY/RECORD", self.w(sec.line_of("objecttype")), idx,
                            rule="DCF023")
            ot = dt.OT_RECORD if not is_network_variable_index(idx) else dt.OT_ARRAY
        obj.object_type = ot if ot is not None else dt.OT_VAR
        dev.objects[idx] = obj
        return obj

    def _compact_entries(self, obj: Obj, sec: ini_mod.Section,
                         subsecs: dict[int, ini_mod.Section],
                         aux: dict[tuple[int, str], ini_mod.Section], obj_flags: int,
                         obj_map: bool) -> None:
        """The sub-entries CompactSubObj describes, named and valued by the object's
        [xxxxName]/[xxxxValue]/[xxxxDenotation] sections."""
        dev, idx = self.dev, obj.index
        for s in sorted(subsecs):
            if s != 0:
                dev.warning(f"[{shorten(subsecs[s].name)}] given although [{shorten(sec.name)}] "
                            "has "
                            "CompactSubObj; the sub-section wins", self.w(subsecs[s].line),
                            idx, s, rule="DCF024")
        if sec.get("parametervalue") is not None:
            dev.warning(f"ParameterValue in [{shorten(sec.name)}] of a CompactSubObj object is "
                        "ignored (use [%04XValue])" % idx,
                        self.w(sec.line_of("parametervalue")), idx, rule="DCF025")
        names = aux.get((idx, "name"))
        vals = aux.get((idx, "value"))
        dens = aux.get((idx, "denotation"))
        base_name = obj.name
        proto = lines = None     # every compact sub-entry is the object's section
        for s in range(1, obj.compact + 1):
            if s in subsecs:
                continue
            if proto is not None:
                obj.entries[s] = Entry(idx, s, f"{base_name}{s}", *proto,
                                       Where(self.path, sec.line), dict(lines), False,
                                       None)
                continue
            problems = len(dev.problems)
            e = self._entry(idx, s, sec, obj_flags=obj_flags, obj_map=obj_map)
            e.name = f"{base_name}{s}"
            e.param = None
            e.where = Where(self.path, sec.line)   # (not from the section, which goes:)
            e.section = None            # its keys are the object's: lines by hand
            e.lines = {k: sec.line_of(k) for k in sec.values if k != "parametervalue"}
            obj.entries[s] = e
            if len(dev.problems) == problems:   # else each reports its own
                proto, lines = _proto(e), e.lines
        for kind, asec in (("name", names), ("value", vals), ("denotation", dens)):
            if asec is None:
                continue
            for key, k in asec.keys.items():
                if key == "nrofentries":
                    continue
                try:
                    if len(key) > values.MAX_DIGITS:      # never a huge int (issue 26)
                        raise ValueError(key)
                    s = int(key, 10)  # SPEC §1: decimal subindexes
                except ValueError:
                    dev.warning(f"[{shorten(asec.name)}] key '{shorten(k.name)}' is not a decimal "
                                "subindex", self.w(k.line), idx, rule="DCF026")
                    continue
                e = obj.entries.get(s)
                if e is None or s == 0:
                    dev.warning(f"[{shorten(asec.name)}] subindex {s} is outside CompactSubObj="
                                f"{obj.compact}; ignored", self.w(k.line), idx, rule="DCF026")
                    continue
                if kind == "name":
                    e.name = k.value
                elif kind == "value":
                    e.param = k.value if k.value != "" else None
                    e.lines["parametervalue"] = k.line
                else:
                    e.denotation = k.value

    def _sub_entries(self, obj: Obj, subsecs: dict[int, ini_mod.Section], obj_flags: int,
                     obj_map: bool) -> None:
        """One entry per [xxxxsubN] section, in ascending subindex order."""
        idx = obj.index
        protos: dict[int, tuple] = {}
        entries, path, lazy = obj.entries, self.path, self.lazy_where
        new = object.__new__
        last_rest = last_proto = None    # runs of sub-sections share one template
        for s in sorted(subsecs):
            ssec = subsecs[s]
            if s and ssec.param_name is not None:
                # an entry like one already built but for its names (see _entry), its
                # fields stored here one by one: 60,000 of them in a large PLC file, and
                # Entry(...) with *proto would spend more on the call than on the stores
                rest = ssec.rest
                if rest is last_rest:
                    proto = last_proto
                else:
                    proto = protos.get(id(rest))
                    if proto is not None:
                        last_rest, last_proto = rest, proto
                if proto is not None:
                    e = entries[s] = new(Entry)
                    e.index, e.sub, e.name = idx, s, ssec.param_name or ""
                    (e.dtype, e.access, e.pdo_mapping, e.obj_flags, e.default, e.param,
                     e.download_file, e.low, e.high, e.denotation) = proto
                    e._where = lazy if lazy is not None else Where(path, ssec.line)
                    e.lines, e.implicit, e.section = None, False, ssec
                    if ssec.denotation is not None:   # cut out of the template too
                        e.denotation = ssec.denotation or None
                    continue
            if s == 0:
                # an explicit sub 0 section inherits ObjFlags/PDOMapping like any
                # sub-entry (SPEC §1); only an implied or created sub 0 does not
                e = self._entry(idx, 0, ssec, obj_flags=obj_flags, obj_map=obj_map, sub0=True)
            else:
                e = self._entry(idx, s, ssec, obj_flags=obj_flags, obj_map=obj_map,
                                protos=protos)
            obj.entries[s] = e

    def _sub0(self, obj: Obj) -> None:
        """Sub 0 (highest sub-index) when no section gives it or gives no value; the
        entries end up by ascending subindex."""
        idx = obj.index
        ordered = not obj.compact   # so far added by ascending subindex
        if 0 not in obj.entries:
            highest = max((s for s in obj.entries), default=0)
            ordered = ordered and not obj.entries   # sub 0 goes last
            obj.entries[0] = Entry(idx, 0, "Highest sub-index supported", dt.UNSIGNED8, "ro",
                                   default=str(obj.compact or highest), where=obj.where,
                                   implicit=True)
        else:
            e0 = obj.entries[0]
            if e0.default is None and e0.param is None:
                e0.default = str(obj.compact or max(obj.entries))
        if not ordered:  # entries are kept by ascending subindex
            obj.entries = dict(sorted(obj.entries.items()))
