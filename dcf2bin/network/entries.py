"""One configured value of a node: a :class:`Write` with its exact bytes, checked against
the node's file (the entry exists; a slave's is writable)."""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import Diagnostics, Where, shorten
from dcf2bin.network.model import Write

# CiA 301/302 data types of the entries configure writes, for a master without a file
STANDARD_TYPES = {0x1005: dt.UNSIGNED32, 0x1006: dt.UNSIGNED32, 0x1007: dt.UNSIGNED32,
                  0x100C: dt.UNSIGNED16, 0x100D: dt.UNSIGNED8, 0x1016: dt.UNSIGNED32,
                  0x1017: dt.UNSIGNED16, 0x1F22: dt.BY_NAME["DOMAIN"],
                  0x1F55: dt.UNSIGNED32, 0x1F80: dt.UNSIGNED32, 0x1F81: dt.UNSIGNED32,
                  0x1F84: dt.UNSIGNED32, 0x1F85: dt.UNSIGNED32, 0x1F86: dt.UNSIGNED32,
                  0x1F87: dt.UNSIGNED32, 0x1F88: dt.UNSIGNED32, 0x1F89: dt.UNSIGNED32}
for _i in range(0x1400, 0x1C00):
    STANDARD_TYPES[_i] = dt.UNSIGNED32        # COB-ID, mapping entries (sub types below)
_COMM_SUB_TYPES = {0: dt.UNSIGNED8, 2: dt.UNSIGNED8, 3: dt.UNSIGNED16, 4: dt.UNSIGNED8,
                   5: dt.UNSIGNED16, 6: dt.UNSIGNED8}


def standard_type(index: int, sub: int) -> dt.DataType:
    if 0x1400 <= index <= 0x15FF or 0x1800 <= index <= 0x19FF:
        return _COMM_SUB_TYPES.get(sub, dt.UNSIGNED32)
    if 0x1600 <= index <= 0x17FF or 0x1A00 <= index <= 0x1BFF:
        return dt.UNSIGNED8 if sub == 0 else dt.UNSIGNED32
    if index == 0x1016 and sub == 0:
        return dt.UNSIGNED8
    return STANDARD_TYPES.get(index, dt.UNSIGNED32)


def int_write(dtype: dt.DataType, index: int, sub: int, value: int, name: str, why: str,
              where: Where | None) -> Write:
    """A Write of an integer value that is known to fit (range-checked by the caller)."""
    data = value.to_bytes(dtype.size, "little", signed=dtype.kind == dt.SINT)
    return Write(index, sub, dtype.code, value, data, name, why, where)


def write_to(dev, index: int, sub: int, value, why: str, where: Where | None,
             diags: Diagnostics, *, rule: str, slave: bool, who: str) -> Write | None:
    """The Write of ``value`` (an int, or bytes for a DOMAIN) into ``dev``'s entry, or
    None with the error reported: the entry missing, read-only on a slave, or the value
    out of its type's range."""
    if dev is None:
        dtype = standard_type(index, sub)
        if isinstance(value, bytes):
            return Write(index, sub, dtype.code, value, value, "", why, where)
        return int_write(dtype, index, sub, value, "", why, where)
    e = dev.entry(index, sub)
    if e is None:
        what = "object" if index not in dev.objects else "sub-index"
        diags.error(f"{who}'s file has no 0x{index:04X}sub{sub:X} ({why}): that {what} "
                    "is missing", where, rule=rule)
        return None
    if slave and e.access in ("ro", "const"):
        diags.error(f"0x{index:04X}sub{sub:X} of {who} is {e.access}: it cannot be written "
                    f"({why})", where, rule=rule)
        return None
    dtype = e.dtype
    if isinstance(value, bytes):
        if dtype is None or dtype.size is not None:
            diags.error(f"0x{index:04X}sub{sub:X} of {who} is not a DOMAIN ({why})", where,
                        rule=rule)
            return None
        return Write(index, sub, dtype.code, value, value, e.name, why, where)
    if dtype is None or not dtype.is_integer:
        diags.error(f"0x{index:04X}sub{sub:X} of {who} is "
                    f"{dtype.name if dtype else 'without DataType'}, not an integer ({why})",
                    where, rule=rule)
        return None
    if not dtype.min <= value <= dtype.max:
        diags.error(f"{why}: {value} does not fit 0x{index:04X}sub{sub:X} of {who} "
                    f"({dtype.name})", where, rule="NET112")
        return None
    return int_write(dtype, index, sub, value, e.name, why, where)


def sdo_write(dev, index: int, sub: int, value, where: Where, who: str,
              diags: Diagnostics) -> Write | None:
    """An ``sdo:`` item: converted to its entry's type as a DCF DefaultValue would be
    (REAL32 takes 1.5, VISIBLE_STRING a text, DOMAIN/OCTET_STRING hex), range-checked; a
    YAML boolean only for a BOOLEAN entry."""
    e = dev.entry(index, sub)
    if e is None:
        what = "object" if index not in dev.objects else "sub-index"
        diags.error(f"{who}'s file has no 0x{index:04X}sub{sub:X} to write: that {what} is "
                    "missing", where, rule="NET114")
        return None
    if e.access in ("ro", "const"):
        diags.error(f"0x{index:04X}sub{sub:X} of {who} is {e.access}: it cannot be written",
                    where, rule="NET114")
        return None
    dtype = e.dtype
    if dtype is None:
        diags.error(f"0x{index:04X}sub{sub:X} of {who} has no valid DataType", where,
                    rule="NET117")
        return None
    label = f"0x{index:04X}sub{sub:X}"
    if isinstance(value, bool):
        if dtype.kind != dt.BOOL:
            diags.error(f"value {str(value).lower()} for {label} ({dtype.name}): a boolean "
                        "is accepted only for a BOOLEAN entry", where, rule="NET117")
            return None
        text = "1" if value else "0"
    elif isinstance(value, float):
        if dtype.kind != dt.REAL:
            diags.error(f"value {value} for {label} ({dtype.name}): not an integer", where,
                        rule="NET117")
            return None
        text = repr(value)
    elif isinstance(value, int):
        text = str(value)
    elif isinstance(value, str):
        text = value
        if dtype.is_numeric and values.uses_nodeid(text):
            diags.error(f"value '{shorten(text)}' for {label}: $NODEID is not allowed in the "
                        "network "
                        "file", where, rule="NET117")
            return None
    else:
        diags.error(f"value for {label} must be a number or a text", where, rule="NET117")
        return None
    try:
        data = values.encode(dtype, text, encoding=dev.encoding)
    except values.ValueProblem as exc:
        diags.error(f"value for {label} ({dtype.name}): {exc}", where, rule="NET117")
        return None
    decoded = values.to_python(dtype, data)
    return Write(index, sub, dtype.code, decoded, data, e.name, "sdo", where)
