"""A Device as a CiA 311 v1.1 file: an XDD (a device's description) or an XDC (the same,
configured: ``actualValue``s, denotations and ``deviceCommissioning``).
``formats.xdd.dump`` is the entry point.

The shape is CiA 311's ISO 15745 frame: a device profile (``ProfileHeader``, then a
``ProfileBody`` of type ``ProfileBody_Device_CANopen`` with ``DeviceIdentity`` and the
``ApplicationProcess``' ``parameterList``) and a communication network profile
(``ProfileBody_CommunicationNetwork_CANopen``: ``ApplicationLayers`` with the
``CANopenObjectList`` and ``dummyUsage``, ``TransportLayers`` with the baud rates,
``NetworkManagement`` with the general and master features and, in an XDC, the
``deviceCommissioning``).

Every ``CANopenObject``/``CANopenSubObject`` says its own data type, access, values,
limits, PDO mapping and flags as attributes, the form CiA 311 gives every object (and the
one vendors' tools read). A ``parameter`` is written only for what attributes cannot say:
a description, CANopenNode's ``property`` settings, and the access ``rwr``/``rww``
(``readWriteInput``/``readWriteOutput``), which the ``accessType`` attribute has no word
for -- the object then names its parameter (``uniqueIDRef``) and has no ``accessType``.
Such a parameter repeats the object's type (an IEC 61131 element, where one gives the
same CiA 301 type back) and its access, so that the reader finds nothing to disagree with.
The objects a CiA 311 source marked ``CO_disabled`` are written back with that property.
"""
from __future__ import annotations

from dcf2bin.formats import written as w
from dcf2bin.formats.written import Losses, Written
from dcf2bin.formats.xdd import vocabulary as voc
from dcf2bin.formats.xdd.writer_header import Header, attr, text

# CiA 306 AccessType -> the accessType attribute (None: it has no word) and parameter@access
ATTR_ACCESS = {"const": "const", "ro": "ro", "wo": "wo", "rw": "rw", "rwr": None, "rww": None}
PARAM_ACCESS = {v: k for k, v in voc.PARAM_ACCESS.items()}
# CiA 301 code -> the IEC 61131 element that reads back as that code
IEC_OF = {code: name for name, code in voc.IEC_TYPES.items()
          if name not in ("CHAR", "BYTE", "WORD", "DWORD", "LWORD", "BITSTRING")}
IEC_OF.update({voc.OCTET_STRING: "BITSTRING", voc.DOMAIN: "BITSTRING"})


def dump(dev, kind: str = "xdd", *, name: str | None = None,
         node_id: int | None = None) -> Written:
    """``dev`` as a CiA 311 v1.1 XDD or (``kind`` "xdc") XDC."""
    losses = Losses(dev)
    xdc = kind == "xdc"
    head = Header(dev, losses, xdc=xdc, name=name, node_id=node_id)
    body = _Objects(dev, losses, xdc)
    for obj in w.objects(dev, disabled=True):
        body.obj(obj)
    declared, codec = xml_encoding(dev.encoding)
    out = head.document(body.params, body.objects, declared)
    # a character the encoding has no byte for (an output's name) as a reference
    return Written(out.encode(codec, "xmlcharrefreplace"), losses.diagnostics(kind))


def xml_encoding(encoding: str) -> tuple[str, str]:
    """(declared name, Python codec) of the file written of a model whose strings are in
    ``encoding``: the same encoding, so that a string's bytes stay the bytes that stood
    in the source (a Latin-1 DCF's "caf\\xE9" is 4 bytes in the XDC too, read back by
    its declaration); UTF-8 for UTF-8 and UTF-16 (XML's own two)."""
    if encoding in ("utf-8", "utf-16"):
        return "UTF-8", "utf-8"
    if encoding == "latin-1":
        return "ISO-8859-1", "latin-1"
    name = encoding.upper()                     # Python's name -> the registered one
    if name.startswith("ISO8859-"):
        name = "ISO-8859-" + name[8:]
    elif name.startswith("CP125"):
        name = "windows-" + name[2:]
    return name, encoding


class _Objects:
    """The CANopenObjectList and the parameterList, one object at a time."""

    def __init__(self, dev, losses: Losses, xdc: bool):
        self.dev, self.losses, self.xdc = dev, losses, xdc
        self.objects: list[str] = []
        self.params: list[str] = []

    def obj(self, obj) -> None:
        idx = obj.index
        if obj.implicit:
            self.losses.say("CNV005", idx, f"0x{idx:04X}: written out as an object: CiA 311 "
                            "has no CompactPDO, which implied it")
        attrs = [("index", f"{idx:04X}"), ("name", obj.name),
                 ("objectType", str(obj.object_type))]
        if not obj.complex:
            e = obj.entries[0]
            attrs += self.entry_attrs(e, obj, own=True)
            attrs += self.parameter(e, obj, var=True)
            self.objects.append(f"\t\t\t\t\t<CANopenObject{_attrs(attrs, self, idx)}/>")
            return
        for key, name in (("pdomapping", "PDOmapping"), ("objflags", "objFlags")):
            n = w.section_number(obj, key)
            if isinstance(n, str):          # no number: written as it is, never as 0
                attrs.append((name, n))
            elif n is not None:
                attrs.append((name, self.pdo(obj.index, None, n == 1) if key ==
                              "pdomapping" else f"{n:04X}"))
        attrs += self.parameter(None, obj, var=False)
        if obj.sub_number is not None:
            attrs.append(("subNumber", str(obj.sub_number)))
        if obj.compact:
            n = obj.compact
            self.losses.say("CNV001", idx, f"0x{idx:04X}: CompactSubObj={n} has no CiA 311 "
                            f"form; its {n} sub-object{'s are' if n != 1 else ' is'} "
                            "written one by one")
        subs = []
        kept = w.entries(obj)
        if obj.compact and 0 in obj.entries and obj.entries[0].implicit:
            kept.insert(0, obj.entries[0])  # CompactSubObj's implied sub 0, said in CiA 311
        for e in kept:
            sattrs = [("subIndex", f"{e.sub:02X}"), ("name", e.name), ("objectType", "7")]
            sattrs += self.entry_attrs(e, obj, own=False)
            sattrs += self.parameter(e, obj, var=True)
            subs.append(f"\t\t\t\t\t\t<CANopenSubObject{_attrs(sattrs, self, idx, e.sub)}/>")
        if subs:
            self.objects.append(f"\t\t\t\t\t<CANopenObject{_attrs(attrs, self, idx)}>")
            self.objects.extend(subs)
            self.objects.append("\t\t\t\t\t</CANopenObject>")
        else:
            self.objects.append(f"\t\t\t\t\t<CANopenObject{_attrs(attrs, self, idx)}/>")

    def entry_attrs(self, e, obj, *, own: bool) -> list[tuple[str, str]]:
        """The attributes of one entry (a VAR object's own, or a sub-object's)."""
        out = []
        if e.dtype is not None:
            out.append(("dataType", f"{e.dtype.code:04X}"))
        if e.access is not None and ATTR_ACCESS.get(e.access) is not None:
            out.append(("accessType", ATTR_ACCESS[e.access]))
        for value, name in ((e.default, "defaultValue"), (e.low, "lowLimit"),
                            (e.high, "highLimit")):
            if value is not None:
                out.append((name, value))
        at = "" if own else f"sub{e.sub:X} "
        for value, name, key in ((e.param, "actualValue", "ParameterValue"),
                                 (e.denotation, "denotation", "Denotation")):
            if value is None:
                continue
            if self.xdc:
                out.append((name, value))
            else:
                self.losses.add("CNV002", e.index, f"{at}{key}={w.shown(value)}")
        if e.download_file is not None:
            self.losses.add("CNV005", e.index, f"{at}DownloadFile={w.shown(e.download_file)}")
        out.append(("PDOmapping", self.pdo(e.index, None if own else e.sub, e.pdo_mapping)))
        inherited = 0 if own else w.section_number(obj, "objflags")
        inherited = inherited if isinstance(inherited, int) else 0   # the object's text
        raw = w.own_text(e, "objflags")       # no number: written as it is, never as 0
        if raw is not None:
            out.append(("objFlags", raw))
        elif e.obj_flags or inherited:
            if e.obj_flags > 0xFFFF:
                self.losses.add("CNV005", e.index, f"{at}ObjFlags=0x{e.obj_flags:X} (objFlags "
                                "holds 2 bytes)")
            else:
                out.append(("objFlags", f"{e.obj_flags:04X}"))
        return out

    def pdo(self, index: int, sub: int | None, mapped: bool) -> str:
        """PDOmapping: the kind a CiA 311 source said (TPDO, RPDO, default), else
        "optional" for CiA 306's PDOMapping=1."""
        if not mapped:
            return "no"
        said = self.dev.specifics.get((index, sub), {}).get("PDOmapping")
        return said if said in voc.PDO_MAPPING and said != "no" else "optional"

    def parameter(self, e, obj, *, var: bool) -> list[tuple[str, str]]:
        """A parameter for what the attributes cannot say, and the uniqueIDRef naming it;
        [] when none is needed."""
        sub = None if e is None or not obj.complex else e.sub
        spec = self.dev.specifics.get((obj.index, sub), {})
        label = obj.name if e is None else e.name
        description = spec.get("description")
        props = [(k, v) for k, v in spec.items() if k not in ("description", "PDOmapping")]
        special = e is not None and var and e.access in ("rwr", "rww")
        if description is None and not props and not special:
            return []
        uid = (f"UID_OBJ_{obj.index:04X}" if sub is None else f"UID_SUB_{obj.index:04X}{sub:02X}")
        head = f'\t\t\t\t\t<parameter uniqueID="{uid}"'
        if e is not None and var and e.access in PARAM_ACCESS:
            head += f' access="{PARAM_ACCESS[e.access]}"'
        lines = [head + ">", f'\t\t\t\t\t\t<label lang="en">{text(label)}</label>']
        if description is not None and description != label:
            lines.append(f'\t\t\t\t\t\t<description lang="en">{text(description)}</description>')
        if e is not None and var and e.dtype is not None:
            iec = IEC_OF.get(e.dtype.code)
            if iec is not None and voc.type_code(iec, e.default) == e.dtype.code:
                lines.append(f"\t\t\t\t\t\t<{iec}/>")
        for name, value in props:
            lines.append(f'\t\t\t\t\t\t<property name="{attr(name)}" value="{attr(value)}"/>')
        lines.append("\t\t\t\t\t</parameter>")
        self.params.extend(lines)
        if special:
            at = "" if sub is None else f"sub{sub:X} "
            self.losses.add("CNV006", obj.index, f"{at}AccessType={e.access}")
        return [("uniqueIDRef", uid)]


def _attrs(pairs, objects: _Objects, index: int, sub: int | None = None) -> str:
    """ name="value" ... with XML's escapes; a value XML cannot hold is left out (CNV007)."""
    out = []
    for name, value in pairs:
        escaped = attr(value)
        if escaped is None:
            objects.losses.add("CNV007", index, name if sub is None else f"sub{sub:X} {name}")
            continue
        out.append(f' {name}="{escaped}"')
    return "".join(out)
