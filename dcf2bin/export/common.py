"""What the export formats share: the result type, the exported objects, value encoding and
one-line diagnostics, an entry's values as the file writes them and its PDO direction, and
CANopenNode's own settings as a file states them. Every format module builds on it;
``export/__init__`` dispatches."""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin.diagnostics import DcfError, Diagnostic, Severity, Where, shorten

FORMATS = ("lenze-st", "lenze-bin", "port-c", "markdown", "html", "canopennode")
FIRST_INDEX = 0x1000


@dataclass
class ExportResult:
    # the output; a dict (file name -> text) for a format that writes several files;
    # None when errors stop the export
    output: bytes | str | dict[str, str] | None
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return self.output is not None

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.severity is Severity.ERROR]


def model_diagnostics(dev) -> list[Diagnostic]:
    """The model's problems; errors about objects that are not exported become warnings."""
    out = []
    for p in dev.problems:
        d = p.diagnostic
        if d.severity is Severity.ERROR and p.index is not None and p.index < FIRST_INDEX:
            d = Diagnostic(Severity.WARNING, d.message + " (not exported)", d.file, d.line,
                           d.column, d.offset, d.rule, d.hint)
        out.append(d)
    return out


def exported_objects(dev) -> list:
    return [o for o in dev.sorted_objects() if o.index >= FIRST_INDEX]


def encode(dev, entry, errors: list[Diagnostic]) -> bytes | None:
    """The entry's value bytes, or None after appending the error."""
    if entry.dtype is None:
        return None  # the model already reported the missing/unknown DataType
    try:
        return dev.encode(entry)
    except DcfError as exc:
        errors.append(exc.diagnostic)
        return None


def warning(message: str, where, rule: str, hint: str = "") -> Diagnostic:
    return Diagnostic(Severity.WARNING, message, where.file if where else "",
                      where.line if where else None, None, None, rule, hint)


def error(message: str, where, rule: str, hint: str = "") -> Diagnostic:
    return Diagnostic(Severity.ERROR, message, where.file if where else "",
                      where.line if where else None, None, None, rule, hint)


def ascii_text(text: str) -> str:
    """A name made safe for a comment in generated source: ASCII, one line."""
    out = []
    for ch in text:
        if ch in "\r\n\t":
            out.append(" ")
        elif 32 <= ord(ch) < 127:
            out.append(ch)
        else:
            out.append("?")
    return "".join(out).strip()


# -- an entry as the file writes it ---------------------------------------------------------

def written_default(entry) -> str | None:
    """The DefaultValue as the file writes it, None when it gives none or an empty one. The
    model fills an ARRAY/RECORD's sub 0 that has no value with the highest subindex (SPEC
    §1); a description that leaves it empty (CANopenNode's 0x1003 sub 0, counted at run
    time) is documented and exported empty, as written. An entry without a section of its
    own (created by the model, or a CompactSubObj element) has the model's value."""
    sec = entry.section
    if sec is None:
        return entry.default
    return sec.values.get("defaultvalue") or None


def pdo_direction(dev, entry, obj) -> str:
    """How the entry may be mapped: "" (not at all), "t" (into a TPDO), "r" (from an RPDO)
    or "tr" (either). A CiA 311 file's PDOmapping TPDO or RPDO says it; a mappable entry
    otherwise (PDOMapping=1, PDOmapping optional or default) is mapped as a PDO reads and
    writes it (SPEC §5: ro, const and rwr are read by a TPDO; wo and rww written by an
    RPDO; rw both)."""
    said = dev.specifics.get((entry.index, entry.sub if obj.complex else None), {})
    word = said.get("PDOmapping")
    if word in ("TPDO", "RPDO"):
        return word[0].lower()
    if not entry.pdo_mapping:
        return ""
    access = entry.access or ""
    return ("t" if access in dt.READABLE else "") + ("r" if access in dt.WRITABLE else "")


def description(dev, entry, obj) -> str:
    """A CiA 311 parameter's description (text, as written), "" when it has none or only
    repeats the entry's name (the reader takes a parameter's label when it has no
    description)."""
    said = dev.specifics.get((entry.index, entry.sub if obj.complex else None), {})
    text = said.get("description", "")
    name = obj.name if not obj.complex else entry.name
    return "" if text.strip() == name.strip() else text


def object_description(dev, obj) -> str:
    """The description of an ARRAY/RECORD object itself ("" when none, or only its name)."""
    text = dev.specifics.get((obj.index, None), {}).get("description", "")
    return "" if text.strip() == obj.name.strip() else text


# -- CANopenNode's own settings ---------------------------------------------------------------

# The settings CANopenNode's object dictionary takes beyond CiA 306/311 (CANopenEditor's
# ``property`` elements); an EDS states them as comment lines ";CO_name=value" in the
# object's or entry's section, and CANopenEditor writes the storage group there as
# ";StorageLocation=NAME".
CO_SETTINGS = ("CO_countLabel", "CO_storageGroup", "CO_accessSRDO", "CO_stringLengthMin")
_EDS_ALIASES = {"storagelocation": "CO_storageGroup"}
_SECTION_RE = re.compile(r"\[\s*([0-9A-Fa-f]{4})(?:sub([0-9A-Fa-f]{1,3}))?\s*\]\s*$")
_COMMENT_RE = re.compile(r";\s*([A-Za-z_]+)\s*=(.*)$")


def canopennode_settings(dev, source: bytes | None) -> dict:
    """(index, subindex or None for the object) -> {CO name: (value, line or None)}: what
    the file states of CANopenNode's settings. A CiA 311 file states them as ``property``
    elements (``dev.specifics``, no line of their own); a CiA 306 file as comment lines,
    read from ``source`` (its bytes), each with its line."""
    out: dict = {}
    if dev.ini is not None and dev.ini.format != "ini":
        for key, said in dev.specifics.items():
            got = {k: (v, None) for k, v in said.items() if k in CO_SETTINGS}
            if got:
                out[key] = got
        return out
    if not source:
        return out
    from dcf2bin import ini as ini_mod
    text = ini_mod.decode_bytes(source)[0]
    where = None
    for n, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        m = _SECTION_RE.match(stripped)
        if m:
            sub = m.group(2)
            where = (int(m.group(1), 16), int(sub, 16) if sub is not None else None)
            continue
        if stripped.startswith("["):
            where = None
            continue
        m = _COMMENT_RE.match(stripped)
        if m is None or where is None:
            continue
        name = _EDS_ALIASES.get(m.group(1).lower(), m.group(1))
        if name in CO_SETTINGS:
            out.setdefault(where, {})[name] = (m.group(2).strip(), n)
    return out


# CANopenNode's stack finds the objects it runs on by these count labels
# (OD_CNT_<label>); the ranges are the ones CANopenNode's "Object Dictionary Requirements"
# table gives. An object in a range gets its label when the file states none.
STANDARD_COUNT_LABELS = (
    (0x1000, 0x1000, "NMT"), (0x1001, 0x1001, "EM"), (0x1005, 0x1005, "SYNC"),
    (0x1006, 0x1006, "SYNC_PROD"), (0x1010, 0x1010, "STORAGE"), (0x1012, 0x1012, "TIME"),
    (0x1014, 0x1014, "EM_PROD"), (0x1016, 0x1016, "HB_CONS"), (0x1017, 0x1017, "HB_PROD"),
    (0x1200, 0x127F, "SDO_SRV"), (0x1280, 0x12FF, "SDO_CLI"), (0x1300, 0x1300, "GFC"),
    (0x1301, 0x1340, "SRDO"), (0x1400, 0x15FF, "RPDO"), (0x1800, 0x19FF, "TPDO"))
DEFAULT_STORAGE_GROUP = "RAM"
_WORD_RE = re.compile(r"[A-Za-z0-9_]+")


def standard_count_label(index: int) -> str:
    for first, last, label in STANDARD_COUNT_LABELS:
        if first <= index <= last:
            return label
    return ""


@dataclass(frozen=True)
class ObjectSettings:
    """CANopenNode's settings of one object as its object dictionary gets them."""
    count_label: str            # "" for none
    storage_group: str


def object_settings(dev, settings: dict, obj, diags: list | None = None) -> ObjectSettings:
    """The count label and storage group of ``obj``: as the file states them, else the
    standard label of its index and storage group RAM. A stated label that is not the
    standard one of a standard object is replaced by it (CANopenNode's stack needs it),
    with warning EXP311 appended to ``diags``; a label or group that cannot be part of a
    C name is error EXP310."""
    said = settings.get((obj.index, None), {})
    standard = standard_count_label(obj.index)
    label, line = said.get("CO_countLabel", ("", None))
    where = Where(obj.where.file if obj.where else dev.path,
                  line if line is not None else (obj.where.line if obj.where else None))
    label = label.strip()
    if standard and label != standard:
        if diags is not None:
            what = f"states count label '{shorten(label)}'" if label else "states no count label"
            # an EDS states no label (CANopenEditor writes none), nor does a CiA 311 file
            # from a tool that knows nothing of CANopenNode: the standard label goes
            # without a word; a CANopenNode project that left it out is told
            if label or (settings and getattr(dev.ini, "format", "ini") != "ini"):
                diags.append(warning(
                    f"0x{obj.index:04X} {what}; CANopenNode's stack needs {standard} there, "
                    "which is used", where, "EXP311",
                    f"set CO_countLabel to {standard}"))
        label = standard
    group, gline = said.get("CO_storageGroup", (DEFAULT_STORAGE_GROUP, None))
    group = group.strip() or DEFAULT_STORAGE_GROUP
    if diags is not None:
        for what, value, at in (("count label", label, line), ("storage group", group, gline)):
            if value and not _WORD_RE.fullmatch(value):
                diags.append(error(
                    f"0x{obj.index:04X}: {what} '{shorten(value)}' cannot be part of a C name",
                    Where(where.file, at if at is not None else where.line), "EXP310",
                    "use letters, digits and '_' only"))
    return ObjectSettings(label, group)


def entry_setting(settings: dict, entry, obj, name: str) -> tuple[str, int | None] | None:
    """A setting of one entry (CO_accessSRDO, CO_stringLengthMin): (value, line), or None."""
    return settings.get((entry.index, entry.sub if obj.complex else None), {}).get(name)
