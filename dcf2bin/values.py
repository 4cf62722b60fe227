"""Value texts of EDS/DCF files (SPEC §1) to bytes and back (SPEC §4).

``encode`` turns the text of a ``DefaultValue``/``ParameterValue`` into exactly the bytes
the container stores; ``decode`` is its inverse for ``bin2dcf``: it returns a text that
``encode`` maps back to the same bytes, or ``None`` when there is none.

Conventions of ``decode`` (deterministic, so bin2dcf output is stable):

* UNSIGNEDn, TIME_OF_DAY, TIME_DIFFERENCE: ``0x`` + uppercase hex, at least 2 digits
  (``0x05``, ``0x80000181``);
* INTEGERn: decimal (``-1``, ``-2147483648``);
* BOOLEAN: ``0`` or ``1`` (any other byte: ``None``);
* REAL32/REAL64: the shortest decimal text that gives the same bits, in Python ``repr``
  style (``0.1``, ``1.0``, ``-0.0``, ``1e+20``); NaN and infinities as raw IEEE bits
  ``0x%08X`` / ``0x%016X``;
* VISIBLE_STRING/UNICODE_STRING: the raw text, put in double quotes when it is empty,
  starts or ends with white space, or is itself wrapped in double quotes; ``None`` when it
  holds a CR or LF, or cannot be written in the file's encoding;
* OCTET_STRING/DOMAIN: uppercase hex pairs without blanks (``0A0B``); empty is ``""``.

Only the standard library is used here: this module sits on the hot path of ``compile``.
"""
from __future__ import annotations

import math
import re
import struct

from .datatypes import (BOOL, BY_CODE, DOMAIN, OSTRING, REAL, SINT, TIME, UINT, USTRING,
                        VSTRING, DataType)
from .diagnostics import shorten

__all__ = ["ValueProblem", "NeedsNodeId", "MAX_DIGITS", "too_long", "uses_nodeid", "parse_int",
           "eval_int",
           "split_numeric_comment", "hex_prefix", "hex_problem", "hex_prefix_problem",
           "as_number", "limit_problem", "inverted_limits", "encode", "zero", "decode", "to_python"]


class ValueProblem(Exception):
    """A value that cannot be parsed/encoded; message is one line, no location (caller adds file:line)."""


class NeedsNodeId(ValueProblem):
    """The text uses $NODEID but no node-ID was given."""


_BLANKS = " \t"   # SPEC §1: blanks are space and tab

# ---------------------------------------------------------------------------------------
# Integer literals (SPEC §1): decimal; hex with 0x/0X; octal with a leading 0 (012 == 10,
# 08 is an error); an optional + or - sign in front of any of them (-0x10 == -16).
# Explicit ASCII classes: Python's int() would also take '1_000', ' 1', and non-ASCII digits.
_INT_RE = re.compile(r"([+-]?)(?:0[xX]([0-9A-Fa-f]+)|(0[0-7]*)|([1-9][0-9]*))")
_HEX, _OCT, _DEC = "hex", "octal", "decimal"


# No CANopen type is wider than 64 bits (20 decimal, 16 hex, 22 octal digits). A literal
# with more digits than this is refused before it becomes a Python int, so no message
# ever has to print a number of thousands of digits (Python refuses to turn an int of
# more than 4300 decimal digits into text) and no check works on a huge one.
MAX_DIGITS = 64


def too_long(digits: int) -> ValueProblem:
    """The one wording of an integer literal of more than MAX_DIGITS digits, wherever it
    is read: a DCF/EDS, the network file, a .cpj, a CSV, an option."""
    return ValueProblem(f"integer literal too long ({digits} digits, at most {MAX_DIGITS})")


def _q(text: str) -> str:
    """A value text quoted in a message (``diagnostics.shorten``): a long one is cut in
    the middle, so that a message stays one readable line whatever the file holds."""
    return shorten(text)


def _literal(text: str) -> tuple[int, str, str]:
    """Parse one integer literal (already trimmed) -> (value, form, sign)."""
    if len(text) > MAX_DIGITS:
        body = text[1:] if text[:1] in ("+", "-") else text
        digits = body[2:] if body[:2] in ("0x", "0X") else body
        if len(digits) > MAX_DIGITS and not digits.strip("0123456789abcdefABCDEF"):
            raise too_long(len(digits))
    m = _INT_RE.fullmatch(text)
    if m is None:
        body = text[1:] if text[:1] in ("+", "-") else text
        if not text:
            raise ValueProblem("missing integer value")
        if body[:2] in ("0x", "0X"):
            raise ValueProblem(f"invalid hex literal '{_q(text)}'")
        if body[:1] == "0" and body.isascii() and body.isdigit():
            raise ValueProblem(f"invalid octal literal '{_q(text)}'")  # 08, 09, 0128 ...
        raise ValueProblem(f"invalid integer '{_q(text)}'")
    sign, hexd, octd, decd = m.groups()
    if hexd is not None:
        value, form = int(hexd, 16), _HEX
    elif octd is not None:
        value, form = int(octd, 8), _OCT
    else:
        value, form = int(decd), _DEC
    return (-value if sign == "-" else value), form, sign


def uses_nodeid(text: str) -> bool:
    """True when the text mentions ``$NODEID`` (any case), wherever it stands."""
    return "$" in text and "$NODEID" in text.upper()


def parse_int(text: str) -> int:
    """Parse a SPEC §1 integer literal (no ``$NODEID``); blanks around it are ignored."""
    t = text.strip(_BLANKS)
    if t.isascii() and len(t) <= MAX_DIGITS:
        # fast paths, what _literal gives: a decimal literal (no sign, no leading 0), or
        # 0x and hex digits (isalnum keeps out the '_' and blanks int() would take; a
        # letter after 'f' makes int() fail: the slow way words the message)
        if t.isdigit():
            if t[0] != "0":
                return int(t)
        elif t[:2] in ("0x", "0X") and t[2:].isalnum():
            try:
                return int(t[2:], 16)
            except ValueError:
                pass
    if uses_nodeid(t):
        raise ValueProblem(f"$NODEID is not allowed here: '{_q(t)}'")
    return _literal(t)[0]


# SPEC §1: bare $NODEID, $NODEID+N (the standard form) and N+$NODEID, case-insensitive,
# blanks around '+' allowed. N is an unsigned literal (a sign after '+' is refused).
_NODEID_RE = re.compile(r"\$NODEID(?:[ \t]*\+[ \t]*([^ \t+]+))?|([^ \t+]+)[ \t]*\+[ \t]*\$NODEID",
                        re.IGNORECASE)


def _nodeid_formula(t: str, node_id: int | None) -> int:
    m = _NODEID_RE.fullmatch(t)
    if m is None:
        raise ValueProblem(f"invalid $NODEID formula '{_q(t)}' (expected $NODEID, $NODEID+N or N+$NODEID)")
    offset_text = m.group(1) if m.group(1) is not None else m.group(2)
    offset = 0
    if offset_text is not None:
        if uses_nodeid(offset_text):
            raise ValueProblem(f"invalid $NODEID formula '{_q(t)}' (expected $NODEID, $NODEID+N or N+$NODEID)")
        offset, _, sign = _literal(offset_text)
        if sign:
            raise ValueProblem(f"invalid $NODEID formula '{_q(t)}' (no sign allowed on '{_q(offset_text)}')")
    if node_id is None:
        raise NeedsNodeId(f"'{_q(t)}' uses $NODEID but no node-ID is known "
                          "(give --node-id or [DeviceComissioning] NodeID)")
    return node_id + offset


def eval_int(text: str, node_id: int | None) -> tuple[int, bool]:
    """Value of an integer field, ``$NODEID`` formulas included -> (value, is_bit_pattern).

    ``is_bit_pattern`` is True for a hex literal without a ``-`` sign and without
    ``$NODEID``: SPEC §1 reads it as a bit pattern of the type's width for signed types.
    (SPEC says "no ``-``", so ``+0xFF`` counts as a bit pattern too.) Octal and decimal
    literals and formulas never are. The formula syntax is checked before the node-ID is
    asked for, so a malformed formula is a ValueProblem even without a node-ID.
    """
    t = text.strip(_BLANKS)
    if uses_nodeid(t):
        return _nodeid_formula(t, node_id), False
    value, form, sign = _literal(t)
    return value, form is _HEX and sign != "-"


# ---------------------------------------------------------------------------------------
# Numeric comments (SPEC §1): "only in numeric fields may a number be followed by blanks
# and a ';' or '#' comment". Without a blank before it, ';'/'#' stays part of the value.
# A blank then the marker; the comment's blanks are found from there. (The obvious
# r"[ \t]+([;#].*)" is quadratic in the length of a run of blanks without a marker.)
_MARK_RE = re.compile(r"[ \t][;#]")


def split_numeric_comment(text: str) -> tuple[str, str | None]:
    """Split ``'0x10  ; note'`` into ``('0x10', '; note')``.

    The comment is returned with its ``;``/``#`` marker and without trailing blanks;
    ``None`` when there is none. A value that *starts* with the marker is not split.
    """
    if ";" not in text and "#" not in text:
        return text, None
    m = _MARK_RE.search(text)
    if m is None:
        return text, None
    number = text[:m.start()].rstrip(_BLANKS)
    if not number:
        return text, None
    return number, text[m.start() + 1:].rstrip(_BLANKS)


# ---------------------------------------------------------------------------------------
# Integer-like types (BOOLEAN, INTEGERn, UNSIGNEDn, TIME_*): precomputed per type code
# (size, min, max, mask, is_signed, name). int.to_bytes gives every width 1..8 right,
# including 3/5/6/7 bytes (SPEC §1: never truncate, never a 4-byte pack for 3 bytes).
_INT_INFO: dict[int, tuple[int, int, int, int, bool, str]] = {
    t.code: (t.size, t.min, t.max, (1 << t.bits) - 1, t.kind == SINT, t.name)
    for t in BY_CODE.values() if t.kind in (BOOL, SINT, UINT, TIME)
}
_REAL_INFO = {t.code: (t.size, "<f" if t.size == 4 else "<d", t.name)
              for t in BY_CODE.values() if t.kind == REAL}


def _out_of_range(t: str, value: int, name: str, lo: int, hi: int) -> ValueProblem:
    shown = _q(t) if t == str(value) else f"{_q(t)} (= {value})"
    return ValueProblem(f"value {shown} out of range for {name} ({lo}..{hi})")


def _encode_int(dtype: DataType, text: str, node_id: int | None) -> bytes:
    size, lo, hi, mask, signed, name = _INT_INFO[dtype.code]
    t = text.strip(_BLANKS)
    if dtype.kind == BOOL:
        # SPEC §1: BOOLEAN accepts 0/1 and TRUE/FALSE in any case (hex/octal 0/1 too).
        upper = t.upper()
        if upper == "TRUE":
            return b"\x01"
        if upper == "FALSE":
            return b"\x00"
        try:
            value, _ = eval_int(t, node_id)
        except NeedsNodeId:
            raise
        except ValueProblem:
            raise ValueProblem(f"invalid BOOLEAN value '{_q(t)}' (expected 0, 1, TRUE or FALSE)") from None
    else:
        value, pattern = eval_int(t, node_id)
        if pattern and signed and value > hi:
            # SPEC §1: for a signed type an unsigned hex literal is a bit pattern of the
            # type's width (INTEGER8 0xFF = -1); wider than the type is an error.
            if value > mask:
                raise ValueProblem(f"hex literal {_q(t)} is wider than {name} ({size * 8} bits)")
            return value.to_bytes(size, "little")
    if value < lo or value > hi:
        raise _out_of_range(t, value, name, lo, hi)
    return (value & mask).to_bytes(size, "little")


def _encode_real(dtype: DataType, text: str) -> bytes:
    size, fmt, name = _REAL_INFO[dtype.code]
    t = text.strip(_BLANKS)
    if uses_nodeid(t):
        raise ValueProblem(f"$NODEID is not allowed in a {name} value: '{_q(t)}'")  # SPEC §1
    sign = t[:1] if t[:1] in ("+", "-") else ""
    body = t[len(sign):]
    if body[:2] in ("0x", "0X"):
        # SPEC §1: 0x... is the raw IEEE bit pattern, below 2^32 / 2^64; negative is an error.
        if sign == "-":
            raise ValueProblem(f"negative hex literal {_q(t)} is not a {name} bit pattern")
        value, _, _ = _literal(t)
        if value >> (size * 8):
            raise ValueProblem(f"hex literal {_q(t)} is wider than {name} ({size * 8} bits)")
        return value.to_bytes(size, "little")
    if body.lower() in ("inf", "infinity", "nan"):
        raise ValueProblem(f"{name} value must be finite: '{_q(t)}'")
    if _FLOAT_RE.fullmatch(t) is None:
        raise ValueProblem(f"invalid {name} value '{_q(t)}'")
    # SPEC §1: decimal only (010 == 10.0, never octal), converted as struct.pack does:
    # nearest double, then nearest single; overflow is an error.
    f = float(t)
    if math.isinf(f):
        raise ValueProblem(f"{name} overflow: {_q(t)}")
    try:
        return struct.pack(fmt, f)
    except OverflowError:
        raise ValueProblem(f"{name} overflow: {_q(t)}") from None


# (not [0-9]+\.?[0-9]*, which backtracks quadratically on a long run of digits)
_FLOAT_RE = re.compile(r"[+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")


def _unquote(text: str) -> str:
    # SPEC §1: no quotes are stripped unless the whole value is in quotes ("" = empty).
    if len(text) >= 2 and text[0] == '"' and text[-1] == '"':
        return text[1:-1]
    return text


def _encode_hex(dtype: DataType, text: str) -> bytes:
    # SPEC §1: OCTET_STRING and DOMAIN are hex byte pairs without 0x; blanks may stand
    # between pairs (not inside one). "" is the empty value. Sevcon's DriveWizard writes
    # them with a 0x prefix: the bytes are those after it (lint warns, see hex_prefix).
    t = text.strip(_BLANKS)
    if t == '""':
        return b""
    body = t[2:] if hex_prefix(t) else t
    try:
        if body.isascii() and "\n" not in body and "\r" not in body and "\f" not in body \
                and "\v" not in body:
            return bytes.fromhex(body)
    except ValueError:
        pass
    name = dtype.name
    if t[:2] in ("0x", "0X") and body is t:
        raise ValueProblem(f"{name} value '{_q(t)}' has no hex byte pairs after 0x")
    for ch in body:
        if ch not in _BLANKS and ch not in "0123456789abcdefABCDEF":
            raise ValueProblem(f"invalid character '{ch}' in {name} value '{_q(t)}'")
    if sum(ch not in _BLANKS for ch in body) % 2:
        raise ValueProblem(f"odd number of hex digits in {name} value '{_q(t)}'")
    raise ValueProblem(f"a blank splits a hex byte pair in {name} value '{_q(t)}'")


_HEX_DIGITS = frozenset("0123456789abcdefABCDEF")


def hex_prefix(text: str) -> bool:
    """True when an OCTET_STRING/DOMAIN value text starts with ``0x``/``0X`` directly
    followed by a hex digit (``0x0102``): CiA 306 writes these without the prefix, Sevcon
    DriveWizard with it; ``encode`` takes the bytes after it, and lint warns."""
    t = text.lstrip(_BLANKS)
    return t[:2] in ("0x", "0X") and t[2:3] in _HEX_DIGITS


def hex_problem(dtype: DataType, text: str) -> str | None:
    """What is wrong with an OCTET_STRING/DOMAIN value text (None: nothing)."""
    try:
        _encode_hex(dtype, text)
    except ValueProblem as exc:
        return str(exc)
    return None


def hex_prefix_problem(dtype: DataType) -> str:
    """The words of a 0x-prefixed OCTET_STRING/DOMAIN value (validate's DCF218; compile
    says the same), after ``<entry> <key>: ``."""
    return (f"{dtype.name} value starts with 0x; hex byte pairs are written without it "
            "(the bytes after it are used)")


def encode(dtype: DataType, text: str, *, node_id: int | None = None,
           encoding: str = "utf-8") -> bytes:
    """Encode an INI value text as ``dtype`` (SPEC §1): little-endian, range-checked.

    Fixed types give exactly ``dtype.size`` bytes. ``text`` is the value as the INI parser
    left it (trimmed, numeric comments already split off with ``split_numeric_comment``).
    ``encoding`` is the file's own encoding, used for VISIBLE_STRING.
    """
    info = _INT_INFO.get(dtype.code)
    if info is not None:
        # Fast path: a plain decimal literal (no sign, no leading 0) that fits.
        if text.isdigit() and text.isascii() and len(text) < 21 and (text[0] != "0" or len(text) == 1):
            value = int(text)
            if value <= info[2]:
                return value.to_bytes(info[0], "little")
        # Fast path: 0x + hex digits that fit (isalnum excludes the '_', blanks and signs
        # int() would take; other letters make int() fail and go the slow way).
        elif text[:2] in ("0x", "0X") and text.isascii() and text[2:].isalnum():
            try:
                value = int(text[2:], 16)
            except ValueError:
                pass
            else:
                if value <= info[2]:
                    return value.to_bytes(info[0], "little")
        return _encode_int(dtype, text, node_id)
    kind = dtype.kind
    if kind == REAL:
        return _encode_real(dtype, text)
    if kind == VSTRING:
        # SPEC §1: the raw text ($NODEID is plain text here), in the file's encoding.
        s = _unquote(text)
        try:
            return s.encode(encoding)
        except UnicodeEncodeError as e:
            raise ValueProblem(f"character '{s[e.start]}' cannot be written in {encoding}") from None
    if kind == USTRING:
        # SPEC §1: text as for VISIBLE_STRING, UTF-16LE, no BOM, no terminator.
        s = _unquote(text)
        try:
            return s.encode("utf-16-le")
        except UnicodeEncodeError as e:
            raise ValueProblem(f"character {s[e.start]!r} cannot be written in UTF-16") from None
    if kind in (OSTRING, DOMAIN):
        return _encode_hex(dtype, text)
    raise ValueProblem(f"cannot encode values of type {dtype.name}")  # not in the table


def zero(dtype: DataType) -> bytes:
    """The type's zero value (SPEC §1 "else the type's zero/empty value")."""
    return b"" if dtype.size is None else bytes(dtype.size)


# ---------------------------------------------------------------------------------------
# Back to text (bin2dcf, SPEC §4).

def _quote(text: str) -> str | None:
    if "\n" in text or "\r" in text:
        return None  # SPEC §1: LF and CRLF end lines; no escape exists
    if (not text or text[0].isspace() or text[-1].isspace()
            or (len(text) >= 2 and text[0] == '"' and text[-1] == '"')):
        return f'"{text}"'  # the parser trims blanks, "" is empty, outer quotes are stripped
    return text


def _real_text(dtype: DataType, data: bytes) -> str:
    size, fmt, _ = _REAL_INFO[dtype.code]
    (f,) = struct.unpack(fmt, data)
    if math.isfinite(f):
        if size == 8:
            return repr(f)
        for digits in range(1, 10):  # 9 significant digits always round-trip a float32
            candidate = float(f"{f:.{digits}g}")
            try:
                if struct.pack(fmt, candidate) == data:
                    return repr(candidate)
            except OverflowError:  # rounded past FLT_MAX: try more digits
                continue
    return f"0x{int.from_bytes(data, 'little'):0{size * 2}X}"


def decode(dtype: DataType, data: bytes, *, encoding: str = "utf-8") -> str | None:
    """A text that ``encode(dtype, text, encoding=encoding)`` maps back to ``data``.

    ``None`` when no such text exists (wrong size for a fixed type, a BOOLEAN byte other
    than 0/1, string bytes not valid in ``encoding``, a string holding CR/LF ...).
    See the module docstring for the text forms.
    """
    data = bytes(data)
    kind, size = dtype.kind, dtype.size
    if size is not None and len(data) != size:
        return None
    if kind in (UINT, TIME):
        return f"0x{int.from_bytes(data, 'little'):02X}"
    if kind == SINT:
        return str(int.from_bytes(data, "little", signed=True))
    if kind == BOOL:
        return {b"\x00": "0", b"\x01": "1"}.get(data)
    if kind in (OSTRING, DOMAIN):
        return data.hex().upper() or '""'
    if kind == REAL:
        text = _real_text(dtype, data)
    elif kind == VSTRING:
        try:
            text = _quote(data.decode(encoding))
        except UnicodeDecodeError:
            return None
    elif kind == USTRING:
        try:
            s = data.decode("utf-16-le")
            s.encode(encoding)  # the text must be writable in the DCF itself
        except UnicodeError:
            return None
        text = _quote(s)
    else:
        return None
    if text is None:
        return None
    # Belt and braces for the text types: the promise is encode(decode(b)) == b.
    try:
        return text if encode(dtype, text, encoding=encoding) == data else None
    except ValueProblem:
        return None


def to_python(dtype: DataType, data: bytes,
              encoding: str = "utf-8") -> int | float | str | bytes | bool:
    """The value as a Python object, for display and for a canopen ObjectDictionary.

    BOOLEAN -> bool (any non-zero byte is True), INTEGERn/UNSIGNEDn/TIME_* -> int,
    REAL -> float, VISIBLE_STRING -> str (in ``encoding``, the one its bytes were written
    in: the file's own for a DCF value; errors replaced), UNICODE_STRING -> str
    (UTF-16LE, errors replaced), OCTET_STRING/DOMAIN -> bytes. A fixed type with the wrong
    number of bytes raises ValueProblem.
    """
    kind, size = dtype.kind, dtype.size
    if size is not None and len(data) != size:
        raise ValueProblem(f"{dtype.name} needs {size} bytes, got {len(data)}")
    if kind == BOOL:
        return data[0] != 0
    if kind == SINT:
        return int.from_bytes(data, "little", signed=True)
    if kind in (UINT, TIME):
        return int.from_bytes(data, "little")
    if kind == REAL:
        return struct.unpack(_REAL_INFO[dtype.code][1], data)[0]
    if kind == VSTRING:
        return bytes(data).decode(encoding, errors="replace")
    if kind == USTRING:
        return bytes(data).decode("utf-16-le", errors="replace")
    return bytes(data)


# ---------------------------------------------------------------------------------------
# LowLimit/HighLimit (validate's DCF210-DCF212; compile checks them with the same words).

def as_number(dtype: DataType, text: str, node_id: int | None, *,
              encoding: str = "utf-8") -> int | float | None:
    """The value of a numeric text (a numeric comment split off) as an int or float of
    ``dtype``; None when it uses ``$NODEID`` and no node-ID is known. Raises
    ValueProblem for a text that is not a value of the type."""
    if uses_nodeid(text) and node_id is None:
        return None
    data = encode(dtype, split_numeric_comment(text)[0], node_id=node_id, encoding=encoding)
    if dtype.kind == REAL:
        return struct.unpack(_REAL_INFO[dtype.code][1], data)[0]
    return int.from_bytes(data, "little", signed=dtype.kind == SINT)


def shown(text: str, value) -> str:
    """'0xFF (= -1)' where the text is not the plain decimal number."""
    return text if text.strip() == str(value) else f"{text} (= {value})"


def inverted_limits(label: str, low_text: str, low, high_text: str, high) -> str | None:
    """DCF211's words when LowLimit is greater than HighLimit, else None."""
    if low is None or high is None or low <= high:
        return None
    return (f"{label} LowLimit {shown(low_text, low)} is greater than HighLimit "
            f"{shown(high_text, high)}")


def limit_problem(label: str, key: str, text: str, value, low_text: str | None, low,
                  high_text: str | None, high) -> str | None:
    """DCF212's words when ``value`` (the number of ``text``, the entry's ``key``:
    DefaultValue or ParameterValue) lies outside LowLimit..HighLimit, else None."""
    if low is not None and value < low:
        return (f"{label} {key} {shown(text, value)} is below LowLimit "
                f"{shown(low_text, low)}")
    if high is not None and value > high:
        return (f"{label} {key} {shown(text, value)} is above HighLimit "
                f"{shown(high_text, high)}")
    return None


def clip(message: str, n: int = 160) -> str:
    """A message part cut in the middle to ``n`` characters."""
    return message if len(message) <= n else message[:n - 20] + "..." + message[-17:]
