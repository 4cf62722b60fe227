"""The variable map as a C header (SPEC.md §9.1, D-14 identifiers).

``<P>PI_SIZE``, ``<P>IN_OFFSET``, ``<P>IN_SIZE``, ``<P>OUT_OFFSET``, ``<P>OUT_SIZE`` and
per variable ``<P><IDENT>_ADDR``: its image address. The identifiers avoid what C
reserves (no leading ``_``, no ``__``).
"""
from __future__ import annotations

import re

from dcf2bin.diagnostics import shorten
from dcf2bin.plc.idents import identifiers
from dcf2bin.plc.varmap import VarMap

DEFAULT_PREFIX = "DCF_"
_C_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


def prefix_problem(prefix: str) -> str | None:
    """Why ``prefix`` cannot start the header's macro names (None: it can)."""
    if not _C_IDENT.match(prefix) or "__" in prefix:
        return (f"prefix '{shorten(prefix)}' must start with a letter, hold only letters, "
                "digits and "
                "'_', and have no '__' (C reserves such names)")
    return None


def _join(prefix: str, ident: str) -> str:
    """``<P><IDENT>`` without a ``__`` where a prefix ending in ``_`` meets an identifier
    that starts with one (a name that began with a digit)."""
    if prefix.endswith("_") and ident.startswith("_"):
        ident = ident[1:]
    return prefix + ident


def _comment_text(text: str) -> str:
    return text.replace("*/", "* /").replace("/*", "/ *")


def render(vm: VarMap, prefix: str = DEFAULT_PREFIX) -> str:
    total, in_off, in_size, out_off, out_size = vm.pi
    guard = _join(prefix, "VARMAP_H").upper()
    out = [f"/* Network variables of {_comment_text(vm.source)}, made by dcf2bin map.",
           " * The *_ADDR values are image addresses: offsets from the start of the complete",
           " * process image (input area first, then output area). The IEC 61131-3 form of",
           " * the map gives offsets within the area instead. */",
           f"#ifndef {guard}",
           f"#define {guard}",
           "",
           f"#define {prefix}PI_SIZE {total}u",
           f"#define {prefix}IN_OFFSET {in_off}u",
           f"#define {prefix}IN_SIZE {in_size}u",
           f"#define {prefix}OUT_OFFSET {out_off}u",
           f"#define {prefix}OUT_SIZE {out_size}u",
           ""]
    for r, ident in zip(vm.rows, identifiers(vm.rows)):
        name = r.name
        if "*" in name:
            name = _comment_text(name)
        if ident[0] == "_" and prefix[-1] == "_":
            ident = ident[1:]
        out.append(f"#define {prefix}{ident.upper()}_ADDR 0x{r.address:04X}u /* "
                   f"{r.dtype.name} {r.label} {r.direction} {name} */")
    out += ["", f"#endif /* {guard} */"]
    return "\n".join(out) + "\n"
