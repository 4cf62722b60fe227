"""The data type of a concise DCF's entry, and where it comes from (``entry_type``).

A concise DCF stores an entry's bytes and nothing about their type. ``dump`` decodes a
value and ``bin2dcf`` writes a DataType only as far as something says what the type is:

* ``EDS``: the device's description (``--eds``), where its type has the entry's size;
* ``CiA 301``: the communication objects whose type CiA 301 fixes (a PDO's COB-ID and
  mapping, heartbeat, guarding, SYNC, the NMT master's objects), where the size fits;
* ``CiA 405``: a network variable's range (SPEC §2.1), where the size fits;
* ``guess``: else, by the size alone -- UNSIGNED8/16/24/32/40/48/56/64 for 1 to 8 bytes,
  the guess ``bin2dcf`` makes (SPEC §4) -- always shown as a guess;
* none: other sizes, shown as bytes (a DOMAIN).
"""
from __future__ import annotations

from dcf2bin import datatypes as dt
from dcf2bin.dump.eds import EdsInfo
from dcf2bin.dump.text import nv_type

EDS, CIA301, CIA405, GUESS = "EDS", "CiA 301", "CiA 405", "guess"

_U8, _U16, _U32 = dt.UNSIGNED8, dt.UNSIGNED16, dt.UNSIGNED32
#: VAR objects (sub 0) of CiA 301/302 whose type is fixed
_VARS = {0x1005: _U32, 0x1006: _U32, 0x1007: _U32, 0x100C: _U16, 0x100D: _U8,
         0x1012: _U32, 0x1014: _U32, 0x1015: _U16, 0x1017: _U16, 0x1019: _U8,
         0x1F80: _U32, 0x1F89: _U32}
#: ARRAY objects of CiA 301/302: sub 0 UNSIGNED8, the others this type
_ARRAYS = {0x1010: _U32, 0x1011: _U32, 0x1016: _U32, 0x1029: _U8, 0x1F81: _U32,
           0x1F84: _U32, 0x1F85: _U32, 0x1F86: _U32, 0x1F87: _U32, 0x1F88: _U32}
#: a PDO communication object's subs (sub 4 is reserved: UNSIGNED8 where it exists)
_COMM = {0: _U8, 1: _U32, 2: _U8, 3: _U16, 4: _U8, 5: _U16, 6: _U8}


def standard_type(index: int, sub: int) -> dt.DataType | None:
    """The type CiA 301 gives an entry of the communication profile, None elsewhere."""
    if 0x1400 <= index <= 0x15FF or 0x1800 <= index <= 0x19FF:
        return _COMM.get(sub)
    if 0x1600 <= index <= 0x17FF or 0x1A00 <= index <= 0x1BFF:
        return _U8 if sub == 0 else _U32 if sub <= 64 else None
    if index in _VARS:
        return _VARS[index] if sub == 0 else None
    if index in _ARRAYS:
        return _U8 if sub == 0 else _ARRAYS[index]
    return None


def entry_type(index: int, sub: int, size: int,
               eds: EdsInfo | None = None) -> tuple[dt.DataType | None, str | None]:
    """(type, where it comes from: EDS, CiA 301, CiA 405, guess) of an entry of ``size``
    bytes; (None, None) when nothing says and the size is no integer's."""
    t = eds.dtype(index, sub) if eds is not None else None
    if t is not None and t.size in (None, size):
        return t, EDS
    t = standard_type(index, sub)
    if t is not None and t.size == size:
        return t, CIA301
    t = nv_type(index, sub, size)
    if t is not None:
        return t, CIA405
    if size in dt.UNSIGNED_BY_SIZE:
        return dt.UNSIGNED_BY_SIZE[size], GUESS
    return None, None


__all__ = ["CIA301", "CIA405", "EDS", "GUESS", "entry_type", "standard_type"]
