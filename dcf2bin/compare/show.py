"""An entry's value and facts as words, for both renderers: typed values (integers of up to
16 bits in decimal, wider ones in hex of their width, strings quoted), what a PDO mapping
entry maps ("0x6041sub0 Statusword, 16 bits") and what a PDO's COB-ID says.

The type is the entry's own, else the other side's (a container or a node knows none),
else what a container's attribute byte and the size say; without any, the bytes in hex.

Every value is shown bounded: long bytes as their first 32 and the count, a string or a
value as written of more than 80 characters as its first 40 and last 12 and the count
(``diagnostics.shorten``); the JSON form's ``data`` holds the whole bytes. Two values of
other bytes that read as the same text (a Latin-1 string against a UTF-8 one) show their
bytes after it: ``"café" (63 61 66 E9)``.
"""
from __future__ import annotations

import json

from dcf2bin import datatypes as dt
from dcf2bin.compare.side import Item, Side
from dcf2bin.diagnostics import shorten
from dcf2bin.indexes import is_pdo_comm, is_pdo_mapping

LONG = 32        # bytes of a long OCTET_STRING/DOMAIN shown before "..."
LONG_TEXT = 80   # characters of a string, or a value as written, shown whole (else shortened)


# The data types CiA 301/302 give the communication objects, for a value whose side and
# other side know none (two concise DCFs): used only where the size is the type's.
_U8, _U16, _U32 = dt.UNSIGNED8, dt.UNSIGNED16, dt.UNSIGNED32
_STANDARD = {0x1000: _U32, 0x1001: _U8, 0x1005: _U32, 0x1006: _U32, 0x1007: _U32,
             0x100C: _U16, 0x100D: _U8, 0x1012: _U32, 0x1014: _U32, 0x1015: _U16,
             0x1016: _U32, 0x1017: _U16, 0x1019: _U8, 0x1F80: _U32, 0x1F81: _U32,
             0x1F84: _U32, 0x1F85: _U32, 0x1F86: _U32, 0x1F87: _U32, 0x1F88: _U32,
             0x1F89: _U32}
_PDO_COMM_SUBS = {0: _U8, 1: _U32, 2: _U8, 3: _U16, 4: _U8, 5: _U16, 6: _U8}


def standard_type(index: int, sub: int) -> dt.DataType | None:
    """The type CiA 301 gives an entry of the communication profile, or None."""
    if is_pdo_comm(index):
        return _PDO_COMM_SUBS.get(sub)
    if is_pdo_mapping(index):
        return _U8 if sub == 0 else _U32
    if sub == 0 and index in (0x1016, 0x1F81, 0x1F84, 0x1F85, 0x1F86, 0x1F87, 0x1F88):
        return _U8                          # ARRAYs: sub 0 counts their entries
    return _STANDARD.get(index)


def type_of(item: Item, other: Item | None) -> dt.DataType | None:
    """The type a value is read as: its own, the other side's, the attribute's, or the one
    CiA 301 gives a communication object (each only where the size fits it)."""
    size = len(item.value.data) if item.value.data is not None else None
    for t in (item.dtype, other.dtype if other is not None else None):
        if t is not None and (t.size is None or size is None or t.size == size):
            return t
    if item.attr is not None and size is not None:
        kinds = item.attr & dt.ATTR_TYPE_MASK
        if kinds == dt.ATTR_BOOLEAN and size == 1:
            return dt.BOOLEAN
        if kinds == dt.ATTR_VSTRING:
            return dt.VISIBLE_STRING
        if kinds == dt.ATTR_NUMERIC:
            return dt.UNSIGNED_BY_SIZE.get(size)
    t = standard_type(item.index, item.sub)
    return t if t is not None and t.size == size else None


def value_text(item: Item, other: Item | None = None) -> str:
    """The value as the output shows it (without what it means)."""
    v = item.value
    if v.data is None:
        # the text as written is the user's: shortened as every message quotes one
        if v.problem is not None:
            problem = shorten(v.problem, LONG_TEXT)
            return f"{shorten(v.text, LONG_TEXT)} (invalid: {problem})" if v.text else problem
        if v.text is not None:
            return shorten(v.text, LONG_TEXT)   # a $NODEID formula without a node-ID
        return "(no value)"
    text = typed(v.data, type_of(item, other))
    if _looks_alike(text, item, other):
        text += f" ({_spaced(v.data)})"
    if v.source is not None:
        return f"{text} (from {v.source})"
    return f"{text} (no value given)" if v.implied else text


def _looks_alike(text: str, item: Item, other: Item | None) -> bool:
    """Two values of other bytes shown as the same text (a Latin-1 "café" and a UTF-8
    one): the lines would differ in nothing a reader sees, so each shows its bytes too."""
    if other is None or other.value.data is None or other.value.data == item.value.data:
        return False
    return typed(other.value.data, type_of(other, item)) == text


def _spaced(data: bytes) -> str:
    """Bytes as spaced hex (``63 61 66 E9``), the first 32 of longer ones and the count."""
    shown = " ".join(f"{b:02X}" for b in data[:LONG])
    return f"{shown} ... {len(data)} bytes" if len(data) > LONG else shown


def typed(data: bytes, t: dt.DataType | None) -> str:
    if t is None or (t.size is not None and t.size != len(data)):
        n = len(data)            # bytes of no known type: the hex and how many they are
        return f"{_hex(data)} ({n} byte{'' if n == 1 else 's'})" if n <= LONG else _hex(data)
    if t.kind == dt.BOOL:
        return {b"\x00": "0", b"\x01": "1"}.get(data, _hex(data))
    if t.kind in (dt.UINT, dt.TIME):
        n = int.from_bytes(data, "little")
        return str(n) if len(data) <= 2 and t.kind == dt.UINT else f"0x{n:0{2 * len(data)}X}"
    if t.kind == dt.SINT:
        return str(int.from_bytes(data, "little", signed=True))
    if t.kind == dt.REAL:
        from dcf2bin import values
        return values.decode(t, data) or _hex(data)
    if t.kind in (dt.VSTRING, dt.USTRING):
        try:
            text = data.decode("utf-16-le" if t.kind == dt.USTRING else "utf-8")
        except UnicodeDecodeError:
            if t.kind == dt.USTRING:
                return _hex(data)
            text = data.decode("latin-1")        # a DCF in Latin-1 writes its strings so
        return shorten(json.dumps(text, ensure_ascii=False), LONG_TEXT)
    return _hex(data)


def _hex(data: bytes) -> str:
    if not data:
        return '""'
    if len(data) > LONG:
        return f"{data[:LONG].hex().upper()}... ({len(data)} bytes)"
    return data.hex().upper()


def meaning(item: Item, a: Side, b: Side) -> str | None:
    """What a PDO mapping entry maps, or a PDO's COB-ID says; None for other entries."""
    data = item.value.data
    if data is None or len(data) != 4 or item.sub == 0:
        return None
    n = int.from_bytes(data, "little")
    if is_pdo_mapping(item.index):
        if n == 0:
            return "nothing mapped"
        index, sub, bits = n >> 16, (n >> 8) & 0xFF, n & 0xFF
        name = entry_name(index, sub, a, b)
        return f"0x{index:04X}sub{sub:X}" + (f" {name}" if name else "") + f", {bits} bits"
    if is_pdo_comm(item.index) and item.sub == 1:
        ext = n & 0x20000000
        can_id = n & (0x1FFFFFFF if ext else 0x7FF)
        return f"COB-ID 0x{can_id:X}" + (", invalid" if n & 0x80000000 else "")
    return None


def entry_name(index: int, sub: int, a: Side, b: Side) -> str:
    """An entry's name as either side's description gives it: the sub-entry's own for
    an ARRAY/RECORD, the object's for a VAR; a data type's index (a dummy mapping)
    "dummy UNSIGNED8"."""
    if index < 0x1000:
        t = dt.BY_CODE.get(index)
        return f"dummy {t.name}" if t is not None and sub == 0 else ""
    for s in (a, b):
        it = s.items.get((index, sub))
        if it is not None and it.name:
            return it.name
    for s in (a, b):
        name = s.object_name(index)
        if name and sub == 0:
            return name
    return ""


def object_name(index: int, a: Side, b: Side) -> str:
    return a.object_name(index) or b.object_name(index)


def facts(item: Item, facets=None) -> str:
    """The data type, access and PDO mapping flag (``facets``: only those named), as
    ``UNSIGNED8, rw, mappable``; a container's attribute byte as ``attribute 0x70
    NUM|R|W``."""
    parts = []
    want = (lambda f: True) if facets is None else (lambda f: f in facets)
    if item.dtype is not None and want("datatype"):
        parts.append(item.dtype.name)
    if item.access is not None and want("access"):
        parts.append(item.access)
    if item.pdo_mapping is not None and want("pdo_mapping"):
        parts.append("mappable" if item.pdo_mapping else "not mappable")
    if item.attr is not None and want("attribute"):
        parts.append(f"attribute 0x{item.attr:02X} {dt.attr_flags(item.attr)}")
    return ", ".join(parts)
