"""Allocating network variables (SPEC.md §9.2, D-15): the configurator's job of seed 000 §6.

Input: a CSV with the header row ``name,type,direction``. Per area, the kinds (data
types) in order of first appearance; ``used`` = 0, or when merging into a DCF that has
network variables, the end of the bytes they occupy in that area. For each kind of size
s with c variables the first free element is ``e = ceil(used / s)``; its variables take
elements e ... e+c-1 in input order, element x being index ``range_start + x // 254``,
sub ``x % 254 + 1``; then ``used = (e + c) * s``.

``standalone`` writes a complete DCF; ``merge`` adds the variables to an existing DCF,
keeping every other line of it byte for byte.
"""
from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass

from dcf2bin import datatypes as dt
from dcf2bin import values
from dcf2bin.diagnostics import Diagnostic, Severity, shorten
from dcf2bin.layout import INPUT, OUTPUT, PER_INDEX, RANGE_LEN, TABLE_405

# One code per kind of problem (docs/plc.md, man/dcf2bin-allocate.1); ids never change
# meaning. ALC001 once named every bad CSV line; it keeps the file's structure.
RULE_CSV = "ALC001"       # not a variable list: header row, field count, not CSV, empty
RULE_FULL = "ALC002"      # a kind needs more than its 0x40 indices
RULE_BASE = "ALC003"      # the DCF to merge into cannot take the variables
RULE_NAME = "ALC004"      # an empty name, or one holding a control character
RULE_REPEAT = "ALC005"    # a name repeated (compared without regard to case)
RULE_TYPE = "ALC006"      # an unknown data type
RULE_NO_RANGE = "ALC007"  # a data type without a CiA 405 network-variable range
RULE_DIR = "ALC008"       # a direction other than input/output (in/out)

_DIRECTIONS = {"input": INPUT, "in": INPUT, "output": OUTPUT, "out": OUTPUT}
# (data type code, direction) -> first index of its CiA 405 range (SPEC §2.1)
RANGE_START = {(t.code, d): first for first, (t, d) in TABLE_405.items()}
_CONTROL = re.compile(r"[\x00-\x1f\x7f]")


@dataclass(slots=True)
class Var:
    name: str
    dtype: dt.DataType
    direction: str
    line: int


@dataclass(slots=True)
class Placed:
    var: Var
    index: int
    sub: int
    offset: int          # within its area (SPEC §2.2: element * size)


class AllocationError(Exception):
    """Errors stopped the allocation; ``diagnostics`` holds them (``ok`` is False, as for a
    compile result, so the CLI ends both the same way)."""
    ok = False

    def __init__(self, diagnostics: list[Diagnostic]):
        super().__init__("\n".join(d.format() for d in diagnostics))
        self.diagnostics = diagnostics


def _err(message: str, path: str, line: int | None, rule: str) -> Diagnostic:
    return Diagnostic(Severity.ERROR, message, path, line, rule=rule)


def _dtype(text: str) -> dt.DataType | None:
    t = text.strip()
    if t[:2].lower() == "0x":
        try:       # the DCF's own integer syntax, bounded in digits (int() takes "0x_6")
            return dt.BY_CODE.get(values.parse_int(t))
        except values.ValueProblem:
            return None
    return dt.BY_NAME.get(t.upper())


def read_vars(data: bytes, path: str) -> list[Var]:
    """Parse the CSV; every bad line is an error at ``path:line``."""
    from dcf2bin.ini import decode_bytes
    text, _ = decode_bytes(data)
    reader = csv.reader(io.StringIO(text, newline=""))
    diags: list[Diagnostic] = []
    out: list[Var] = []
    seen: dict[str, int] = {}
    header = False
    try:
        for row in reader:
            line = reader.line_num
            if not row or all(not c.strip() for c in row):
                continue
            if not header:
                if [c.strip().lower() for c in row] != ["name", "type", "direction"]:
                    diags.append(_err("the first line must be the header row "
                                      "'name,type,direction'", path, line, RULE_CSV))
                    break
                header = True
                continue
            if len(row) != 3:
                diags.append(_err(f"expected 3 fields (name, type, direction), found {len(row)}",
                                  path, line, RULE_CSV))
                continue
            name, type_text, dir_text = (c.strip() for c in row)
            bad = False
            if not name:
                diags.append(_err("empty name", path, line, RULE_NAME))
                bad = True
            elif _CONTROL.search(name):
                diags.append(_err(f"name {shorten(repr(name))} holds a control character",
                                  path, line, RULE_NAME))
                bad = True
            elif name.casefold() in seen:
                diags.append(_err(f"name '{shorten(name)}' repeats line {seen[name.casefold()]} "
                                  "(names are compared without regard to case)", path, line,
                                  RULE_REPEAT))
                bad = True
            else:
                seen[name.casefold()] = line
            dtype = _dtype(type_text)
            direction = _DIRECTIONS.get(dir_text.lower())
            if dtype is None:
                diags.append(_err(f"unknown data type '{shorten(type_text)}' (a CiA 306 name "
                                  "such as UNSIGNED16, or a code such as 0x0006)", path, line,
                                  RULE_TYPE))
                bad = True
            elif (dtype.code, INPUT) not in RANGE_START:
                diags.append(_err(f"data type {dtype.name} has no network-variable range "
                                  "(CiA 405 ranges exist for the integer types of 8 to 64 "
                                  "bits, BOOLEAN and REAL32)", path, line, RULE_NO_RANGE))
                bad = True
            if direction is None:
                diags.append(_err(f"direction '{shorten(dir_text)}' must be input or output "
                                  "(in, out)", path, line, RULE_DIR))
                bad = True
            if not bad:
                out.append(Var(name, dtype, direction, line))
    except csv.Error as exc:
        diags.append(_err(f"not CSV: {exc}", path, reader.line_num, RULE_CSV))
    if not header and not diags:
        diags.append(_err("empty file: expected the header row 'name,type,direction'", path,
                          None, RULE_CSV))
    if diags:
        raise AllocationError(diags)
    return out


def allocate(variables: list[Var], path: str, used: dict[str, int] | None = None
             ) -> list[Placed]:
    """Place new variables by D-15. ``used``: per area, the end of the bytes that
    variables already there occupy (merging), else 0."""
    used = dict(used or {INPUT: 0, OUTPUT: 0})
    diags: list[Diagnostic] = []
    placed: list[Placed] = []
    for area in (INPUT, OUTPUT):
        kinds: dict[int, list[Var]] = {}
        for v in variables:
            if v.direction == area:
                kinds.setdefault(v.dtype.code, []).append(v)
        for vs in kinds.values():
            dtype = vs[0].dtype
            size = dtype.size
            first = RANGE_START[(dtype.code, area)]
            e = -(-used[area] // size)
            for j, v in enumerate(vs):
                x = e + j
                if x // PER_INDEX >= RANGE_LEN:
                    diags.append(_err(
                        f"'{shorten(v.name)}': the {dtype.name} {area}s do not fit their "
                        f"0x40 indices 0x{first:04X}-0x{first + RANGE_LEN - 1:04X} (this is "
                        f"element {x}; "
                        f"there are {RANGE_LEN * PER_INDEX})", path, v.line, RULE_FULL))
                    break
                placed.append(Placed(v, first + x // PER_INDEX, x % PER_INDEX + 1, x * size))
            used[area] = (e + len(vs)) * size
    if diags:
        raise AllocationError(diags)
    return placed


# -- DCF text -----------------------------------------------------------------------------

def _objects(placed: list[Placed]) -> dict[int, list[Placed]]:
    objs: dict[int, list[Placed]] = {}
    for p in placed:
        objs.setdefault(p.index, []).append(p)
    for ps in objs.values():
        ps.sort(key=lambda p: p.sub)
    return dict(sorted(objs.items()))


def _object_name(index: int) -> str:
    t, direction = TABLE_405[index - (index - 0xA000) % RANGE_LEN]
    return f"{t.name} {direction}s 0x{index:04X}"


def _sub_section(index: int, p: Placed, nl: str) -> str:
    v = p.var
    return (f"[{index:04X}sub{p.sub:X}]{nl}ParameterName={v.name}{nl}ObjectType=0x7{nl}"
            f"DataType=0x{v.dtype.code:04X}{nl}"
            f"AccessType={'ro' if v.direction == INPUT else 'rw'}{nl}PDOMapping=1{nl}")


def _object_text(index: int, ps: list[Placed], nl: str) -> str:
    out = [f"[{index:04X}]{nl}ParameterName={_object_name(index)}{nl}ObjectType=0x8{nl}"
           f"SubNumber={len(ps) + 1}{nl}",
           f"[{index:04X}sub0]{nl}ParameterName=Highest sub-index supported{nl}"
           f"ObjectType=0x7{nl}DataType=0x0005{nl}AccessType=ro{nl}"
           f"DefaultValue={ps[-1].sub}{nl}PDOMapping=0{nl}"]
    out += [_sub_section(index, p, nl) for p in ps]
    return nl.join(out)


def standalone(placed: list[Placed], file_name: str) -> str:
    """A complete DCF (FileInfo, DeviceInfo, the mandatory objects and the variables)."""
    nl = "\n"
    objs = _objects(placed)
    head = f"""; Network variables allocated by dcf2bin allocate (CiA 405 ranges)
[FileInfo]
FileName={file_name}
FileVersion=1
FileRevision=0
EDSVersion=4.0
Description=Network variables allocated by dcf2bin allocate
CreatedBy=dcf2bin allocate

[DeviceInfo]
VendorName=unknown
ProductName=PLC
VendorNumber=0x00000000
ProductNumber=0x00000000
BaudRate_250=1
SimpleBootUpMaster=0
SimpleBootUpSlave=1
Granularity=8
DynamicChannelsSupported=0
GroupMessaging=0
NrOfRXPDO=0
NrOfTXPDO=0
LSS_Supported=0

[MandatoryObjects]
SupportedObjects=3
1=0x1000
2=0x1001
3=0x1018

[OptionalObjects]
SupportedObjects={len(objs)}
""" + "".join(f"{i}=0x{idx:04X}\n" for i, idx in enumerate(objs, 1)) + """
[ManufacturerObjects]
SupportedObjects=0

[1000]
ParameterName=Device type
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00000195
PDOMapping=0

[1001]
ParameterName=Error register
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=0
PDOMapping=0

[1018]
ParameterName=Identity object
ObjectType=0x9
SubNumber=2

[1018sub0]
ParameterName=Highest sub-index supported
ObjectType=0x7
DataType=0x0005
AccessType=ro
DefaultValue=1
PDOMapping=0

[1018sub1]
ParameterName=Vendor-ID
ObjectType=0x7
DataType=0x0007
AccessType=ro
DefaultValue=0x00000000
PDOMapping=0
"""
    return head + "".join(nl + _object_text(idx, ps, nl) for idx, ps in objs.items())
