"""The variable map as IEC 61131-3 declarations (SPEC.md D-14).

One ``VAR_GLOBAL`` ... ``END_VAR`` block; per variable
``<ident> AT %<I|Q><X|B|W|D|L><n> : <type>; (* <name> 0xIIIIsubS *)``. ``n`` counts bytes
within the area (OpenPCS) or, with ``addressing="element"``, units of the size prefix
(CODESYS: ``%IW1`` is bytes 2..3), where an offset that is not a multiple of the unit is
an error.
"""
from __future__ import annotations

from dcf2bin.diagnostics import Diagnostic, Severity
from dcf2bin.layout import INPUT
from dcf2bin.plc.idents import identifiers
from dcf2bin.plc.varmap import VarMap

BYTE, ELEMENT = "byte", "element"
RULE_ALIGN = "MAP002"

# data type -> (size prefix, IEC type); anything else is ARRAY[0..s-1] OF BYTE at %B (D-14)
IEC_TYPES = {
    "BOOLEAN": ("X", "BOOL"),
    "INTEGER8": ("B", "SINT"), "UNSIGNED8": ("B", "USINT"),
    "INTEGER16": ("W", "INT"), "UNSIGNED16": ("W", "UINT"),
    "INTEGER32": ("D", "DINT"), "UNSIGNED32": ("D", "UDINT"), "REAL32": ("D", "REAL"),
    "INTEGER64": ("L", "LINT"), "UNSIGNED64": ("L", "ULINT"), "REAL64": ("L", "LREAL"),
}
UNIT = {"X": 1, "B": 1, "W": 2, "D": 4, "L": 8}


def _comment_text(text: str) -> str:
    """``(*`` and ``*)`` inside a name would end or nest the comment: break them up."""
    while "(*" in text or "*)" in text:
        text = text.replace("(*", "( *").replace("*)", "* )")
    return text


def render(vm: VarMap, addressing: str = BYTE) -> tuple[str | None, list[Diagnostic]]:
    """The declarations, or None and the errors (element addressing: a misaligned offset)."""
    diags: list[Diagnostic] = []
    idents = identifiers(vm.rows)
    total, in_off, in_size, out_off, out_size = vm.pi
    mode = ("byte offsets within the area" if addressing == BYTE else
            "offsets within the area in units of the size prefix (X, B: 1 byte, W: 2, D: 4, "
            "L: 8)")
    out = [f"(* Network variables of {_comment_text(vm.source)}, made by dcf2bin map *)",
           f"(* Process image: complete size {total}; input area offset {in_off} size "
           f"{in_size}; output area offset {out_off} size {out_size} *)",
           f"(* %I = input area, %Q = output area; addresses are {mode} *)",
           "VAR_GLOBAL"]
    element = addressing == ELEMENT
    kinds: dict[tuple, tuple[str, str, int]] = {}   # (type, direction) -> (AT, type, unit)
    for r, ident in zip(vm.rows, idents):
        kind = kinds.get((r.dtype, r.direction))
        if kind is None:
            letter = "I" if r.direction == INPUT else "Q"
            prefix, iec_type = IEC_TYPES.get(r.dtype.name,
                                             ("B", f"ARRAY[0..{r.size - 1}] OF BYTE"))
            kind = kinds[(r.dtype, r.direction)] = (f"%{letter}{prefix}", iec_type,
                                                    UNIT[prefix] if element else 1)
        at, iec_type, unit = kind
        n = r.offset
        if unit != 1:
            if n % unit:
                diags.append(Diagnostic(
                    Severity.ERROR, f"{r.label} ({r.dtype.name}) lies at byte {n} of the "
                    f"{r.direction} area, not a multiple of {unit}: {at} cannot address it "
                    "in element addressing",
                    r.where.file if r.where else vm.source, r.where.line if r.where else None,
                    rule=RULE_ALIGN))
                continue
            n //= unit
        name = r.name
        if "*" in name:
            name = _comment_text(name)
        out.append(f"    {ident} AT {at}{n}{'.0' if at[2] == 'X' else ''} : {iec_type}; "
                   f"(* {name} {r.label} *)")
    out.append("END_VAR")
    if diags:
        return None, diags
    return "\n".join(out) + "\n", diags
