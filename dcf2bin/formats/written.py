"""What every writer of a description format shares: ``Written`` (the bytes and the
warnings), ``Losses`` (what the target format cannot say, one warning per object and kind,
so that nothing is dropped without a word) and the walk over a Device's objects that
every writer makes (the objects of the model, and the objects a CiA 311 file marked
``CO_disabled``, which the model leaves out but a writer of CiA 311 gives back).

The warnings have rule ids CNV0xx (man/dcf2bin-convert.1, docs/convert.md):

* CNV001 -- CompactSubObj has no CiA 311 form: the sub-objects are written one by one;
* CNV002 -- configured values (ParameterValue, Denotation, DownloadFile, the device
  commissioning) in a target that holds none (an EDS, an XDD);
* CNV003 -- what an EDS has no key for: a CiA 311 description, CANopenNode's ``CO_*``
  properties, the kind of PDO mapping (``TPDO``, ``RPDO``, ``default``);
* CNV004 -- the objects marked ``CO_disabled`` left out of an EDS;
* CNV005 -- keys and sections of CiA 306 text that CiA 311 has no place for;
* CNV006 -- an access the object's attribute cannot say, written in the parameter's form;
* CNV007 -- a value that XML cannot hold (a control character);
* CNV008 -- the comment lines of CiA 306 text, which no reader keeps.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin.diagnostics import Diagnostic, Severity

HINTS = {
    "CNV001": "nothing is lost: the sub-objects say what CompactSubObj said",
    "CNV002": "convert to a DCF or an XDC to keep the configured values",
    "CNV003": "convert to an XDD to keep them",
    "CNV004": "remove the CO_disabled property to write an object",
    "CNV005": "CiA 311 has no element for these; keep the DCF/EDS beside the XDD if they "
              "matter",
    "CNV006": "a reader that takes the object's attributes only sees no access",
    "CNV007": "XML 1.0 cannot hold control characters; change the value",
    "CNV008": "no reader keeps comments; the converted file has none",
}


@dataclass
class Written:
    """A description written in a format: its bytes, and the warnings about what the
    format could not say (each naming the object and the source's line)."""
    data: bytes
    diagnostics: list[Diagnostic] = field(default_factory=list)
    ok: bool = True


class Losses:
    """What a writer could not say: (rule, index) -> the words for each sub-object, each
    object rendered as one warning at the source's line of the object."""

    def __init__(self, dev):
        self.dev = dev
        self.found: dict[tuple, list[str]] = {}
        self.lines: dict[tuple, int | None] = {}
        self.texts: dict[tuple, str] = {}

    def add(self, rule: str, index: int | None, what: str, line: int | None = None,
            group: str = "") -> None:
        """``what`` cannot be said of object ``index`` (None: of the file; ``group``, as
        "[FileInfo]", then heads the list)."""
        key = (rule, index, group)
        if key not in self.found:
            self.found[key] = []
            self.lines[key] = line if line is not None else self._line(index)
        if what not in self.found[key]:
            self.found[key].append(what)

    def say(self, rule: str, index: int | None, message: str, line: int | None = None) -> None:
        """One whole message (not a list of things) for ``index``."""
        key = (rule, index, "")
        self.texts[key] = message
        self.lines[key] = line if line is not None else self._line(index)

    def _line(self, index: int | None) -> int | None:
        obj = self.dev.objects.get(index) if index is not None else None
        where = obj.where if obj is not None else None
        return where.line if where is not None else None

    def diagnostics(self, target: str) -> list[Diagnostic]:
        """The warnings, by source line (file-level ones first), then rule."""
        out = []
        for key in sorted(set(self.found) | set(self.texts),
                          key=lambda k: (self.lines[k] or 0, k[1] if k[1] is not None else -1,
                                         k[0], k[2])):
            rule, index, group = key
            if key in self.texts:
                message = self.texts[key]
            else:
                message = _MESSAGES[rule](index, self.found[key], target)
                if group:
                    message = f"{group} {message}"
            out.append(Diagnostic(Severity.WARNING, message, self.dev.path, self.lines[key],
                                  rule=rule, hint=HINTS[rule]))
        return out


def _label(index: int | None) -> str:
    return f"0x{index:04X}: " if index is not None else ""


def _listed(items: list[str], most: int = 4) -> str:
    """'a', 'a and b', 'a, b and c'; past ``most`` items the first three and how many
    more (an array of 254 network variables is one short line)."""
    if len(items) == 1:
        return items[0]
    if len(items) > most:
        return ", ".join(items[:3]) + f" and {len(items) - 3} more"
    return ", ".join(items[:-1]) + " and " + items[-1]


_MESSAGES = {
    "CNV002": lambda i, what, target: (
        f"{_label(i)}{_listed(what)} left out: an {target.upper()} holds no configured values"),
    "CNV003": lambda i, what, target: (
        f"{_label(i)}{_listed(what)} left out: an EDS has no key for "
        f"{'it' if len(what) == 1 else 'them'}"),
    "CNV005": lambda i, what, target: (
        f"{_label(i)}{_listed(what)} left out: CiA 311 has no place for "
        f"{'it' if len(what) == 1 else 'them'}"),
    "CNV006": lambda i, what, target: (
        f"{_label(i)}{_listed(what)} written as the access of "
        f"{'its parameter' if len(what) == 1 else 'their parameters'} (rwr as "
        "readWriteInput, rww as readWriteOutput): the accessType attribute says only const, "
        "ro, wo, rw"),
    "CNV007": lambda i, what, target: (
        f"{_label(i)}{_listed(what)} left out: XML cannot hold its control characters"),
}


# -- the objects a writer writes --------------------------------------------------------------

def objects(dev, *, disabled: bool) -> list:
    """The objects to write, by index: the model's, and (``disabled``) those a CiA 311 file
    marked CO_disabled, built from the sections its reader kept (``XddFile.disabled``)."""
    out = dict(dev.objects)
    if disabled:
        out.update(disabled_objects(dev))
    return [out[i] for i in sorted(out)]


def disabled_objects(dev) -> dict:
    """index -> Obj of the objects marked CO_disabled (none for CiA 306 text)."""
    kept = getattr(dev.ini, "disabled", None)
    if not kept:
        return {}
    from dcf2bin import ini as ini_mod, model
    from dcf2bin.diagnostics import Diagnostics
    parsed = ini_mod.IniFile(dev.path, dev.encoding, dict(kept), [], Diagnostics(),
                             format="xdd")
    return model.build(parsed).objects


def entries(obj) -> list:
    """The entries a writer writes: those of a section of the file (an implied sub 0, or
    the objects CompactPDO implies, the reader makes again)."""
    if obj.implicit:                # CompactPDO's: every entry, for a format without it
        return list(obj.entries.values())
    return [e for e in obj.entries.values() if not e.implicit]


def section_value(obj, key: str) -> str | None:
    """The value of an object-level key of ``obj``'s section (ObjFlags, PDOMapping of an
    ARRAY/RECORD, which its sub-objects inherit), or None."""
    sec = obj.section
    return sec.get(key) if sec is not None else None


def number(text: str | None) -> int | str | None:
    """An integer key's text (ObjFlags, PDOMapping) as its number; None for no text; the
    text as written where it is no integer (the reader reported it, DCF020), which a
    writer writes as it is -- never a number made up in its place."""
    if text is None:
        return None
    from dcf2bin import values
    try:
        return values.parse_int(values.split_numeric_comment(text)[0])
    except values.ValueProblem:
        return text


def section_number(obj, key: str) -> int | str | None:
    """``number`` of an object-level key (``section_value``)."""
    return number(section_value(obj, key))


def own_text(e, key: str) -> str | None:
    """An entry's own text of an integer key where it is no integer: written as it is,
    in place of the number the model could not take from it; None otherwise."""
    n = number(e.section.get(key)) if e.section is not None else None
    return n if isinstance(n, str) else None


def shown(value: str, n: int = 40) -> str:
    """A value named in a loss: whole up to ``n`` characters, else cut with "..."."""
    return value if len(value) <= n else value[:n - 3] + "..."


def disabled_indexes(dev) -> list[int]:
    kept = getattr(dev.ini, "disabled", None) or {}
    return sorted({int(c[:4], 16) for c in kept})


def header(dev, name: str):
    """A header section of the source ([FileInfo], [DeviceInfo], ...), or None."""
    return dev.ini.section(name) if dev.ini is not None else None


def comment_lines(data: bytes, path: str) -> list[Diagnostic]:
    """CNV008 for CiA 306 text with comment lines (';'), which the reader does not keep:
    one warning at the first of them."""
    import re
    found = list(re.finditer(rb"(?m)^[ \t]*;", data))
    if not found:
        return []
    n, line = len(found), data.count(b"\n", 0, found[0].start()) + 1
    return [Diagnostic(Severity.WARNING, f"{n} comment line{'s' if n != 1 else ''} "
                       f"(;...) left out: no reader keeps comments", path, line,
                       rule="CNV008", hint=HINTS["CNV008"])]
