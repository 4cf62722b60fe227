"""The container as C source (SPEC.md §9.1), to link it into the target as ex_dynod.c does
(seed 000 §3):

    #define <NAME>_PI_SIZE <complete PI size>
    const unsigned char <name>[<total>] = { ... };

12 bytes a line, a comment at the start of the header and of each segment.
"""
from __future__ import annotations

import os
import re

from dcf2bin import schema
from dcf2bin.diagnostics import shorten

DEFAULT_DECL = "const unsigned char"
PER_LINE = 12
_C_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_TITLES = {"index": "index segment", "address": "PI address segment",
           "extinfo": "extended info segment", "piparam": "PI parameter segment"}


def name_problem(name: str) -> str | None:
    if not _C_IDENT.match(name) or "__" in name:
        return (f"C name '{shorten(name)}' must start with a letter, hold only letters, digits and "
                "'_', and have no '__'")
    return None


def decl_problem(decl: str) -> str | None:
    if not decl.strip() or any(ch in decl for ch in "\r\n;{}=[]"):
        return f"declaration '{shorten(decl)}' must be one line of type words (no ; {{ }} = [ ])"
    return None


def default_name(input_path: str) -> str:
    """The input's base name as a C identifier: ``samples/plc.dcf`` -> ``plc``."""
    stem = os.path.splitext(os.path.basename(input_path))[0]
    ident = re.sub(r"[^A-Za-z0-9]+", "_", stem).strip("_")
    if not ident or not ident[0].isalpha():
        ident = "dcf_" + ident if ident else "dcf_container"
    return ident


def render(data: bytes, name: str, *, decl: str = DEFAULT_DECL, source: str = "") -> str:
    """C source of the container bytes ``data`` (as compile wrote them)."""
    c, _ = _read(data)
    h = dict(c.header) if c.header is not None else c.canonical_header()
    pi_size = c.pi[0] if c.pi is not None else 0
    starts = {0: f"header ({schema.HEADER_SIZE} bytes)"}
    for seg in schema.SEGMENTS:
        if h[f"{seg}_size"]:
            starts[h[f"{seg}_offset"]] = (f"{_TITLES[seg]} (offset {h[f'{seg}_offset']}, "
                                          f"{h[f'{seg}_size']} bytes)")
    origin = f" from {source}" if source else ""
    out = [f"/* DCF segment container{origin}, {len(data)} bytes, made by dcf2bin compile.",
           f" * {name.upper()}_PI_SIZE: size of the process image the container describes",
           " * (0 without PI segments); declare the PI memory with it. */",
           f"#define {name.upper()}_PI_SIZE {pi_size}",
           "",
           f"{decl} {name}[{len(data)}] = {{"]
    cuts = sorted(starts)
    for i, start in enumerate(cuts):
        end = cuts[i + 1] if i + 1 < len(cuts) else len(data)
        out.append(f"    /* {starts[start]} */")
        for pos in range(start, end, PER_LINE):
            chunk = data[pos:min(pos + PER_LINE, end)]
            last = pos + len(chunk) == len(data)
            out.append("    " + ", ".join(f"0x{b:02X}" for b in chunk) + ("" if last else ","))
    out.append("};")
    return "\n".join(out) + "\n"


def _read(data: bytes):
    from dcf2bin.container import read
    return read(data)
