"""Two folders compared file by file, by name: two builds (``network build -o DIR``), or a
build and an upload (``network upload -o DIR``: one ``<slave>.dcf`` per slave).

The files read are the regular files whose names end as a description or a write list
does (``.dcf .eds .xdd .xdc .xpd .bin .json``), hidden ones (``.dcf2bin-build.lock``)
left out; a name that ends so but is no regular file (a FIFO, a folder) is not read, and
the command says what it is. Files of one name are compared; a file only in one folder is a difference --
except that a folder without ``.bin`` files (an upload: DCFs only) compared with one that
has them (a build) is compared by its own files: each of them must be in the build, and
the build's other files (its concise DCFs, the master's DCF) are listed as not compared.
"""
from __future__ import annotations

import os
import stat
from dataclasses import dataclass, field

SUFFIXES = (".dcf", ".eds", ".xdd", ".xdc", ".xpd", ".bin", ".json")


@dataclass
class Pairing:
    common: list[str] = field(default_factory=list)
    only_a: list[str] = field(default_factory=list)
    only_b: list[str] = field(default_factory=list)
    not_compared: list[str] = field(default_factory=list)


@dataclass
class Listing:
    """A folder's names as diff sees them: ``files``, the regular files it reads (sorted);
    ``others``, the names that end as those do but are no regular file (a FIFO, a folder,
    a link to nothing) -> what they are: not read, and said so."""
    files: list[str] = field(default_factory=list)
    others: dict[str, str] = field(default_factory=dict)


def listing(folder: str) -> Listing:
    """The names of ``folder`` diff reads, and those it does not (OSError when the folder
    cannot be listed)."""
    out = Listing()
    with os.scandir(folder) as it:
        for e in it:
            if e.name.startswith(".") or not e.name.lower().endswith(SUFFIXES):
                continue
            if e.is_file():
                out.files.append(e.name)
            else:
                out.others[e.name] = what(os.path.join(folder, e.name))
    out.files.sort()
    out.others = dict(sorted(out.others.items()))
    return out


def what(path: str) -> str:
    """What a name that is no regular file names, in words."""
    try:
        mode = os.stat(path).st_mode
    except FileNotFoundError:
        return "a symbolic link to nothing"
    except OSError as exc:
        return f"not readable ({exc.strerror or exc})"
    if stat.S_ISDIR(mode):
        return "a folder"
    if stat.S_ISFIFO(mode):
        return "a FIFO"
    if stat.S_ISSOCK(mode):
        return "a socket"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device"
    return "not a regular file"


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
