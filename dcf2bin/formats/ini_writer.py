"""A Device as CiA 306 text: an EDS (a device's description) or a DCF (the same, with the
configured values of one device: ParameterValue, Denotation, DownloadFile and
[DeviceComissioning]). ``formats.ini.dump`` is the entry point.

The object sections are written from the model (every entry's type, access, values and
flags, each key in CiA 306's own form), so that an EDS written from a CiA 311 file and one
written from CiA 306 text look alike, and reading the text back gives the same model.
PDOMapping is written on every sub-object and ObjFlags wherever an object-level value
would otherwise be inherited, so no sub-object takes a flag it did not have. A
CompactSubObj object is written compact again, its names, values and denotations in
[xxxxName]/[xxxxValue]/[xxxxDenotation]. Keys the model does not read, vendor sections,
[Comments] and [DynamicChannels] of CiA 306 text are written back as they were.
What an EDS cannot say -- configured values, a CiA 311 description, CANopenNode's
properties, the objects marked CO_disabled -- is a warning (``written.Losses``).
"""
from __future__ import annotations

import os
import re

from dcf2bin.diagnostics import shorten
from dcf2bin.formats import written as w
from dcf2bin.formats.written import Losses, Written

# the keys of an object section the model reads; any other key is the file's own
KNOWN = frozenset({"parametername", "objecttype", "datatype", "accesstype", "defaultvalue",
                   "parametervalue", "lowlimit", "highlimit", "pdomapping", "objflags",
                   "denotation", "downloadfile", "subnumber", "compactsubobj"})
OBJECT_SECTION = re.compile(r"[0-9a-f]{4}(?:sub[0-9a-f]+)?")     # an object or sub-object
_OBJECT = re.compile(r"[0-9a-f]{4}(?:sub[0-9a-f]+|name|value|denotation)?")
_LISTS = ("mandatoryobjects", "optionalobjects", "manufacturerobjects")
_HEADERS = ("fileinfo", "deviceinfo", "dummyusage", "devicecomissioning",
            "devicecommissioning", "comments")
CONFIGURED = (("param", "ParameterValue"), ("denotation", "Denotation"),
              ("download_file", "DownloadFile"))


def dump(dev, kind: str = "eds", *, name: str | None = None,
         node_id: int | None = None) -> Written:
    """``dev`` as CiA 306 text (``kind`` "eds" or "dcf"); ``name``: the file's name for
    [FileInfo] FileName (default: the source's); ``node_id``: a DCF's NodeID."""
    writer = _Writer(dev, kind == "dcf", Losses(dev))
    text = writer.text(name, node_id)
    return Written(_encoded(text, dev.encoding), writer.losses.diagnostics(kind))


def _encoded(text: str, encoding: str) -> bytes:
    """The text in the model's own encoding (a Latin-1 DCF's, or a CiA 311 file's
    declared one), so that every string is the bytes that stood in the source: a reader
    of CiA 306 text takes bytes that are no UTF-8 as Latin-1, byte for byte. UTF-8 for a
    UTF-8 or UTF-16 model, and where the encoding has no byte for a character."""
    if encoding not in ("utf-8", "utf-16"):
        try:
            return text.encode(encoding)
        except UnicodeEncodeError:
            pass
    return text.encode("utf-8")


class _Writer:
    def __init__(self, dev, dcf: bool, losses: Losses):
        self.dev, self.dcf, self.losses = dev, dcf, losses
        self.out: list[str] = []

    def text(self, name: str | None, node_id: int | None) -> str:
        dev = self.dev
        self.file_info(name)
        for canon in ("deviceinfo", "dummyusage"):
            self.copy(w.header(dev, canon))
        self.commissioning(node_id)
        self.copy(w.header(dev, "comments"))
        groups: dict[str, list] = {n: [] for n in _LISTS}
        for obj in w.objects(dev, disabled=False):
            if obj.implicit:
                continue                # CompactPDO's objects: [DeviceInfo] implies them
            groups[_list_of(obj.index)].append(obj)
        for canon, title in zip(_LISTS, ("MandatoryObjects", "OptionalObjects",
                                         "ManufacturerObjects")):
            objs = groups[canon]
            self.section(title, [("SupportedObjects", str(len(objs)))]
                         + [(str(n), f"0x{o.index:04X}") for n, o in enumerate(objs, 1)])
            for obj in objs:
                self.obj(obj)
        self.other_sections()
        self.disabled_note()
        self.specifics_lost()
        return "\n".join(self.out) + "\n"

    # -- sections ------------------------------------------------------------------------
    def section(self, title: str, keys: list[tuple[str, str]]) -> None:
        self.out.append(f"[{title}]")
        self.out.extend(f"{k}={_one_line(v)}" for k, v in keys)
        self.out.append("")

    def copy(self, sec, skip=(), replace=None) -> None:
        """A header section of the source as it was: its keys as written, in order."""
        if sec is None:
            return
        keys = [(k.name, k.value) for low, k in sec.keys.items() if low not in skip]
        self.section(sec.name.strip(), keys + list(replace or ()))

    def file_info(self, name: str | None) -> None:
        sec = w.header(self.dev, "fileinfo")
        keys = [(k.name, k.value) for k in sec.keys.values()] if sec is not None else []
        if name is not None:
            keys = [(k, name if k.lower() == "filename" else v) for k, v in keys]
            if not any(k.lower() == "filename" for k, _ in keys):
                keys.insert(0, ("FileName", name))
        if not any(k.lower() == "edsversion" for k, _ in keys):
            keys.append(("EDSVersion", "4.0"))
        self.section("FileInfo", keys)

    def commissioning(self, node_id: int | None) -> None:
        sec = w.header(self.dev, "devicecomissioning") or w.header(self.dev,
                                                                   "devicecommissioning")
        if not self.dcf:
            if sec is not None and sec.keys:
                for k in sec.keys.values():
                    self.losses.add("CNV002", None, f"{k.name}={k.value}", sec.line,
                                    group="[DeviceComissioning]")
            return
        keys = [(k.name, k.value) for k in sec.keys.values()] if sec is not None else []
        if node_id is not None:
            keys = [(k, v) for k, v in keys if k.lower() != "nodeid"]
            keys.insert(0, ("NodeID", str(node_id)))
        if keys:
            self.section("DeviceComissioning", keys)

    def other_sections(self) -> None:
        """Sections of CiA 306 text the model does not read (vendor sections, [Tools],
        [DynamicChannels], [xxxxObjectLinks]), as they were."""
        if self.dev.ini is None or self.dev.ini.format != "ini":
            return
        for canon, sec in self.dev.ini.sections.items():
            if canon in _HEADERS or canon in _LISTS or _OBJECT.fullmatch(canon):
                continue
            self.copy(sec)

    # -- objects -------------------------------------------------------------------------
    def obj(self, obj) -> None:
        keys = [("ParameterName", obj.name), ("ObjectType", f"0x{obj.object_type:X}")]
        if not obj.complex:
            e = obj.entries[0]
            flags = bool(e.obj_flags) or w.section_value(obj, "objflags") is not None
            keys += self.entry_keys(e, flags=flags, at="")
            keys += _unknown(obj.section)
            self.section(f"{obj.index:04X}", keys)
            return
        if obj.sub_number is not None:
            keys.append(("SubNumber", f"0x{obj.sub_number:X}"))
        for key, title in (("pdomapping", "PDOMapping"), ("objflags", "ObjFlags")):
            value = w.section_value(obj, key)
            if value is not None:
                keys.append((title, value))
        inherited = w.section_number(obj, "objflags")
        inherited = inherited if isinstance(inherited, int) else 0   # its text is kept above
        compact = obj.entries.get(1) if obj.compact else None
        if compact is not None:     # the keys CompactSubObj's sub-objects share: sub 1's
            keys += [k for k in _typed(compact) if k[0] != "PDOMapping"
                     or w.section_value(obj, "pdomapping") is None]
        if obj.compact:
            keys.append(("CompactSubObj", str(obj.compact)))
        keys += _unknown(obj.section)
        self.section(f"{obj.index:04X}", keys)
        for e in w.entries(obj):
            if obj.compact and e.section is None and e.sub:
                continue            # one of CompactSubObj's: in [xxxxName]/[xxxxValue]
            sub = [("ParameterName", e.name), ("ObjectType", "0x7")]
            sub += self.entry_keys(e, flags=bool(e.obj_flags or inherited), at=f"sub{e.sub:X} ")
            sub += _unknown(e.section)
            self.section(f"{obj.index:04X}sub{e.sub:X}", sub)
        if obj.compact:
            self.compact_sections(obj)

    def entry_keys(self, e, *, flags: bool, at: str) -> list[tuple[str, str]]:
        """An entry's keys; ObjFlags where ``flags``; its configured values in a DCF, and
        a loss in an EDS (``at``: how the loss names the sub-object)."""
        keys = _typed(e)
        raw = w.own_text(e, "objflags")       # no number: written as it is, never as 0
        if flags or raw is not None:
            keys.append(("ObjFlags", raw if raw is not None else f"0x{e.obj_flags:X}"))
        for attr, key in CONFIGURED:
            value = getattr(e, attr)
            if value is None:
                continue
            if self.dcf:
                keys.append((key, value))
            else:
                self.losses.add("CNV002", e.index, f"{at}{key}={w.shown(value)}")
        return keys

    def compact_sections(self, obj) -> None:
        subs = [e for e in w.entries(obj) if e.sub and e.section is None]
        names = [(str(e.sub), e.name) for e in subs if e.name != f"{obj.name}{e.sub}"]
        if names:
            self.section(f"{obj.index:04X}Name", [("NrOfEntries", str(len(names)))] + names)
        for title, attr, key in (("Value", "param", "ParameterValue"),
                                 ("Denotation", "denotation", "Denotation")):
            got = [(str(e.sub), getattr(e, attr)) for e in subs if getattr(e, attr) is not None]
            if not got:
                continue
            if self.dcf:
                self.section(f"{obj.index:04X}{title}",
                             [("NrOfEntries", str(len(got)))] + got)
            else:
                for sub, value in got:
                    self.losses.add("CNV002", obj.index,
                                    f"sub{int(sub):X} {key}={w.shown(value)}")

    # -- what an EDS cannot say --------------------------------------------------------------
    def disabled_note(self) -> None:
        left = w.disabled_indexes(self.dev)
        if left:
            n = len(left)
            self.losses.say("CNV004", None, (
                f"{n} object{'s' if n != 1 else ''} marked CO_disabled left out (CANopenNode "
                f"builds {'them' if n != 1 else 'it'} into no object dictionary, and an EDS "
                f"has no way to say so): {', '.join(f'0x{i:04X}' for i in left)}"))

    def specifics_lost(self) -> None:
        dev = self.dev
        for (index, sub), spec in sorted(dev.specifics.items(),
                                         key=lambda kv: (kv[0][0], -1 if kv[0][1] is None
                                                         else kv[0][1])):
            if index not in dev.objects:
                continue                # a CO_disabled object: CNV004 names it
            e = dev.entry(index, 0 if sub is None else sub)
            at = "" if sub is None else f"sub{sub:X} "
            for key, value in spec.items():
                if key == "description":
                    if e is not None and value == e.name:
                        continue        # a CiA 311 label: the name, which the EDS keeps
                    self.losses.add("CNV003", index, f"{at}description")
                elif key == "PDOmapping":
                    if value != "optional":     # "optional" is CiA 306's PDOMapping=1
                        self.losses.add("CNV003", index, f'{at}PDOmapping="{shorten(value)}"')
                else:
                    self.losses.add("CNV003", index, f"{at}{key}={value}")



def _list_of(index: int) -> str:
    if index in (0x1000, 0x1001, 0x1018):
        return "mandatoryobjects"
    return "manufacturerobjects" if 0x2000 <= index <= 0x5FFF else "optionalobjects"


def _unknown(sec) -> list[tuple[str, str]]:
    """The keys of a CiA 306 section the model does not read, as written."""
    if sec is None or not any(k not in KNOWN for k in sec.key_names()):
        return []
    return [(k.name, k.value) for low, k in sec.keys.items() if low not in KNOWN]


def _typed(e) -> list[tuple[str, str]]:
    """Type, access, values, limits and PDOMapping of an entry, as CiA 306 keys."""
    keys = []
    if e.dtype is not None:
        keys.append(("DataType", f"0x{e.dtype.code:04X}"))
    if e.access is not None:
        keys.append(("AccessType", e.access))
    for value, key in ((e.default, "DefaultValue"), (e.low, "LowLimit"), (e.high, "HighLimit")):
        if value is not None:
            keys.append((key, value))
    keys.append(("PDOMapping", "1" if e.pdo_mapping else "0"))
    return keys


def _one_line(value: str) -> str:
    return " ".join(value.split()) if ("\n" in value or "\r" in value) else value




def output_name(path: str | None) -> str | None:
    """The file name a written [FileInfo] gives (the output's), or None for stdout."""
    return os.path.basename(path) if path and path != "-" else None
