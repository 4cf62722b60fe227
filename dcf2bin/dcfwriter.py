"""Container -> DCF text: ``bin2dcf`` (SPEC.md §4).

One object section per index; ``ParameterValue`` is the last value written to each
(index, subindex) and comments list the earlier writes (PDO reconfiguration
sequences). DataType: from the CiA 405 range for network variables; else from the
attribute bits and the size (BOOLEAN, VISIBLE_STRING, NUMERIC 1..8 bytes ->
UNSIGNED8..64, no type bit -> DOMAIN); AccessType and PDOMapping from the attribute.
With an EDS (``--eds``) types, access and names come from it where they agree with
what the container stores.

The output is chosen so that ``compile`` with default options gives the same bytes
for every container compiled with default options from a DCF: network-variable
objects are ARRAYs (creation group, sub 0 first), other written entries keep their
access so the configuration group selects them again, PDO objects carry the final
COB-ID and mapping so compile regenerates the CiA 301 block, and a
``[DynamicChannels]`` section is reconstructed from the PI addresses when the
variables do not sit where the CiA 405 table puts them.

``convert`` also *predicts* what compile makes of the text, by replaying the rules of
SPEC §3 on the objects it writes (D-8 order and blocks, D-9 attributes, §2 layout,
D-10 addresses); where the prediction differs from the container it returns
warnings naming what will not round-trip. tests/test_bin2dcf.py checks the
prediction against the real compiler.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.container import BinContainer
from dcf2bin.diagnostics import Diagnostic, Severity
from dcf2bin.dump import EdsInfo, entry_offsets, header_of
from dcf2bin.layout import (INPUT, OUTPUT, OUTPUT_FIRST, PER_INDEX, RANGE_LEN, TABLE_405,
                            TABLE_END)
from dcf2bin.model import NV_FIRST, NV_LAST
from dcf2bin.model import is_network_variable_index as is_nv
from dcf2bin.model import is_pdo_comm as is_comm
from dcf2bin.model import is_pdo_mapping as is_mapping
from dcf2bin.select import COB_INVALID, MAX_MAPPED
from dcf2bin.select import attribute_byte as attribute
MAX_SHOWN = 5            # warnings of one kind shown before "... and N more"

# Warning rules of bin2dcf (what will not compile back to the same bytes).
R_HEADER = "B2D001"      # header, layout, attribute segment length
R_ATTR = "B2D002"        # an attribute byte no DCF entry produces
R_REPEAT = "B2D003"      # repeated writes outside a PDO block
R_SELECT = "B2D004"      # an entry compile would not write (ro, below 0x1000, missing sub 0)
R_PDO = "B2D005"         # a PDO block compile would not regenerate
R_PI = "B2D006"          # process image: addresses, PI parameters, channels
R_VALUE = "B2D007"       # a value that its type cannot express in a DCF
R_EDS = "B2D008"         # the EDS disagrees with the container
R_SUMMARY = "B2D010"     # the overall verdict

_STD_NAMES = {
    0x1000: "Device type", 0x1001: "Error register", 0x1002: "Manufacturer status register",
    0x1003: "Pre-defined error field", 0x1005: "COB-ID SYNC message",
    0x1006: "Communication cycle period", 0x1007: "Synchronous window length",
    0x1008: "Manufacturer device name", 0x1009: "Manufacturer hardware version",
    0x100A: "Manufacturer software version", 0x100C: "Guard time",
    0x100D: "Life time factor", 0x1010: "Store parameters",
    0x1011: "Restore default parameters", 0x1012: "COB-ID time stamp object",
    0x1013: "High resolution time stamp", 0x1014: "COB-ID EMCY",
    0x1015: "Inhibit time EMCY", 0x1016: "Consumer heartbeat time",
    0x1017: "Producer heartbeat time", 0x1018: "Identity object",
    0x1019: "Synchronous counter overflow value", 0x1020: "Verify configuration",
    0x1029: "Error behavior", 0x1200: "SDO server parameter",
    0x1280: "SDO client parameter", 0x1F80: "NMT startup", 0x1F81: "NMT slave assignment",
    0x1F82: "Request NMT", 0x1F89: "Boot time",
}
_COMM_SUBS = {0: "Highest sub-index supported", 1: "COB-ID", 2: "Transmission type",
              3: "Inhibit time", 4: "Reserved", 5: "Event timer", 6: "SYNC start value"}


def table_type(index: int) -> tuple[dt.DataType, str] | None:
    if not NV_FIRST <= index < TABLE_END:
        return None
    return TABLE_405[NV_FIRST + (index - NV_FIRST) // RANGE_LEN * RANGE_LEN]


# -- the objects the DCF will hold ------------------------------------------------------------

@dataclass(slots=True)
class Write:
    pos: int               # 0-based entry number
    offset: int            # byte offset of the entry in the container
    data: bytes
    attr: int | None


@dataclass(slots=True)
class SubSpec:
    index: int
    sub: int
    dtype: dt.DataType
    access: str
    pdo: bool
    writes: list[Write]
    name: str = ""
    value: str = ""        # ParameterValue text ("" = none: an implied sub 0)
    default: str = ""      # DefaultValue text (implied sub 0 only)

    @property
    def data(self) -> bytes:
        return self.writes[-1].data

    @property
    def attr(self) -> int:
        return attribute(self.index, self.sub, self.dtype, self.access, self.pdo)


@dataclass(slots=True)
class ObjSpec:
    index: int
    object_type: int
    name: str = ""
    subs: dict[int, SubSpec] = field(default_factory=dict)


@dataclass(slots=True)
class ChannelSpec:
    dtype: dt.DataType
    direction: str
    first: int
    last: int = 0
    pp: int | None = None


@dataclass
class Result:
    text: str
    diagnostics: list[Diagnostic]
    roundtrip: bool        # compile(text) with default options == the container
    options: list[str]     # compile options that would give the same bytes, when not default
    encoding: str = "utf-8"

    def to_bytes(self) -> bytes:
        """The DCF in its encoding (Latin-1 only when a string needs it; SPEC §1)."""
        return self.text.encode(self.encoding, errors="replace")


class _Issues:
    """Warnings grouped by rule; at most MAX_SHOWN per rule are reported."""

    def __init__(self, name: str):
        self.name = name
        self.items: dict[str, list[tuple[int | None, str]]] = {}

    def add(self, rule: str, offset: int | None, message: str) -> None:
        self.items.setdefault(rule, []).append((offset, message))

    def __bool__(self) -> bool:
        return any(self.items.values())

    def diagnostics(self) -> list[Diagnostic]:
        out = []
        for rule, items in self.items.items():
            for offset, message in items[:MAX_SHOWN]:
                out.append(Diagnostic(Severity.WARNING, message, self.name, offset=offset,
                                      rule=rule))
            if len(items) > MAX_SHOWN:
                out.append(Diagnostic(Severity.WARNING, f"... and {len(items) - MAX_SHOWN} "
                                      "more like this", self.name, rule=rule))
        return out


def _text(dtype: dt.DataType, data: bytes, encoding: str) -> str | None:
    """ParameterValue text for ``data``; unsigned values padded to the type's width."""
    if dtype.kind in (dt.UINT, dt.TIME) and dtype.size == len(data):
        return f"0x{int.from_bytes(data, 'little'):0{2 * dtype.size}X}"
    return values.decode(dtype, data, encoding=encoding)


class _Converter:
    def __init__(self, c: BinContainer, name: str, dcf_name: str, eds: EdsInfo | None,
                 eds_device=None):
        self.c = c
        self.name = name
        self.dcf_name = dcf_name
        self.eds = eds
        self.eds_device = eds_device
        self.issues = _Issues(name)
        self.header = header_of(c)
        self.offsets = entry_offsets(c, self.header)
        self.objects: dict[int, ObjSpec] = {}
        self.channels: list[ChannelSpec] = []
        self.encoding = "utf-8"

    # -- building -----------------------------------------------------------------------------
    def run(self) -> Result:
        c = self.c
        attrs = c.attributes or b""
        n = len(c.entries)
        self._header_issues(n, attrs)
        groups: dict[tuple[int, int], list[Write]] = {}
        offsets = self.offsets
        n_attrs = len(attrs)
        nv_order = self.nv_order = []      # network variables, first occurrence (SPEC §3.4)
        for i, (index, sub, data) in enumerate(c.entries):
            w = Write(i, offsets[i], data, attrs[i] if i < n_attrs else None)
            g = groups.get((index, sub))
            if g is None:
                groups[(index, sub)] = [w]
                if sub and NV_FIRST <= index <= NV_LAST:
                    nv_order.append((index, sub))
            else:
                g.append(w)
        nv_vars = []
        subs_of: dict[int, list[int]] = {}
        for index, sub in groups:
            subs_of.setdefault(index, []).append(sub)
        objects = self.objects
        for key in sorted(groups):
            index, sub = key
            obj = objects.get(index)
            if obj is None:
                obj = objects[index] = ObjSpec(index, self._object_type(index, subs_of[index]),
                                               self._object_name(index))
            if sub and NV_FIRST <= index <= NV_LAST:
                nv_vars.append((index, sub, groups[key]))
                continue
            obj.subs[sub] = self._entry(index, sub, groups[key])
        self._network_variables(nv_vars)
        for obj in self.objects.values():
            obj.subs = dict(sorted(obj.subs.items()))
        self._implied_sub0()
        self._choose_encoding()
        self._values()
        text = self._render()
        roundtrip, options = self._predict()
        return Result(text, self.issues.diagnostics(), roundtrip, options, self.encoding)

    def _header_issues(self, n: int, attrs: bytes) -> None:
        c = self.c
        if c.header is not None:
            self.issues.add(R_HEADER, 0, "the header or segment layout is not the canonical one "
                            "(D-6/D-7); compile writes the canonical layout")
        if c.raw_piparam is not None:
            self.issues.add(R_HEADER, self.header["piparam_offset"],
                            f"the PI parameter segment has {len(c.raw_piparam)} bytes, not 20")
        if c.attributes is None and n:
            self.issues.add(R_HEADER, 0x18, f"no extended info segment: the {n} entries have "
                            "no attribute; written as DOMAIN rw")
        elif len(attrs) != n:
            self.issues.add(R_HEADER, 0x1C, f"the extended info segment has {len(attrs)} bytes "
                            f"for {n} entries")

    def _object_type(self, index: int, subs: list[int]) -> int:
        if is_nv(index):
            return dt.OT_ARRAY
        only_sub0 = all(s == 0 for s in subs)
        eo = self.eds.objects.get(index) if self.eds is not None else None
        if eo is not None and eo.object_type in (dt.OT_ARRAY, dt.OT_RECORD):
            return eo.object_type
        if is_comm(index) or is_mapping(index):
            return dt.OT_RECORD
        return dt.OT_VAR if only_sub0 else dt.OT_RECORD

    def _object_name(self, index: int) -> str:
        if self.eds is not None:
            eo = self.eds.objects.get(index)
            if eo is not None and eo.name:
                return eo.name
        if index in _STD_NAMES:
            return _STD_NAMES[index]
        if is_comm(index):
            kind, base = ("RPDO", 0x1400) if index < 0x1800 else ("TPDO", 0x1800)
            return f"{kind}{index - base + 1} communication parameter"
        if is_mapping(index):
            kind, base = ("RPDO", 0x1600) if index < 0x1A00 else ("TPDO", 0x1A00)
            return f"{kind}{index - base + 1} mapping parameter"
        if is_nv(index):
            t = table_type(index)
            if t is not None:
                return f"{t[0].name} {t[1]}s"
            return "Network variables"
        return f"Object {index:04X}"

    def _sub_name(self, index: int, sub: int) -> str:
        if self.eds is not None:
            e = self.eds.entries.get((index, sub))
            if e is not None and e.name:
                return e.name
        if sub == 0:
            return "Number of mapped objects" if is_mapping(index) else \
                "Highest sub-index supported"
        if is_comm(index) and sub in _COMM_SUBS:
            return _COMM_SUBS[sub]
        if is_mapping(index):
            return f"Mapped object {sub}"
        if is_nv(index):
            return f"Variable {sub}"
        return f"Sub-index {sub}"

    def _entry(self, index: int, sub: int, writes: list[Write]) -> SubSpec:
        last = writes[-1]
        attr, data, off = last.attr, last.data, last.offset
        label = f"0x{index:04X}sub{sub:X}"
        if any(w.attr != attr for w in writes):
            shown = ", ".join(sorted({f"0x{w.attr:02X}" if w.attr is not None else "none"
                                      for w in writes}))
            self.issues.add(R_ATTR, off, f"{label} is written with different attributes "
                            f"({shown}); the DCF can give it only one")
        if len(writes) > 1 and not (is_comm(index) or is_mapping(index)):
            self.issues.add(R_REPEAT, writes[0].offset, f"{label} is written {len(writes)} "
                            "times outside a PDO block; the DCF keeps the last value "
                            "(earlier ones are comments)")
        if index < 0x1000:
            self.issues.add(R_SELECT, off, f"{label}: compile never writes objects below "
                            "0x1000 (data type definitions)")
        if is_nv(index):   # sub 0 of a network-variable object
            dtype = dt.UNSIGNED8 if len(data) == 1 else _by_size(len(data))
            if attr is not None and attr != 0x30:
                self.issues.add(R_ATTR, off, f"{label} has attribute 0x{attr:02X}; compile "
                                "gives sub 0 of a network-variable object 0x30 (D-9)")
            return SubSpec(index, sub, dtype, "ro", False, writes, self._sub_name(index, sub))
        dtype, access, pdo = self._infer(label, off, attr, data)
        eds_e = self.eds.entries.get((index, sub)) if self.eds is not None else None
        if eds_e is not None and eds_e.dtype is not None and eds_e.access is not None:
            et = eds_e.dtype
            exact = attribute(index, sub, et, eds_e.access, eds_e.pdo_mapping)
            if et.size is not None and et.size != len(data):
                self.issues.add(R_EDS, off, f"{label}: the EDS says {et.name} ({et.size} "
                                f"bytes), the container writes {len(data)} bytes; "
                                "the container wins")
            elif attr is not None and exact != attr:
                self.issues.add(R_EDS, off, f"{label}: the EDS gives attribute 0x{exact:02X} "
                                f"({dt.attr_flags(exact)}), the container has 0x{attr:02X} "
                                f"({dt.attr_flags(attr)}); the container wins")
            else:
                dtype, access, pdo = et, eds_e.access, eds_e.pdo_mapping
        if access in ("ro", "const") and not (is_comm(index) or is_mapping(index)):
            self.issues.add(R_SELECT, off, f"{label} is read-only (attribute "
                            f"0x{attr:02X}); compile does not write ro entries in the "
                            "configuration group (D-8)")
        return SubSpec(index, sub, dtype, access, pdo, writes, self._sub_name(index, sub))

    def _infer(self, label: str, off: int, attr: int | None, data: bytes):
        """DataType, AccessType, PDOMapping from an attribute byte and a size (SPEC §4)."""
        size = len(data)
        if attr is None:
            return dt.DOMAIN_T, "rw", False
        if attr & dt.ATTR_UNDEFINED:
            self.issues.add(R_ATTR, off, f"{label} has undefined attribute bits "
                            f"0x{attr & dt.ATTR_UNDEFINED:02X} (0x{attr:02X}); no DCF entry "
                            "produces them")
        kinds = attr & dt.ATTR_TYPE_MASK
        if kinds not in (0, dt.ATTR_BOOLEAN, dt.ATTR_VSTRING, dt.ATTR_NUMERIC):
            self.issues.add(R_ATTR, off, f"{label} has more than one type bit "
                            f"({dt.attr_flags(attr)}); no DCF entry produces that")
        if kinds & dt.ATTR_NUMERIC and size in dt.UNSIGNED_BY_SIZE:
            dtype = dt.UNSIGNED_BY_SIZE[size]
        elif kinds & dt.ATTR_VSTRING:
            dtype = dt.VISIBLE_STRING
        elif kinds & dt.ATTR_BOOLEAN and size == 1:
            dtype = dt.BOOLEAN
        else:
            if kinds:
                self.issues.add(R_ATTR, off, f"{label}: attribute {dt.attr_flags(attr)} with "
                                f"{size} data bytes fits no data type; written as DOMAIN")
            dtype = dt.DOMAIN_T
        r, w = attr & dt.ATTR_READ, attr & dt.ATTR_WRITE
        if r and w:
            access = "rw"
        elif w:
            access = "wo"
        elif r:
            access = "ro"
        else:
            self.issues.add(R_ATTR, off, f"{label} has neither READ nor WRITE in attribute "
                            f"0x{attr:02X}; written as AccessType=rw")
            access = "rw"
        return dtype, access, bool(attr & dt.ATTR_PDO)

    # -- network variables and [DynamicChannels] --------------------------------------------------
    def _network_variables(self, nv_vars) -> None:
        c = self.c
        addr_of = {}
        if c.addresses is not None:
            addr_of = dict(zip(self.nv_order, c.addresses))
        vars_ = []
        range_type: dict[int, dt.DataType | None] = {}
        eds = self.eds
        for index, sub, writes in nv_vars:
            last = writes[-1]
            if len(writes) > 1 or last.attr != 0xF0 or sub > PER_INDEX:
                self._nv_checks(index, sub, writes)
            dtype = None
            if eds is None:  # fast path: the range's type fits
                tt = range_type.get(index, 0)
                if tt == 0:
                    t = table_type(index)
                    tt = range_type[index] = t[0] if t is not None else None
                data = last.data
                if tt is not None and tt.size == len(data) and (tt.kind != dt.BOOL
                                                                 or data[0] < 2):
                    dtype = tt
            if dtype is None:
                dtype = self._nv_type(index, sub, last)
            vars_.append((index, sub, dtype, writes, addr_of.get((index, sub))))
        self._plan_channels(vars_)
        direction_of = {}
        objects = self.objects
        for index, sub, dtype, writes, _ in vars_:
            direction = direction_of.get(index)
            if direction is None:
                direction = direction_of[index] = self._direction_of(index)
            objects[index].subs[sub] = SubSpec(index, sub, dtype,
                                               "ro" if direction == INPUT else "rw", True,
                                               writes, f"Variable {sub}" if self.eds is None
                                               else self._sub_name(index, sub))

    def _nv_checks(self, index: int, sub: int, writes: list[Write]) -> None:
        label = f"0x{index:04X}sub{sub:X}"
        if any(w.attr != 0xF0 for w in writes):
            bad = next(w for w in writes if w.attr != 0xF0)
            shown = f"0x{bad.attr:02X}" if bad.attr is not None else "none"
            self.issues.add(R_ATTR, bad.offset, f"{label} has attribute {shown}; compile "
                            "gives every network variable 0xF0 (D-9)")
        if len(writes) > 1:
            self.issues.add(R_REPEAT, writes[0].offset, f"{label} is written "
                            f"{len(writes)} times; compile writes a network variable once")
        if sub > PER_INDEX:
            self.issues.add(R_PI, writes[-1].offset, f"{label}: subindex {sub} is above 254, "
                            "the last network variable of an index")

    def _nv_type(self, index: int, sub: int, last: Write) -> dt.DataType:
        data = last.data
        size = len(data)
        if self.eds is not None:
            t = self.eds.dtype(index, sub)
            if t is not None and t.size == size and _text(t, data, "utf-8") is not None:
                return t
            if t is not None and t.size != size:
                self.issues.add(R_EDS, last.offset, f"0x{index:04X}sub{sub:X}: the EDS says "
                                f"{t.name}, the container writes {size} bytes; the container "
                                "wins")
        tt = table_type(index)
        if tt is not None and tt[0].size == size and (tt[0].kind != dt.BOOL or data[0] < 2):
            return tt[0]
        if size in dt.UNSIGNED_BY_SIZE:
            return dt.UNSIGNED_BY_SIZE[size]   # a [DynamicChannels] segment gives the type
        self.issues.add(R_PI, last.offset, f"0x{index:04X}sub{sub:X} has {size} data bytes; a "
                        "network variable has 1 to 8 (compile will reject this DCF)")
        return dt.DOMAIN_T

    def _direction_of(self, index: int) -> str:
        for ch in self.channels:
            if ch.first <= index <= ch.last:
                return ch.direction
        return INPUT if index < OUTPUT_FIRST else OUTPUT

    def _plan_channels(self, vars_) -> None:
        """Reconstruct [DynamicChannels] segments from the addresses (SPEC §2.3)."""
        c = self.c
        pi = c.pi
        by_index: dict[int, list] = {}
        for index, sub, dtype, writes, addr in vars_:
            if dtype.size is None:
                continue      # reported: no segment can hold it, compile rejects it
            direction, off = self._area(index, addr, pi, writes[0].offset)
            by_index.setdefault(index, []).append((sub, dtype, direction, off, writes[0].offset))
        nv_objects = sorted(i for i in self.objects if is_nv(i))
        regions = [(NV_FIRST + k * 0x40, NV_FIRST + k * 0x40 + 0x3F) for k in range(36)]
        regions.append((TABLE_END, NV_LAST))
        channels: list[ChannelSpec] = []
        for first, last in regions:
            idxs = [i for i in nv_objects if first <= i <= last]
            if not idxs:
                continue
            tt = table_type(first)
            region: list[ChannelSpec] = []
            for index in idxs:
                vs = by_index.get(index)
                if not vs:
                    continue
                _, dtype, direction, _, where = vs[0]
                if any(v[1] is not dtype or v[2] != direction for v in vs[1:]):
                    self.issues.add(R_PI, where, f"0x{index:04X}: its variables differ in type "
                                    "or area; one [DynamicChannels] segment cannot hold them")
                cur = region[-1] if region else None
                if cur is not None and cur.dtype is dtype and cur.direction == direction:
                    p = _pp(vs, index, cur.first, dtype)
                    if p is None:
                        continue                 # no address: any placement will do
                    if p != "mixed" and p >= 0 and (cur.pp is None or p == cur.pp):
                        cur.pp = p
                        continue
                start = first if not region else index
                p = _pp(vs, index, start, dtype)
                if start != index and (p == "mixed" or (p is not None and p < 0)):
                    start = index
                    p = _pp(vs, index, start, dtype)
                if p == "mixed" or (p is not None and p < 0):
                    self.issues.add(R_PI, where, f"0x{index:04X}: the addresses of its "
                                    "variables do not follow the layout of SPEC §2.2 "
                                    "(start + element * size)")
                    p0 = _pp(vs[:1], index, start, dtype)
                    p = p0 if isinstance(p0, int) and p0 >= 0 else 0
                region.append(ChannelSpec(dtype, direction, start, pp=p))
            for a, b in zip(region, region[1:]):
                a.last = b.first - 1
            if region:
                region[-1].last = last
            if tt is not None and region:
                r0 = region[0]
                if r0.first == first and r0.dtype is tt[0] and r0.direction == tt[1] and \
                        not r0.pp:
                    region = region[1:]
            elif tt is None and idxs:
                lowest = idxs[0]
                if not region:
                    region = [ChannelSpec(dt.UNSIGNED8, OUTPUT, lowest, last, 0)]
                elif lowest < region[0].first:
                    region.insert(0, ChannelSpec(dt.UNSIGNED8, OUTPUT, lowest,
                                                 region[0].first - 1, 0))
            for ch in region:
                if ch.pp is None:
                    ch.pp = 0
            channels.extend(region)
        self.channels = channels

    def _area(self, index: int, addr: int | None, pi, offset: int):
        table_dir = INPUT if index < OUTPUT_FIRST else (OUTPUT if index < TABLE_END else None)
        if addr is None or pi is None:
            return table_dir or OUTPUT, None
        _, in_off, in_size, out_off, out_size = pi
        in_in = in_off <= addr < in_off + in_size
        in_out = out_off <= addr < out_off + out_size
        if table_dir == INPUT and in_in:
            return INPUT, addr - in_off
        if table_dir == OUTPUT and in_out:
            return OUTPUT, addr - out_off
        if in_in:
            return INPUT, addr - in_off
        if in_out:
            return OUTPUT, addr - out_off
        self.issues.add(R_PI, offset, f"0x{index:04X}: address 0x{addr:04X} lies outside both "
                        "areas of the PI parameter segment")
        return table_dir or OUTPUT, None

    def _implied_sub0(self) -> None:
        """ARRAY/RECORD objects without a written sub 0 get the one the model would imply."""
        for obj in self.objects.values():
            if obj.object_type == dt.OT_VAR or 0 in obj.subs:
                continue
            highest = max(obj.subs)
            spec = SubSpec(obj.index, 0, dt.UNSIGNED8, "ro", False, [],
                           self._sub_name(obj.index, 0), default=str(highest))
            obj.subs[0] = spec
            obj.subs = dict(sorted(obj.subs.items()))
            if is_nv(obj.index):
                self.issues.add(R_SELECT, None, f"0x{obj.index:04X}sub0 is not in the "
                                "container; compile writes sub 0 of every network-variable "
                                "object")

    # -- values -----------------------------------------------------------------------------------
    def _choose_encoding(self) -> None:
        """UTF-8, unless a VISIBLE_STRING holds bytes that are not: then Latin-1 (SPEC §1)."""
        for obj in self.objects.values():
            for s in obj.subs.values():
                if s.writes and s.dtype.kind == dt.VSTRING:
                    try:
                        s.data.decode("utf-8")
                    except UnicodeDecodeError:
                        self.encoding = "latin-1"
                        return

    def _values(self) -> None:
        enc = self.encoding
        for obj in self.objects.values():
            for s in obj.subs.values():
                if not s.writes:
                    continue
                text = _text(s.dtype, s.data, enc)
                if text is None:
                    # BOOLEAN other than 0/1, a string with CR/LF or not in the file's
                    # encoding: keep the bytes exact, lose the type (and its attribute bit)
                    old = s.dtype
                    s.dtype = dt.OCTET_STRING if old.size is None else _by_size(len(s.data))
                    text = _text(s.dtype, s.data, enc)
                    self.issues.add(R_VALUE, s.writes[-1].offset,
                                    f"0x{s.index:04X}sub{s.sub:X}: {_short(s.data)} cannot be "
                                    f"written as a {old.name} value in a DCF; written as "
                                    f"{s.dtype.name}")
                s.value = text

    def _earlier(self, s: SubSpec) -> list[str]:
        out = []
        for w in s.writes[:-1]:
            text = _text(s.dtype, w.data, self.encoding)
            if text is None or "\n" in text or "\r" in text:
                text = w.data.hex().upper() or '""'
            out.append(f"; entry {w.pos + 1} (offset 0x{w.offset:X}) wrote {text}")
        if len(s.writes) > 1:
            out.append(f"; entry {s.writes[-1].pos + 1} (offset 0x{s.writes[-1].offset:X}) "
                       "wrote the ParameterValue below")
        return out

    # -- text -------------------------------------------------------------------------------------
    def _render(self) -> str:
        c = self.c
        out: list[str] = []
        w = out.append
        n = len(c.entries)
        w(f"; DCF written by dcf2bin bin2dcf from {self.name} "
          f"({self.header['total_size']} bytes, {n} entr{'y' if n == 1 else 'ies'}).")
        w("; ParameterValue is the last value written to each entry; comments list earlier "
          "writes.")
        w("")
        w("[FileInfo]")
        w(f"FileName={self.dcf_name}")
        w("FileVersion=1")
        w("FileRevision=0")
        w("EDSVersion=4.0")
        w(f"Description=Converted from the binary DCF segment container {self.name}")
        w("CreatedBy=dcf2bin bin2dcf")
        w("")
        self._device_info(w)
        self._dummy_usage(w)
        if self.channels:
            w("[DynamicChannels]")
            w(f"NrOfSeg={len(self.channels)}")
            for k, ch in enumerate(self.channels, 1):
                w(f"Type{k}=0x{ch.dtype.code:04X}")
                w(f"Dir{k}={'ro' if ch.direction == INPUT else 'rw'}")
                w(f"Range{k}=0x{ch.first:04X}-0x{ch.last:04X}")
                w(f"PPOffset{k}={ch.pp}")
            w("")
        idxs = sorted(i for i in self.objects if i >= 0x1000)
        mandatory = [i for i in idxs if i in (0x1000, 0x1001, 0x1018)]
        manufacturer = [i for i in idxs if 0x2000 <= i <= 0x5FFF]
        optional = [i for i in idxs if i not in mandatory and i not in manufacturer]
        for title, lst in (("MandatoryObjects", mandatory), ("OptionalObjects", optional),
                           ("ManufacturerObjects", manufacturer)):
            w(f"[{title}]")
            w(f"SupportedObjects={len(lst)}")
            for k, i in enumerate(lst, 1):
                w(f"{k}=0x{i:04X}")
            w("")
        for index in sorted(self.objects):
            self._object(w, self.objects[index])
        return "\n".join(out).rstrip("\n") + "\n"

    def _device_info(self, w) -> None:
        sec = None
        if self.eds_device is not None and self.eds_device.ini is not None:
            sec = self.eds_device.ini.section("deviceinfo")
        rx = sum(1 for i in self.objects if 0x1400 <= i <= 0x15FF)
        tx = sum(1 for i in self.objects if 0x1800 <= i <= 0x19FF)
        w("[DeviceInfo]")
        if sec is not None:
            for key, k in sec.keys.items():
                if key in ("compactpdo", "nrofrxpdo", "nroftxpdo") or not k.value:
                    continue       # CompactPDO would create objects the container lacks
                w(f"{k.name}={_clean(k.value)}")
        w(f"NrOfRXPDO={rx}")
        w(f"NrOfTXPDO={tx}")
        if self.channels:
            if sec is None or "dynamicchannelssupported" not in sec.keys:
                w(f"DynamicChannelsSupported={len(self.channels)}")
        w("")

    def _dummy_usage(self, w) -> None:
        dummies = set()
        for obj in self.objects.values():
            if not is_mapping(obj.index):
                continue
            for s in obj.subs.values():
                if s.sub and s.writes and len(s.data) == 4:
                    v = int.from_bytes(s.data, "little")
                    if 1 <= v >> 16 <= 7 and (v >> 8) & 0xFF == 0:
                        dummies.add(v >> 16)
        if self.eds_device is not None:
            dummies |= set(self.eds_device.dummy_usage)
        if dummies:
            w("[DummyUsage]")
            for code in sorted(dummies):
                w(f"Dummy{code:04X}=1")
            w("")

    def _object(self, w, obj: ObjSpec) -> None:
        if obj.object_type == dt.OT_VAR:
            s = obj.subs[0]
            w(f"[{obj.index:04X}]\nParameterName={_clean(obj.name or s.name)}\nObjectType=0x7")
            w(self._keys(s))
            return
        w(f"[{obj.index:04X}]\nParameterName={_clean(obj.name)}\n"
          f"ObjectType=0x{obj.object_type:X}\nSubNumber={len(obj.subs)}\n")
        index = obj.index
        keys = self._keys
        for sub, s in obj.subs.items():
            w(f"[{index:04X}sub{sub:X}]\nParameterName={_clean(s.name)}\nObjectType=0x7")
            w(keys(s))

    def _keys(self, s: SubSpec) -> str:
        if len(s.writes) == 1:
            return (f"DataType=0x{s.dtype.code:04X}\nAccessType={s.access}\n"
                    f"PDOMapping={1 if s.pdo else 0}\nParameterValue={s.value}\n")
        lines = self._earlier(s)
        if not s.writes:
            lines.append("; not in the container: the sub 0 that compile implies")
        lines.append(f"DataType=0x{s.dtype.code:04X}")
        lines.append(f"AccessType={s.access}")
        if s.default:
            lines.append(f"DefaultValue={s.default}")
        lines.append(f"PDOMapping={1 if s.pdo else 0}")
        if s.writes:
            lines.append(f"ParameterValue={s.value}")
        return "\n".join(lines) + "\n"

    # -- prediction ------------------------------------------------------------------------------
    def _predict(self) -> tuple[bool, list[str]]:
        """Replay compile's rules on the objects written; warn where the bytes would differ."""
        c = self.c
        writes, error = self._expected_writes()
        layout = None
        if error is None:
            layout, error = self._expected_layout(writes)
        if error is not None:
            self.issues.add(R_SUMMARY, None, f"the DCF will not compile: {error}; for a "
                            "lossless copy use 'dcf2bin dump --format json'")
            return False, []
        attrs = c.attributes or b""
        actual = c.entries
        first_diff = None
        n = max(len(writes), len(actual))
        for i in range(n):
            e = writes[i] if i < len(writes) else None
            a = actual[i] if i < len(actual) else None
            a_attr = attrs[i] if i < len(attrs) else None
            if e is None or a is None or e[:3] != a or e[3] != a_attr:
                first_diff = i
                break
        entries_ok = first_diff is None and len(attrs) == len(actual)
        addresses, pi = layout
        pi_ok = (addresses == c.addresses and pi == c.pi and c.raw_piparam is None)
        no_pi_ok = c.addresses is None and c.pi is None and c.raw_piparam is None
        version_ok = c.version == 1
        layout_ok = c.header is None
        if entries_ok and pi_ok and version_ok and layout_ok:
            return True, []
        options = []
        if entries_ok and layout_ok and (pi_ok or (no_pi_ok and addresses is not None)):
            if not version_ok:
                options.append(f"--container-version {c.version}")
            if not pi_ok:
                options.append("--no-process-image")
            self.issues.add(R_SUMMARY, None, "compile gives the same bytes only with "
                            f"{' '.join(options)}")
            return False, options
        if first_diff is not None:
            where = self.offsets[first_diff] if first_diff < len(actual) else None
            got = _describe(actual[first_diff], attrs[first_diff] if first_diff < len(attrs)
                            else None) if first_diff < len(actual) else "nothing"
            exp = _describe(writes[first_diff][:3], writes[first_diff][3]) \
                if first_diff < len(writes) else "nothing"
            self.issues.add(R_SUMMARY, where, f"the DCF will not compile back to the same "
                            f"container: entry {first_diff + 1} is {got}, compile writes {exp}; "
                            "for a lossless copy use 'dcf2bin dump --format json'")
        elif not entries_ok:
            self.issues.add(R_SUMMARY, None, "the DCF will not compile back to the same "
                            "container (attribute segment); for a lossless copy use "
                            "'dcf2bin dump --format json'")
        else:
            what = []
            if not (pi_ok or no_pi_ok):
                if addresses != c.addresses:
                    what.append("PI addresses")
                if pi != c.pi or c.raw_piparam is not None:
                    what.append("PI parameters")
            if not version_ok:
                what.append("header version")
            if not layout_ok:
                what.append("header layout")
            if no_pi_ok and addresses is not None and not pi_ok:
                what.append("PI segments (--no-process-image)")
            self.issues.add(R_SUMMARY, None, "the DCF will not compile back to the same "
                            f"container ({', '.join(what)}); for a lossless copy use "
                            "'dcf2bin dump --format json'")
        return False, options

    def _expected_writes(self) -> tuple[list[tuple[int, int, bytes, int]], str | None]:
        objs = self.objects
        exp: list[tuple[int, int, bytes, int]] = []
        idxs = sorted(i for i in objs if i >= 0x1000)
        # 1. creation: network-variable objects, all sub-entries, sub 0 first
        for index in idxs:
            if is_nv(index):
                for sub, s in objs[index].subs.items():
                    data = s.data if s.writes else int(s.default).to_bytes(1, "little")
                    exp.append((index, sub, data, 0x30 if sub == 0 else 0xF0))
        # 2. configuration: configured, writable entries (every written entry is configured)
        for index in idxs:
            if is_nv(index) or is_comm(index) or is_mapping(index):
                continue
            for sub, s in objs[index].subs.items():
                if s.writes and s.access not in ("ro", "const"):
                    exp.append((index, sub, s.data, s.attr))
        # 3. PDO blocks (CiA 301 sequence)
        for index in idxs:
            if is_comm(index) and index + 0x200 not in objs:
                return exp, (f"PDO communication object 0x{index:04X} has no mapping object "
                             f"0x{index + 0x200:04X} in the container")
            if is_mapping(index) and index - 0x200 not in objs:
                return exp, (f"PDO mapping object 0x{index:04X} has no communication object "
                             f"0x{index - 0x200:04X} in the container")
        for index in idxs:
            if not is_comm(index):
                continue
            err = self._pdo_block(index, exp)
            if err:
                return exp, err
        return exp, None

    def _pdo_block(self, comm_idx: int, exp: list) -> str | None:
        comm, mapping = self.objects[comm_idx], self.objects[comm_idx + 0x200]
        cob = comm.subs.get(1)
        if cob is None or not cob.writes:
            return f"PDO 0x{comm_idx:04X} has no COB-ID (sub 1) in the container"
        if cob.dtype.code != dt.UNSIGNED32.code:
            return f"0x{comm_idx:04X}sub1: the COB-ID is not 4 bytes NUMERIC"
        final = int.from_bytes(cob.data, "little")
        exp.append((comm_idx, 1, (final | COB_INVALID).to_bytes(4, "little"), cob.attr))
        for s in (2, 3, 5, 6):
            e = comm.subs.get(s)
            if e is not None and e.writes:
                exp.append((comm_idx, s, e.data, e.attr))
        sub0 = mapping.subs[0]
        data0 = sub0.data if sub0.writes else int(sub0.default).to_bytes(1, "little")
        n = int.from_bytes(data0, "little", signed=sub0.dtype.kind == dt.SINT)
        if n > MAX_MAPPED or n < 0:
            return f"0x{mapping.index:04X}sub0: {n} mapped objects"
        size0 = sub0.dtype.size or 1
        exp.append((mapping.index, 0, (0).to_bytes(size0, "little"), sub0.attr))
        for k in range(1, n + 1):
            e = mapping.subs.get(k)
            if e is None:
                return (f"PDO mapping 0x{mapping.index:04X} maps {n} objects but sub {k} is "
                        "not in the container")
            exp.append((mapping.index, k, e.data, e.attr))
        exp.append((mapping.index, 0, n.to_bytes(size0, "little"), sub0.attr))
        if not final & COB_INVALID:
            exp.append((comm_idx, 1, final.to_bytes(4, "little"), cob.attr))
        for s in sorted(comm.subs):
            if s in (0, 4) or s >= 7:
                e = comm.subs[s]
                if e.writes:
                    self.issues.add(R_PDO, e.writes[-1].offset, f"0x{comm_idx:04X}sub{s:X}: "
                                    "compile never writes comm sub 0, 4 or >= 7 in a PDO block")
        for k in sorted(mapping.subs):
            if k > n and mapping.subs[k].writes:
                self.issues.add(R_PDO, mapping.subs[k].writes[-1].offset,
                                f"0x{mapping.index:04X}sub{k:X} lies above the {n} mapped "
                                "objects; compile does not write it")
        return None

    def _expected_layout(self, writes):
        """SPEC §2.2-2.4 and D-10 for the variables written -> (addresses, PI) or an error."""
        nv_objs = [i for i in self.objects if is_nv(i)]
        if not nv_objs:
            return (None, None), None
        has_nv = any(s for i in nv_objs for s in self.objects[i].subs)
        spans: dict[str, list] = {INPUT: [], OUTPUT: []}
        placed = {}
        for index in sorted(nv_objs):
            ch = self._channel(index)
            if ch is None:
                return None, (f"0x{index:04X} lies in 0xA900-0xAFFF without a "
                              "[DynamicChannels] segment")
            first, dtype, direction, pp = ch
            for sub, s in self.objects[index].subs.items():
                if sub == 0:
                    continue
                if sub > PER_INDEX:
                    return None, f"0x{index:04X}sub{sub:X}: subindex above 254"
                if s.dtype.code != dtype.code:
                    return None, (f"0x{index:04X}sub{sub:X}: {s.dtype.name} does not match "
                                  f"the range type {dtype.name}")
                off = pp + ((index - first) * PER_INDEX + sub - 1) * dtype.size
                placed[(index, sub)] = (direction, off)
                spans[direction].append((off, off + dtype.size, index, sub))
        sizes = {}
        for area, lst in spans.items():
            lst.sort()
            reach = -1
            for start, end, index, sub in lst:
                if start < reach:
                    return None, (f"0x{index:04X}sub{sub:X} overlaps another variable in the "
                                  f"{area} area")
                reach = max(reach, end)
            sizes[area] = max((e for _, e, _, _ in lst), default=0)
        in_size, out_size = sizes[INPUT], sizes[OUTPUT]
        out_off = -(-in_size // 8) * 8 if out_size else 0
        total = out_off + out_size if out_size else in_size
        addresses = []
        seen = set()
        for index, sub, _, _ in writes:
            key = (index, sub)
            if key in placed and key not in seen:
                seen.add(key)
                direction, off = placed[key]
                addr = off if direction == INPUT else out_off + off
                if addr > 0xFFFF:
                    return None, f"0x{index:04X}sub{sub:X}: address 0x{addr:X} above 0xFFFF"
                addresses.append(addr)
        if not has_nv:
            return (None, None), None
        return (addresses, (total, 0, in_size, out_off, out_size)), None

    def _channel(self, index: int):
        for ch in self.channels:
            if ch.first <= index <= ch.last:
                return ch.first, ch.dtype, ch.direction, ch.pp
        tt = table_type(index)
        if tt is None:
            return None
        return NV_FIRST + (index - NV_FIRST) // RANGE_LEN * RANGE_LEN, tt[0], tt[1], 0


def _pp(vs, index: int, start: int, dtype: dt.DataType):
    """The segment start (PPOffset) that places all of ``vs`` in index ``index``."""
    pps = set()
    for sub, _, _, off, _ in vs:
        if off is None:
            continue
        pps.add(off - ((index - start) * PER_INDEX + sub - 1) * dtype.size)
    if not pps:
        return None
    if len(pps) > 1:
        return "mixed"
    return pps.pop()


def _by_size(size: int) -> dt.DataType:
    return dt.UNSIGNED_BY_SIZE.get(size, dt.DOMAIN_T)


def _short(data: bytes) -> str:
    h = data.hex().upper()
    return h if len(h) <= 24 else h[:20] + "..."


def _clean(text: str) -> str:
    return text.replace("\r", " ").replace("\n", " ").strip() or '""'


def _describe(entry, attr) -> str:
    index, sub, data = entry
    a = f"attribute 0x{attr:02X}" if attr is not None else "no attribute"
    return f"0x{index:04X}sub{sub:X} = {_short(data) or '(empty)'} ({a})"


def convert(c: BinContainer, name: str, *, dcf_name: str, eds: EdsInfo | None = None,
            eds_device=None) -> Result:
    """A container as DCF text, with warnings where compile would not give the same bytes."""
    return _Converter(c, name, dcf_name, eds, eds_device).run()
