"""The short ways ``objects.Objects`` makes an entry's section (``_Direct``, a mixin of
it), and ``_Param``, what a parameter says. An object whose attributes and parameter
cannot disagree -- no parameter, or none of the attributes a parameter also says -- needs
no comparison, so its section is made straight in CiA 306's key order (``quick``), and the
common CANopenEditor object with nothing wrong in it without even the general attribute
checks (``editor``). ``Straight`` takes a whole CANopenEditor object with its sub-objects
in one pass before ``Objects`` sees it, and gives its sections one shared template per
shape (``document.SharedXmlSection``), as the INI reader does: the builder then builds one
entry per shape and copies it for its like (``model.build_object``). All give exactly the
sections, lines, specifics and findings ``Objects.read`` gives (benchmarks/xdd.py measures
what they save; tests/test_xdd*.py hold them to it, and so did a comparison with the
reader without them on the corpus, on every file convert writes of it and on random
mutations of those).
"""
from __future__ import annotations

from operator import itemgetter
from typing import Any

from dcf2bin.formats.xdd import vocabulary as voc
from dcf2bin.formats.xdd.document import SharedXmlSection, XmlSection
from dcf2bin.formats.xdd.markup import local

# the keys of an entry in the order a section lists them, with their lower-case names
_ORDER = tuple((k, k.lower()) for k in (
    "ParameterName", "ObjectType", "SubNumber", "DataType", "AccessType", "DefaultValue",
    "ParameterValue", "LowLimit", "HighLimit", "PDOMapping", "ObjFlags", "Denotation"))
# plain attributes of CANopenObject/CANopenSubObject -> CiA 306 keys
_VALUES = {"defaultValue": "DefaultValue", "actualValue": "ParameterValue",
           "lowLimit": "LowLimit", "highLimit": "HighLimit", "denotation": "Denotation"}
# the attributes that need a look of their own (all but index, name, uniqueIDRef, ...)
_CHECKED = frozenset({"objectType", "subNumber", "dataType", "accessType", "PDOmapping",
                      "objFlags", *_VALUES})
# the attributes whose key a parameter says too (DataType, AccessType, the values)
_SAID = frozenset({"dataType", "accessType", *_VALUES})
# the attributes of a CANopenEditor object besides its name and references
_PLAIN = frozenset({"objectType", "subNumber", "PDOmapping"})
# (attribute, its text) -> (CiA 306 key, value, the raw PDOmapping kept in the specifics)
_PLAIN_VALUES = {("objectType", str(n)): ("ObjectType", "objecttype", f"0x{n:X}", None)
                 for n in range(10)}
_PLAIN_VALUES.update({("subNumber", str(n)): ("SubNumber", "subnumber", str(n), None)
                      for n in range(256)})
_PLAIN_VALUES.update({("PDOmapping", k): ("PDOMapping", "pdomapping", v, None if k == "no"
                                          else k) for k, v in voc.PDO_MAPPING.items()})
# what ``editor`` takes: the attributes of a CANopenEditor object
_EDITOR = frozenset({"index", "subIndex", "name", "objectType", "subNumber", "PDOmapping",
                     "uniqueIDRef"})
# an IEC 61131 type element's tag (in CiA 311's namespaces or none) and whether the entry
# has a default value -> its CiA 301 code as DataType says it
_CODES = {(f"{ns}{name}", has): f"0x{voc.type_code(name, 'x' if has else ''):04X}"
          for name in voc.IEC_TYPES for has in (False, True)
          for ns in ("", "{http://www.canopen.org/xml/1.0}", "{http://www.canopen.org/xml/1.1}")}
# parameter@access exactly as CANopenEditor writes it (absent: XML Schema's "read")
_PARAM_ACCESS = {**voc.PARAM_ACCESS, None: voc.PARAM_ACCESS[voc.DEFAULT_PARAM_ACCESS]}
_PARAM_VALUES = (("DefaultValue", "defaultvalue"), ("ParameterValue", "parametervalue"),
                 ("LowLimit", "lowlimit"), ("HighLimit", "highlimit"))
_ORDERS: dict = {}       # the keys of an entry as found -> the same in CiA 306's order
# what a child element of a parameter is to _Param, by its tag (its name in any namespace)
(_LABEL, _DESCRIPTION, _DEFAULT, _ACTUAL, _PROPERTY, _ALLOWED, _DENOTATION, _REF, _OTHER,
 _TYPE, _NAMELESS) = range(11)
_KINDS = {name: _OTHER for name in voc.NOT_TYPES}
_KINDS.update({"label": _LABEL, "description": _DESCRIPTION, "defaultValue": _DEFAULT,
               "actualValue": _ACTUAL, "property": _PROPERTY, "allowedValues": _ALLOWED,
               "denotation": _DENOTATION, "dataTypeIDRef": _REF})
_KIND_NAMES = {kind: name for name, kind in _KINDS.items() if kind != _OTHER}
_TAG_KINDS: dict = {}


def _tag_kind(tag) -> int:
    name = local(tag)
    kind = _KINDS.get(name, _TYPE if name else _NAMELESS)
    if len(_TAG_KINDS) < 4096:
        _TAG_KINDS[tag] = kind
    return kind


class _Direct:
    """``editor`` and ``quick``; the rest of the reader is ``objects.Objects``."""

    def editor(self, attrs: dict, line, param, idx: int, sub: int | None, var: bool):
        """``entry`` of the common CANopenEditor object (a name, objectType, subNumber,
        PDOmapping and a parameter with an IEC 61131 type), when nothing in it is wrong:
        the section made straight in CiA 306's key order. None -- having changed nothing
        -- for anything else, which ``quick`` reads with its findings."""
        get = attrs.get
        plain = []
        for attr in ("objectType", "subNumber", "PDOmapping"):
            text = get(attr)
            if text is not None:
                got = _PLAIN_VALUES.get((attr, text))
                if got is None:
                    return None
                plain.append(got)
        said = param.said
        type_el = param.type_el
        code = None
        if type_el is not None:
            default = said.get("DefaultValue")
            code = _CODES.get((type_el.tag, bool(default and default[0])))
            if code is None:
                return None
        elif param.ref is not None:     # an array or a struct: its sub-objects are typed
            target = self.types.get(param.ref.get("uniqueIDRef"))
            if target is None or target.tag.rpartition("}")[2] not in ("array", "struct"):
                return None
            var = False                 # (as from_parameter: no access of its own)
        mapped = None
        if var:
            el = param.el
            mapped = _PARAM_ACCESS.get(el.get("access"))
            if mapped is None:
                return None
        values: dict = {}
        lines: dict = {}
        name = get("name")
        if name is None:
            name = param.label()
        if name is not None:
            values["parametername"], lines["parametername"] = name, ("ParameterName", line)
        pdo = None
        for key, low, value, kept in plain:
            if key == "PDOMapping":
                pdo = (value, kept)
                continue
            values[low], lines[low] = value, (key, line)
        if code is not None:
            values["datatype"] = code
            lines["datatype"] = ("DataType", type_el.sourceline or line)
        if mapped is not None:
            values["accesstype"], lines["accesstype"] = mapped, ("AccessType",
                                                                 el.sourceline or line)
        if said:
            for key, low in _PARAM_VALUES:
                got = said.get(key)
                if got is not None:
                    values[low], lines[low] = got[0], (key, got[1] or line)
        if pdo is not None:
            values["pdomapping"], lines["pdomapping"] = pdo[0], ("PDOMapping", line)
            if pdo[1]:
                self.doc.specifics.setdefault((idx, sub), {})["PDOmapping"] = pdo[1]
        got = said.get("Denotation") if said else None
        if got is not None:
            values["denotation"], lines["denotation"] = got[0], ("Denotation", got[1] or line)
        sec = XmlSection.__new__(XmlSection)
        sec.name = f"{idx:04X}" if sub is None else f"{idx:04X}sub{sub:X}"
        sec.line, sec._keys, sec.values, sec._lines = line, None, values, lines
        return sec

    def quick(self, attrs: dict, line, param, idx: int, sub: int | None, var: bool):
        """``entry`` where the attributes and the parameter cannot disagree (no parameter,
        or none of the attributes a parameter also says): the same section, built
        straight in CiA 306's key order, the words of a finding made only for one."""
        label = f"0x{idx:04X}" if sub is None else f"0x{idx:04X}sub{sub:X}"
        checked = attrs.keys() & _CHECKED
        if checked - _PLAIN or (param is None and "name" not in attrs):
            own = self.attributes(attrs, line, label, idx, sub, param)
        else:                           # name, objectType, subNumber, PDOmapping: common
            own = {}
            name = attrs.get("name")
            if name is None:
                name = param.label()
            if name is not None:
                own["ParameterName"] = (name, line, None)
            if checked:
                for attr in ("objectType", "subNumber", "PDOmapping"):
                    text = attrs.get(attr)
                    if text is None:
                        continue
                    got = _PLAIN_VALUES.get((attr, text))
                    if got is None:
                        own = self.attributes(attrs, line, label, idx, sub, param)
                        break
                    own[got[0]] = (got[2], line, (0, attr, text))
                    if attr == "PDOmapping" and got[3]:
                        self.doc.specifics.setdefault((idx, sub), {})["PDOmapping"] = got[3]
        if param is not None:
            own.update(self.from_parameter(param, label, idx, sub, var, own))
        sec = XmlSection.__new__(XmlSection)
        sec.name = label[2:6] if sub is None else label[2:]
        sec.line, sec._keys = line, None
        keys = own.keys()
        order = _ORDERS.get(tuple(keys))
        if order is None:
            order = _ORDERS[tuple(keys)] = tuple((k, low) for k, low in _ORDER if k in keys)
        sec.values = {low: own[key][0] for key, low in order}
        sec._lines = {low: (key, own[key][1] or line) for key, low in order}
        return sec


class _Param:
    """What one ``parameter`` says, from one walk over its children: ``spec`` (its
    description and properties), ``said`` (CiA 306 key -> (value, line, how to show it)
    for its values, limits and denotation, in the order they stand), its type element or
    ``dataTypeIDRef`` and its first label."""
    __slots__ = ("el", "spec", "said", "type_el", "ref", "first_label")

    def __init__(self, el):
        type_el = ref = first_label = None
        spec: dict = {}
        said: dict = {}
        kinds = _TAG_KINDS
        for child in el:
            tag = child.tag
            kind = kinds.get(tag)
            if kind is None:
                kind = _tag_kind(tag)
            if kind == _TYPE:           # not one of a parameter's own elements: its type
                if type_el is None:
                    type_el = child
            elif kind == _DEFAULT or kind == _ACTUAL:
                v = child.get("value")
                if v is not None:
                    said["DefaultValue" if kind == _DEFAULT else "ParameterValue"] = (
                        v, child.sourceline, (1, _KIND_NAMES[kind], v))
            elif kind == _LABEL or kind == _DESCRIPTION:
                if kind == _LABEL and first_label is None:
                    first_label = child
                text = child.text
                if text:
                    text = text.strip()
                    if text and (kind == _DESCRIPTION or "description" not in spec):
                        spec["description"] = text
            elif kind == _PROPERTY:
                name = child.get("name")
                if name:
                    spec[name] = child.get("value", "")
            elif kind == _ALLOWED:
                for r in child.iter():
                    rname = local(r.tag)
                    if rname in ("minValue", "maxValue") and r.get("value") is not None:
                        key = "LowLimit" if rname == "minValue" else "HighLimit"
                        said.setdefault(key, (r.get("value"), r.sourceline,
                                              (1, rname, r.get("value"))))
            elif kind == _DENOTATION:
                text = " ".join("".join(child.itertext()).split())
                if text:
                    said["Denotation"] = (text, child.sourceline, (1, "denotation", text))
            elif kind == _REF:
                ref = child
        self.el, self.type_el, self.ref, self.first_label = el, type_el, ref, first_label
        self.spec, self.said = spec, said

    def label(self) -> str | None:
        """The name its first label gives (a CANopenEditor object has no name of its own)."""
        if self.first_label is None:
            return None
        return " ".join("".join(self.first_label.itertext()).split()) or None


# -- one pass over a whole CANopenEditor object ------------------------------------------------

_HEX_DIGITS = "0123456789abcdefABCDEF"
# a subIndex as CANopenEditor writes it (2 hex digits, either case) -> the number
_SUB_TEXT = {a + b: int(a + b, 16) for a in _HEX_DIGITS for b in _HEX_DIGITS}
_SUB_CANON = [f"sub{n:x}" for n in range(256)]
# the attributes ``Straight`` reads, in the order ``Straight.attributes`` gives them
_ATTRS = ("index", "subIndex", "name", "objectType", "subNumber", "PDOmapping",
          "uniqueIDRef")
_ARRAYS = ("array", "struct")
_new = object.__new__


class Straight:
    """``Objects.read`` of a whole CANopenObject whose every part is the common
    CANopenEditor shape -- the object and each sub-object with the attributes ``editor``
    takes, their numbers as CANopenEditor writes them, each parameter found and typed --
    in one pass, with nothing looked at twice: what ``read``, ``parameter`` and
    ``editor`` give, and no finding (where one could arise, ``read`` says False, having
    changed nothing, and ``Objects.read`` takes the object). Its sections share their
    templates (``document.SharedXmlSection``): one per shape of the file's entries."""

    def __init__(self, reader):
        self.reader = reader
        self.doc, self.params, self.types = reader.doc, reader.params, reader.types
        self.plans: dict[tuple, Any] = {}      # attribute names -> their getter (None: not taken)
        self.shapes: dict[tuple, tuple] = {}           # an entry's shape -> its template
        self.indexes: dict[str, int] = {}              # an index's text -> the number

    def read(self, el) -> bool:
        got = self.attributes(el)
        if got is None:
            return False
        attrs, line = got
        idx_text = attrs[0]
        idx = self.indexes.get(idx_text)
        if idx is None:
            if idx_text is None or len(idx_text) != 4 or idx_text.strip(_HEX_DIGITS):
                return False
            idx = self.indexes[idx_text] = int(idx_text, 16)
        if idx in self.reader.seen:
            return False
        subs = list(el.iterchildren("{*}CANopenSubObject"))
        ot = attrs[3]
        canon = f"{idx:04x}"
        head = self.entry(attrs, line, canon, None, not subs and ot != "8" and ot != "9")
        if head is None:
            return False
        made = [head]
        taken: set = set()
        for child in subs:
            got = self.attributes(child)
            if got is None:
                return False
            cattrs, cline = got
            sub = _SUB_TEXT.get(cattrs[1])
            if sub is None or sub in taken:
                return False
            taken.add(sub)
            part = self.entry(cattrs, cline, canon + _SUB_CANON[sub], sub, True)
            if part is None:
                return False
            made.append(part)
        # nothing can be wrong: the sections, specifics and line as Objects.read keeps them
        self.reader.seen[idx] = line
        disabled = head[2] is not None and head[2].get("CO_disabled") == "true"
        target = self.doc.disabled if disabled else self.doc.sections
        specifics = self.doc.specifics
        for sec, sub, spec, kept in made:
            target[sec.canon] = sec
            if spec or kept:
                mine = specifics.setdefault((idx, sub), {})
                if spec:
                    mine.update(spec)
                if kept:
                    mine["PDOmapping"] = kept
        return True

    def attributes(self, el):
        """(the values of ``_ATTRS``, line) of an element with no attribute but those."""
        names = tuple(el.keys())
        plan = self.plans.get(names, False)
        if plan is False:       # each of _ATTRS at its place, an absent one at the end
            plan = self.plans[names] = (
                itemgetter(*(names.index(a) if a in names else len(names) for a in _ATTRS))
                if _EDITOR.issuperset(names) else None)
        if plan is None:
            return None
        values = el.values()
        values.append(None)
        return plan(values), el.sourceline

    def entry(self, attrs, line, canon: str, sub, var: bool):
        """(section, sub, the parameter's specifics, the raw PDOmapping kept) of one
        object or sub-object; None where ``editor`` would not take it."""
        ref = attrs[6]
        pel = self.params.get(ref) if ref is not None else None
        if pel is None:
            return None
        got = _walk(pel)
        if got is None:                 # limits or a denotation: _Param reads them
            param = _Param(pel)
            said = param.said
            got = (param.type_el, param.ref, param.first_label, param.spec,
                   [(low, said[key][0], said[key][1]) for key, low in _PARAM_VALUES
                    if key in said], said.get("Denotation"))
        type_el, ref_el, first_label, spec, values, denotation = got
        code = None
        if type_el is not None:         # (a default value makes a BITSTRING an OCTET_STRING)
            code = _CODES.get((type_el.tag, bool(values and values[0][0] == "defaultvalue"
                                                 and values[0][1])))
            if code is None:
                return None
        elif ref_el is not None:        # an array or a struct: its sub-objects are typed
            target = self.types.get(ref_el.get("uniqueIDRef"))
            if target is None or target.tag.rpartition("}")[2] not in _ARRAYS:
                return None
            var = False
        mapped = None
        if var:
            mapped = _PARAM_ACCESS.get(pel.get("access"))
            if mapped is None:
                return None
        name = attrs[2]
        if name is None and first_label is not None:
            name = " ".join("".join(first_label.itertext()).split()) or None
        # the template's keys and values, flat (the names' values left empty), and the
        # line of each key: what ``editor`` makes, in its order
        if name is not None:
            flat, lines = ["parametername", ""], [line]
        else:
            flat, lines = [], []
        for at, attr, low in _PLAIN_ATTRS:      # objectType, subNumber
            text = attrs[at]
            if text is not None:
                plain = _PLAIN_VALUES.get((attr, text))
                if plain is None:
                    return None
                flat += (low, plain[2])
                lines.append(line)
        pdo = kept = None
        text = attrs[5]
        if text is not None:            # PDOmapping, after the parameter's keys
            plain = _PLAIN_VALUES.get(("PDOmapping", text))
            if plain is None:
                return None
            pdo, kept = plain[2], plain[3]
        if code is not None:
            flat += ("datatype", code)
            lines.append(type_el.sourceline or line)
        if mapped is not None:
            flat += ("accesstype", mapped)
            lines.append(pel.sourceline or line)
        for low, value, at in values:
            flat += (low, value)
            lines.append(at or line)
        if pdo is not None:
            flat += ("pdomapping", pdo)
            lines.append(line)
        if denotation is not None:
            flat += ("denotation", "")
            lines.append(denotation[1] or line)
        shape = tuple(flat)
        rest = self.shapes.get(shape)
        if rest is None:
            rest = self.shapes[shape] = dict(zip(shape[::2], shape[1::2]))
        sec = _new(SharedXmlSection)
        sec.canon, sec.line, sec.param_name, sec.rest = canon, line, name, rest
        sec.denotation = None if denotation is None else denotation[0]
        sec.linev, sec._values, sec._keys = tuple(lines), None, None
        return sec, sub, spec, kept


_PLAIN_ATTRS = ((3, "objectType", "objecttype"), (4, "subNumber", "subnumber"))


def _walk(pel):
    """What ``_Param`` reads of a parameter -- (type element, dataTypeIDRef, first label,
    specifics, [(key, value, line)] of its default and actual value, None) -- in one walk
    for the elements a CANopenEditor parameter has; None for one with limits or a
    denotation (``_Param`` reads those)."""
    type_el = ref_el = first_label = default = actual = None
    spec: dict = {}
    kinds = _TAG_KINDS
    for child in pel:
        tag = child.tag
        kind = kinds.get(tag)
        if kind is None:
            kind = _tag_kind(tag)
        if kind == _TYPE:
            if type_el is None:
                type_el = child
        elif kind == _DEFAULT:
            if child.get("value") is not None:
                default = child
        elif kind == _LABEL or kind == _DESCRIPTION:
            if kind == _LABEL and first_label is None:
                first_label = child
            text = child.text
            if text:
                text = text.strip()
                if text and (kind == _DESCRIPTION or "description" not in spec):
                    spec["description"] = text
        elif kind == _PROPERTY:
            name = child.get("name")
            if name:
                spec[name] = child.get("value", "")
        elif kind == _ACTUAL:
            if child.get("value") is not None:
                actual = child
        elif kind == _REF:
            ref_el = child
        elif kind != _OTHER and kind != _NAMELESS:
            return None
    values = []
    if default is not None:
        values.append(("defaultvalue", default.get("value"), default.sourceline))
    if actual is not None:
        values.append(("parametervalue", actual.get("value"), actual.sourceline))
    return type_el, ref_el, first_label, spec, values, None
