"""XML parsed safely, with a line for every element: the one place lxml is used.

Why lxml (a dependency since issue 28) and not the standard library:

* every element keeps its line (``sourceline``), which every diagnostic needs;
  ElementTree keeps none, and expat gives lines only to a handler written in Python, which
  is what makes a tree of it about 3x slower than lxml's parse (benchmarks/xdd.py, which
  also shows lxml's parse of a 150 KB XDD at about 1.2x reading the EDS written from it);
* libxml2 is told to expand no entity (``resolve_entities=False``), load no DTD
  (``load_dtd=False``), touch no network (``no_network=True``) and keep its limits on depth
  (256) and on the size of one text (``huge_tree=False``); blank text between elements is
  not kept (``remove_blank_text``: the reader strips every text it reads, and libxml2 builds
  fewer nodes); and the input itself is bounded
  by ``fileio.read_file`` (64 MiB), so time and memory are too.

A CiA 311 description is defined by XML Schema and has no DOCTYPE: a file with one is
refused in one line (``XDD002``) before the XML parser sees the file (``doctype`` looks at
its prolog as text) -- an entity bomb, an external entity or a DTD to fetch are never
parsed, let alone expanded or fetched.
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
    refused = doctype(data)
    if refused is not None:
        raise MarkupError(*refused, "XDD002")
    from lxml import etree
    parser = etree.XMLParser(resolve_entities=False, load_dtd=False, no_network=True,
                             huge_tree=False, remove_comments=True, remove_pis=True,
                             remove_blank_text=True,
                             dtd_validation=False, attribute_defaults=False, collect_ids=False)
    try:
        root = etree.fromstring(data, parser)
    except etree.XMLSyntaxError as exc:
        message = _WHERE.sub("", exc.msg or "")
        if message.startswith("Excessive depth in document"):
            message = "elements are nested more than 256 deep"
        raise MarkupError(f"not well-formed XML: {message}", exc.lineno, "XDD001") from None
    info = root.getroottree().docinfo
    if info.doctype or info.internalDTD is not None:      # (doctype() has refused it)
        raise MarkupError(_sentence("has a DOCTYPE"), None, "XDD002")
    return root


_PROLOG = re.compile(r"\s*(?:<\?.*?\?>|<!--.*?-->)", re.S)
_DTD_ID = re.compile(r"\s*\S+\s+(?:SYSTEM\s+|PUBLIC\s+(['\"]).*?\1\s*)(['\"])(.*?)\2", re.S)


def doctype(data: bytes) -> tuple[str, int] | None:
    """(sentence, line) when the prolog of ``data`` -- what stands before the root element,
    the only place a DOCTYPE may stand -- holds one; looked at as text, before any XML
    parser sees the file: its first 64 KiB, of which the first 4 KiB are decoded first
    (a 64 KiB string made and freed before every parse made libxml2's parse of a 150 KB
    file a sixth slower), all of them only where the prolog may go on beyond those."""
    for size in (1 << 12, 1 << 16):
        head = data[:size]
        if head[:2] in (b"\xff\xfe", b"\xfe\xff"):
            text = head.decode("utf-16", "replace")
        else:
            text = head.decode("utf-8", "replace").lstrip("\ufeff")
        at = 0
        while (m := _PROLOG.match(text, at)) is not None:
            at = m.end()
        while at < len(text) and text[at].isspace():
            at += 1
        if size < 1 << 16 and len(data) > size and (
                at + 16 > len(text) or text.startswith(("<!DOCTYPE", "<!--", "<?"), at)):
            continue        # the prolog may go on beyond these 4 KiB: as before, on 64 KiB
        if not text.startswith("<!DOCTYPE", at):
            return None
        line = text.count("\n", 0, at) + 1
        rest = text[at + 9:]
        if "<!ENTITY" in rest:
            return _sentence("declares XML entities"), line
        if (m := _DTD_ID.match(rest)) is not None:
            return _sentence(f"names a DTD ({m.group(3)})"), line
        return _sentence("has a DOCTYPE"), line
    return None         # (not reached: the second round always answers)


def _sentence(what: str) -> str:
    return (f"the file {what}; a CiA 311 description has no DOCTYPE, and dcf2bin expands "
            "no entity and fetches no DTD")


_LOCAL: dict = {}


def local(tag) -> str:
    """An element's name without its namespace ('' for anything but an element)."""
    name = _LOCAL.get(tag)
    if name is None:
        name = tag.rpartition("}")[2] if tag.__class__ is str else ""
        if len(_LOCAL) < 4096:
            _LOCAL[tag] = name
    return name
