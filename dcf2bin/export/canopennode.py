"""CANopenNode v4's object dictionary (``export --format canopennode``): ``OD.h`` and
``OD.c`` for the object-dictionary interface of CANopenNode's ``301/CO_ODinterface.h``.

What the two files hold (the layout CANopenNode's documentation, doc/objectDictionary.md,
describes and its OD editor writes; the code here is this project's own):

* ``OD.h``: ``OD_CNT_<label>``, how many objects carry each count label (the stack finds
  its objects by them: ``OD_CNT_RPDO 4``); ``OD_CNT_ARR_<index>``, the elements of each
  ARRAY; one structure type per storage group (``OD_RAM_t``, ``OD_PERSIST_COMM_t``, ...)
  with a member per entry that has data, and its ``extern`` variable; ``extern OD_t *OD``;
  ``OD_ENTRY_H<index>`` and ``OD_ENTRY_H<index>_<name>``, the address of each object's
  entry in the list (in parentheses, so that ``OD_ENTRY_H1017->index`` means what it
  says); ``OD_INIT_CONFIG`` for a build with several object dictionaries
  (``CO_MULTIPLE_OD``).
* ``OD.c``: the storage groups' variables at their values; one constant object per OD
  object (``OD_obj_var_t`` for a VAR, ``OD_obj_array_t`` for an ARRAY,
  ``OD_obj_record_t[]`` for a RECORD) with the data's address, its attributes
  (``ODA_SDO_R``/``_W``/``_RW``, ``ODA_TPDO``/``_RPDO``/``_TRPDO``, ``ODA_TSRDO``/
  ``_RSRDO``/``_TRSRDO``, ``ODA_MB`` for a multi-byte number, ``ODA_STR`` for a string)
  and its length; the list of entries by index, ending in a zero entry; ``OD``.

An entry has data in the object dictionary when the file gives it a value (ParameterValue,
else DefaultValue); an empty or missing one leaves the data to the application (NULL), as
CANopenNode's 0x1003 is counted at run time. CANopenNode's own settings (count label,
storage group, SRDO access, least string length) come from the file
(``common.canopennode_settings``) or from the defaults in docs/export.md.
Identifiers are made from the names by CANopenNode's rule (``cname``), so that code
written against another generator's OD.h finds the same names. The output is the same
every run: no date, no tool version.
"""
from __future__ import annotations

import math
import os
import re
import struct
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt, values
from dcf2bin.diagnostics import Where, shorten
from dcf2bin.export.common import (ExportResult, ascii_text, canopennode_settings,
                                   entry_setting, error, exported_objects, model_diagnostics,
                                   object_settings, pdo_direction, warning, written_default)

DEFAULT_NAME = "OD"

# the C type of each CiA 301 type CANopenNode holds as a number
C_TYPES = {"BOOLEAN": "bool_t", "INTEGER8": "int8_t", "INTEGER16": "int16_t",
           "INTEGER32": "int32_t", "INTEGER64": "int64_t", "UNSIGNED8": "uint8_t",
           "UNSIGNED16": "uint16_t", "UNSIGNED32": "uint32_t", "UNSIGNED64": "uint64_t",
           "REAL32": "float32_t", "REAL64": "float64_t"}
MULTI_BYTE = frozenset({"INTEGER16", "INTEGER32", "INTEGER64", "UNSIGNED16", "UNSIGNED32",
                        "UNSIGNED64", "REAL32", "REAL64"})
SDO_ATTR = {"ro": "ODA_SDO_R", "const": "ODA_SDO_R", "wo": "ODA_SDO_W", "rw": "ODA_SDO_RW",
            "rwr": "ODA_SDO_RW", "rww": "ODA_SDO_RW"}
PDO_ATTR = {"t": "ODA_TPDO", "r": "ODA_RPDO", "tr": "ODA_TRPDO"}
SRDO_ATTR = {"tx": "ODA_TSRDO", "rx": "ODA_RSRDO", "trx": "ODA_TRSRDO", "no": ""}
# the COB-IDs to which CANopenNode's stack adds the node-ID itself: a $NODEID in their
# values is left out (EMCY, SDO servers, SRDOs, PDOs)
NODE_ID_ADDED = ((0x1014, 0x1014), (0x1200, 0x127F), (0x1301, 0x1340), (0x1400, 0x15FF),
                 (0x1800, 0x19FF))
C_KEYWORDS = frozenset(
    "auto break case char const continue default do double else enum extern float for goto "
    "if inline int long register restrict return short signed sizeof static struct switch "
    "typedef union unsigned void volatile while bool true false".split())
# CO_config_t's members that OD_INIT_CONFIG sets (CANopenNode's CANopen.h): ("CNT", label)
# is a count, ("ARR", index) an array's size, ("ENTRY", index) an object's entry; None
# members are counts no object dictionary gives (LEDs, LSS, gateway, trace: 0)
CONFIG = (("CNT_NMT", "CNT", "NMT"), ("ENTRY_H1017", "ENTRY", 0x1017),
          ("CNT_HB_CONS", "CNT", "HB_CONS"), ("CNT_ARR_1016", "ARR", 0x1016),
          ("ENTRY_H1016", "ENTRY", 0x1016), ("CNT_EM", "CNT", "EM"),
          ("ENTRY_H1001", "ENTRY", 0x1001), ("ENTRY_H1014", "ENTRY", 0x1014),
          ("ENTRY_H1015", "ENTRY", 0x1015), ("CNT_ARR_1003", "ARR", 0x1003),
          ("ENTRY_H1003", "ENTRY", 0x1003), ("CNT_SDO_SRV", "CNT", "SDO_SRV"),
          ("ENTRY_H1200", "ENTRY", 0x1200), ("CNT_SDO_CLI", "CNT", "SDO_CLI"),
          ("ENTRY_H1280", "ENTRY", 0x1280), ("CNT_TIME", "CNT", "TIME"),
          ("ENTRY_H1012", "ENTRY", 0x1012), ("CNT_SYNC", "CNT", "SYNC"),
          ("ENTRY_H1005", "ENTRY", 0x1005), ("ENTRY_H1006", "ENTRY", 0x1006),
          ("ENTRY_H1007", "ENTRY", 0x1007), ("ENTRY_H1019", "ENTRY", 0x1019),
          ("CNT_RPDO", "CNT", "RPDO"), ("ENTRY_H1400", "ENTRY", 0x1400),
          ("ENTRY_H1600", "ENTRY", 0x1600), ("CNT_TPDO", "CNT", "TPDO"),
          ("ENTRY_H1800", "ENTRY", 0x1800), ("ENTRY_H1A00", "ENTRY", 0x1A00),
          ("CNT_LEDS", None, None), ("CNT_GFC", "CNT", "GFC"),
          ("ENTRY_H1300", "ENTRY", 0x1300), ("CNT_SRDO", "CNT", "SRDO"),
          ("ENTRY_H1301", "ENTRY", 0x1301), ("ENTRY_H1381", "ENTRY", 0x1381),
          ("ENTRY_H13FE", "ENTRY", 0x13FE), ("ENTRY_H13FF", "ENTRY", 0x13FF),
          ("CNT_LSS_SLV", None, None), ("CNT_LSS_MST", None, None),
          ("CNT_GTWA", None, None), ("CNT_TRACE", None, None))


def cname(name: str) -> str:
    """A C name made of an object's name by CANopenNode's rule: '-' becomes '_'; the name
    is cut into words at every character that is no ASCII letter, digit or '_'; the words
    are joined, each word of two or more characters that starts with a letter with that
    letter upper-cased, and with '_' between a word ending and the next starting with an
    upper-case letter; a name starting with a digit gets a leading '_', and the first
    letter is lower-cased when the second is lower-case (or when it is the only one).
    "COB-ID SYNC message" -> "COB_ID_SYNCMessage", "Highest sub-index supported" ->
    "highestSub_indexSupported", "" -> ""."""
    words = [w for w in re.split(r"[^A-Za-z0-9_]+", name.replace("-", "_")) if w]
    out, prev = "", " "
    for w in words:
        if prev.isupper() and w[0].isupper():
            out += "_"
        out += w[0].upper() + w[1:] if len(w) > 1 and w[0].isalpha() else w
        prev = w[-1]
    if not out:
        return ""
    if out[0].isdigit():
        return "_" + out
    if len(out) == 1:
        return out.lower()
    if out[0].isalpha() and out[1].islower():
        return out[0].lower() + out[1:]
    return out


@dataclass
class Data:
    """One entry's data as CANopenNode holds it."""
    ctype: str                  # the C type of one element ("uint32_t", "char")
    dims: str = ""              # "[N]" for a string or byte array, else ""
    init: str | None = None     # the C initializer; None: no data in the OD (NULL)
    length: int = 0             # dataLength in bytes (0: not given)
    attribute: str = "0"        # the ODA_* expression

    @property
    def shape(self) -> tuple:
        return (self.ctype, self.dims, self.length)

    @property
    def index0(self) -> str:
        """What takes the first element's address of an array-typed member."""
        return "[0]" if self.dims else ""


@dataclass
class Built:
    """What the two files are made of."""
    name: str
    counts: dict[str, int] = field(default_factory=dict)      # label -> objects
    arrays: dict[int, int] = field(default_factory=dict)      # index -> elements
    groups: dict[str, list[tuple[str, str]]] = field(default_factory=dict)  # (decl, init)
    objs_t: list[str] = field(default_factory=list)
    objs: list[list[str]] = field(default_factory=list)
    entries: list[tuple[int, int, str, str, str]] = field(default_factory=list)
    # (index, sub-entries, ODT kind, variable name, its name part)


class _Builder:
    """Turns the model into ``Built``, collecting diagnostics."""

    def __init__(self, dev, settings: dict, name: str):
        self.dev, self.settings = dev, settings
        self.out = Built(name)
        self.diags: list = []

    def run(self) -> Built:
        for obj in exported_objects(self.dev):
            s = object_settings(self.dev, self.settings, obj, self.diags)
            var = f"{obj.index:04X}" + (f"_{n}" if (n := cname(obj.name)) else "")
            if not obj.complex:
                done = self.var(obj, var, s.storage_group)
            elif obj.object_type == dt.OT_ARRAY:
                done = self.array(obj, var, s.storage_group)
            else:
                done = self.record(obj, var, s.storage_group)
            if done is None:
                continue
            self.out.entries.append((obj.index, done[0], done[1], var, cname(obj.name)))
            if s.count_label:
                self.out.counts[s.count_label] = self.out.counts.get(s.count_label, 0) + 1
        return self.out

    # -- one entry ----------------------------------------------------------------------
    def data(self, entry, obj) -> Data | None:
        """The entry's C data, or None after an error."""
        t = entry.dtype
        if t is None:
            return None         # the model already said so
        text = entry.param if entry.param is not None else written_default(entry)
        if entry.param is None and entry.download_file is not None:
            self.diags.append(warning(
                f"{entry.label}: the DownloadFile is not put into the object dictionary; "
                "the application gives the data", entry.key_where("downloadfile"), "EXP313"))
        if t.kind == dt.DOMAIN:
            if text:
                self.diags.append(warning(
                    f"{entry.label}: a DOMAIN holds no data in CANopenNode's object "
                    "dictionary; its value is left out", entry.value_where, "EXP313"))
            attribute = self.attrs(entry, obj, t)
            return Data("uint8_t", attribute=attribute) if attribute is not None else None
        raw = self.encode(entry, text) if text else b""
        if raw is None:
            return None
        at_least = self.least_length(entry, obj)
        if at_least is None:
            return None
        d = self.shape(entry, t, raw, bool(text), at_least)
        attribute = self.attrs(entry, obj, t)
        if d is None or attribute is None:
            return None
        d.attribute = attribute
        return d

    def shape(self, entry, t, raw: bytes, given: bool, at_least: int) -> Data | None:
        if t.name in C_TYPES:
            init = _number(t, raw) if given else None
            if init is None and given:
                self.diags.append(error(f"{entry.label}: {t.name} value '{shorten(entry.value_text)}' "
                                        "is not finite and has no C initializer",
                                        entry.value_where, "EXP314"))
                return None
            return Data(C_TYPES[t.name], "", init, t.size)
        if t.kind == dt.VSTRING:
            n = max(len(raw), at_least)
            return Data("char", f"[{n + 1}]", _string(raw) if n else None, n)
        if t.kind == dt.USTRING:
            words = [int.from_bytes(raw[k:k + 2], "little") for k in range(0, len(raw), 2)]
            n = max(len(words), at_least)
            words += [0] * (n + 1 - len(words))
            init = "{" + ", ".join(f"0x{w:04X}" for w in words) + "}" if n else None
            return Data("uint16_t", f"[{n + 1}]", init, 2 * n)
        if t.kind == dt.OSTRING:
            n = max(len(raw), at_least)
            data = raw + bytes(n - len(raw))
            return Data("uint8_t", f"[{n}]", _bytes(data) if n else None, n)
        # 24/40/48/56-bit integers, TIME_OF_DAY, TIME_DIFFERENCE: their bytes
        return Data("uint8_t", f"[{t.size}]", _bytes(raw) if given else None, t.size)

    def encode(self, entry, text: str) -> bytes | None:
        t = entry.dtype
        if t.is_numeric or t.kind == dt.BOOL:
            text, comment = values.split_numeric_comment(text)
            if comment is not None:
                self.diags.append(warning(f"{entry.label}: comment '{shorten(comment)}' after the "
                                          "number is ignored", entry.value_where, "DCF203"))
        if values.uses_nodeid(text) and t.is_numeric:
            if not any(a <= entry.index <= b for a, b in NODE_ID_ADDED):
                self.diags.append(warning(
                    f"{entry.label}: '{shorten(text)}' is written without $NODEID; CANopenNode adds "
                    "the node-ID only to the pre-defined COB-IDs of EMCY, SDO servers, "
                    "SRDOs and PDOs", entry.value_where, "EXP312",
                    "give the value for the node, or add the node-ID in the application"))
        try:
            return values.encode(t, text, node_id=0, encoding=self.dev.encoding)
        except values.ValueProblem as exc:
            self.diags.append(error(f"{entry.label}: {values.clip(str(exc))}",
                                    entry.value_where, "DCF200"))
            return None

    def least_length(self, entry, obj) -> int | None:
        said = entry_setting(self.settings, entry, obj, "CO_stringLengthMin")
        if said is None:
            return 0
        text, line = said
        if text.strip().isdigit() and int(text) <= 0xFFFF:
            return int(text)
        self.diags.append(error(f"{entry.label}: CO_stringLengthMin '{shorten(text)}' is not a "
                                "length from 0 to 65535", _where(entry, line), "EXP310"))
        return None

    def attrs(self, entry, obj, t) -> str | None:
        """The ODA_* expression, or None after an error."""
        names = [SDO_ATTR.get(entry.access or "", ""),
                 PDO_ATTR.get(pdo_direction(self.dev, entry, obj), "")]
        said = entry_setting(self.settings, entry, obj, "CO_accessSRDO")
        if said is not None:
            srdo = SRDO_ATTR.get(said[0].strip())
            if srdo is None:
                self.diags.append(error(f"{entry.label}: CO_accessSRDO '{shorten(said[0])}' is none "
                                        "of tx, rx, trx, no", _where(entry, said[1]),
                                        "EXP310"))
                return None
            names.append(srdo)
        names.append("ODA_MB" if t.name in MULTI_BYTE else "")
        names.append("ODA_STR" if t.kind in (dt.VSTRING, dt.USTRING) else "")
        return " | ".join(n for n in names if n) or "0"

    # -- objects ----------------------------------------------------------------------------
    def member(self, group: str, decl: str, init: str) -> None:
        self.out.groups.setdefault(group, []).append((decl, init))

    def var(self, obj, var: str, group: str):
        e = obj.entries.get(0)
        d = self.data(e, obj) if e is not None else None
        if d is None:
            return None
        ptr = "NULL"
        if d.init is not None:
            self.member(group, f"{d.ctype} x{var}{d.dims};", f".x{var} = {d.init}")
            ptr = f"&{self.out.name}_{group}.x{var}{d.index0}"
        self.out.objs_t.append(f"OD_obj_var_t o_{var};")
        self.out.objs.append([f".o_{var} = {{", f"    .dataOrig = {ptr},",
                              f"    .attribute = {d.attribute},",
                              f"    .dataLength = {d.length}", "}"])
        return 1, "VAR"

    def array(self, obj, var: str, group: str):
        entries = obj.sorted_entries()
        label = f"0x{obj.index:04X}"
        why = None
        if len(entries) < 2:
            why = "it has no element after sub-index 0"
        elif [e.sub for e in entries] != list(range(len(entries))):
            why = "its sub-indexes are not 0, 1, 2, ... without a gap"
        elif len(entries) > 255:
            why = f"it has {len(entries)} sub-indexes (CANopenNode counts at most 255)"
        if why and len(entries) > 255:
            return self.refuse(obj, f"{label} cannot be a CANopenNode ARRAY: {why}")
        if why:
            return self.as_record(obj, var, group, why)
        data = [self.data(e, obj) for e in entries]
        if any(d is None for d in data):
            return None
        d0, first = data[0], data[1]
        if d0.shape != ("uint8_t", "", 1):
            return self.refuse(obj, f"{label}: sub-index 0 of an ARRAY is UNSIGNED8 in "
                               "CANopenNode")
        for e, d in zip(entries[2:], data[2:]):
            if d.shape != first.shape or d.attribute != first.attribute:
                return self.as_record(obj, var, group, f"sub-index 0x{e.sub:02X} differs from "
                                      "sub-index 0x01 in data type, length or access")
            if (d.init is None) != (first.init is None):
                return self.as_record(obj, var, group,
                                      "some elements have a value and some have none")
        n, name = len(entries) - 1, self.out.name
        self.out.arrays[obj.index] = n
        ptr0 = ptr = "NULL"
        if d0.init is not None:
            self.member(group, f"uint8_t x{var}_sub0;", f".x{var}_sub0 = {d0.init}")
            ptr0 = f"&{name}_{group}.x{var}_sub0"
        if first.init is not None:
            self.member(group, f"{first.ctype} x{var}[{name}_CNT_ARR_{obj.index:04X}]"
                               f"{first.dims};",
                        f".x{var} = {{{', '.join(d.init for d in data[1:])}}}")
            ptr = f"&{name}_{group}.x{var}[0]{first.index0}"
        size = "0" if entries[1].dtype.kind == dt.DOMAIN else f"sizeof({first.ctype}{first.dims})"
        self.out.objs_t.append(f"OD_obj_array_t o_{var};")
        self.out.objs.append([f".o_{var} = {{", f"    .dataOrig0 = {ptr0},",
                              f"    .dataOrig = {ptr},", f"    .attribute0 = {d0.attribute},",
                              f"    .attribute = {first.attribute},",
                              f"    .dataElementLength = {first.length},",
                              f"    .dataElementSizeof = {size}", "}"])
        return len(entries), "ARR"

    def as_record(self, obj, var: str, group: str, why: str):
        """An ARRAY that is no C array (CANopenNode's OD_obj_array_t is one: elements of one
        type, length, access and kind of value, sub-indexes 0..n): the stack reads and
        writes it as well as a RECORD, so it is written as one, with a warning -- the
        application reaches its elements as members of a struct, not by an index."""
        self.diags.append(warning(
            f"0x{obj.index:04X} is written as a RECORD: it cannot be a CANopenNode ARRAY "
            f"({why}); the stack serves it the same, the application reaches its elements as "
            "struct members", obj.where, "EXP317",
            "give its elements one type, access and kind of value to keep it an ARRAY"))
        return self.record(obj, var, group)

    def record(self, obj, var: str, group: str):
        entries = obj.sorted_entries()
        if len(entries) > 255:
            return self.refuse(obj, f"0x{obj.index:04X} has {len(entries)} sub-indexes "
                               "(CANopenNode counts at most 255)")
        data = [self.data(e, obj) for e in entries]
        if any(d is None for d in data):
            return None
        e0 = obj.entries.get(0)
        if e0 is not None and data[0].shape != ("uint8_t", "", 1):
            return self.refuse(obj, f"0x{obj.index:04X}: sub-index 0 of a RECORD is "
                               "UNSIGNED8 in CANopenNode")
        members, inits, rows, taken = [], [], [], {}
        for e, d in zip(entries, data):
            m = _member_name(e, taken, self.diags)
            ptr = "NULL"
            if d.init is not None:
                members.append(f"{d.ctype} {m}{d.dims};")
                inits.append(f".{m} = {d.init}")
                ptr = f"&{self.out.name}_{group}.x{var}.{m}{d.index0}"
            rows += ["    {", f"        .dataOrig = {ptr},", f"        .subIndex = {e.sub},",
                     f"        .attribute = {d.attribute},",
                     f"        .dataLength = {d.length}", "    },"]
        rows[-1] = "    }"
        if members:
            self.member(group, "struct {\n" + "\n".join("    " + m for m in members)
                        + f"\n}} x{var};",
                        f".x{var} = {{\n" + ",\n".join("    " + i for i in inits) + "\n}")
        self.out.objs_t.append(f"OD_obj_record_t o_{var}[{len(entries)}];")
        self.out.objs.append([f".o_{var} = {{", *rows, "}"])
        return len(entries), "REC"

    def refuse(self, obj, message: str):
        self.diags.append(error(message, obj.where, "EXP316",
                                "make it a RECORD (ObjectType=0x9), or give its elements one "
                                "type, access and kind of value"))
        return None


def _member_name(entry, taken: dict, diags: list) -> str:
    """A sub-entry's member name: its C name; the sub-index where the name gives none,
    is a C keyword, or is taken by an earlier sub-entry (warning EXP315)."""
    m = cname(entry.name)
    if not m or m in C_KEYWORDS:
        m = f"{m}_sub{entry.sub:X}" if m else f"sub{entry.sub:X}"
    if m in taken:
        first = taken[m]
        m2 = f"{m}_sub{entry.sub:X}"
        diags.append(warning(
            f"{entry.label}: its C name '{shorten(m)}' is taken by sub-index 0x{first:02X}; "
            f"it is named '{shorten(m2)}'", entry.where, "EXP315",
            "give the sub-entries different names"))
        m = m2
    taken[m] = entry.sub
    return m


def _where(entry, line: int | None) -> Where:
    w = entry.where or Where("")
    return Where(w.file, line) if line is not None else w


# -- C literals -------------------------------------------------------------------------------

def _number(t, raw: bytes) -> str | None:
    """The C literal of a number's bytes; None for a REAL that is not finite."""
    if t.kind == dt.BOOL:
        return "true" if raw[0] else "false"
    if t.kind == dt.REAL:
        v = struct.unpack("<f" if t.size == 4 else "<d", raw)[0]
        if not math.isfinite(v):
            return None
        return _real(v, t.size == 4)
    if t.kind == dt.SINT:
        v = int.from_bytes(raw, "little", signed=True)
        if v == t.min:                  # -2147483648 is no C literal: a minus and a number
            return f"({t.min + 1} - 1)"
        return str(v)
    return f"0x{int.from_bytes(raw, 'little'):0{2 * t.size}X}"


def _real(v: float, single: bool) -> str:
    """The shortest decimal that reads back as the same float32 (suffix f) or double."""
    if single:
        for digits in range(1, 10):
            text = f"{v:.{digits}g}"
            if struct.unpack("<f", struct.pack("<f", float(text)))[0] == v:
                break
    else:
        text = repr(v)
    if not any(c in text for c in ".en"):
        text += ".0"
    return text + ("f" if single else "")


def _string(raw: bytes) -> str:
    """A C string literal of the bytes; what is not printable ASCII, and the characters a
    C string or a trigraph would read otherwise, as octal escapes."""
    out = []
    for b in raw:
        if 32 <= b < 127 and chr(b) not in '"\\?':
            out.append(chr(b))
        else:
            out.append(f"\\{b:03o}")
    return '"' + "".join(out) + '"'


def _bytes(data: bytes) -> str:
    return "{" + ", ".join(f"0x{b:02X}" for b in data) + "}"


# -- the files --------------------------------------------------------------------------------

def _banner(dev, b: Built, what: str) -> list[str]:
    """The first lines of both files: what they are, and of which description."""
    def v(section: str, key: str) -> str:
        sec = dev.ini.sections.get(section) if dev.ini is not None else None
        return ascii_text(sec.values.get(key, "")) if sec is not None else ""
    source = ascii_text(os.path.basename(dev.path))
    lines = ["/*", f"    {b.name}.{what}: CANopenNode v4 object dictionary "
             f"({b.name}.h, {b.name}.c)", f"    of {source}"]
    for label, section, key in (("Product", "deviceinfo", "productname"),
                                ("Vendor", "deviceinfo", "vendorname"),
                                ("File version", "fileinfo", "fileversion"),
                                ("Modified", "fileinfo", "modificationdate")):
        text = v(section, key).replace("*/", "* /")
        if text:
            lines.append(f"    {label}: {text}")
    lines += ["", "    Written by dcf2bin export --format canopennode: change the description",
              "    and export again rather than editing this file.", "*/", ""]
    return lines


def h_file(dev, b: Built) -> str:
    n = b.name
    L = _banner(dev, b, "h") + [f"#ifndef {n}_H", f"#define {n}_H", "",
                                "/* How many objects carry each count label */"]
    L += [f"#define {n}_CNT_{label} {k}" for label, k in b.counts.items()]
    L += ["", "/* How many elements each ARRAY has (sub-index 0 not counted) */"]
    L += [f"#define {n}_CNT_ARR_{index:04X} {k}" for index, k in b.arrays.items()]
    L += ["", "/* The data of the object dictionary, one structure per storage group */"]
    for group, members in b.groups.items():
        L.append("typedef struct {")
        L += ["    " + ln for decl, _ in members for ln in decl.split("\n")]
        L += [f"}} {n}_{group}_t;", ""]
    for group in b.groups:
        L += [f"#ifndef {n}_ATTR_{group}", f"#define {n}_ATTR_{group}", "#endif",
              f"extern {n}_ATTR_{group} {n}_{group}_t {n}_{group};", ""]
    L += [f"#ifndef {n}_ATTR_OD", f"#define {n}_ATTR_OD", "#endif",
          f"extern {n}_ATTR_OD OD_t *{n};", "", "/* Each object's entry, by index */"]
    L += [f"#define {n}_ENTRY_H{i:04X} (&{n}->list[{k}])"
          for k, (i, *_) in enumerate(b.entries)]
    L += ["", "/* Each object's entry, by index and name */"]
    L += [f"#define {n}_ENTRY_H{var} (&{n}->list[{k}])"
          for k, (_, _, _, var, part) in enumerate(b.entries) if part]
    L += ["", "/* CANopenNode's configuration from this object dictionary, for a build with",
          "   several object dictionaries (CO_MULTIPLE_OD) */", "#ifdef CO_MULTIPLE_OD",
          f"#define {n}_INIT_CONFIG(config) {{\\"]
    present = {i for i, *_ in b.entries}
    for member, kind, key in CONFIG:
        if kind == "CNT":
            value = f"{n}_CNT_{key}" if key in b.counts else "0"
        elif kind == "ARR":
            value = f"{n}_CNT_ARR_{key:04X}" if key in b.arrays else "0"
        elif kind == "ENTRY":
            value = f"{n}_ENTRY_H{key:04X}" if key in present else "NULL"
        else:
            value = "0"
        L.append(f"    (config).{member} = {value};\\")
    L += ["}", "#endif", "", f"#endif /* {n}_H */", ""]
    return "\n".join(L)


def c_file(dev, b: Built) -> str:
    n = b.name
    L = _banner(dev, b, "c") + ["#define OD_DEFINITION", '#include "301/CO_ODinterface.h"',
                                f'#include "{n}.h"', "", "#if CO_VERSION_MAJOR < 4",
                                "#error This object dictionary is for CANopenNode v4 or later",
                                "#endif", "", "/* The data, at their values */"]
    for group, members in b.groups.items():
        L.append(f"{n}_ATTR_{group} {n}_{group}_t {n}_{group} = {{")
        inits = [init for _, init in members]
        for k, init in enumerate(inits):
            lines = init.split("\n")
            lines[-1] += "," if k < len(inits) - 1 else ""
            L += ["    " + ln for ln in lines]
        L += ["};", ""]
    L += ["/* Every object: where its data is, its attributes and length */", "typedef struct {"]
    L += ["    " + t for t in b.objs_t]
    L += [f"}} {n}Objs_t;", "", f"static CO_PROGMEM {n}Objs_t {n}Objs = {{"]
    for k, lines in enumerate(b.objs):
        lines = list(lines)
        lines[-1] += "," if k < len(b.objs) - 1 else ""
        L += ["    " + ln for ln in lines]
    L += ["};", "", "/* The object dictionary: every object's entry by index, then an empty one */",
          f"static {n}_ATTR_OD OD_entry_t {n}List[] = {{"]
    for index, count, kind, var, _ in b.entries:
        L.append(f"    {{0x{index:04X}, 0x{count:02X}, ODT_{kind}, &{n}Objs.o_{var}, NULL}},")
    L += ["    {0x0000, 0x00, 0, NULL, NULL}", "};", "",
          f"static OD_t {n}Dictionary = {{", f"    (sizeof({n}List) / sizeof({n}List[0])) - 1,",
          f"    &{n}List[0]", "};", "", f"OD_t *{n} = &{n}Dictionary;", ""]
    return "\n".join(L)


def export(dev, *, source: bytes | None = None, od_name: str = DEFAULT_NAME,
           **_ignored) -> ExportResult:
    """{"<name>.h": text, "<name>.c": text} (``source``: the file's bytes, for an EDS's
    ``;CO_`` lines; ``od_name``: the files' and the C names' stem, "OD")."""
    diags = model_diagnostics(dev)
    if any(d.severity.value == "error" for d in diags):
        return ExportResult(None, diags)
    if not exported_objects(dev):
        diags.append(error("no objects from 0x1000 up: nothing to export", Where(dev.path),
                           "EXP100"))
        return ExportResult(None, diags)
    builder = _Builder(dev, canopennode_settings(dev, source), od_name)
    built = builder.run()
    diags += builder.diags
    if any(d.severity.value == "error" for d in diags):
        return ExportResult(None, diags)
    return ExportResult({f"{od_name}.h": h_file(dev, built),
                         f"{od_name}.c": c_file(dev, built)}, diags)
