"""The two short ways ``objects.Objects`` makes an entry's section (a mixin of it): an
object whose attributes and parameter cannot disagree -- no parameter, or none of the
attributes a parameter also says -- needs no comparison, so its section is made straight
in CiA 306's key order (``quick``), and the common CANopenEditor object with nothing wrong
in it without even the general attribute checks (``editor``). Both give exactly the
section, lines, specifics and findings ``Objects.entry`` gives (benchmarks/xdd.py measures
what they save; tests/test_xdd*.py and the reader's own findings hold them to it).
"""
from __future__ import annotations

from dcf2bin.formats.xdd import vocabulary as voc
from dcf2bin.formats.xdd.document import XmlSection

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
# a parameter's own elements (any other is its type) -> what _Param does with it
_CHILD_KINDS = {name: 6 for name in voc.NOT_TYPES}
_CHILD_KINDS.update({"label": 0, "description": 0, "defaultValue": 1, "actualValue": 1,
                     "property": 2, "allowedValues": 3, "denotation": 4, "dataTypeIDRef": 5})
_ORDERS: dict = {}       # the keys of an entry as found -> the same in CiA 306's order


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
