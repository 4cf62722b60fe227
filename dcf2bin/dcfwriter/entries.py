"""Typing the entries of a container (SPEC §4): DataType, AccessType, PDOMapping and
names for each (index, subindex), from the CiA 405 range of a network variable, from
the attribute byte and the data size, or from an EDS (``--eds``) where it agrees
with what the container stores. Where no DCF entry gives the stored attribute,
a warning says so.
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin.dcfwriter.spec import (R_ATTR, R_EDS, R_PI, R_REPEAT, R_SELECT, Issues, SubSpec,
                                    Write, by_size, holds, table_type, value_text)
from dcf2bin.dump import EdsInfo, entry_type
from dcf2bin.dump.concise_types import GUESS
from dcf2bin.layout import PER_INDEX
from dcf2bin.model import is_network_variable_index as is_nv
from dcf2bin.model import is_pdo_comm as is_comm
from dcf2bin.model import is_pdo_mapping as is_mapping
from dcf2bin.select import attribute_byte as attribute

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


class EntryTyper:
    """Object types, names and entry types, warning into ``issues`` where the DCF
    cannot say what the container stores."""

    def __init__(self, eds: EdsInfo | None, issues: Issues, what: str = "container"):
        self.eds = eds
        self.issues = issues
        self.what = what                  # "container", or "concise DCF"
        self.concise = what != "container"

    def object_type(self, index: int, subs: list[int]) -> int:
        if is_nv(index):
            return dt.OT_ARRAY
        only_sub0 = all(s == 0 for s in subs)
        eo = self.eds.objects.get(index) if self.eds is not None else None
        if eo is not None and eo.object_type in (dt.OT_ARRAY, dt.OT_RECORD):
            return eo.object_type
        if is_comm(index) or is_mapping(index):
            return dt.OT_RECORD
        return dt.OT_VAR if only_sub0 else dt.OT_RECORD

    def object_name(self, index: int) -> str:
        if self.eds is not None:
            eo = self.eds.objects.get(index)
            if eo is not None and eo.name:
                return eo.name
        if index in _STD_NAMES:
            return _STD_NAMES[index]
        if is_comm(index) or is_mapping(index):
            comm = index if is_comm(index) else index - 0x200
            kind, number = ("RPDO", comm - 0x1400) if comm < 0x1800 else ("TPDO", comm - 0x1800)
            what = "communication" if comm == index else "mapping"
            return f"{kind}{number + 1} {what} parameter"
        if is_nv(index):
            t = table_type(index)
            if t is not None:
                return f"{t[0].name} {t[1]}s"
            return "Network variables"
        return f"Object {index:04X}"

    def sub_name(self, index: int, sub: int) -> str:
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

    def entry(self, index: int, sub: int, writes: list[Write]) -> SubSpec:
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
        if index < 0x1000 and not self.concise:
            self.issues.add(R_SELECT, off, f"{label}: compile never writes objects below "
                            "0x1000 (data type definitions)")
        if is_nv(index):   # sub 0 of a network-variable object
            dtype = dt.UNSIGNED8 if len(data) == 1 else by_size(len(data))
            if attr is not None and attr != 0x30:
                self.issues.add(R_ATTR, off, f"{label} has attribute 0x{attr:02X}; compile "
                                "gives sub 0 of a network-variable object 0x30")
            return SubSpec(index, sub, dtype, "ro", False, writes, self.sub_name(index, sub))
        note = ""
        if attr is None and self.concise:   # no attribute: CiA 301's type, or by the size
            dtype, source = entry_type(index, sub, len(data))
            dtype, access, pdo = dtype or dt.DOMAIN_T, "rw", False
            if source == GUESS:
                note = "; DataType guessed from the size alone (--eds gives the device's)"
        else:
            dtype, access, pdo = self.infer(label, off, attr, data)
        eds_e = self.eds.entries.get((index, sub)) if self.eds is not None else None
        if eds_e is not None and eds_e.dtype is not None and eds_e.access is not None:
            et = eds_e.dtype
            exact = attribute(index, sub, et, eds_e.access, eds_e.pdo_mapping)
            if et.size is not None and et.size != len(data):
                self.issues.add(R_EDS, off, f"{label}: the EDS says {et.name} ({et.size} "
                                f"bytes), the {self.what} writes {len(data)} bytes; "
                                f"the {self.what} wins")
            elif attr is not None and exact != attr:
                self.issues.add(R_EDS, off, f"{label}: the EDS gives attribute 0x{exact:02X} "
                                f"({dt.attr_flags(exact)}), the container has 0x{attr:02X} "
                                f"({dt.attr_flags(attr)}); the container wins")
            else:
                dtype, access, pdo = et, eds_e.access, eds_e.pdo_mapping
                note = ""
        if access in ("ro", "const") and not (is_comm(index) or is_mapping(index)) \
                and not self.concise:
            self.issues.add(R_SELECT, off, f"{label} is read-only (attribute "
                            f"0x{attr:02X}); compile does not write ro entries outside "
                            "the PDO objects")
        return SubSpec(index, sub, dtype, access, pdo, writes, self.sub_name(index, sub),
                       note=note)

    def infer(self, label: str, off: int, attr: int | None, data: bytes):
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

    # -- network variables (SPEC §2.1, D-9) ----------------------------------------------------
    def nv_checks(self, index: int, sub: int, writes: list[Write]) -> None:
        label = f"0x{index:04X}sub{sub:X}"
        if not self.concise and any(w.attr != 0xF0 for w in writes):
            bad = next(w for w in writes if w.attr != 0xF0)
            shown = f"0x{bad.attr:02X}" if bad.attr is not None else "none"
            self.issues.add(R_ATTR, bad.offset, f"{label} has attribute {shown}; compile "
                            "gives every network variable 0xF0")
        if len(writes) > 1:
            self.issues.add(R_REPEAT, writes[0].offset, f"{label} is written "
                            f"{len(writes)} times; compile writes a network variable once")
        if sub > PER_INDEX:
            self.issues.add(R_PI, writes[-1].offset, f"{label}: subindex {sub} is above 254, "
                            "the last network variable of an index")

    def nv_type(self, index: int, sub: int, last: Write) -> dt.DataType:
        data = last.data
        size = len(data)
        if self.eds is not None:
            t = self.eds.dtype(index, sub)
            if t is not None and t.size == size and value_text(t, data, "utf-8") is not None:
                return t
            if t is not None and t.size != size:
                self.issues.add(R_EDS, last.offset, f"0x{index:04X}sub{sub:X}: the EDS says "
                                f"{t.name}, the {self.what} writes {size} bytes; the {self.what} "
                                "wins")
        tt = table_type(index)
        if tt is not None and holds(tt[0], data):
            return tt[0]
        if size in dt.UNSIGNED_BY_SIZE:
            return dt.UNSIGNED_BY_SIZE[size]   # a [DynamicChannels] segment gives the type
        self.issues.add(R_PI, last.offset, f"0x{index:04X}sub{sub:X} has {size} data bytes; a "
                        "network variable has 1 to 8 (compile will reject this DCF)")
        return dt.DOMAIN_T



__all__ = ["EntryTyper"]
