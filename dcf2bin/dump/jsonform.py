"""The lossless JSON form of a container (SPEC.md §4): its constants and rule ids, its JSON
Schema (``JSON_SCHEMA``, explained in docs/dump.md), container -> document (``to_dict``,
``to_json``) and ``JsonProblem``, the one error a document that is not a valid dump raises.
"""
from __future__ import annotations

import json

from dcf2bin import schema
from dcf2bin.container import BinContainer
from dcf2bin.dump.binary import header_of
from dcf2bin.schemas import load as load_schema


FORMAT = "dcf2bin-container"
SCHEMA_VERSION = 1            # the document's "version" (written as "schema_version" before)
CANONICAL, STORED = "canonical", "stored"

RULE_JSON_SYNTAX = "JSN001"   # not JSON at all
RULE_JSON = "JSN002"          # JSON that is not a valid dump
RULE_JSON_HEADER = "JSN003"   # canonical layout: a stale header field (recomputed)

PIPARAM_FIELDS = list(schema.PIPARAM_FIELDS)
HEADER_FIELDS = list(schema.HEADER_FIELDS)
_DWORD, _WORD = 0xFFFFFFFF, 0xFFFF
_HEADER_MAX = {name: (_WORD if name in ("version", "segment_count") else _DWORD)
               for name in HEADER_FIELDS}
_ADDR_PER_LINE = 16

# JSON Schema (draft 2020-12) of the document ``to_dict`` writes: dcf2bin/schemas/dump.json,
# explained in docs/dump.md. The reader (``document.from_dict``) also takes what older
# versions wrote: ``schema_version`` for ``version``, indexes as integers or short hex.
JSON_SCHEMA = load_schema("dump")


# -- container -> JSON ----------------------------------------------------------------------

def to_dict(c: BinContainer, *, entries: bool = True) -> dict:
    """The lossless document as Python data (key order is the documented one).
    ``entries=False``: an empty list for the entries (``to_json`` writes them itself)."""
    h = header_of(c)
    attrs = c.attributes or b""
    n = len(c.entries)
    rows = []
    for i, (index, sub, data) in enumerate(c.entries if entries else ()):
        rows.append({"index": f"0x{index:04X}", "subindex": sub, "data": data.hex().upper(),
                     "attribute": f"0x{attrs[i]:02X}" if i < len(attrs) else None})
    if c.raw_piparam is not None:
        pi = {"raw": c.raw_piparam.hex().upper()}
    elif c.pi is not None:
        pi = dict(zip(PIPARAM_FIELDS, c.pi))
    else:
        pi = None
    return {
        "format": FORMAT,
        "version": SCHEMA_VERSION,
        "layout": STORED if c.header is not None else CANONICAL,
        "header": {k: h[k] for k in HEADER_FIELDS},
        "entries": rows,
        "extra_attributes": attrs[n:].hex().upper(),
        "addresses": list(c.addresses) if c.addresses is not None else None,
        "pi_parameters": pi,
        "gaps": [{"offset": off, "data": data.hex().upper()} for off, data in c.gaps],
    }


def to_json(c: BinContainer) -> str:
    """``to_dict`` as stable, diff-friendly JSON text: one entry per line."""
    doc = to_dict(c, entries=False)
    doc["entries"] = _entry_lines(c)
    return format_json(doc)


class _Lines(list):
    """Array items already written as JSON text (``format_json`` puts them as they are)."""


# the JSON text of one entry, as json.dumps writes its object (key order of to_dict)
_ENTRY_JSON = '{"index": "0x%04X", "subindex": %d, "data": "%s", "attribute": %s}'
_ATTR_JSON = [f'"0x{a:02X}"' for a in range(256)]


def _entry_lines(c: BinContainer) -> _Lines:
    """The entries of ``to_dict`` as JSON text, written column by column with one template
    instead of a dict and a json.dumps each."""
    n = len(c.entries)
    if not n:
        return _Lines()
    indexes, subs, datas = zip(*c.entries)
    attrs = c.attributes or b""
    attr_json = list(map(_ATTR_JSON.__getitem__, attrs[:n])) + ["null"] * (n - len(attrs))
    return _Lines(map(_ENTRY_JSON.__mod__, zip(indexes, subs, map(str.upper, map(
        bytes.hex, datas)), attr_json)))


def format_json(doc: dict) -> str:
    d = json.dumps
    out = ["{"]
    keys = list(doc)
    for k_i, key in enumerate(keys):
        value = doc[key]
        comma = "," if k_i < len(keys) - 1 else ""
        if key == "header" and isinstance(value, dict):
            out.append('  "header": {')
            items = list(value.items())
            for i, (hk, hv) in enumerate(items):
                out.append(f"    {d(hk)}: {d(hv)}{',' if i < len(items) - 1 else ''}")
            out.append(f"  }}{comma}")
        elif key in ("entries", "gaps") and isinstance(value, list) and value:
            out.append(f"  {d(key)}: [")
            items = value if isinstance(value, _Lines) else list(map(d, value))
            out += map("    %s,".__mod__, items[:-1])
            out.append(f"    {items[-1]}")
            out.append(f"  ]{comma}")
        elif key == "addresses" and isinstance(value, list) and value:
            out.append('  "addresses": [')
            rows = [value[i:i + _ADDR_PER_LINE] for i in range(0, len(value), _ADDR_PER_LINE)]
            for i, row in enumerate(rows):
                out.append("    " + ", ".join(str(v) for v in row)
                           + ("," if i < len(rows) - 1 else ""))
            out.append(f"  ]{comma}")
        else:
            out.append(f"  {d(key)}: {d(value)}{comma}")
    out.append("}")
    return "\n".join(out) + "\n"


# -- the error of a document that is not a valid dump ---------------------------------------

class JsonProblem(Exception):
    """A document that is not a valid dump; ``path`` is a tuple of keys/indexes."""

    def __init__(self, path: tuple, message: str):
        super().__init__(message)
        self.path = path


def path_text(path: tuple) -> str:
    out = ""
    for p in path:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out or "(document)"
