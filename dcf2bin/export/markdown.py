"""The documentation of a device's object dictionary (``export --format markdown``), and
the page both documentation formats share (``html`` renders the same page).

The page is data (``build``: a list of ``Block``s) and each format only renders it: the
file and device it describes, then the objects from 0x1000 up grouped by CiA 301's areas
(communication profile, manufacturer-specific, standardized profile, network variables,
system variables, reserved), each object with its index, name and object type, and a table
of its entries: data type, access, PDO mapping, default value as the file writes it, and,
where the object has them, the configured value, the limits, the denotation and
CANopenNode's SRDO access; then its description (a CiA 311 parameter's ``description``).
What CANopenNode's object dictionary takes beyond CiA 306/311 (count label, storage group)
is shown when the file states any of it (``common.canopennode_settings``). The page is the
same every run: no date, no tool version.

Like the page CANopenEditor writes from its GUI; the layout, the words and the columns are
this project's own (docs/export.md compares the two).
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt, values
from dcf2bin.diagnostics import Where
from dcf2bin.export.common import (ExportResult, canopennode_settings, description,
                                   entry_setting, error, exported_objects, model_diagnostics,
                                   object_description, object_settings, pdo_direction,
                                   written_default)

# CiA 301's areas of the object dictionary (index ranges)
AREAS = ((0x1000, 0x1FFF, "Communication profile area"),
         (0x2000, 0x5FFF, "Manufacturer-specific profile area"),
         (0x6000, 0x9FFF, "Standardized profile area"),
         (0xA000, 0xAFFF, "Standardized network variable area"),
         (0xB000, 0xBFFF, "Standardized system variable area"),
         (0xC000, 0xFFFF, "Reserved area"))
PDO_WORDS = {"": "no", "t": "TPDO", "r": "RPDO", "tr": "TPDO, RPDO"}
BAUD_RATES = (10, 20, 50, 125, 250, 500, 800, 1000)


@dataclass
class Block:
    """One piece of the page. ``kind``: "h1", "h2", "h3" (``text``, ``anchor``), "info"
    (``rows`` of label and value), "p" (``text``), "table" (``head``, ``rows``), "desc" (a
    description: ``text`` as the file writes it, lines kept), "toc" (``rows`` of anchor,
    text and depth)."""
    kind: str
    text: str = ""
    anchor: str = ""
    head: list[str] = field(default_factory=list)
    rows: list = field(default_factory=list)


def build(dev, settings: dict) -> list[Block]:
    """The page of ``dev`` (``settings``: CANopenNode's, as the file states them)."""
    objs = exported_objects(dev)
    title = _title(dev)
    page = [Block("h1", title), Block("info", rows=_info(dev)),
            Block("p", f"Written by dcf2bin from {os.path.basename(dev.path)}: "
                       f"{len(objs)} object{'s' if len(objs) != 1 else ''} from 0x1000 up.")]
    toc = Block("toc")
    page.append(toc)
    pdos = _pdos(dev)
    if pdos:
        page.append(Block("h2", "PDO mapping", "pdo-mapping"))
        toc.rows.append(("pdo-mapping", "PDO mapping", 0))
        page += pdos
    for first, last, area in AREAS:
        inside = [o for o in objs if first <= o.index <= last]
        if not inside:
            continue
        anchor = f"area-{first:04x}"
        page.append(Block("h2", f"{area} (0x{first:04X}-0x{last:04X})", anchor))
        toc.rows.append((anchor, f"{area} (0x{first:04X}-0x{last:04X})", 0))
        for obj in inside:
            heading = f"0x{obj.index:04X} {obj.name}".rstrip()
            page.append(Block("h3", heading, f"x{obj.index:04x}"))
            toc.rows.append((f"x{obj.index:04x}", heading, 1))
            page += _object(dev, settings, obj)
    return page


def _number(entry) -> int | None:
    """The entry's value (ParameterValue, else DefaultValue as written) as a number, or
    None ($NODEID formulas and what is no number)."""
    if entry is None:
        return None
    text = entry.param if entry.param is not None else written_default(entry)
    try:
        return values.parse_int(text) if text else None
    except values.ValueProblem:
        return None


def _pdos(dev) -> list[Block]:
    """Every PDO that maps something (sub 0 of its mapping object above 0): its COB-ID
    and transmission type as written, and what it maps, named."""
    out = []
    for first, what in ((0x1400, "RPDO"), (0x1800, "TPDO")):
        for n in range(512):
            comm = dev.objects.get(first + n)
            mapping = dev.objects.get(first + 0x200 + n)
            count = _number(mapping.entries.get(0)) if mapping is not None else None
            if not count:
                continue
            said = []
            for sub, label in ((1, "COB-ID"), (2, "transmission type"), (3, "inhibit time"),
                               (5, "event timer")):
                e = comm.entries.get(sub) if comm is not None else None
                text = (e.param if e.param is not None else written_default(e)) if e else None
                if text:
                    said.append(f"{label} {text}")
            out.append(Block("p", f"{what} {n + 1} (0x{first + n:04X}, mapping "
                                  f"0x{first + 0x200 + n:04X}): " + (", ".join(said) or
                                                                   "no parameters given")
                             + "."))
            rows = []
            for sub in range(1, min(count, 255) + 1):
                v = _number(mapping.entries.get(sub))
                if v is None:
                    rows.append([f"0x{sub:02X}", "", "", "(no value)"])
                    continue
                index, s, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
                rows.append([f"0x{sub:02X}", f"0x{index:04X}sub{s:X}", str(bits),
                             _mapped_name(dev, index, s)])
            out.append(Block("table", head=["Sub", "Entry", "Bits", "Name"], rows=rows))
    return out


def _mapped_name(dev, index: int, sub: int) -> str:
    if index < 0x20 and sub == 0 and index in dt.BY_CODE:
        return f"dummy {dt.BY_CODE[index].name}"
    obj = dev.objects.get(index)
    e = obj.entries.get(sub) if obj is not None else None
    if e is None:
        return "(not in the object dictionary)"
    return f"{obj.name}: {e.name}" if obj.complex else obj.name


def _title(dev) -> str:
    info = dev.ini.sections.get("deviceinfo") if dev.ini is not None else None
    product = info.values.get("productname", "").strip() if info is not None else ""
    return f"Object dictionary of {product or os.path.basename(dev.path)}"


def _value(dev, section: str, key: str) -> str:
    sec = dev.ini.sections.get(section) if dev.ini is not None else None
    return sec.values.get(key, "").strip() if sec is not None else ""


def _info(dev) -> list[tuple[str, str]]:
    """(label, value) of what the file says about itself and the device; empty ones left
    out."""
    def v(key: str, section: str = "fileinfo") -> str:
        return _value(dev, section, key)

    def when(date: str, time: str, who: str) -> str:
        text = " ".join(x for x in (date, time) if x)
        return f"{text} by {who}" if who and text else (text or (f"by {who}" if who else ""))

    version = ".".join(x for x in (v("fileversion"), v("filerevision")) if x)
    rates = [str(k) for k in BAUD_RATES if v(f"baudrate_{k}", "deviceinfo") == "1"]
    rx, tx = v("nrofrxpdo", "deviceinfo"), v("nroftxpdo", "deviceinfo")
    lss = v("lss_supported", "deviceinfo")
    rows = [("File", v("filename")), ("File version", version),
            ("EDS version", v("edsversion")), ("Description", v("description")),
            ("Created", when(v("creationdate"), v("creationtime"), v("createdby"))),
            ("Modified", when(v("modificationdate"), v("modificationtime"), v("modifiedby"))),
            ("Vendor name", v("vendorname", "deviceinfo")),
            ("Vendor-ID", v("vendornumber", "deviceinfo")),
            ("Product name", v("productname", "deviceinfo")),
            ("Product code", v("productnumber", "deviceinfo")),
            ("Revision number", v("revisionnumber", "deviceinfo")),
            ("Order code", v("ordercode", "deviceinfo")),
            ("Baud rates", ", ".join(rates) + " kbit/s" if rates else ""),
            ("PDOs", f"{rx or 0} RPDO, {tx or 0} TPDO" if rx or tx else ""),
            ("Granularity", v("granularity", "deviceinfo")),
            ("LSS", {"1": "supported", "0": "not supported"}.get(lss, lss)),
            ("Node-ID", v("nodeid", "devicecomissioning")),
            ("Node name", v("nodename", "devicecomissioning"))]
    return [(label, value) for label, value in rows if value]


def _object(dev, settings: dict, obj) -> list[Block]:
    kind = dt.OBJECT_TYPES.get(obj.object_type, f"0x{obj.object_type:X}")
    line = f"Object type {kind}."
    if settings:
        s = object_settings(dev, settings, obj)
        label = f"count label {s.count_label}, " if s.count_label else ""
        line += f" CANopenNode: {label}storage group {s.storage_group}."
    entries = obj.sorted_entries()
    out = [Block("p", line), _table(dev, settings, obj, entries)]
    text = object_description(dev, obj) if obj.complex else ""
    if text:
        out.append(Block("desc", text))
    for e in entries:
        text = description(dev, e, obj)
        if text and obj.complex:
            out.append(Block("p", f"Sub-index 0x{e.sub:02X} ({e.name}):"))
        if text:
            out.append(Block("desc", text))
    return out


def _table(dev, settings: dict, obj, entries) -> Block:
    """The entries' table; a column the object has no value for is left out (but data
    type, access, PDO and default)."""
    srdo = {e.sub: (entry_setting(settings, e, obj, "CO_accessSRDO") or ("", None))[0]
            for e in entries}
    columns = [("Sub", lambda e: f"0x{e.sub:02X}"), ("Name", lambda e: e.name)] \
        if obj.complex else []
    columns += [("Data type", lambda e: _type(e, settings, obj)),
                ("Access", lambda e: e.access or ""),
                ("PDO", lambda e: PDO_WORDS[pdo_direction(dev, e, obj)])]
    if any(v not in ("", "no") for v in srdo.values()):
        columns.append(("SRDO", lambda e: srdo[e.sub] or "no"))
    columns.append(("Default", lambda e: written_default(e) or ""))
    optional = (("Value", _configured), ("Low limit", lambda e: e.low or ""),
                ("High limit", lambda e: e.high or ""),
                ("Denotation", lambda e: e.denotation or ""))
    columns += [(head, get) for head, get in optional if any(get(e) for e in entries)]
    return Block("table", head=[h for h, _ in columns],
                 rows=[[get(e) for _, get in columns] for e in entries])


def _type(entry, settings: dict, obj) -> str:
    name = entry.dtype.name if entry.dtype is not None else ""
    said = entry_setting(settings, entry, obj, "CO_stringLengthMin")
    if said is not None and entry.dtype is not None and entry.dtype.size is None:
        name += f" (CANopenNode length at least {said[0].strip()})"
    return name


def _configured(entry) -> str:
    if entry.param is not None:
        return entry.param
    if entry.download_file is not None:
        return f"DownloadFile {entry.download_file}"
    return ""


# -- Markdown -------------------------------------------------------------------------------

# characters that start markup inside a line (CommonMark, GFM tables and strikethrough);
# '_' only where it can (not inside a word: PERSIST_COMM stays as it is)
_MARKUP = re.compile(r"[\\`*\[\]<>|&~]|(?<![A-Za-z0-9])_|_(?![A-Za-z0-9])")


def escape(text: str) -> str:
    """Text for a Markdown paragraph or table cell: one line, markup characters escaped."""
    return _MARKUP.sub(lambda m: "\\" + m.group(0), " ".join(text.split()))


def _desc_lines(text: str) -> list[str]:
    """A description as written (CANopenEditor writes Markdown lists there), HTML's
    characters escaped, line ends normalised, trailing blanks and blank edges dropped."""
    lines = [ln.rstrip() for ln in text.replace("\r\n", "\n").replace("\r", "\n").split("\n")]
    while lines and not lines[0]:
        lines.pop(0)
    while lines and not lines[-1]:
        lines.pop()
    return [ln.replace("\\", "\\\\").replace("<", "\\<").replace(">", "\\>")
            .replace("&", "\\&") for ln in lines]


def _md_table(head: list[str], rows: list[list[str]]) -> list[str]:
    cells = [[escape(c) for c in head]] + [[escape(c) for c in r] for r in rows]
    width = [max(3, *(len(r[k]) for r in cells)) for k in range(len(head))]
    out = []
    for n, r in enumerate(cells):
        out.append("| " + " | ".join(c.ljust(w) for c, w in zip(r, width)) + " |")
        if n == 0:
            out.append("| " + " | ".join("-" * w for w in width) + " |")
    return [ln.rstrip() for ln in out]


def to_markdown(page: list[Block]) -> str:
    out: list[str] = []
    for b in page:
        if b.kind in ("h1", "h2", "h3"):
            out += ["#" * int(b.kind[1]) + " " + escape(b.text), ""]
        elif b.kind == "info":
            out += _md_table(["", ""], [list(r) for r in b.rows]) + [""]
        elif b.kind == "p":
            out += [escape(b.text), ""]
        elif b.kind == "table":
            out += _md_table(b.head, b.rows) + [""]
        elif b.kind == "desc":
            out += _desc_lines(b.text) + [""]
    while out and not out[-1]:
        out.pop()
    return "\n".join(out) + "\n"


def export(dev, *, source: bytes | None = None, **_ignored) -> ExportResult:
    """The Markdown page (``source``: the file's bytes, for an EDS's ``;CO_`` lines)."""
    page, diags = prepare(dev, source)
    if page is None:
        return ExportResult(None, diags)
    return ExportResult(to_markdown(page), diags)


def prepare(dev, source: bytes | None):
    """(page or None, diagnostics): the model's errors stop it, as every export."""
    diags = model_diagnostics(dev)
    if any(d.severity.value == "error" for d in diags):
        return None, diags
    if not exported_objects(dev):
        diags.append(error("no objects from 0x1000 up: nothing to export", Where(dev.path),
                           "EXP100"))
        return None, diags
    return build(dev, canopennode_settings(dev, source)), diags
