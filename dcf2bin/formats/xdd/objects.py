"""The object dictionary of a CiA 311 file as CiA 306 sections: one section per
``CANopenObject`` and per ``CANopenSubObject``, its keys from the element's own attributes
(vendor style, CiA 311 v1.0: ``dataType``, ``accessType``, ``defaultValue``,
``actualValue``, ...) and from the ``parameter`` its ``uniqueIDRef`` names (CANopenEditor
style: the type as an IEC 61131 element or a ``dataTypeIDRef``, ``access``,
``defaultValue``, ``allowedValues``, ``denotation``, CANopenNode's ``property``s).

The style is not told by namespace or version (real files mix them): every object is read
both ways, and where both say something the object's own attribute wins (XDD012 says so
when they disagree). Every key keeps the line of the element that gave it.

Lean by measurement (benchmarks/xdd.py): an element's attributes are taken in one call
(``items``) and only those present are looked at, a parameter's children are walked once,
and what a diagnostic would show of a value is worked out only when one is written.
"""
from __future__ import annotations

import re

from dcf2bin import values
from dcf2bin.diagnostics import Severity
from dcf2bin.formats.xdd import vocabulary as voc
from dcf2bin.formats.xdd.direct import _CHECKED, _EDITOR, _ORDER, _SAID, _VALUES, _Direct, _Param
from dcf2bin.formats.xdd.document import XddFile, XmlSection
from dcf2bin.formats.xdd.markup import _LOCAL, local

ERROR, WARNING, INFO = Severity.ERROR, Severity.WARNING, Severity.INFO
_HEX = {2: re.compile(r"[0-9A-Fa-f]{2}"), 4: re.compile(r"[0-9A-Fa-f]{4}")}
_FLAGS = re.compile(r"[0-9A-Fa-f]{1,4}")
_NUMBERS: dict[str, int] = {}       # an index's or subindex's text, as read before
_TWICE = "remove one of them; dcf2bin does not guess which is meant"


def _shown(how) -> str:
    """How a diagnostic shows a value: (0, attr, text) -> attr="text"; (1, element, text)
    -> element "text"; (2, element, code) -> <element> (0xCODE)."""
    kind, a, b = how
    if kind == 0:
        return f'{a}="{b}"'
    if kind == 1:
        return f'{a} "{b}"'
    return f"<{a}> (0x{b:04X})"


class Objects(_Direct):
    """Reads the CANopenObjects of one file into ``doc``'s sections."""

    def __init__(self, doc: XddFile, params: dict, types: dict):
        self.doc, self.params, self.types = doc, params, types
        self.seen: dict[int, int] = {}       # index -> line of its first CANopenObject

    def error(self, message, line, index=None, sub=None, *, rule, hint=""):
        self.doc.problem(ERROR, message, line, index, sub, rule=rule, hint=hint)

    # -- objects and sub-objects -------------------------------------------------------------
    def read(self, el) -> None:
        line = el.sourceline
        attrs = dict(el.items())
        idx = self.number(attrs.get("index"), line, "index", 4, "CANopenObject", None)
        if idx is None:
            return
        if idx in self.seen:
            self.error(f"0x{idx:04X} is given twice (first at line {self.seen[idx]}); the "
                       "first is read", line, idx, rule="XDD014", hint=_TWICE)
            return
        self.seen[idx] = line
        subs = list(el.iterchildren("{*}CANopenSubObject"))
        param = self.parameter(attrs, line, idx, None)
        props = self.doc.specifics.get((idx, None), {})
        target = self.doc.disabled if props.get("CO_disabled") == "true" else self.doc.sections
        ot = attrs.get("objectType", "").strip()
        complex_ = bool(subs) or ot in ("8", "9")
        target[f"{idx:04x}"] = self.entry(el, attrs, line, param, idx, None,
                                          var=not complex_)
        seen_subs: dict[int, int] = {}
        for child in subs:
            cline = child.sourceline
            cattrs = dict(child.items())
            sub = self.number(cattrs.get("subIndex"), cline, "subIndex", 2,
                              f"0x{idx:04X}: CANopenSubObject", idx)
            if sub is None:
                continue
            if sub in seen_subs:
                self.error(f"0x{idx:04X}sub{sub:X} is given twice (first at line "
                           f"{seen_subs[sub]}); the first is read", cline, idx, sub,
                           rule="XDD014", hint=_TWICE)
                continue
            seen_subs[sub] = cline
            sparam = self.parameter(cattrs, cline, idx, sub)
            target[f"{idx:04x}sub{sub:x}"] = self.entry(child, cattrs, cline, sparam, idx, sub,
                                                        var=True)

    def number(self, text, line, attr: str, digits: int, what: str,
               idx: int | None) -> int | None:
        """An index (4 hex digits) or subindex (2), or None after XDD013."""
        known = _NUMBERS.get(text)
        if known is not None and len(text) == digits:
            return known
        if text is not None and _HEX[digits].fullmatch(text.strip()):
            if len(_NUMBERS) < 4096:
                _NUMBERS[text] = int(text, 16)
            return int(text, 16)
        said = "has no " + attr if text is None else f"{attr}=\"{text}\" is not {digits} hex digits"
        self.error(f"{what} {said}; it is not read", line, idx, rule="XDD013",
                   hint=f"{attr} is {digits} hex digits, as in {'1018' if digits == 4 else '01'}")
        return None

    def parameter(self, attrs: dict, line, idx: int, sub: int | None):
        """The parameter ``uniqueIDRef`` names, read in one walk over its children
        (``_Param``); None: none named, or XDD010. Its description and properties go into
        the specifics."""
        ref = attrs.get("uniqueIDRef")
        if ref is None:
            return None
        el = self.params.get(ref)
        if el is None:
            label = f"0x{idx:04X}" if sub is None else f"0x{idx:04X}sub{sub:X}"
            self.error(f"{label}: uniqueIDRef=\"{ref}\" names no parameter of the "
                       "parameterList", line, idx, sub, rule="XDD010",
                       hint="add the parameter, or correct the reference")
            self.doc.follows(idx, sub, "DCF031", "DCF033")
            return None
        param = _Param(el)
        if param.spec:
            self.doc.specifics.setdefault((idx, sub), {}).update(param.spec)
        return param

    # -- one entry ---------------------------------------------------------------------------
    def entry(self, el, attrs: dict, line, param, idx: int, sub: int | None, *, var: bool):
        """The section of one object or sub-object: its attributes, then what its parameter
        adds (the attribute wins, XDD012 when they differ)."""
        if param is None or not attrs.keys() & _SAID:
            if param is not None and attrs.keys() <= _EDITOR:
                sec = self.editor(attrs, line, param, idx, sub, var)
                if sec is not None:
                    return sec
            return self.quick(attrs, line, param, idx, sub, var)
        label = f"0x{idx:04X}" if sub is None else f"0x{idx:04X}sub{sub:X}"
        own = self.attributes(attrs, line, label, idx, sub, param)
        if param is not None:
            said = self.from_parameter(param, label, idx, sub, var, own)
            for key, got in said.items():
                mine = own.get(key)
                if mine is None:
                    own[key] = got
                elif not _same(key, mine[0], got[0]):
                    tag = _LOCAL.get(el.tag) or local(el.tag)
                    self.doc.problem(
                        WARNING, f"{label}: the {tag} says {_shown(mine[2])} and its "
                        f"parameter {param.el.get('uniqueID')} (line {got[1]}) says "
                        f"{_shown(got[2])}; the {tag}'s attribute is read", line, idx, sub,
                        rule="XDD012", hint="make the attribute and the parameter agree, "
                                            "or drop one")
        sec = XmlSection.__new__(XmlSection)
        sec.name = label[2:6] if sub is None else f"{idx:04X}sub{sub:X}"
        sec.line, sec._keys = line, None
        sec.values = {low: own[key][0] for key, low in _ORDER if key in own}
        sec._lines = {low: (key, own[key][1] or line) for key, low in _ORDER if key in own}
        return sec

    def attributes(self, attrs: dict, line, label: str, idx: int, sub: int | None,
                   param) -> dict:
        """CiA 306 key -> (value, line, how to show it) from the element's attributes."""
        out: dict[str, tuple] = {}
        name = attrs.get("name")
        if name is None and param is not None:
            name = param.label()
        if name is not None:        # else the parameter's label names it (CANopenEditor)
            out["ParameterName"] = (name, line, None)
        checked = attrs.keys() & _CHECKED
        if not checked:
            return out
        for attr, key in (("objectType", "ObjectType"), ("subNumber", "SubNumber")):
            text = attrs.get(attr)
            if text is None:
                continue
            if text.strip().isdigit():      # XML Schema's unsignedByte: decimal
                n = int(text)
                out[key] = (f"0x{n:X}" if key == "ObjectType" else str(n), line, None)
            else:
                self.error(f"{label}: {attr}=\"{text}\" is not a decimal number", line, idx,
                           sub, rule="XDD013", hint=f"{attr} is a decimal number")
        if "dataType" in checked:
            text = attrs["dataType"]
            if _HEX[4].fullmatch(text.strip()):
                out["DataType"] = (f"0x{int(text, 16):04X}", line, (0, "dataType", text))
            else:
                self.untyped(label, f"dataType=\"{text}\" is not 4 hex digits", line, idx, sub)
        if "accessType" in checked:
            text = attrs["accessType"]
            if text.strip() in voc.OBJECT_ACCESS:
                out["AccessType"] = (text.strip(), line, (0, "accessType", text))
            else:
                self.error(f"{label}: accessType=\"{text}\" is none of const, ro, wo, rw",
                           line, idx, sub, rule="XDD013",
                           hint="accessType is const, ro, wo or rw (rwr, rww)")
        for attr, key in _VALUES.items():
            text = attrs.get(attr)
            if text is not None:
                out[key] = (text, line, (0, attr, text))
        if "PDOmapping" in checked:
            self.pdo_mapping(attrs["PDOmapping"], out, line, label, idx, sub)
        if "objFlags" in checked:
            text = attrs["objFlags"]
            if _FLAGS.fullmatch(text.strip()):
                out["ObjFlags"] = (f"0x{int(text, 16):X}", line, (0, "objFlags", text))
            else:
                self.error(f"{label}: objFlags=\"{text}\" is not hex digits", line, idx, sub,
                           rule="XDD013", hint="objFlags is hex digits, as in 0002")
        return out

    def pdo_mapping(self, text: str, out: dict, line, label, idx, sub) -> None:
        mapped = voc.PDO_MAPPING.get(text.strip())
        if mapped is None:
            self.error(f"{label}: PDOmapping=\"{text}\" is none of no, default, optional, "
                       "TPDO, RPDO", line, idx, sub, rule="XDD013",
                       hint="PDOmapping is no, default, optional, TPDO or RPDO")
            return
        out["PDOMapping"] = (mapped, line, (0, "PDOmapping", text))
        if text.strip() != "no":
            self.doc.specifics.setdefault((idx, sub), {})["PDOmapping"] = text.strip()

    def untyped(self, label, said, line, idx, sub) -> None:
        self.error(f"{label}: {said}", line, idx, sub, rule="XDD011",
                   hint="give one of CiA 301's data types (dataType) or IEC 61131's (UDINT, "
                        "...)")
        self.doc.follows(idx, sub, "DCF031")

    def from_parameter(self, param, label, idx, sub, var: bool, own: dict) -> dict:
        """CiA 306 key -> (value, line, how to show it) from a parameter."""
        out = dict(param.said)
        type_el = param.type_el
        if param.ref is not None and type_el is None:
            type_el = self.resolve_type(param.ref, label, idx, sub)
            if type_el is False:       # an array or a struct: the object is not a VAR
                return out
        if type_el is not None:
            default = (own.get("DefaultValue") or out.get("DefaultValue") or ("",))[0]
            tag = _LOCAL.get(type_el.tag) or local(type_el.tag)
            code = voc.type_code(tag, default)
            if code is None:
                self.untyped(label, f"<{tag}> is not a data type dcf2bin knows",
                             type_el.sourceline, idx, sub)
            else:
                out["DataType"] = (f"0x{code:04X}", type_el.sourceline, (2, tag, code))
        if var:
            el = param.el
            access = el.get("access", voc.DEFAULT_PARAM_ACCESS).strip()
            mapped = voc.PARAM_ACCESS.get(access)
            if mapped is None:
                self.error(f"{label}: access=\"{access}\" of parameter "
                           f"{el.get('uniqueID')} has no CiA 306 AccessType",
                           el.sourceline, idx, sub, rule="XDD013",
                           hint="access is const, read, write, readWrite, readWriteInput or "
                                "readWriteOutput")
            else:
                out["AccessType"] = (mapped, el.sourceline, (1, "access", access))
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
