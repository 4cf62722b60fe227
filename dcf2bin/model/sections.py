"""Small helpers of the builder: section names -> (index, sub), the few key texts a file
repeats (DataType, AccessType, PDOMapping) cached, and one-line clipping of messages.
"""
from __future__ import annotations

import re

from dcf2bin import datatypes as dt, values
from dcf2bin.model.objects import Entry


_SECTION_RE = re.compile(r"([0-9a-f]{4})(?:sub([0-9a-f]+))?")   # an object or sub-object
_SUB_HEX = {f"{i:x}": i for i in range(256)}   # canonical subindex texts
_AUX_RE = re.compile(r"([0-9a-f]{4})(name|value|denotation|objectlinks)")


def _int_or(text: str | None, default: int) -> int:
    if text is None:
        return default
    return values.parse_int(values.split_numeric_comment(text)[0])


def _clip(message: str, n: int = 160) -> str:
    """Keep diagnostics one readable line even for a 4 KiB DOMAIN value or control bytes."""
    if not message.isprintable():
        message = "".join(c if c.isprintable() else f"\\x{ord(c):02x}" for c in message)
    return message if len(message) <= n else message[:n - 20] + "..." + message[-17:]


# Caches of the few distinct texts a file uses for these keys (hot path: one lookup
# per entry instead of parsing "0x0007" 60,000 times).
_DTYPES: dict[str, dt.DataType] = {}
_ACCESS = {a: a for a in dt.ACCESS_ATTR}
_PDO_FLAG: dict[str, bool] = {}


def _pdo_flag(text: str | None) -> bool:
    if text is None:
        return False
    flag = _PDO_FLAG.get(text)
    if flag is None:
        try:
            flag = values.parse_int(values.split_numeric_comment(text)[0]) == 1
        except values.ValueProblem:
            flag = False
        if len(_PDO_FLAG) < 64:
            _PDO_FLAG[text] = flag
    return flag


def _proto(e: Entry) -> tuple:
    """The fields of ``e`` that entries built like it share: Entry's fields after index,
    sub and name, up to where (``Entry(index, sub, name, *_proto(e), where, ...)``)."""
    return (e.dtype, e.access, e.pdo_mapping, e.obj_flags, e.default, e.param,
            e.download_file, e.low, e.high, e.denotation)


def _section_target(canon: str) -> tuple[int | None, int | None]:
    m = _SECTION_RE.fullmatch(canon)
    if m:
        obj_hex, sub_hex = m.groups()
        return int(obj_hex, 16), int(sub_hex, 16) if sub_hex is not None else None
    m = _AUX_RE.fullmatch(canon)
    if m:
        return int(m.group(1), 16), None
    return None, None
