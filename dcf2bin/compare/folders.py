"""Two folders compared file by file, by name: two builds (``network build -o DIR``), or a
build and an upload (``network upload -o DIR``: one ``<slave>.dcf`` per slave).

The files read are the regular files whose names end as a description or a write list
does (``.dcf .eds .xdd .xdc .xpd .bin .json``), hidden ones (``.dcf2bin-build.lock``)
left out. Files of one name are compared; a file only in one folder is a difference --
except that a folder without ``.bin`` files (an upload: DCFs only) compared with one that
has them (a build) is compared by its own files: each of them must be in the build, and
the build's other files (its concise DCFs, the master's DCF) are listed as not compared.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field

SUFFIXES = (".dcf", ".eds", ".xdd", ".xdc", ".xpd", ".bin", ".json")


@dataclass
class Pairing:
    common: list[str] = field(default_factory=list)
    only_a: list[str] = field(default_factory=list)
    only_b: list[str] = field(default_factory=list)
    not_compared: list[str] = field(default_factory=list)


def listing(folder: str) -> list[str]:
    """The names of the files of ``folder`` diff reads, sorted (OSError when it cannot be
    listed)."""
    names = []
    with os.scandir(folder) as it:
        for e in it:
            if e.name.startswith(".") or not e.name.lower().endswith(SUFFIXES):
                continue
            if e.is_file():
                names.append(e.name)
    return sorted(names)


def pair(a: list[str], b: list[str]) -> Pairing:
    sa, sb = set(a), set(b)
    bins_a = any(n.lower().endswith(".bin") for n in a)
    bins_b = any(n.lower().endswith(".bin") for n in b)
    out = Pairing(sorted(sa & sb))
    if bins_a and not bins_b:          # a build (a) and an upload (b)
        out.only_b, out.not_compared = sorted(sb - sa), sorted(sa - sb)
    elif bins_b and not bins_a:
        out.only_a, out.not_compared = sorted(sa - sb), sorted(sb - sa)
    else:
        out.only_a, out.only_b = sorted(sa - sb), sorted(sb - sa)
    return out
