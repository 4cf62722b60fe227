"""The object dictionary of a CiA 311 file as CiA 306 sections: one section per
``CANopenObject`` and per ``CANopenSubObject``, its keys from the element's own attributes
(vendor style, CiA 311 v1.0: ``dataType``, ``accessType``, ``defaultValue``,
``actualValue``, ...) and from the ``parameter`` its ``uniqueIDRef`` names (CANopenEditor
style: the type as an IEC 61131 element or a ``dataTypeIDRef``, ``access``,
``defaultValue``, ``allowedValues``, ``denotation``, CANopenNode's ``property``s).

The style is not told by namespace or version (real files mix them): every object is read
both ways, and where both say something the object's own attribute wins (XDD012 says so
when they disagree). Every key keeps the line of the element that gave it.
"""
from __future__ import annotations

import re

from dcf2bin import values
from dcf2bin.diagnostics import Severity
from dcf2bin.formats.xdd import vocabulary as voc
from dcf2bin.formats.xdd.document import XddFile, add, section
from dcf2bin.formats.xdd.markup import local

ERROR, WARNING, INFO = Severity.ERROR, Severity.WARNING, Severity.INFO
_HEX = {2: re.compile(r"[0-9A-Fa-f]{2}"), 4: re.compile(r"[0-9A-Fa-f]{4}")}
# the keys of an entry in the order a section lists them
_ORDER = ("ParameterName", "ObjectType", "SubNumber", "DataType", "AccessType",
          "DefaultValue", "ParameterValue", "LowLimit", "HighLimit", "PDOMapping",
          "ObjFlags", "Denotation")
# plain attributes of CANopenObject/CANopenSubObject -> CiA 306 keys
_VALUES = (("defaultValue", "DefaultValue"), ("actualValue", "ParameterValue"),
           ("lowLimit", "LowLimit"), ("highLimit", "HighLimit"), ("denotation", "Denotation"))


class Objects:
    """Reads the CANopenObjects of one file into ``doc``'s sections."""

    def __init__(self, doc: XddFile, params: dict, types: dict):
        self.doc, self.params, self.types = doc, params, types
        self.seen: dict[int, int] = {}       # index -> line of its first CANopenObject

    def error(self, message, line, index=None, sub=None, *, rule, hint=""):
        self.doc.problem(ERROR, message, line, index, sub, rule=rule, hint=hint)

    # -- objects and sub-objects -------------------------------------------------------------
    def read(self, el) -> None:
        line = el.sourceline
        idx = self.number(el, "index", 4, "CANopenObject", None)
        if idx is None:
            return
        if idx in self.seen:
            self.error(f"0x{idx:04X} is given twice (first at line {self.seen[idx]}); the "
                       "first is read", line, idx, rule="XDD014",
                       hint="remove one of them; dcf2bin does not guess which is meant")
            return
        self.seen[idx] = line
        subs = [c for c in el if local(c.tag) == "CANopenSubObject"]
        param = self.parameter(el, f"0x{idx:04X}", idx, None)
        props = self.doc.specifics.get((idx, None), {})
        target = self.doc.disabled if props.get("CO_disabled") == "true" else self.doc.sections
        ot = el.get("objectType", "").strip()
        complex_ = bool(subs) or ot in ("8", "9")
        sec = self.entry(el, param, idx, None, var=not complex_)
        target[f"{idx:04x}"] = sec
        seen_subs: dict[int, int] = {}
        for child in subs:
            sub = self.number(child, "subIndex", 2, f"0x{idx:04X}: CANopenSubObject", idx)
            if sub is None:
                continue
            if sub in seen_subs:
                self.error(f"0x{idx:04X}sub{sub:X} is given twice (first at line "
                           f"{seen_subs[sub]}); the first is read", child.sourceline, idx,
                           sub, rule="XDD014",
                           hint="remove one of them; dcf2bin does not guess which is meant")
                continue
            seen_subs[sub] = child.sourceline
            sparam = self.parameter(child, f"0x{idx:04X}sub{sub:X}", idx, sub)
            target[f"{idx:04x}sub{sub:x}"] = self.entry(child, sparam, idx, sub, var=True)

    def number(self, el, attr: str, digits: int, what: str, idx: int | None) -> int | None:
        """An index (4 hex digits) or subindex (2), or None after XDD013."""
        text = el.get(attr)
        if text is not None and _HEX[digits].fullmatch(text.strip()):
            return int(text, 16)
        said = "has no " + attr if text is None else f"{attr}=\"{text}\" is not {digits} hex digits"
        self.error(f"{what} {said}; it is not read", el.sourceline, idx, rule="XDD013",
                   hint=f"{attr} is {digits} hex digits, as in {'1018' if digits == 4 else '01'}")
        return None

    def parameter(self, el, label: str, idx: int, sub: int | None):
        """The parameter ``uniqueIDRef`` names (None: none named, or XDD010); its
        description and properties go into the specifics."""
        ref = el.get("uniqueIDRef")
        if ref is None:
            return None
        param = self.params.get(ref)
        if param is None:
            self.error(f"{label}: uniqueIDRef=\"{ref}\" names no parameter of the "
                       "parameterList", el.sourceline, idx, sub, rule="XDD010",
                       hint="add the parameter, or correct the reference")
            self.doc.follows(idx, sub, "DCF031", "DCF033")
            return None
        spec = {}
        for child in param:
            name = local(child.tag)
            if name == "property" and child.get("name"):
                spec[child.get("name")] = child.get("value", "")
            elif name in ("description", "label") and (text := (child.text or "").strip()):
                if name == "description" or "description" not in spec:
                    spec["description"] = text
        if spec:
            self.doc.specifics.setdefault((idx, sub), {}).update(spec)
        return param

    # -- one entry ---------------------------------------------------------------------------
    def entry(self, el, param, idx: int, sub: int | None, *, var: bool):
        """The section of one object or sub-object: its attributes, then what its parameter
        adds (the attribute wins, XDD012 when they differ)."""
        line = el.sourceline
        label = f"0x{idx:04X}" if sub is None else f"0x{idx:04X}sub{sub:X}"
        own = self.attributes(el, label, idx, sub)
        if param is not None:
            said = self.from_parameter(param, label, idx, sub, var, own)
            for key, (value, pline, shown) in said.items():
                mine = own.get(key)
                if mine is None:
                    own[key] = (value, pline, shown)
                elif not _same(key, mine[0], value):
                    self.doc.problem(
                        WARNING, f"{label}: the {local(el.tag)} says {mine[2]} and its "
                        f"parameter {param.get('uniqueID')} (line {pline}) says {shown}; the "
                        f"{local(el.tag)}'s attribute is read", line, idx, sub, rule="XDD012",
                        hint="make the attribute and the parameter agree, or drop one")
        sec = section(label[2:6] if sub is None else f"{idx:04X}sub{sub:X}", line)
        for key in _ORDER:
            if key in own:
                add(sec, key, own[key][0], own[key][1])
        return sec

    def attributes(self, el, label: str, idx: int, sub: int | None) -> dict:
        """CiA 306 key -> (value, line, how to show it) from the element's attributes."""
        line, get = el.sourceline, el.get
        out: dict[str, tuple[str, int, str]] = {}
        name = get("name")
        if name is None and (param := self.params.get(get("uniqueIDRef"))) is not None:
            name = " ".join("".join(next((c.itertext() for c in param
                                          if local(c.tag) == "label"), ())).split()) or None
        if name is not None:        # else the parameter's label names it (CANopenEditor)
            out["ParameterName"] = (name, line, "")
        for attr, key in (("objectType", "ObjectType"), ("subNumber", "SubNumber")):
            text = get(attr)
            if text is None:
                continue
            if text.strip().isdigit():      # XML Schema's unsignedByte: decimal
                n = int(text)
                out[key] = (f"0x{n:X}" if key == "ObjectType" else str(n), line, "")
            else:
                self.error(f"{label}: {attr}=\"{text}\" is not a decimal number", line, idx,
                           sub, rule="XDD013", hint=f"{attr} is a decimal number")
        text = get("dataType")
        if text is not None:
            if _HEX[4].fullmatch(text.strip()):
                out["DataType"] = (f"0x{int(text, 16):04X}", line, f"dataType=\"{text}\"")
            else:
                self.untyped(label, f"dataType=\"{text}\" is not 4 hex digits", line, idx, sub)
        text = get("accessType")
        if text is not None:
            if text.strip() in voc.OBJECT_ACCESS:
                out["AccessType"] = (text.strip(), line, f"accessType=\"{text}\"")
            else:
                self.error(f"{label}: accessType=\"{text}\" is none of const, ro, wo, rw",
                           line, idx, sub, rule="XDD013",
                           hint="accessType is const, ro, wo or rw (rwr, rww)")
        for attr, key in _VALUES:
            text = get(attr)
            if text is not None:
                out[key] = (text, line, f"{attr}=\"{text}\"")
        text = get("PDOmapping")
        if text is not None:
            mapped = voc.PDO_MAPPING.get(text.strip())
            if mapped is None:
                self.error(f"{label}: PDOmapping=\"{text}\" is none of no, default, optional, "
                           "TPDO, RPDO", line, idx, sub, rule="XDD013",
                           hint="PDOmapping is no, default, optional, TPDO or RPDO")
            else:
                out["PDOMapping"] = (mapped, line, f"PDOmapping=\"{text}\"")
                if text.strip() != "no":
                    self.doc.specifics.setdefault((idx, sub), {})["PDOmapping"] = text.strip()
        text = get("objFlags")
        if text is not None:
            if re.fullmatch(r"[0-9A-Fa-f]{1,4}", text.strip()):
                out["ObjFlags"] = (f"0x{int(text, 16):X}", line, f"objFlags=\"{text}\"")
            else:
                self.error(f"{label}: objFlags=\"{text}\" is not hex digits", line, idx, sub,
                           rule="XDD013", hint="objFlags is hex digits, as in 0002")
        return out

    def untyped(self, label, said, line, idx, sub) -> None:
        self.error(f"{label}: {said}", line, idx, sub, rule="XDD011",
                   hint="give one of CiA 301's data types (dataType) or IEC 61131's (UDINT, "
                        "...)")
        self.doc.follows(idx, sub, "DCF031")

    def from_parameter(self, param, label, idx, sub, var: bool, own: dict) -> dict:
        """CiA 306 key -> (value, line, how to show it) from a parameter."""
        out: dict[str, tuple[str, int, str]] = {}
        type_el = ref = None
        for child in param:
            name = local(child.tag)
            if name in ("defaultValue", "actualValue") and child.get("value") is not None:
                key = "DefaultValue" if name == "defaultValue" else "ParameterValue"
                v = child.get("value")
                out[key] = (v, child.sourceline, f"{name} \"{v}\"")
            elif name == "allowedValues":
                for r in child.iter():
                    if local(r.tag) in ("minValue", "maxValue") and r.get("value") is not None:
                        key = "LowLimit" if local(r.tag) == "minValue" else "HighLimit"
                        out.setdefault(key, (r.get("value"), r.sourceline,
                                             f"{local(r.tag)} \"{r.get('value')}\""))
            elif name == "denotation":
                text = " ".join("".join(child.itertext()).split())
                if text:
                    out["Denotation"] = (text, child.sourceline, f"denotation \"{text}\"")
            elif name == "dataTypeIDRef":
                ref = child
            elif name and name not in voc.NOT_TYPES and type_el is None:
                type_el = child
        if ref is not None and type_el is None:
            type_el = self.resolve_type(ref, label, idx, sub)
            if type_el is False:       # an array or a struct: the object is not a VAR
                return out
        if type_el is not None:
            default = (own.get("DefaultValue") or out.get("DefaultValue") or ("",))[0]
            code = voc.type_code(local(type_el.tag), default)
            if code is None:
                self.untyped(label, f"<{local(type_el.tag)}> is not a data type dcf2bin knows",
                             type_el.sourceline, idx, sub)
            else:
                out["DataType"] = (f"0x{code:04X}", type_el.sourceline,
                                   f"<{local(type_el.tag)}> (0x{code:04X})")
        if var:
            access = param.get("access", voc.DEFAULT_PARAM_ACCESS).strip()
            mapped = voc.PARAM_ACCESS.get(access)
            if mapped is None:
                self.error(f"{label}: access=\"{access}\" of parameter "
                           f"{param.get('uniqueID')} has no CiA 306 AccessType",
                           param.sourceline, idx, sub, rule="XDD013",
                           hint="access is const, read, write, readWrite, readWriteInput or "
                                "readWriteOutput")
            else:
                out["AccessType"] = (mapped, param.sourceline, f"access \"{access}\"")
        return out

    def resolve_type(self, ref, label, idx, sub):
        """The type element a dataTypeIDRef leads to; False for an array or struct (the
        object's sub-objects have their own types); None after XDD010/XDD011."""
        uid = ref.get("uniqueIDRef")
        target = self.types.get(uid)
        if target is None:
            self.error(f"{label}: dataTypeIDRef uniqueIDRef=\"{uid}\" names no type of the "
                       "dataTypeList", ref.sourceline, idx, sub, rule="XDD010",
                       hint="add the type to the dataTypeList, or correct the reference")
            self.doc.follows(idx, sub, "DCF031")
            return None
        if local(target.tag) in ("array", "struct"):
            return False
        for child in target:        # a derived type or an enum: its base type
            if local(child.tag) in voc.IEC_TYPES:
                return child
        self.untyped(label, f"the type {uid} (line {target.sourceline}) has no IEC 61131 "
                     "base type", ref.sourceline, idx, sub)
        return None


def _same(key: str, a: str, b: str) -> bool:
    """Whether an attribute and a parameter say the same (numbers by value)."""
    if key == "AccessType":
        return voc.SDO_ACCESS.get(a) == voc.SDO_ACCESS.get(b)
    if a.strip() == b.strip():
        return True
    try:
        return values.parse_int(a.strip()) == values.parse_int(b.strip())
    except values.ValueProblem:
        return False
