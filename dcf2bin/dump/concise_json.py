"""The lossless JSON form of a concise DCF (format ``dcf2bin-concise``, version 1; its JSON
Schema is dcf2bin/schemas/dump-concise.json, explained in docs/dump.md): the entries as
stored, in order, each with its data in hex. The count is not written: it is the number of
entries, recomputed when the form is turned back into bytes (``compile FILE.json``), which
gives the same bytes for every concise DCF that reads.

    >>> print(to_json([(0x1017, 0, b"\\x64\\x00")]), end="")
    {
      "format": "dcf2bin-concise",
      "version": 1,
      "entries": [
        {"index": "0x1017", "subindex": 0, "data": "6400"}
      ]
    }
"""
from __future__ import annotations

import json

from dcf2bin.dump.document import _hex, _int, _kind, _obj
from dcf2bin.dump.jsonform import _WORD, JsonProblem, _Lines, format_json
from dcf2bin.schemas import load as load_schema

FORMAT = "dcf2bin-concise"
SCHEMA_VERSION = 1
JSON_SCHEMA = load_schema("dump-concise")

_TOP_KEYS = ["format", "version", "entries"]
_ENTRY_KEYS = ["index", "subindex", "data"]
_ENTRY_JSON = '{"index": "0x%04X", "subindex": %d, "data": "%s"}'


def to_dict(entries) -> dict:
    """The document as Python data (key order is the documented one)."""
    return {"format": FORMAT, "version": SCHEMA_VERSION,
            "entries": [{"index": f"0x{i:04X}", "subindex": s, "data": d.hex().upper()}
                        for i, s, d in entries]}


def to_json(entries) -> str:
    """``to_dict`` as stable, diff-friendly JSON text: one entry per line."""
    doc = to_dict(())
    doc["entries"] = _Lines(_ENTRY_JSON % (i, s, d.hex().upper()) for i, s, d in entries)
    return format_json(doc)


def from_dict(doc) -> list[tuple[int, int, bytes]]:
    """The entries of a document, every key, type and range checked. Raises JsonProblem
    naming the JSON path of the first problem."""
    doc = _obj(doc, (), _TOP_KEYS, _TOP_KEYS)
    if doc["format"] != FORMAT:
        got = json.dumps(doc["format"])[:40]
        raise JsonProblem(("format",), f"expected \"{FORMAT}\", got {got}")
    version = doc["version"]
    if isinstance(version, bool) or not isinstance(version, int):
        raise JsonProblem(("version",), f"expected an integer, got {_kind(version)}")
    if version != SCHEMA_VERSION:
        newer = " (written by a newer dcf2bin?)" if version > SCHEMA_VERSION else ""
        raise JsonProblem(("version",), f"schema version {version} is not supported; this "
                                        f"dcf2bin reads version {SCHEMA_VERSION}{newer}")
    rows = doc["entries"]
    if not isinstance(rows, list):
        raise JsonProblem(("entries",), f"expected an array, got {_kind(rows)}")
    entries = []
    for k, e in enumerate(rows):
        p = ("entries", k)
        e = _obj(e, p, _ENTRY_KEYS, _ENTRY_KEYS)
        entries.append((_int(e["index"], p + ("index",), 0, _WORD, hex_ok=True),
                        _int(e["subindex"], p + ("subindex",), 0, 0xFF, hex_ok=True),
                        _hex(e["data"], p + ("data",))))
    return entries


__all__ = ["FORMAT", "JSON_SCHEMA", "SCHEMA_VERSION", "from_dict", "to_dict", "to_json"]
