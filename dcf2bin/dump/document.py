"""A parsed JSON document -> a ``BinContainer`` (``from_dict``): every key, type and range is
checked, and a problem is a ``JsonProblem`` naming its JSON path.
"""
from __future__ import annotations

import json
import re
from dataclasses import dataclass

from dcf2bin import schema
from dcf2bin.container import BinContainer
from dcf2bin.diagnostics import shorten
from dcf2bin.dump.jsonform import (_DWORD, _HEADER_MAX, _WORD, CANONICAL, FORMAT, HEADER_FIELDS,
                                   JsonProblem, PIPARAM_FIELDS, SCHEMA_VERSION, STORED)


def _int(value, path: tuple, lo: int, hi: int, *, hex_ok: bool = False) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, str)):
        raise JsonProblem(path, f"expected an integer, got {_kind(value)}")
    if isinstance(value, str):
        if not hex_ok or not re.fullmatch(r"0[xX][0-9A-Fa-f]+", value):
            raise JsonProblem(path, f"expected an integer{' or 0x... hex string' if hex_ok else ''}"
                                    f", got {json.dumps(value)[:40]}")
        value = int(value, 16)
    if not lo <= value <= hi:
        raise JsonProblem(path, f"{value} is outside {lo}..{hi}")
    return value


def _hex(value, path: tuple) -> bytes:
    if not isinstance(value, str):
        raise JsonProblem(path, f"expected a hex string, got {_kind(value)}")
    if len(value) % 2:
        raise JsonProblem(path, f"odd number of hex digits ({len(value)})")
    if not value.isascii() or not all(ch in "0123456789abcdefABCDEF" for ch in value):
        bad = next(ch for ch in value if ch not in "0123456789abcdefABCDEF")
        raise JsonProblem(path, f"invalid character {bad!r} in hex data")
    return bytes.fromhex(value)


def _kind(value) -> str:
    if value is None:
        return "null"
    return {bool: "a boolean", int: "a number", float: "a number", str: "a string",
            list: "an array", dict: "an object"}.get(type(value), type(value).__name__)


def _obj(value, path: tuple, allowed: list[str], required: list[str]) -> dict:
    if not isinstance(value, dict):
        raise JsonProblem(path, f"expected an object, got {_kind(value)}")
    for key in value:
        if key not in allowed:
            raise JsonProblem(path + (key,), f"unknown key '{shorten(key)}' (expected one of "
                                              f"{', '.join(allowed)})")
    for key in required:
        if key not in value:
            raise JsonProblem(path, f"missing key '{key}'")
    return value


_TOP_KEYS = ["format", "version", "layout", "header", "entries", "extra_attributes",
             "addresses", "pi_parameters", "gaps"]
_ENTRY_KEYS = ["index", "subindex", "data", "attribute"]


@dataclass
class Parsed:
    container: BinContainer
    layout: str
    header: dict[str, int] | None      # as given in the document


def from_dict(doc) -> Parsed:
    """Check a document and turn it into a container model. Raises JsonProblem."""
    # "schema_version" is what dcf2bin wrote before "version": old dumps still compile
    old_name = isinstance(doc, dict) and "schema_version" in doc
    allowed = _TOP_KEYS + ["schema_version"] if old_name else _TOP_KEYS
    doc = _obj(doc, (), allowed, ["format", "entries"])
    if doc["format"] != FORMAT:
        got = json.dumps(doc["format"])[:40]
        raise JsonProblem(("format",), f"expected \"{FORMAT}\", got {got}")
    if "version" in doc and "schema_version" in doc:
        raise JsonProblem(("schema_version",), "both 'version' and 'schema_version' (the old "
                                               "name of 'version'): give one")
    vkey = "version" if "version" in doc else "schema_version"
    if vkey not in doc:
        raise JsonProblem((), "missing key 'version'")
    version = doc[vkey]
    if isinstance(version, bool) or not isinstance(version, int):
        raise JsonProblem((vkey,), f"expected an integer, got {_kind(version)}")
    if version != SCHEMA_VERSION:
        newer = " (written by a newer dcf2bin?)" if version > SCHEMA_VERSION else ""
        raise JsonProblem((vkey,),
                          f"schema version {version} is not supported; this dcf2bin reads "
                          f"version {SCHEMA_VERSION}{newer}")
    layout = doc.get("layout", CANONICAL)
    if layout not in (CANONICAL, STORED):
        raise JsonProblem(("layout",), f"expected \"{CANONICAL}\" or \"{STORED}\", got "
                                       f"{json.dumps(layout)[:40]}")
    header = None
    if "header" in doc:
        hdoc = _obj(doc["header"], ("header",), HEADER_FIELDS, HEADER_FIELDS)
        header = {k: _int(hdoc[k], ("header", k), 0, _HEADER_MAX[k]) for k in HEADER_FIELDS}
    elif layout == STORED:
        raise JsonProblem((), "missing key 'header' (required by layout \"stored\")")

    entries_doc = doc["entries"]
    if not isinstance(entries_doc, list):
        raise JsonProblem(("entries",), f"expected an array, got {_kind(entries_doc)}")
    entries = []
    attrs = bytearray()
    missing_from = None
    for i, e in enumerate(entries_doc):
        p = ("entries", i)
        e = _obj(e, p, _ENTRY_KEYS, _ENTRY_KEYS)
        index = _int(e["index"], p + ("index",), 0, _WORD, hex_ok=True)
        sub = _int(e["subindex"], p + ("subindex",), 0, 0xFF, hex_ok=True)
        data = _hex(e["data"], p + ("data",))
        attr = e["attribute"]
        if attr is None:
            if missing_from is None:
                missing_from = i
        else:
            attr = _int(attr, p + ("attribute",), 0, 0xFF, hex_ok=True)
            if missing_from is not None:
                raise JsonProblem(p + ("attribute",), f"entry {i} has an attribute but entry "
                                  f"{missing_from} has none: the extended info segment holds "
                                  "one byte per entry from the first")
            attrs.append(attr)
        entries.append((index, sub, data))
    extra = _hex(doc.get("extra_attributes", ""), ("extra_attributes",))
    if extra and missing_from is not None:
        raise JsonProblem(("extra_attributes",), f"extra attribute bytes, but entry "
                                                 f"{missing_from} has no attribute")
    attrs += extra

    addresses = doc.get("addresses")
    if addresses is not None:
        if not isinstance(addresses, list):
            raise JsonProblem(("addresses",), f"expected an array or null, got {_kind(addresses)}")
        addresses = [_int(a, ("addresses", i), 0, _WORD) for i, a in enumerate(addresses)]

    pi = raw_pi = None
    pdoc = doc.get("pi_parameters")
    if pdoc is not None:
        if isinstance(pdoc, dict) and "raw" in pdoc:
            _obj(pdoc, ("pi_parameters",), ["raw"], ["raw"])
            raw = _hex(pdoc["raw"], ("pi_parameters", "raw"))
            if len(raw) == schema.PIPARAMS.size:
                pi = schema.PIPARAMS.unpack(raw)
            elif raw:
                raw_pi = raw
        else:
            pdoc = _obj(pdoc, ("pi_parameters",), PIPARAM_FIELDS, PIPARAM_FIELDS)
            pi = tuple(_int(pdoc[k], ("pi_parameters", k), 0, _DWORD) for k in PIPARAM_FIELDS)

    gaps = []
    gdoc = doc.get("gaps", [])
    if not isinstance(gdoc, list):
        raise JsonProblem(("gaps",), f"expected an array, got {_kind(gdoc)}")
    for i, g in enumerate(gdoc):
        g = _obj(g, ("gaps", i), ["offset", "data"], ["offset", "data"])
        gaps.append((_int(g["offset"], ("gaps", i, "offset"), 0, _DWORD),
                     _hex(g["data"], ("gaps", i, "data"))))
    if gaps and layout != STORED:
        raise JsonProblem(("gaps",), "gaps are only possible with layout \"stored\"")

    c = BinContainer(entries=entries, attributes=bytes(attrs) if (attrs or entries_doc) else None,
                     addresses=addresses or None, pi=pi,
                     version=header["version"] if header else 1, raw_piparam=raw_pi)
    if addresses == []:
        c.addresses = None
    if layout == STORED:
        c.header = header
        c.gaps = gaps
    return Parsed(c, layout, header)
