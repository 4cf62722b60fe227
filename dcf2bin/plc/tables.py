"""The variable map as text, CSV and JSON (SPEC.md §9.1)."""
from __future__ import annotations

import csv
import io
import json
from operator import attrgetter

from dcf2bin.plc.varmap import VarMap

CSV_HEADER = ("name", "index", "subindex", "type", "direction", "offset", "address", "size")


# the fields of a row in the text table, in its order (offsets are >= 0)
_TEXT_FIELDS = attrgetter("address", "direction", "offset", "label", "dtype.size",
                          "dtype.name", "name")


def to_text(vm: VarMap) -> str:
    """A readable table; the PI parameter numbers above it."""
    total, in_off, in_size, out_off, out_size = vm.pi
    out = [f"{vm.source}: {len(vm.rows)} network variable{'s' if len(vm.rows) != 1 else ''}, "
           f"process image {total} bytes",
           f"  input area   offset {in_off:<6} size {in_size}",
           f"  output area  offset {out_off:<6} size {out_size}",
           ""]
    rows = vm.rows
    # the widths from three columns, then one printf template over each row's fields
    w_off = max(len("offset"), len(str(max(map(attrgetter("offset"), rows), default=0))))
    w_entry = max(len("entry"), max(map(len, map(attrgetter("label"), rows)), default=0))
    w_type = max(len("type"), max(map(len, set(map(attrgetter("dtype.name"), rows))),
                                  default=0))
    w_size = len("size")          # sizes are 1..8
    out.append(f"address  area    {'offset':>{w_off}}  {'entry':<{w_entry}}  "
               f"{'size':>{w_size}}  {'type':<{w_type}}  name")
    fmt = f"0x%04X   %-6s  %{w_off}d  %-{w_entry}s  %{w_size}d  %-{w_type}s  %s"
    out += map(str.rstrip, map(fmt.__mod__, map(_TEXT_FIELDS, rows)))
    return "\n".join(out) + "\n"


def to_csv(vm: VarMap) -> str:
    """One row per variable under a header row; numbers in decimal, the index in hex.
    (The PI parameter numbers are in every other format; CSV has no place for them.)"""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(CSV_HEADER)
    w.writerows((r.name, f"0x{r.index:04X}", r.sub, r.dtype.name, r.direction, r.offset,
                 r.address, r.size) for r in vm.rows)
    return buf.getvalue()


FORMAT, VERSION = "dcf2bin-map", 1     # schema: dcf2bin/schemas/map.json


def to_json(vm: VarMap) -> str:
    """``{"format": "dcf2bin-map", "version": 1, "file": ..., "variables": [...],
    "areas": {...}}``: indexes as ``"0xA040"`` strings, every other number a JSON integer,
    one variable a line (diff-friendly)."""
    d = json.dumps
    total, in_off, in_size, out_off, out_size = vm.pi
    areas = {"pi_size": total, "input_offset": in_off, "input_size": in_size,
             "output_offset": out_off, "output_size": out_size}
    lines = ["{", f'  "format": "{FORMAT}",', f'  "version": {VERSION},',
             f'  "file": {d(vm.source, ensure_ascii=False)},', '  "variables": [']
    last = len(vm.rows) - 1
    for i, r in enumerate(vm.rows):
        lines.append(
            f'    {{"name": {d(r.name, ensure_ascii=False)}, "index": "0x{r.index:04X}", '
            f'"subindex": {r.sub}, "type": "{r.dtype.name}", "direction": "{r.direction}", '
            f'"offset": {r.offset}, "address": {r.address}, "size": {r.size}}}'
            + ("," if i < last else ""))
    lines.append("  ],")
    lines.append(f'  "areas": {d(areas)}')
    lines.append("}")
    return "\n".join(lines) + "\n"
