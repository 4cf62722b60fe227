"""Lenze PLC Designer master object dictionary (seed 001, SPEC §7).

PLC Designer gives the CANopen master an object dictionary: an array of

    TYPE CanOpenODEntry : STRUCT
        dwIdxSubIdxF : DWORD;   (* 16#iiiissff: index, subindex, flags *)
        dwContent    : DWORD;   (* the entry's content *)
        wLen         : WORD;    (* data length *)
        byAttrib     : BYTE;    (* free for the master application *)
        byAccess     : BYTE;    (* free for the master application *)
    END_STRUCT END_TYPE

created from an EDS, every entry with length 4 and flags 16#41, the last one 16#01.
This module builds those records from the model and writes them as IEC 61131-3 structured
text (``lenze-st``) or packed little-endian (``lenze-bin``, 12 bytes per record, through
``schema.LenzeRecord``).

Choices the manual leaves open (documented in docs/export.md):

* Records: every entry of every object from 0x1000 up, ascending index then subindex.
* dwContent: the entry's value in 32 bits. Unsigned types, BOOLEAN and the time types are
  zero-extended, signed types sign-extended (INTEGER8 -1 -> 16#FFFFFFFF), REAL32 is its
  IEEE bit pattern; strings and byte types of at most 4 bytes are their bytes in little-
  endian order (``"AB"`` -> 16#00004241). A value that does not fit 32 bits (a long string,
  a large 64-bit number, a non-zero REAL64) is exported as 0 with a warning naming the
  entry's file:line - never truncated.
* byAttrib: the entry's attribute byte of SPEC §3.3 (D-9), as in the extended info segment.
* byAccess: 16#01 readable, 16#02 writable, 16#04 const (ro 1, wo 2, rw/rwr/rww 3, const 5).
"""
from __future__ import annotations

import os
from dataclasses import dataclass

from dcf2bin import datatypes as dt
from dcf2bin.export.common import (ExportResult, ascii_text, encode, exported_objects,
                            model_diagnostics, warning)

FLAGS = 0x41           # every entry
FLAGS_LAST = 0x01      # the last entry
LENGTH = 4             # wLen of every entry
ACCESS_READ, ACCESS_WRITE, ACCESS_CONST = 0x01, 0x02, 0x04
DEFAULT_VAR_NAME = "MasterOD"

TYPE_DECLARATION = """TYPE CanOpenODEntry :
STRUCT
    dwIdxSubIdxF : DWORD;   (* 16#iiiissff: index, subindex, flags *)
    dwContent : DWORD;      (* content of the entry *)
    wLen : WORD;            (* data length *)
    byAttrib : BYTE;        (* free for the master application *)
    byAccess : BYTE;        (* free for the master application *)
END_STRUCT
END_TYPE
"""


@dataclass(frozen=True)
class Record:
    index: int
    sub: int
    flags: int
    content: int
    length: int
    attrib: int
    access: int
    name: str = ""

    @property
    def idx_sub_flags(self) -> int:
        return self.index << 16 | self.sub << 8 | self.flags


def access_byte(access: str | None) -> int:
    """byAccess from the access type, with D-9's reading of it (rwr/rww: read and write)."""
    a = access or ""
    bits = dt.ACCESS_ATTR.get(a, 0)
    value = 0
    if bits & dt.ATTR_READ:
        value |= ACCESS_READ
    if bits & dt.ATTR_WRITE:
        value |= ACCESS_WRITE
    if a == "const":
        value |= ACCESS_CONST
    return value


def content(dtype: dt.DataType, data: bytes) -> int | None:
    """dwContent of a value, or None when it does not fit 32 bits."""
    kind = dtype.kind
    if kind == dt.SINT:
        v = int.from_bytes(data, "little", signed=True)
        return v & 0xFFFFFFFF if -0x80000000 <= v <= 0x7FFFFFFF else None
    if kind in (dt.UINT, dt.BOOL, dt.TIME):
        v = int.from_bytes(data, "little")
        return v if v <= 0xFFFFFFFF else None
    if kind == dt.REAL:
        if len(data) == 4:
            return int.from_bytes(data, "little")
        return 0 if not any(data) else None
    # byte copy types: VISIBLE_STRING, OCTET_STRING, UNICODE_STRING, DOMAIN
    return int.from_bytes(data, "little") if len(data) <= 4 else None


def records(dev) -> tuple[list[Record], list]:
    """The master OD records of a device -> (records, diagnostics of the export itself)."""
    from dcf2bin.select import attribute
    diags: list = []
    out: list[Record] = []
    for obj in exported_objects(dev):
        for e in obj.entries.values():
            data = encode(dev, e, diags)
            if data is None:
                continue
            value = content(e.dtype, data)
            if value is None:
                if e.dtype.is_integer:
                    signed = e.dtype.kind == dt.SINT
                    shown = f"value {int.from_bytes(data, 'little', signed=signed)}"
                else:
                    shown = f"{len(data)}-byte value"
                diags.append(warning(
                    f"{e.label}: {e.dtype.name} {shown} does not fit the 32-bit dwContent; "
                    "exported as 0", e.value_where, "EXP101",
                    hint="the master application may fill it in at run time"))
                value = 0
            name = e.name or obj.name
            out.append(Record(e.index, e.sub, FLAGS, value, LENGTH, attribute(e),
                              access_byte(e.access), name))
    if out:
        last = out[-1]
        out[-1] = Record(last.index, last.sub, FLAGS_LAST, last.content, last.length,
                         last.attrib, last.access, last.name)
    return out, diags


def to_bin(recs: list[Record]) -> bytes:
    """The records packed little-endian, 12 bytes each (schema.LenzeRecord)."""
    from dcf2bin.schema import LenzeRecord
    build = LenzeRecord.build
    return b"".join(build(dict(dwIdxSubIdxF=r.idx_sub_flags, dwContent=r.content,
                               wLen=r.length, byAttrib=r.attrib, byAccess=r.access))
                    for r in recs)


def _comment(text: str) -> str:
    return ascii_text(text).replace("(*", "( *").replace("*)", "* )")


def to_st(recs: list[Record], *, var_name: str = DEFAULT_VAR_NAME, with_type: bool = False,
          source: str = "") -> str:
    """IEC 61131-3 structured text: VAR_GLOBAL var_name : ARRAY [0..n-1] OF CanOpenODEntry."""
    from dcf2bin import __version__
    lines = ["(* CANopen master object dictionary for Lenze PLC Designer (CanOpenODEntry)",
             f"   generated by dcf2bin {__version__}"
             + (f" from {_comment(source)}" if source else "") + "; do not edit.",
             "   dwIdxSubIdxF = 16#iiiissff: index, subindex, flags 16#41 (16#01 on the last",
             "   entry); wLen = 4; byAttrib = attribute byte (16#10 numeric, 16#20 read,",
             "   16#40 write, 16#80 PDO); byAccess = 16#01 read, 16#02 write, 16#04 const. *)",
             ""]
    if with_type:
        lines += [TYPE_DECLARATION]
    lines += ["VAR_GLOBAL",
              f"    {var_name} : ARRAY [0..{len(recs) - 1}] OF CanOpenODEntry := ["]
    for i, r in enumerate(recs):
        sep = "," if i < len(recs) - 1 else " "
        lines.append(
            f"        (dwIdxSubIdxF := 16#{r.idx_sub_flags:08X}, dwContent := 16#{r.content:08X}, "
            f"wLen := {r.length}, byAttrib := 16#{r.attrib:02X}, byAccess := 16#{r.access:02X})"
            f"{sep} (* {r.index:04X}sub{r.sub:X} {_comment(r.name)} *)".rstrip())
    lines += ["    ];", "END_VAR", ""]
    return "\n".join(lines)


def export(dev, *, binary: bool = False, var_name: str = DEFAULT_VAR_NAME,
           with_type: bool = False, **_ignored) -> ExportResult:
    diags = model_diagnostics(dev)
    recs, own = records(dev)
    diags.extend(own)
    if any(d.severity.value == "error" for d in diags):
        return ExportResult(None, diags)
    if not recs:
        from dcf2bin.export.common import error
        from dcf2bin.diagnostics import Where
        diags.append(error("no objects from 0x1000 up: nothing to export", Where(dev.path),
                           "EXP100"))
        return ExportResult(None, diags)
    if binary:
        return ExportResult(to_bin(recs), diags)
    return ExportResult(to_st(recs, var_name=var_name, with_type=with_type,
                              source=os.path.basename(dev.path)), diags)
