#!/usr/bin/env python3
"""Generate a large, realistic CiA 405 PLC DCF for benchmarking.

    python benchmarks/gen_dcf.py N -o out.dcf

writes a CiA 306 DCF (CRLF line ends, ASCII, deterministic: no timestamps)
describing a PLC with N network variables (SPEC.md §2) over the input and
output ranges of five types:

    type        input  output  share of each direction
    BOOLEAN     A080   A500    ~48 %
    UNSIGNED8   A040   A4C0    ~48 %
    INTEGER16   A0C0   A540     2 %
    UNSIGNED32  A200   A680     1 %
    REAL32      A240   A6C0     1 %

Every network-variable index is an ARRAY (ObjectType=0x8) with sub 0
(UNSIGNED8 ro, DefaultValue = highest subindex) and up to 254 variables; an
index is filled completely before the next index of the range is used.  Inputs
are ro, outputs rw, all PDO-mappable with DefaultValue=0.

Why a [DynamicChannels] section and why mostly 1-byte types: by SPEC §2.2 a
variable's offset is segment_start + element * size, with element counted
from the start of *its own type's range*.  Without segment offsets every type
would start at byte 0 of its area and densely filled ranges of two types would
overlap (an error).  So, as a configurator does, the file declares one
CiA 306-3 segment per range with PPOffset<k> placing the types one after the
other in their area.  And the PI address segment holds WORDs: every variable's
image offset must be <= 0xFFFF, so N network variables need N bytes at least;
the 2/1/1 % of 2- and 4-byte types keep N = 60000 inside 64 KiB.  N above
MAX_VARS (about 60600) is refused.

Besides the variables the file has what a configurator writes: [FileInfo],
[DeviceInfo], [DeviceComissioning] (NodeID=5), [Comments], the three object
lists with correct counts, mandatory objects 1000/1001/1018, optional 1008 and
1017, two manufacturer objects, and 4 RPDOs + 4 TPDOs (comm + mapping) with
ParameterValue= on their entries (COB-IDs as $NODEID+0x...).  RPDOs map
output variables (writable), TPDOs input variables (readable), <= 64 bits each.

``generate(n)`` returns the text (with CRLF line ends) for use from Python.
Only the standard library is used.
"""
from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

VARS_PER_INDEX = 254          # subindex 1..254 (SPEC §2.2)
INDICES_PER_RANGE = 0x40      # each CiA 405 range is 0x40 indices (SPEC §2.1)
MAX_ADDRESS = 0xFFFF          # PI address segment entries are WORDs (SPEC §2.2)
PI_ALIGN = 8                  # output area starts 8-aligned (SPEC §2.4, default)
NODE_ID = 5


@dataclass(frozen=True)
class Kind:
    """One network-variable range: a data type in one direction."""
    type_name: str
    type_code: int
    size: int          # bytes in the process image
    bits: int          # PDO mapping length of one variable
    short: str         # used in parameter names
    start: int         # first index of the range (CiA 405 table)
    output: bool       # False = input area (ro), True = output area (rw)

    @property
    def access(self) -> str:
        return "rw" if self.output else "ro"

    @property
    def direction(self) -> str:
        return "Out" if self.output else "In"


# In the order the types are laid out in each area (small types first, so
# aligning the larger ones wastes at most a few bytes).
_TYPES = [
    # name,        code, size, bits, short, input,  output
    ("BOOLEAN",    0x01, 1, 1,  "bo",  0xA080, 0xA500),
    ("UNSIGNED8",  0x05, 1, 8,  "u8",  0xA040, 0xA4C0),
    ("INTEGER16",  0x03, 2, 16, "i16", 0xA0C0, 0xA540),
    ("UNSIGNED32", 0x07, 4, 32, "u32", 0xA200, 0xA680),
    ("REAL32",     0x08, 4, 32, "r32", 0xA240, 0xA6C0),
]
KINDS = [Kind(n, c, sz, b, s, i, False) for n, c, sz, b, s, i, _ in _TYPES] + \
        [Kind(n, c, sz, b, s, o, True) for n, c, sz, b, s, _, o in _TYPES]
_BY_NAME = {(k.type_name, k.output): k for k in KINDS}

# Percent of a direction's variables for the multi-byte types (rounded up,
# so small files have some of each); BOOLEAN and UNSIGNED8 share the rest.
_PERCENT = {"INTEGER16": 2, "UNSIGNED32": 1, "REAL32": 1}

# PDO layout: the type each PDO 1..4 maps.  RPDOs map outputs (writable
# targets), TPDOs map inputs.  BOOLEAN is left out on purpose: its PDO
# mapping length (1 bit vs. 8) is a device-specific question.
_PDO_TYPES = ["UNSIGNED8", "INTEGER16", "UNSIGNED32", "REAL32"]
_RPDO_COB = [0x200, 0x300, 0x400, 0x500]
_TPDO_COB = [0x180, 0x280, 0x380, 0x480]


def _direction_counts(n: int, output: bool) -> dict[Kind, int]:
    counts = {}
    rest = n
    for name, pct in _PERCENT.items():
        c = min(rest, -(-n * pct // 100))          # ceil, never above n
        counts[_BY_NAME[(name, output)]] = c
        rest -= c
    counts[_BY_NAME[("UNSIGNED8", output)]] = rest - rest // 2
    counts[_BY_NAME[("BOOLEAN", output)]] = rest // 2
    return counts


@dataclass
class Plan:
    """Variable counts and process-image layout of one generated file."""
    counts: dict[Kind, int]
    offsets: dict[Kind, int]      # PPOffset of each kind's segment in its area
    image_size: int               # complete PI size (SPEC §2.4)
    max_address: int              # highest PI address written (SPEC §3.4)


def plan(n: int) -> Plan:
    """Split n over the kinds (inputs get the odd one) and lay out the areas."""
    if n < 0:
        raise ValueError("N must be >= 0")
    counts = _direction_counts(n - n // 2, False) | _direction_counts(n // 2, True)
    for kind, c in counts.items():
        if c > INDICES_PER_RANGE * VARS_PER_INDEX:
            raise ValueError(f"N={n}: {c} {kind.type_name} variables do not fit "
                             f"range 0x{kind.start:04X} ({INDICES_PER_RANGE} x "
                             f"{VARS_PER_INDEX})")
    offsets: dict[Kind, int] = {}
    area_size = {False: 0, True: 0}
    last_start = {False: -1, True: -1}            # offset of the last variable
    for kind in KINDS:
        pos = -(-area_size[kind.output] // kind.size) * kind.size   # align
        offsets[kind] = pos
        if counts[kind]:
            last_start[kind.output] = pos + (counts[kind] - 1) * kind.size
            area_size[kind.output] = pos + counts[kind] * kind.size
    out_offset = -(-area_size[False] // PI_ALIGN) * PI_ALIGN if area_size[True] else 0
    image = out_offset + area_size[True] if area_size[True] else area_size[False]
    max_address = max(last_start[False], out_offset + last_start[True]
                      if last_start[True] >= 0 else -1)
    return Plan(counts, offsets, image, max_address)


def _max_vars() -> int:
    """Largest N whose highest PI address still fits a WORD (binary search)."""
    lo, hi = 0, 1 << 20
    while lo < hi:
        mid = (lo + hi + 1) // 2
        try:
            ok = plan(mid).max_address <= MAX_ADDRESS
        except ValueError:
            ok = False
        lo, hi = (mid, hi) if ok else (lo, mid - 1)
    return lo


MAX_VARS = _max_vars()


def var_address(kind: Kind, element: int) -> tuple[int, int]:
    """(index, subindex) of the element-th variable (0-based) of a kind."""
    return kind.start + element // VARS_PER_INDEX, element % VARS_PER_INDEX + 1


class _Writer:
    """Collects lines; sections are emitted in the order they are written."""

    def __init__(self) -> None:
        self.lines: list[str] = []

    def section(self, name: str, *pairs: tuple[str, object]) -> None:
        out = self.lines
        out.append(f"[{name}]")
        out.extend(f"{k}={v}" for k, v in pairs)
        out.append("")

    def text(self) -> str:
        lines = self.lines
        while lines and lines[-1] == "":      # no blank line at the very end
            lines.pop()
        return "\r\n".join(lines) + "\r\n"


def _var(w: _Writer, section: str, name: str, dtype: int, access: str,
         default: object, pdo: int = 0, value: object = None) -> None:
    """One VAR (or sub-object) section; ParameterValue only when given."""
    pairs: list[tuple[str, object]] = [
        ("ParameterName", name), ("ObjectType", "0x7"),
        ("DataType", f"0x{dtype:04X}"), ("AccessType", access),
        ("DefaultValue", default), ("PDOMapping", pdo)]
    if value is not None:
        pairs.append(("ParameterValue", value))
    w.section(section, *pairs)


def _record(w: _Writer, index: int, name: str, subs: list[tuple], *,
            sub0_name: str = "Highest sub-index supported",
            sub0_access: str = "ro", sub0_default: object = None,
            sub0_value: object = None) -> None:
    """A RECORD with an explicit sub 0 (default: ro, highest subindex).

    subs: (subindex, name, dtype, access, default, pdo, parameter_value)
    """
    if sub0_default is None:
        sub0_default = max((s[0] for s in subs), default=0)
    w.section(f"{index:04X}", ("ParameterName", name), ("ObjectType", "0x9"),
              ("SubNumber", len(subs) + 1))
    _var(w, f"{index:04X}sub0", sub0_name, 0x05, sub0_access, sub0_default,
         0, sub0_value)
    for sub, sname, dtype, access, default, pdo, value in subs:
        _var(w, f"{index:04X}sub{sub:X}", sname, dtype, access, default, pdo,
             value)


def _object_list(w: _Writer, name: str, indices: list[int]) -> None:
    w.section(name, ("SupportedObjects", len(indices)),
              *((str(i), f"0x{x:04X}") for i, x in enumerate(indices, 1)))


def _network_variables(w: _Writer, kind: Kind, count: int,
                       denotations: bool = False) -> None:
    """All indices of one kind, 254 variables per index; with ``denotations`` each
    variable also gets a Denotation= of its own (a configured DCF with signal names),
    so no two variable sections share their text beyond ParameterName."""
    lines = w.lines
    type_hex = f"0x{kind.type_code:04X}"
    element = 0
    index = kind.start
    while element < count:
        n = min(VARS_PER_INDEX, count - element)
        w.section(f"{index:04X}",
                  ("ParameterName",
                   f"Net{kind.direction}_{kind.type_name}_{index - kind.start + 1}"),
                  ("ObjectType", "0x8"),
                  ("SubNumber", n + 1))
        w.section(f"{index:04X}sub0",
                  ("ParameterName", "Highest sub-index supported"),
                  ("ObjectType", "0x7"), ("DataType", "0x0005"),
                  ("AccessType", "ro"), ("DefaultValue", n),
                  ("PDOMapping", 0))
        # Hot loop: inline the section text (60000 variables -> 420k lines).
        prefix = f"{index:04X}sub"
        name = f"{kind.direction.lower()}_{kind.short}_"
        for sub in range(1, n + 1):
            lines += (f"[{prefix}{sub:X}]",
                      f"ParameterName={name}{element + sub:05d}",
                      "ObjectType=0x7",
                      f"DataType={type_hex}",
                      f"AccessType={kind.access}",
                      "DefaultValue=0",
                      "PDOMapping=1")
            if denotations:
                lines.append(f"Denotation=Signal {name}{element + sub:05d}")
            lines.append("")
        element += n
        index += 1


def _pdo_mappings(counts: dict[Kind, int], output: bool) -> list[list[int]]:
    """Mapping values (index<<16 | sub<<8 | bits) for PDOs 1..4.

    Each PDO maps up to 64 bits of one type, picking variables spread evenly
    over that kind's range (so mappings point into later indices too).
    """
    result = []
    for type_name in _PDO_TYPES:
        kind = _BY_NAME[(type_name, output)]
        count = counts[kind]
        m = min(64 // kind.bits, 8, count)
        entries = []
        for j in range(m):
            index, sub = var_address(kind, j * count // m)
            entries.append(index << 16 | sub << 8 | kind.bits)
        result.append(entries)
    return result


def _pdos(w: _Writer, counts: dict[Kind, int]) -> None:
    """4 RPDOs (1400..1403 / 1600..1603) and 4 TPDOs (1800..1803 / 1A00..1A03)."""
    rmaps = _pdo_mappings(counts, output=True)
    tmaps = _pdo_mappings(counts, output=False)
    for i in range(4):
        cob = f"$NODEID+0x{_RPDO_COB[i]:X}"
        _record(w, 0x1400 + i, f"RPDO communication parameter {i + 1}", [
            (1, "COB-ID used by RPDO", 0x07, "rw", cob, 0, cob),
            (2, "Transmission type", 0x05, "rw", "0xFF", 0, "0xFF"),
        ])
    for i in range(4):
        _mapping(w, 0x1600 + i, f"RPDO mapping parameter {i + 1}", rmaps[i])
    for i in range(4):
        cob = f"$NODEID+0x{_TPDO_COB[i]:X}"
        _record(w, 0x1800 + i, f"TPDO communication parameter {i + 1}", [
            (1, "COB-ID used by TPDO", 0x07, "rw", cob, 0, cob),
            (2, "Transmission type", 0x05, "rw", "0xFF", 0, "0xFE"),
            (3, "Inhibit time", 0x06, "rw", 0, 0, 0),
            (5, "Event timer", 0x06, "rw", 0, 0, 100),
        ])
    for i in range(4):
        _mapping(w, 0x1A00 + i, f"TPDO mapping parameter {i + 1}", tmaps[i])


def _mapping(w: _Writer, index: int, name: str, entries: list[int]) -> None:
    """A mapping record with subs 1..8, the first len(entries) in use.

    Sub 0 of a mapping record is rw and holds the number of mapped objects
    (not the highest subindex): default 0, configured to len(entries).
    """
    subs = [(k, f"Mapping entry {k}", 0x07, "rw", "0x00000000", 0,
             f"0x{entries[k - 1]:08X}" if k <= len(entries) else "0x00000000")
            for k in range(1, 9)]
    _record(w, index, name, subs, sub0_name="Number of mapped objects",
            sub0_access="rw", sub0_default=0, sub0_value=len(entries))


def _dynamic_channels(w: _Writer, p: Plan) -> None:
    """[DynamicChannels] (CiA 306-3): one segment per range, full 0x40 indices,
    PPOffset placing the types one after the other in their area."""
    pairs: list[tuple[str, object]] = [("NrOfSeg", len(KINDS))]
    for k, kind in enumerate(KINDS, 1):
        last = kind.start + INDICES_PER_RANGE - 1
        pairs += [(f"Type{k}", f"0x{kind.type_code:04X}"),
                  (f"Dir{k}", kind.access),
                  (f"Range{k}", f"0x{kind.start:04X}-0x{last:04X}"),
                  (f"PPOffset{k}", p.offsets[kind])]
    w.section("DynamicChannels", *pairs)


def generate(n: int, denotations: bool = False) -> str:
    """The DCF text for a PLC with n network variables (CRLF line ends); see
    ``_network_variables`` for ``denotations``."""
    if n > MAX_VARS:
        raise ValueError(f"N={n} is too large: with this type mix the highest "
                         f"process-image address must stay <= 0x{MAX_ADDRESS:X}, "
                         f"which allows at most {MAX_VARS} network variables")
    p = plan(n)
    counts = p.counts
    var_indices = []
    for kind in KINDS:
        used = -(-counts[kind] // VARS_PER_INDEX)   # ceil
        var_indices += range(kind.start, kind.start + used)
    var_indices.sort()

    pdo_indices = ([0x1400 + i for i in range(4)] + [0x1600 + i for i in range(4)]
                   + [0x1800 + i for i in range(4)] + [0x1A00 + i for i in range(4)])
    optional = [0x1008, 0x1017] + pdo_indices + var_indices
    manufacturer = [0x2000, 0x2001]

    w = _Writer()
    w.lines += [f"; CANopen DCF generated by benchmarks/gen_dcf.py ({n} network variables)", ""]
    w.section("FileInfo",
              ("FileName", f"plc_{n}.dcf"), ("FileVersion", 1),
              ("FileRevision", 0), ("EDSVersion", "4.0"),
              ("Description", f"Benchmark PLC, {n} CiA 405 network variables"),
              ("CreationTime", "12:00PM"), ("CreationDate", "01-01-2024"),
              ("CreatedBy", "dcf2bin benchmarks"),
              ("ModificationTime", "12:00PM"), ("ModificationDate", "01-01-2024"),
              ("ModifiedBy", "dcf2bin benchmarks"))
    w.section("DeviceInfo",
              ("VendorName", "Example Automation"), ("VendorNumber", "0x00000123"),
              ("ProductName", "Bench PLC 405"), ("ProductNumber", "0x00004050"),
              ("RevisionNumber", "0x00010000"), ("OrderCode", "BENCH-405"),
              ("BaudRate_10", 1), ("BaudRate_20", 1), ("BaudRate_50", 1),
              ("BaudRate_125", 1), ("BaudRate_250", 1), ("BaudRate_500", 1),
              ("BaudRate_800", 1), ("BaudRate_1000", 1),
              ("SimpleBootUpMaster", 0), ("SimpleBootUpSlave", 1),
              ("Granularity", 8), ("DynamicChannelsSupported", len(KINDS)),
              ("GroupMessaging", 0), ("NrOfRXPDO", 4), ("NrOfTXPDO", 4),
              ("LSS_Supported", 0), ("CompactPDO", 0))
    _dynamic_channels(w, p)
    w.section("DeviceComissioning",
              ("NodeID", NODE_ID), ("NodeName", "BenchPLC"), ("Baudrate", 500),
              ("NetNumber", 1), ("NetworkName", "Plant network"),
              ("CANopenManager", 0), ("LSS_SerialNumber", 0))
    w.section("Comments", ("Lines", 2),
              ("Line1", "Synthetic CiA 405 PLC for dcf2bin benchmarks."),
              ("Line2", "Network variables: 254 per index, inputs ro, outputs rw."))

    # Mandatory objects.
    _object_list(w, "MandatoryObjects", [0x1000, 0x1001, 0x1018])
    _var(w, "1000", "Device type", 0x07, "ro", "0x00000195")   # CiA 405
    _var(w, "1001", "Error register", 0x05, "ro", 0)
    _record(w, 0x1018, "Identity object", [
        (1, "Vendor-ID", 0x07, "ro", "0x00000123", 0, None),
        (2, "Product code", 0x07, "ro", "0x00004050", 0, None),
        (3, "Revision number", 0x07, "ro", "0x00010000", 0, None),
        (4, "Serial number", 0x07, "ro", "0x00000000", 0, None),
    ])

    # Optional objects: a string, heartbeat, PDOs, then the network variables.
    _object_list(w, "OptionalObjects", optional)
    _var(w, "1008", "Manufacturer device name", 0x09, "const", "Bench PLC 405")
    _var(w, "1017", "Producer heartbeat time", 0x06, "rw", 0, 0, 500)
    _pdos(w, counts)
    for kind in sorted(KINDS, key=lambda k: k.start):
        _network_variables(w, kind, counts[kind], denotations)

    # Manufacturer objects: two configured PLC parameters.
    _object_list(w, "ManufacturerObjects", manufacturer)
    _var(w, "2000", "PLC cycle time (ms)", 0x06, "rw", 10, 0, 5)
    _var(w, "2001", "PLC run mode", 0x05, "rw", 0, 0, 1)
    return w.text()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description="Write a synthetic CiA 405 PLC DCF with N network variables.")
    ap.add_argument("n", type=int, metavar="N", help="number of network variables")
    ap.add_argument("-o", "--output", metavar="FILE",
                    help="output file (default: standard output)")
    ap.add_argument("--denotations", action="store_true",
                    help="give every variable a Denotation= of its own")
    args = ap.parse_args(argv)
    try:
        data = generate(args.n, args.denotations).encode("ascii")
    except ValueError as e:
        ap.error(str(e))
    if args.output:
        with open(args.output, "wb") as f:
            f.write(data)
    else:
        sys.stdout.buffer.write(data)
    return 0


if __name__ == "__main__":
    sys.exit(main())
