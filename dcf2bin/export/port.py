"""port CANopen Library object dictionary as C source (seed 002, SPEC §7).

The library's OD is an index-sorted array of ``LIST_ELEMENT_T {pObj, pValDesc, index,
numOfElem}``; ``pValDesc`` points to one ``VALUE_DESC_T {pDefaultVal, varType, attribute}``
per subindex (or, with CO_SHORT_ARRAY_DESC on sub 0, to sub 0 and sub 1 only, sub 1
standing for all identical subindexes 1..n). This module plans that structure from the
model (``plan``) and writes it as C (``to_c``). The conventions of the generated source,
documented in docs/export.md:

* Data: one variable per object, named PREFIX + 4 hex digits (``od_1018``). A VAR is a
  variable of its type; an ARRAY/RECORD is a byte-packed struct (``#pragma pack(1)``) with
  one member per subindex 0..n, so subindex k lies at the sum of the sizes of 0..k-1 (the
  library's addressing without CONFIG_ALIGNMENT). Data variables start at the default value.
* Subindex gaps of a RECORD (e.g. a PDO comm record without sub 4) are filled with an
  UNSIGNED8 placeholder without access rights (attribute 0), because the library counts
  subindexes 0..numOfElem-1.
* Defaults: numeric entries point ``pDefaultVal`` at a ``static const`` of their type.
  VISIBLE_STRING / OCTET_STRING point it at a ``STRING_DATA_T {actLen, maxLen}`` (both the
  default's length; the text itself is the data's initial content). DOMAIN data is an
  ``UNSIGNED8 *`` to a static buffer holding the value, ``pDefaultVal`` a ``DOMAIN_DATA_T
  {len}``, and the attribute has CO_UP_DN_LD_DOMAIN.
* Types: CO_TYPEDESC_BOOL/UNSIGNED8/16/32/64/INTEGER8/16/32/64/REAL32/VISSTRING/
  OCTETSTRING/DOMAIN as in the seed's table; types the table lacks (24/40/48/56-bit
  integers, REAL64, TIME_OF_DAY, TIME_DIFFERENCE, UNICODE_STRING) become OCTETSTRING
  holding their little-endian bytes, with a warning.
* Attribute: CO_NUM_VAL for numeric types; CO_READ_PERM for ro/rw/rwr/rww/const;
  CO_WRITE_PERM for wo/rw/rwr/rww (SDO access, as D-9 reads them); CO_CONST_PERM for
  const; CO_MAP_PERM for PDOMapping=1;
  CO_SHORT_ARRAY_DESC on sub 0 when subindexes 1..n (n >= 2) have the same type,
  attribute and default. CO_OBJ_ATTR_SAVE is never set (an EDS does not say it).
* Splitting (seed 002: a structure or array beyond the sub-index limit needs several
  indices): numOfElem is 8 bits, so an ARRAY/RECORD with subindex 255 is split over
  consecutive indices X, X+1: each part holds up to 254 elements after its own sub 0 (= the
  number of elements in that part). With ``max_object_size=N`` (``--max-object-size``),
  an object whose packed data (sub 0 included) exceeds N bytes is split the same way, as many
  whole elements per part as fit (seed 002 words this limit as "255 bytes"; taken literally
  it would split standard objects such as 0x1003 with 254 UNSIGNED32 (1017 bytes), so it is
  an option, not the default). The following indices must be free; every split is reported
  as a warning because the port OD then addresses those elements differently from the EDS.
  An element of an ARRAY/RECORD must fit 255 bytes (the library adds element sizes as
  8-bit numbers).
* ``LIST_ELEMENT_T SYMBOL[]`` is sorted by index; ``const UNSIGNED16 SYMBOLElements`` holds
  its length. Both structures are initialised through macros that also fit the layouts
  with ``CONFIG_LIMITS_CHECK`` and with ``CO_CONFIG_ENABLE_OBJ_CALLBACK`` (``pObjCallback``
  = 0).
* Limits (``CONFIG_LIMITS_CHECK``): an entry with LowLimit/HighLimit gets a ``static const
  LIMIT_<T>_T`` {low, high} of its type (``LIMIT_U8_T`` as in seed 002, the others named
  alike), ``pLimits`` points at it, cast as the seed's VALUE_DESC_T declares it; others 0.
* UNSIGNED64 defaults and VAR data use the seed's ``SET_U64(b1..b8)``; inside initializer
  lists ``DCF2BIN_U64`` (both defined for a native 64-bit type unless already defined).
* A ``const`` VAR is declared ``const`` (seed 002: "constant and stored at ROM").
"""
from __future__ import annotations

import math
import os
import re
import struct
from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import Where, shorten
from dcf2bin.export.common import (ExportResult, ascii_text, encode, error, exported_objects,
                            model_diagnostics, warning)

# Attribute bits of VALUE_DESC_T (values as in the port library's public header).
ATTR = {
    "CO_UP_DN_LD_DOMAIN": 0x0001,
    "CO_SHORT_ARRAY_DESC": 0x0002,
    "CO_CONST_PERM": 0x0008,
    "CO_NUM_VAL": 0x0010,
    "CO_READ_PERM": 0x0020,
    "CO_WRITE_PERM": 0x0040,
    "CO_MAP_PERM": 0x0080,
    "CO_OBJ_ATTR_SAVE": 0x1000,
}
ATTR_ORDER = ("CO_NUM_VAL", "CO_READ_PERM", "CO_WRITE_PERM", "CO_CONST_PERM", "CO_MAP_PERM",
              "CO_UP_DN_LD_DOMAIN", "CO_SHORT_ARRAY_DESC")

# CANopen data type code -> (CO_TYPEDESC_*, C type). "bytes"/"domain" are byte copies.
TYPES = {
    0x01: ("CO_TYPEDESC_BOOL", "UNSIGNED8"),
    0x05: ("CO_TYPEDESC_UNSIGNED8", "UNSIGNED8"),
    0x06: ("CO_TYPEDESC_UNSIGNED16", "UNSIGNED16"),
    0x07: ("CO_TYPEDESC_UNSIGNED32", "UNSIGNED32"),
    0x1B: ("CO_TYPEDESC_UNSIGNED64", "UNSIGNED64"),
    0x02: ("CO_TYPEDESC_INTEGER8", "INTEGER8"),
    0x03: ("CO_TYPEDESC_INTEGER16", "INTEGER16"),
    0x04: ("CO_TYPEDESC_INTEGER32", "INTEGER32"),
    0x15: ("CO_TYPEDESC_INTEGER64", "INTEGER64"),
    0x08: ("CO_TYPEDESC_REAL32", "REAL32"),
    0x09: ("CO_TYPEDESC_VISSTRING", "bytes"),
    0x0A: ("CO_TYPEDESC_OCTETSTRING", "bytes"),
    0x0F: ("CO_TYPEDESC_DOMAIN", "domain"),
}
FALLBACK = ("CO_TYPEDESC_OCTETSTRING", "bytes")
MAX_ELEMENTS = 254          # numOfElem is 8 bits: subindexes 0..254 per index
MAX_ELEMENT_BYTES = 255     # the library adds element sizes as 8-bit numbers
POINTER_SIZE = 8            # a DOMAIN slot in a record, counted at its largest for splits
DEFAULT_INCLUDE = "co_acces.h"
DEFAULT_SYMBOL = "objDir"
DEFAULT_PREFIX = "od_"
_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")

ENTRY, GAP, COUNT = "entry", "gap", "count"


@dataclass
class PortSub:
    sub: int
    role: str                     # ENTRY, GAP (placeholder) or COUNT (sub 0 of a split part)
    typedesc: str
    ctype: str                    # C type, "bytes" or "domain"
    attrs: tuple[str, ...]
    data: bytes                   # the value, little-endian encoded
    name: str = ""
    source: tuple[int, int] | None = None   # (index, subindex) in the model
    dtype: dt.DataType | None = None
    limits: tuple[bytes, bytes] | None = None   # LowLimit, HighLimit (CONFIG_LIMITS_CHECK)

    @property
    def attribute(self) -> int:
        value = 0
        for a in self.attrs:
            value |= ATTR[a]
        return value

    @property
    def layout_size(self) -> int:
        if self.ctype == "domain":
            return POINTER_SIZE
        return len(self.data)

    def same_description(self, other: "PortSub") -> bool:
        return (self.role == other.role == ENTRY and self.typedesc == other.typedesc
                and self.ctype == other.ctype and self.attrs == other.attrs
                and self.data == other.data and self.limits == other.limits)


@dataclass
class PortObject:
    index: int
    origin: int                   # the model's index (differs for split parts)
    name: str
    is_var: bool
    subs: list[PortSub] = field(default_factory=list)
    short: bool = False
    where: Where | None = None

    @property
    def num_of_elem(self) -> int:
        return len(self.subs)


def _attrs(entry, typedesc: str, ctype: str, numeric: bool) -> tuple[str, ...]:
    acc = entry.access or ""
    bits = dt.ACCESS_ATTR.get(acc, 0)      # D-9's reading: rwr and rww read and write
    names = []
    if numeric:
        names.append("CO_NUM_VAL")
    if bits & dt.ATTR_READ:
        names.append("CO_READ_PERM")
    if bits & dt.ATTR_WRITE:
        names.append("CO_WRITE_PERM")
    if acc == "const":
        names.append("CO_CONST_PERM")
    if entry.pdo_mapping:
        names.append("CO_MAP_PERM")
    if ctype == "domain":
        names.append("CO_UP_DN_LD_DOMAIN")
    return tuple(names)


class _Planner:
    def __init__(self, dev, max_object_size: int | None = None):
        self.dev = dev
        self.max_object_size = max_object_size
        self.diags: list = []
        self.taken: set[int] = set(dev.objects)

    def sub(self, entry, obj) -> PortSub | None:
        data = encode(self.dev, entry, self.diags)
        if data is None:
            return None
        typedesc, ctype = TYPES.get(entry.dtype.code, FALLBACK)
        numeric = ctype not in ("bytes", "domain")
        if entry.dtype.code == 0x08:
            (f,) = struct.unpack("<f", data)
            if not math.isfinite(f):
                self.diags.append(error(
                    f"{entry.label}: REAL32 bit pattern 0x{int.from_bytes(data, 'little'):08X} "
                    "is not finite and has no C initializer", entry.value_where, "EXP207"))
                return None
        return PortSub(entry.sub, ENTRY, typedesc, ctype,
                       _attrs(entry, typedesc, ctype, numeric), data,
                       entry.name or obj.name, (entry.index, entry.sub), entry.dtype,
                       self.limits(entry, ctype) if numeric else None)

    def limits(self, entry, ctype: str) -> tuple[bytes, bytes] | None:
        """LowLimit/HighLimit as bytes of the entry's type (a missing one: the type's own
        end), for ``pLimits``; None without limits, or with one that is no value of the
        type (EXP208: no limits are exported for that entry)."""
        if entry.low is None and entry.high is None:
            return None
        dtype = entry.dtype
        out = []
        for key, text, end in (("LowLimit", entry.low, dtype.min),
                               ("HighLimit", entry.high, dtype.max)):
            if text is None:
                if ctype == "REAL32":   # no finite end is meant: the largest REAL32
                    end = -3.4028234663852886e38 if key == "LowLimit" else 3.4028234663852886e38
                    out.append(struct.pack("<f", end))
                else:
                    out.append((end & ((1 << dtype.bits) - 1)).to_bytes(dtype.size, "little"))
                continue
            try:
                out.append(values.encode(dtype, values.split_numeric_comment(text)[0],
                                         node_id=self.dev.node_id,
                                         encoding=self.dev.encoding))
            except values.ValueProblem as exc:
                self.diags.append(warning(
                    f"{entry.label} {key}: {values.clip(str(exc))}; no limits exported for "
                    "it", entry.key_where(key.lower()), "EXP208"))
                return None
        return out[0], out[1]

    def run(self) -> list[PortObject]:
        out: list[PortObject] = []
        for obj in exported_objects(self.dev):
            fallback = sorted({e.dtype.name for e in obj.entries.values()
                               if e.dtype is not None and e.dtype.code not in TYPES})
            if fallback:
                self.diags.append(warning(
                    f"0x{obj.index:04X}: the port library has no CO_TYPEDESC for "
                    f"{', '.join(fallback)}; exported as CO_TYPEDESC_OCTETSTRING with the "
                    "little-endian bytes", obj.where, "EXP201"))
            if not obj.complex:
                e = obj.entries.get(0)
                s = self.sub(e, obj) if e is not None else None
                if s is not None:
                    out.append(PortObject(obj.index, obj.index, obj.name, True, [s],
                                          where=obj.where))
                continue
            out.extend(self.record(obj))
        out.sort(key=lambda o: o.index)
        for o in out:
            o.short = _is_short(o)
        return out

    def record(self, obj) -> list[PortObject]:
        highest = max(obj.entries)
        subs: list[PortSub] = []
        ok = True
        for s in range(highest + 1):
            e = obj.entries.get(s)
            if e is None:
                subs.append(PortSub(s, GAP, "CO_TYPEDESC_UNSIGNED8", "UNSIGNED8", (), b"\x00",
                                    "(not present)"))
                continue
            p = self.sub(e, obj)
            if p is None:
                ok = False
                continue
            subs.append(p)
        if not ok:
            return []
        s0 = subs[0]
        if s0.role == ENTRY and s0.ctype != "UNSIGNED8":
            e0 = obj.entries[0]
            self.diags.append(error(
                f"0x{obj.index:04X}sub0 is {e0.dtype.name}: the port library reads sub 0 of "
                "an ARRAY/RECORD as one UNSIGNED8", e0.key_where("datatype"), "EXP206"))
            return []
        for p in subs[1:]:
            if p.layout_size > MAX_ELEMENT_BYTES:
                self.diags.append(error(
                    f"0x{obj.index:04X}sub{p.sub:X} takes {p.layout_size} bytes: an element of "
                    f"an ARRAY/RECORD must fit {MAX_ELEMENT_BYTES} bytes for the port library",
                    obj.entries[p.sub].value_where, "EXP205"))
                return []
        size = sum(p.layout_size for p in subs)
        limit = self.max_object_size
        if len(subs) - 1 > MAX_ELEMENTS:
            reason = f"has {len(subs) - 1} elements (more than {MAX_ELEMENTS} per index)"
        elif limit is not None and size > limit:
            reason = f"has {size} bytes of data (more than {limit})"
        else:
            return [PortObject(obj.index, obj.index, obj.name, False, subs, where=obj.where)]
        return self.split(obj, subs, reason)

    def split(self, obj, subs: list[PortSub], reason: str) -> list[PortObject]:
        room = self.max_object_size - 1 if self.max_object_size is not None else None
        parts: list[list[PortSub]] = [[]]
        used = 0
        for p in subs[1:]:
            if room is not None and p.layout_size > room:
                self.diags.append(error(
                    f"0x{obj.index:04X}sub{p.sub:X} takes {p.layout_size} bytes: it cannot be "
                    f"placed in a part of at most {self.max_object_size} bytes",
                    obj.entries[p.sub].value_where, "EXP205"))
                return []
            full = len(parts[-1]) >= MAX_ELEMENTS or (
                room is not None and used + p.layout_size > room)
            if full and parts[-1]:
                parts.append([])
                used = 0
            parts[-1].append(p)
            used += p.layout_size
        indexes = [obj.index + k for k in range(len(parts))]
        for idx in indexes[1:]:
            if idx > 0xFFFF or idx in self.taken:
                self.diags.append(error(
                    f"0x{obj.index:04X} {reason} and must be split over indices "
                    f"0x{indexes[0]:04X}..0x{indexes[-1]:04X}, but "
                    + (f"0x{idx:04X} is already used" if idx <= 0xFFFF else "that passes 0xFFFF"),
                    obj.where, "EXP203",
                    hint="move the following object or shorten this one in the EDS"))
                return []
        self.taken.update(indexes)
        self.diags.append(warning(
            f"0x{obj.index:04X} {reason}: split over indices "
            f"{', '.join(f'0x{i:04X}' for i in indexes)} for the port library",
            obj.where, "EXP202"))
        s0 = subs[0]
        out = []
        for k, (idx, part) in enumerate(zip(indexes, parts)):
            count = PortSub(0, COUNT, "CO_TYPEDESC_UNSIGNED8", "UNSIGNED8",
                            s0.attrs if s0.role == ENTRY else ("CO_NUM_VAL", "CO_READ_PERM"),
                            bytes([len(part)]), s0.name, s0.source, dt.UNSIGNED8)
            renumbered = [PortSub(n, p.role, p.typedesc, p.ctype, p.attrs, p.data, p.name,
                                  p.source, p.dtype, p.limits) for n, p in enumerate(part, 1)]
            name = obj.name if k == 0 else f"{obj.name} (part {k + 1})"
            out.append(PortObject(idx, obj.index, name, False, [count] + renumbered,
                                  where=obj.where))
        return out


def _is_short(o: PortObject) -> bool:
    if o.is_var or len(o.subs) < 3:
        return False
    first = o.subs[1]
    return all(first.same_description(p) for p in o.subs[2:])


def plan(dev, *, max_object_size: int | None = None) -> tuple[list[PortObject], list]:
    """The port OD of a device -> (objects sorted by index, diagnostics of the export).

    ``max_object_size``: split ARRAY/RECORD objects whose packed data exceeds it (bytes).
    """
    if max_object_size is not None and max_object_size < 2:
        raise ValueError("max_object_size must be at least 2 bytes")
    p = _Planner(dev, max_object_size)
    objs = p.run()
    return objs, p.diags


# -- C text ------------------------------------------------------------------------------

_INT_LIMITS = {"INTEGER8": "(-127 - 1)", "INTEGER16": "(-32767 - 1)",
               "INTEGER32": "(-2147483647L - 1L)",
               "INTEGER64": "(-9223372036854775807LL - 1LL)"}
_SUFFIX = {"UNSIGNED8": "u", "UNSIGNED16": "u", "UNSIGNED32": "UL", "UNSIGNED64": "ULL",
           "INTEGER8": "", "INTEGER16": "", "INTEGER32": "L", "INTEGER64": "LL"}


def literal(p: PortSub, data: bytes | None = None, u64: str = "DCF2BIN_U64") -> str:
    """The C initializer of a numeric sub's value (or of ``data`` in its type). An
    UNSIGNED64 is ``u64(b1, ..., b8)``, most significant byte first, as the port manual
    initialises 64-bit values (``SET_U64``), so that a compiler without a 64-bit type can
    take it too."""
    data = p.data if data is None else data
    if p.ctype == "REAL32":
        (f,) = struct.unpack("<f", data)
        return f"{float.hex(f)}f"
    if p.ctype == "UNSIGNED64":
        return f"{u64}(" + ", ".join(f"0x{b:02X}ull" for b in reversed(data)) + ")"
    signed = p.ctype.startswith("INTEGER")
    v = int.from_bytes(data, "little", signed=signed)
    if signed:
        bits = len(data) * 8
        if v == -(1 << (bits - 1)):
            return _INT_LIMITS[p.ctype]
        return f"{v}{_SUFFIX[p.ctype]}"
    return f"0x{v:X}{_SUFFIX[p.ctype]}"


# the port manual's LIMIT_U8_T, by C type (CONFIG_LIMITS_CHECK: pLimits points at one)
LIMIT_TYPES = {"UNSIGNED8": "LIMIT_U8_T", "UNSIGNED16": "LIMIT_U16_T",
               "UNSIGNED32": "LIMIT_U32_T", "UNSIGNED64": "LIMIT_U64_T",
               "INTEGER8": "LIMIT_I8_T", "INTEGER16": "LIMIT_I16_T",
               "INTEGER32": "LIMIT_I32_T", "INTEGER64": "LIMIT_I64_T", "REAL32": "LIMIT_R32_T"}


def _decl(ctype: str, name: str, p: PortSub, const: bool = False) -> str:
    """A complete declaration of a numeric variable at ``p``'s value; an UNSIGNED64 through
    the manual's ``SET_U64``, which brings its own braces and semicolon."""
    head = f"{'const ' if const else ''}{ctype} {name} = "
    if p.ctype == "UNSIGNED64":
        return head + literal(p, u64="SET_U64")
    return head + literal(p) + ";"


def _bytes_init(data: bytes, indent: str = "    ") -> str:
    if not data:
        return "{ 0 }"
    items = [f"0x{b:02X}" for b in data]
    if len(items) <= 12:
        return "{ " + ", ".join(items) + " }"
    rows = [", ".join(items[i:i + 12]) for i in range(0, len(items), 12)]
    return "{\n" + ",\n".join(indent + "    " + r for r in rows) + "\n" + indent + "}"


def _comment(text: str) -> str:
    return ascii_text(text).replace("/*", "/ *").replace("*/", "* /")


def _attr_expr(attrs) -> str:
    names = [a for a in ATTR_ORDER if a in attrs]
    return " | ".join(names) if names else "0u"


class _Writer:
    def __init__(self, objs: list[PortObject], prefix: str):
        self.objs = objs
        self.prefix = prefix
        self.lines: list[str] = []
        self.need_zero = any(p.role == GAP for o in objs for p in o.subs)

    def name(self, o: PortObject) -> str:
        return f"{self.prefix}{o.index:04X}"

    def default_ref(self, o: PortObject, p: PortSub) -> str:
        base = self.name(o)
        if p.role == GAP:
            return "&dcf2bin_zero"
        if p.ctype in ("bytes", "domain"):
            return f"&{base}_l{p.sub}"
        return f"&{base}_d{p.sub}"

    def described(self, o: PortObject) -> list[PortSub]:
        return o.subs[:2] if o.short else o.subs

    def obj(self, o: PortObject) -> None:
        L = self.lines
        base = self.name(o)
        L.append(f"/* 0x{o.index:04X} {_comment(o.name)} */")
        # defaults
        for p in self.described(o):
            if p.role == GAP:
                continue
            if p.ctype == "bytes":
                L.append(f"static STRING_DATA_T {base}_l{p.sub} = {{ {len(p.data)}UL, "
                         f"{len(p.data)}UL }};")
            elif p.ctype == "domain":
                L.append(f"static DOMAIN_DATA_T {base}_l{p.sub} = {{ {len(p.data)}UL }};")
            else:
                L.append(_decl(p.ctype, f"{base}_d{p.sub}", p, const=True).replace(
                    "const ", "static const ", 1))
        # limits (pLimits), only where the library has the member
        limited = [p for p in self.described(o) if p.limits is not None]
        if limited:
            L.append("#ifdef CONFIG_LIMITS_CHECK")
            for p in limited:
                lo, hi = (literal(p, b) for b in p.limits)
                L.append(f"static const {LIMIT_TYPES[p.ctype]} {base}_m{p.sub} = "
                         f"{{ {lo}, {hi} }};")
            L.append("#endif")
        # domain buffers
        for p in o.subs:
            if p.ctype == "domain":
                L.append(f"static UNSIGNED8 {base}_b{p.sub}[{max(len(p.data), 1)}] = "
                         f"{_bytes_init(p.data, '')};")
        # data
        if o.is_var:
            p = o.subs[0]
            const = "CO_CONST_PERM" in p.attrs   # "constant and stored at ROM"
            if p.ctype == "bytes":
                L.append(f"{'const ' if const else ''}UNSIGNED8 {base}[{max(len(p.data), 1)}]"
                         f" = {_bytes_init(p.data, '')};")
            elif p.ctype == "domain":
                L.append(f"UNSIGNED8 *{base} = {base}_b0;")
            else:
                L.append(_decl(p.ctype, base, p, const))
        else:
            L.append("#pragma pack(push, 1)")
            L.append("typedef struct {")
            inits = []
            for p in o.subs:
                if p.ctype == "bytes":
                    if not p.data:
                        continue   # an empty string takes no bytes
                    L.append(f"    UNSIGNED8 s{p.sub}[{len(p.data)}];")
                    inits.append(_bytes_init(p.data, "    "))
                elif p.ctype == "domain":
                    L.append(f"    UNSIGNED8 *s{p.sub};")
                    inits.append(f"{base}_b{p.sub}")
                else:
                    L.append(f"    {p.ctype} s{p.sub};")
                    inits.append(literal(p))
            L.append(f"}} {base}_t;")
            L.append("#pragma pack(pop)")
            L.append(f"{base}_t {base} = {{")
            L.append(",\n".join("    " + i for i in inits))
            L.append("};")
        # descriptions
        L.append(f"static VALUE_DESC_T {base}_desc[] = {{")
        rows = []
        for p in self.described(o):
            attrs = p.attrs + (("CO_SHORT_ARRAY_DESC",) if o.short and p.sub == 0 else ())
            note = f"sub {p.sub}" + (f"..{len(o.subs) - 1}" if o.short and p.sub == 1 else "")
            lim = f"&{base}_m{p.sub}" if p.limits is not None else "0"
            rows.append(f"    DCF2BIN_DESC({self.default_ref(o, p)}, {lim}, {p.typedesc}, "
                        f"{_attr_expr(attrs)}) /* {note} {_comment(p.name)} */")
        # commas go before the comment
        fixed = []
        for i, r in enumerate(rows):
            if i < len(rows) - 1:
                head, _, tail = r.partition(" /* ")
                r = f"{head}, /* {tail}"
            fixed.append(r)
        L.extend(fixed)
        L.append("};")
        L.append("")


def to_c(objs: list[PortObject], *, includes: list[str] | None = None,
         symbol: str = DEFAULT_SYMBOL, prefix: str = DEFAULT_PREFIX, source: str = "") -> str:
    from dcf2bin import __version__
    for ident in (symbol, prefix):
        if not _IDENT.fullmatch(ident):
            raise ValueError(f"'{shorten(ident)}' is not a C identifier")
    includes = includes if includes is not None else [DEFAULT_INCLUDE]
    w = _Writer(objs, prefix)
    L = w.lines
    L += ["/*",
          f" * port CANopen Library object dictionary, generated by dcf2bin {__version__}"
          + (f" from {_comment(source)}" if source else "") + ".",
          " * Do not edit. Conventions (data layout, defaults, attributes, split objects):",
          " * see dcf2bin's docs/export.md, section port-c.",
          " */"]
    for inc in includes:
        L.append(f"#include \"{inc}\"")
    L += ["",
          "#ifdef CONFIG_LIMITS_CHECK",
          "#  define DCF2BIN_DESC(def, lim, type, attr) "
          "{ (UNSIGNED8 *)(def), (LIMIT_U8_T *)(lim), (type), (UNSIGNED16)(attr) }",
          "#else",
          "#  define DCF2BIN_DESC(def, lim, type, attr) "
          "{ (UNSIGNED8 *)(def), (type), (UNSIGNED16)(attr) }",
          "#endif",
          "/* 64-bit values, most significant byte first: SET_U64 as the port manual gives it",
          " * for a compiler with a 64-bit type (the library's own definition wins), and",
          " * DCF2BIN_U64 inside initializer lists (define it as { b8, ..., b1 } where",
          " * UNSIGNED64 is the manual's struct of 8 chars). */",
          "#ifndef SET_U64",
          "#  define SET_U64(b1, b2, b3, b4, b5, b6, b7, b8) \\",
          "  { b1<<56|b2<<48|b3<<40|b4<<32|b5<<24|b6<<16|b7<<8|b8 };",
          "#endif",
          "#ifndef DCF2BIN_U64",
          "#  define DCF2BIN_U64(b1, b2, b3, b4, b5, b6, b7, b8) \\",
          "  ((b1)<<56|(b2)<<48|(b3)<<40|(b4)<<32|(b5)<<24|(b6)<<16|(b7)<<8|(b8))",
          "#endif",
          "#ifdef CO_CONFIG_ENABLE_OBJ_CALLBACK",
          "#  define DCF2BIN_OBJ(obj, desc, index, n) "
          "{ (UNSIGNED8 *)(obj), (desc), (index), (n), 0 }",
          "#else",
          "#  define DCF2BIN_OBJ(obj, desc, index, n) "
          "{ (UNSIGNED8 *)(obj), (desc), (index), (n) }",
          "#endif",
          ""]
    if w.need_zero:
        L += ["/* default of the placeholders that fill subindex gaps */",
              "static const UNSIGNED8 dcf2bin_zero = 0u;", ""]
    for o in objs:
        w.obj(o)
    L.append(f"LIST_ELEMENT_T {symbol}[] = {{")
    rows = []
    for o in objs:
        base = w.name(o)
        rows.append(f"    DCF2BIN_OBJ(&{base}, {base}_desc, 0x{o.index:04X}u, "
                    f"{o.num_of_elem}u)")
    for i, o in enumerate(objs):
        sep = "," if i < len(objs) - 1 else ""
        L.append(f"{rows[i]}{sep} /* {_comment(o.name)} */")
    L.append("};")
    L.append(f"const UNSIGNED16 {symbol}Elements = {len(objs)}u;")
    L.append("")
    return "\n".join(L)


def export(dev, *, includes: list[str] | None = None, symbol: str = DEFAULT_SYMBOL,
           prefix: str = DEFAULT_PREFIX, max_object_size: int | None = None,
           **_ignored) -> ExportResult:
    diags = model_diagnostics(dev)
    objs, own = plan(dev, max_object_size=max_object_size)
    diags.extend(own)
    if any(d.severity.value == "error" for d in diags):
        return ExportResult(None, diags)
    if not objs:
        diags.append(error("no objects from 0x1000 up: nothing to export", Where(dev.path),
                           "EXP100"))
        return ExportResult(None, diags)
    return ExportResult(to_c(objs, includes=includes, symbol=symbol, prefix=prefix,
                             source=os.path.basename(dev.path)), diags)
