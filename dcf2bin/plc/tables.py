"""The variable map as text, CSV and JSON (SPEC.md §9.1)."""
from __future__ import annotations

import csv
import io
import json

from dcf2bin.plc.varmap import VarMap

CSV_HEADER = ("name", "index", "subindex", "type", "direction", "offset", "address", "size")


def to_text(vm: VarMap) -> str:
    """A readable table; the PI parameter numbers above it."""
    total, in_off, in_size, out_off, out_size = vm.pi
    out = [f"{vm.source}: {len(vm.rows)} network variable{'s' if len(vm.rows) != 1 else ''}, "
           f"process image {total} bytes",
           f"  input area   offset {in_off:<6} size {in_size}",
           f"  output area  offset {out_off:<6} size {out_size}",
           ""]
    head = ("address", "area", "offset", "entry", "size", "type", "name")
    rows = [(f"0x{r.address:04X}", r.direction, str(r.offset), r.label, str(r.size),
             r.dtype.name, r.name) for r in vm.rows]
    widths = [len(h) for h in head]
    for col, cells in enumerate(zip(*rows)):
        widths[col] = max(widths[col], max(map(len, cells)))
    right = {2, 4}
    fmt = "  ".join(f"{{{i}:{'>' if i in right else '<'}{w}}}" for i, w in enumerate(widths))
    out.append(fmt.format(*head).rstrip())
    out.extend(fmt.format(*r).rstrip() for r in rows)
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


def to_json(vm: VarMap) -> str:
    """``{"variables": [...], "areas": {...}}``, numbers as JSON integers, one variable a
    line (diff-friendly)."""
    d = json.dumps
    lines = ["{", '  "variables": [']
    last = len(vm.rows) - 1
    for i, r in enumerate(vm.rows):
        lines.append(
            f'    {{"name": {d(r.name, ensure_ascii=False)}, "index": {r.index}, '
            f'"subindex": {r.sub}, "type": "{r.dtype.name}", "direction": "{r.direction}", '
            f'"offset": {r.offset}, "address": {r.address}, "size": {r.size}}}'
            + ("," if i < last else ""))
    lines.append("  ],")
    lines.append(f'  "areas": {d(vm.areas)}')
    lines.append("}")
    return "\n".join(lines) + "\n"
