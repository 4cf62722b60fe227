"""The table of description formats: one ``Format`` a line, the one place that says which
formats dcf2bin knows, by which names and suffixes, and how their content is recognised.

``dcf2bin.filekind`` asks it what a file is (``sniff``, ``kinds_by_suffix``); the readers
and writers are found through it (``Format.module``), so that adding a format is one module
under ``dcf2bin/formats/`` and one line in ``FORMATS``.

A format module is a load/dump pair around the neutral model (cantools' formats, one
module each; see docs/architecture.md "Add a description format"):

* ``sniff(data: bytes) -> bool`` -- the content says it is this format (cheap: it looks
  at the first bytes only, and imports nothing heavy);
* a reader: ``read(data: bytes, path: str) -> ini.IniFile`` -- the file's data as the
  per-object key/value sections of CiA 306 with the file's own line numbers, so that the
  model's builder and every validate rule apply unchanged (``dcf2bin.formats.build``
  makes the ``Device``);
* a writer: ``dump(dev, kind, *, name=None, node_id=None) -> written.Written`` -- the
  bytes of ``kind`` (one of the format's file kinds: "eds"/"dcf", "xdd"/"xdc") and a
  warning for each thing the format cannot say (``formats.dump``, ``dcf2bin convert``).

This module imports nothing of dcf2bin: the modules are named, and imported when used.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass


@dataclass(frozen=True)
class Format:
    """One description format."""
    name: str                   # the registry's name ("ini", "xdd")
    title: str                  # how a sentence names a file of it
    kind: str                   # the file kind dcf2bin.filekind gives it
    suffixes: tuple[str, ...]   # lower case, with the dot
    module: str                 # the module with sniff/read (and dump)
    reads: bool = True
    writes: bool = False

    def code(self):
        """The format's module (imported on first use)."""
        return importlib.import_module(self.module)

    def sniff(self, data: bytes) -> bool:
        return self.code().sniff(data)


# The order is the order of the content tests: XML before CiA 306 text, whose test (a
# "[section]" line) an XML description's free text could pass.
FORMATS: tuple[Format, ...] = (
    Format("xdd", "CiA 311 XML (XDD/XDC)", "xdd", (".xdd", ".xdc", ".xpd"),
           "dcf2bin.formats.xdd", writes=True),
    Format("ini", "DCF/EDS text", "dcf", (".dcf", ".eds", ".ini"), "dcf2bin.formats.ini",
           writes=True),
)

#: the format a file is read with when its content says nothing clear (an empty file)
DEFAULT = FORMATS[-1]


def by_name(name: str) -> Format:
    for f in FORMATS:
        if f.name == name:
            return f
    raise KeyError(name)


def by_kind(kind: str) -> Format | None:
    for f in FORMATS:
        if f.kind == kind:
            return f
    return None


def by_suffix(suffix: str) -> Format | None:
    """The format a file suffix (".XDD", ".eds") names, or None."""
    suffix = suffix.lower()
    for f in FORMATS:
        if suffix in f.suffixes:
            return f
    return None


def kinds_by_suffix() -> dict[str, str]:
    """suffix -> file kind, for dcf2bin.filekind's table of names."""
    return {s: f.kind for f in FORMATS for s in f.suffixes}


def sniff(data: bytes) -> Format | None:
    """The first format whose content test ``data`` passes, or None."""
    for f in FORMATS:
        if f.reads and f.sniff(data):
            return f
    return None
