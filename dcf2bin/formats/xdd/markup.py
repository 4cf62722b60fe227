"""XML parsed safely, with a line for every element: the one place lxml is used.

Why lxml (a dependency since issue 28) and not the standard library:

* every element keeps its line (``sourceline``), which every diagnostic needs;
  ElementTree keeps none, and expat gives lines only to a handler written in Python, which
  is what makes a tree of it about 3x slower than lxml's (benchmarks/xdd.py reads a 150 KB
  XDD within the 3x of its EDS with lxml);
* libxml2 is told to expand no entity (``resolve_entities=False``), load no DTD
  (``load_dtd=False``), touch no network (``no_network=True``) and keep its limits on depth
  (256) and on the size of one text (``huge_tree=False``); and the input itself is bounded
  by ``fileio.read_file`` (64 MiB), so time and memory are too.

A CiA 311 description is defined by XML Schema and has no DOCTYPE: a file with one is
refused in one line (``XDD002``) before anything in it is read -- an entity bomb, an
external entity or a DTD to fetch are never looked at, even unexpanded.
"""
from __future__ import annotations

import re

_WHERE = re.compile(r", line \d+, column \d+$")


class MarkupError(Exception):
    """XML dcf2bin does not read: ``line``, ``message``, ``rule``."""

    def __init__(self, message: str, line: int | None, rule: str):
        super().__init__(message)
        self.message, self.line, self.rule = message, line, rule


def parse(data: bytes):
    """The root element of ``data``; ``MarkupError`` for XML that is not well-formed
    (XDD001) or has a DOCTYPE (XDD002)."""
    from lxml import etree
    parser = etree.XMLParser(resolve_entities=False, load_dtd=False, no_network=True,
                             huge_tree=False, remove_comments=True, remove_pis=True,
                             dtd_validation=False, attribute_defaults=False, collect_ids=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        message = _WHERE.sub("", exc.msg or "")
        if message.startswith("Excessive depth in document"):
            message = "elements are nested more than 256 deep"
        raise MarkupError(f"not well-formed XML: {message}", exc.lineno, "XDD001") from None
    doctype = root.getroottree().docinfo
    if doctype.doctype or doctype.internalDTD is not None:
        raise MarkupError(_doctype_sentence(doctype), _doctype_line(data), "XDD002")
    return root


def _doctype_sentence(info) -> str:
    dtd = info.internalDTD
    if dtd is not None and any(True for _ in dtd.iterentities()):
        what = "declares XML entities"
    elif info.system_url or info.public_id:
        what = f"names a DTD ({info.system_url or info.public_id})"
    else:
        what = "has a DOCTYPE"
    return (f"the file {what}; a CiA 311 description has no DOCTYPE, and dcf2bin expands "
            "no entity and fetches no DTD")


def _doctype_line(data: bytes) -> int | None:
    at = data.find(b"<!DOCTYPE")
    if at < 0:
        at = data.find(b"<\x00!\x00D\x00")       # UTF-16
    return data.count(b"\n", 0, at) + 1 if at >= 0 else None


def local(tag) -> str:
    """An element's name without its namespace ('' for anything but an element)."""
    return tag.rpartition("}")[2] if tag.__class__ is str else ""
