"""CANopen data types (SPEC.md §1) and the attribute bits of SPEC.md §3.3.

The codes match ``canopen.objectdictionary.datatypes`` (tests/test_values.py
checks that); they are kept here as plain data so that importing this module
does not import canopen.
"""
from __future__ import annotations

from dataclasses import dataclass

# Kinds decide how a value is parsed and encoded.
BOOL, SINT, UINT, REAL, VSTRING, OSTRING, USTRING, TIME, DOMAIN = (
    "bool", "sint", "uint", "real", "vstring", "ostring", "ustring", "time", "domain")

# Extended-info attribute bits (SPEC §3.3).
ATTR_BOOLEAN = 0x01
ATTR_VSTRING = 0x08
ATTR_NUMERIC = 0x10
ATTR_READ = 0x20
ATTR_WRITE = 0x40
ATTR_PDO = 0x80
ATTR_UNDEFINED = 0x06
ATTR_TYPE_MASK = ATTR_BOOLEAN | ATTR_VSTRING | ATTR_NUMERIC


@dataclass(frozen=True)
class DataType:
    """A CiA 301 data type: its code, name, size in bytes (None: variable length) and kind."""
    code: int
    name: str
    size: int | None  # bytes; None = variable length
    kind: str

    @property
    def bits(self) -> int | None:
        return None if self.size is None else self.size * 8

    @property
    def is_integer(self) -> bool:
        return self.kind in (BOOL, SINT, UINT, TIME)

    @property
    def is_numeric(self) -> bool:
        return self.kind in (SINT, UINT, REAL, TIME)

    @property
    def type_attr(self) -> int:
        """The type bits of the extended-info attribute byte (SPEC §3.3)."""
        if self.kind == BOOL:
            return ATTR_BOOLEAN
        if self.kind == VSTRING:
            return ATTR_VSTRING
        if self.is_numeric:
            return ATTR_NUMERIC
        return 0  # byte copy: OCTET_STRING, UNICODE_STRING, DOMAIN

    @property
    def min(self) -> int:
        if self.kind == SINT:
            return -(1 << (self.bits - 1))
        return 0

    @property
    def max(self) -> int:
        if self.kind == BOOL:
            return 1
        if self.kind == SINT:
            return (1 << (self.bits - 1)) - 1
        return (1 << self.bits) - 1


_TABLE = [
    DataType(0x01, "BOOLEAN", 1, BOOL),
    DataType(0x02, "INTEGER8", 1, SINT),
    DataType(0x03, "INTEGER16", 2, SINT),
    DataType(0x04, "INTEGER32", 4, SINT),
    DataType(0x05, "UNSIGNED8", 1, UINT),
    DataType(0x06, "UNSIGNED16", 2, UINT),
    DataType(0x07, "UNSIGNED32", 4, UINT),
    DataType(0x08, "REAL32", 4, REAL),
    DataType(0x09, "VISIBLE_STRING", None, VSTRING),
    DataType(0x0A, "OCTET_STRING", None, OSTRING),
    DataType(0x0B, "UNICODE_STRING", None, USTRING),
    DataType(0x0C, "TIME_OF_DAY", 6, TIME),
    DataType(0x0D, "TIME_DIFFERENCE", 6, TIME),
    DataType(0x0F, "DOMAIN", None, DOMAIN),
    DataType(0x10, "INTEGER24", 3, SINT),
    DataType(0x11, "REAL64", 8, REAL),
    DataType(0x12, "INTEGER40", 5, SINT),
    DataType(0x13, "INTEGER48", 6, SINT),
    DataType(0x14, "INTEGER56", 7, SINT),
    DataType(0x15, "INTEGER64", 8, SINT),
    DataType(0x16, "UNSIGNED24", 3, UINT),
    DataType(0x18, "UNSIGNED40", 5, UINT),
    DataType(0x19, "UNSIGNED48", 6, UINT),
    DataType(0x1A, "UNSIGNED56", 7, UINT),
    DataType(0x1B, "UNSIGNED64", 8, UINT),
]

BY_CODE: dict[int, DataType] = {t.code: t for t in _TABLE}
BY_NAME: dict[str, DataType] = {t.name: t for t in _TABLE}

BOOLEAN = BY_CODE[0x01]
UNSIGNED8 = BY_CODE[0x05]
UNSIGNED16 = BY_CODE[0x06]
UNSIGNED32 = BY_CODE[0x07]
DOMAIN_T = BY_CODE[0x0F]
OCTET_STRING = BY_CODE[0x0A]
VISIBLE_STRING = BY_CODE[0x09]

# Numeric types by size, for bin2dcf's inference from a NUMERIC attribute (SPEC §4).
UNSIGNED_BY_SIZE = {1: BY_CODE[0x05], 2: BY_CODE[0x06], 3: BY_CODE[0x16], 4: BY_CODE[0x07],
                    5: BY_CODE[0x18], 6: BY_CODE[0x19], 7: BY_CODE[0x1A], 8: BY_CODE[0x1B]}

# Access types (SPEC §1) and their attribute bits (D-9).
ACCESS_ATTR = {"ro": ATTR_READ, "const": ATTR_READ, "wo": ATTR_WRITE,
               "rw": ATTR_READ | ATTR_WRITE, "rwr": ATTR_READ | ATTR_WRITE,
               "rww": ATTR_READ | ATTR_WRITE}
# PDO directions (SPEC §5), not SDO access: rww is not a TPDO source, rwr not an RPDO target.
READABLE = frozenset({"ro", "rw", "rwr", "const"})   # may be mapped into a TPDO
WRITABLE = frozenset({"wo", "rw", "rww"})            # may be mapped from an RPDO

# ObjectType codes (SPEC §1).
OT_DOMAIN, OT_DEFTYPE, OT_DEFSTRUCT, OT_VAR, OT_ARRAY, OT_RECORD = 0x2, 0x5, 0x6, 0x7, 0x8, 0x9
OBJECT_TYPES = {OT_DOMAIN: "DOMAIN", OT_DEFTYPE: "DEFTYPE", OT_DEFSTRUCT: "DEFSTRUCT",
                OT_VAR: "VAR", OT_ARRAY: "ARRAY", OT_RECORD: "RECORD"}


def attr_flags(attr: int) -> str:
    """Render an attribute byte as ``NUM|R|W|MAP`` (unknown bits as ``0x..``)."""
    parts = []
    for bit, name in ((ATTR_BOOLEAN, "BOOL"), (ATTR_VSTRING, "VSTR"), (ATTR_NUMERIC, "NUM"),
                      (ATTR_READ, "R"), (ATTR_WRITE, "W"), (ATTR_PDO, "MAP")):
        if attr & bit:
            parts.append(name)
    if attr & ATTR_UNDEFINED:
        parts.append(f"0x{attr & ATTR_UNDEFINED:02X}")
    if not attr & ATTR_TYPE_MASK:
        parts.insert(0, "DOM")
    return "|".join(parts)
