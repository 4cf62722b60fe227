"""CiA 311 XML device descriptions (XDD, XDC; CANopenEditor's profiles ``.xpd``), v1.0 and
v1.1, read into the model a DCF/EDS is read into.

The reader hands on the file's data as the sections CiA 306 defines (``document.XddFile``,
an ``ini.IniFile``; every key at the line of the XML element it came from), so the model's
builder, every validate rule and every command apply unchanged, and an XDC's
``actualValue``s and ``deviceCommissioning`` are a DCF's ParameterValues and
[DeviceComissioning]. Why sections and not a Device built directly: one builder, one set of
rules and one set of messages for every format, and the network configurator, which edits a
DCF's text, gets that text from them (``formats.load_with_text``); the cost, measured by
benchmarks/xdd.py, is small beside the XML parse.

Modules: ``markup`` (lxml, safely: why lxml is there), ``vocabulary`` (CiA 311's words as
CiA 306's numbers), ``document`` (``XddFile``), ``header`` ([FileInfo], [DeviceInfo],
[DummyUsage], [DeviceComissioning]) and ``objects`` (the object dictionary, both styles).
Findings have rule ids XDD0xx (dcf2bin/lint/rules_xdd.py, docs/validate.md).
"""
from __future__ import annotations

import codecs
import re

from dcf2bin.diagnostics import Diagnostics, Severity, Where


def sniff(data: bytes) -> bool:
    """XML text: after a byte order mark and blanks, ``<?``, ``<!`` or ``<`` and a name's
    first letter, and no control character in the first 256 bytes but tab, CR and LF (a
    binary file that happens to start with ``<`` is not XML)."""
    head = data[:256]
    if head[:3] == b"\xef\xbb\xbf":
        head = head[3:]
    elif head[:2] in (b"\xff\xfe", b"\xfe\xff"):
        head = head[2:].replace(b"\x00", b"")          # UTF-16: its ASCII characters
    if head.translate(None, b"\t\r\n").translate(None, bytes(range(32, 256))):
        return False                                  # control characters: binary
    body = head.lstrip(b" \t\r\n")
    return body[:1] == b"<" and (body[1:2] in (b"?", b"!", b"_", b":")
                                 or body[1:2].isalpha())


def read(data: bytes, path: str):
    """The file's sections (``XddFile``). A file that is not a CANopen CiA 311 description
    -- not well-formed, a DOCTYPE, another XML, Ethernet POWERLINK -- is one finding and no
    section (``rejected``)."""
    from dcf2bin.formats.xdd import header
    from dcf2bin.formats.xdd.direct import Straight
    from dcf2bin.formats.xdd.document import XddFile
    from dcf2bin.formats.xdd.markup import MarkupError, local, parse
    from dcf2bin.formats.xdd.objects import Objects
    doc = XddFile(path, _encoding(data), {}, [], Diagnostics(), data.count(b"\n") + 1,
                  format="xdd")
    try:
        root = parse(data)
    except MarkupError as exc:
        return _reject(doc, exc.message, exc.line, exc.rule)
    found = _collect(root, local)
    problem = _not_canopen(root, found, local)
    if problem is not None:
        return _reject(doc, *problem)
    params = _unique(doc, found.get("parameter", ()), "parameter")
    types = _unique(doc, [e for n in ("array", "struct", "derived", "enum")
                          for e in found.get(n, ())], "type")
    body = next((b for b in found.get("ProfileBody", ()) if b.get("fileName") is not None),
                None)
    if body is not None:
        doc.sections["fileinfo"] = header.file_info(body)
    one = {n: (found.get(n) or [None])[0] for n in
           ("DeviceIdentity", "CANopenGeneralFeatures", "CANopenMasterFeatures",
            "deviceCommissioning")}
    for canon, sec in (
            ("deviceinfo", header.device_info(one["DeviceIdentity"],
                                              found.get("supportedBaudRate", []),
                                              one["CANopenGeneralFeatures"],
                                              one["CANopenMasterFeatures"])),
            ("dummyusage", header.dummy_usage(found.get("dummy", []))),
            ("devicecomissioning", header.commissioning(one["deviceCommissioning"]))):
        if sec is not None:
            doc.sections[canon] = sec
    reader = Objects(doc, params, types)
    straight = Straight(reader).read
    for el in found.get("CANopenObject", ()):
        if not straight(el):
            reader.read(el)
    doc.sections.update(header.object_lists(doc.sections,
                                            found["CANopenObjectList"][0].sourceline))
    _disabled_note(doc)
    return doc


# the elements the reader looks at, wherever they stand
_WANTED = frozenset({
    "parameter", "array", "struct", "derived", "enum", "CANopenObject", "CANopenObjectList",
    "ObjectList", "ProfileBody", "DeviceIdentity", "CANopenGeneralFeatures",
    "CANopenMasterFeatures", "deviceCommissioning", "supportedBaudRate", "dummy",
    "ProfileTechnology"})


_WILD = tuple("{*}" + name for name in _WANTED)


def _collect(root, local) -> dict:
    """name -> the elements of that name, in document order (lxml's iter picks them, in C;
    one list per tag first, one per name after: a look-up per element, not a call)."""
    by_tag: dict = {}
    for el in root.iter(*_WILD):
        tag = el.tag
        got = by_tag.get(tag)
        if got is None:
            got = by_tag[tag] = []
        got.append(el)
    found: dict[str, list] = {}
    for tag, els in by_tag.items():
        name = local(tag)
        if name in found:       # one name in two namespaces: both in document order
            found = {}
            for el in root.iter(*_WILD):
                found.setdefault(local(el.tag), []).append(el)
            return found
        found[name] = els
    return found


def _not_canopen(root, found: dict, local):
    """(message, line, rule) for a file that is not a CANopen description, else None."""
    if local(root.tag) != "ISO15745ProfileContainer":
        return (f"the root element is <{local(root.tag)}>, not the ISO15745ProfileContainer "
                "of a CiA 311 device description", root.sourceline, "XDD003")
    if found.get("CANopenObjectList"):
        return None
    plk = found.get("ObjectList")
    tech = [e for e in found.get("ProfileTechnology", ())
            if (e.text or "").strip().lower() == "powerlink"]
    if plk or tech:
        at = (plk or tech)[0]
        return ("an Ethernet POWERLINK device description (an ObjectList of Object "
                "elements), not a CANopen one; dcf2bin reads CANopen's CiA 311 XDD/XDC",
                at.sourceline, "XDD004")
    return ("no CANopenObjectList: the file describes no CANopen object dictionary",
            root.sourceline, "XDD003")


def _reject(doc, message: str, line, rule: str):
    hints = {"XDD001": "an XDD/XDC is well-formed XML; an editor that checks XML finds the spot",
             "XDD002": "remove the DOCTYPE; CiA 311 files are checked against XML Schema",
             "XDD003": "dcf2bin reads CiA 311 XDD/XDC files and CiA 306 EDS/DCF files",
             "XDD004": "dcf2bin reads CANopen descriptions only; take the device's CANopen "
                       "XDD or EDS"}
    doc.diagnostics.error(message, Where(doc.path, line), rule=rule, hint=hints[rule])
    doc.rejected = True
    return doc


def _unique(doc, elements, what: str) -> dict:
    """uniqueID -> element; a uniqueID given twice is XDD014 (the first is kept)."""
    out: dict = {}
    for el in elements:
        uid = el.get("uniqueID")
        if uid is None:
            continue
        if uid in out:
            doc.problem(Severity.ERROR, f"uniqueID=\"{uid}\" of a {what} is given twice (first at "
                        f"line {out[uid].sourceline}); the first is read", el.sourceline,
                        rule="XDD014", hint="give every parameter and type its own uniqueID")
            continue
        out[uid] = el
    return out


def _disabled_note(doc) -> None:
    """One line naming the objects CANopenNode leaves out (CO_disabled), which the model
    leaves out too: nothing is dropped without a word."""
    left = sorted({int(c[:4], 16) for c in doc.disabled})
    if left:
        names = ", ".join(f"0x{i:04X}" for i in left)
        many = len(left) != 1
        doc.problem(Severity.INFO, f"{len(left)} object{'s' if many else ''} marked "
                    f"CO_disabled (CANopenNode builds {'them' if many else 'it'} into no "
                    f"object dictionary) {'are' if many else 'is'} left out: {names}", None,
                    rule="XDD020", hint="remove the CO_disabled property to read an object")


# the XML declaration's encoding (XML 1.0 section 4.3.3: at the very start, ASCII letters)
_DECLARED = re.compile(rb"(?:\xef\xbb\xbf)?<\?xml\s[^>]*?\bencoding\s*=\s*[\"']([A-Za-z][\w.-]*)[\"']")


def _encoding(data: bytes) -> str:
    """The encoding the device's strings are written in: the document's own (its
    declaration's, UTF-8 without one), so that a string's bytes are the bytes that stood
    in the file, as in CiA 306 text. ASCII is UTF-8's first half; an encoding Python
    does not know, libxml2 does not either (XDD001)."""
    if data[:2] in (b"\xff\xfe", b"\xfe\xff"):
        return "utf-16"
    m = _DECLARED.match(data, 0, 256)
    if m is None:
        return "utf-8"
    try:
        name = codecs.lookup(m.group(1).decode("ascii")).name
    except LookupError:
        return "utf-8"
    return {"iso8859-1": "latin-1", "ascii": "utf-8"}.get(name, name)


def dump(dev, kind: str = "xdd", *, name: str | None = None, node_id: int | None = None):
    """``dev`` as a CiA 311 v1.1 XDD or (``kind`` "xdc") XDC: a ``written.Written`` (the
    bytes and the warnings about what CiA 311 cannot say). See ``writer``."""
    from dcf2bin.formats.xdd.writer import dump as write
    return write(dev, kind, name=name, node_id=node_id)
