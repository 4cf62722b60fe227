"""Containers as text: the lossless JSON form and the readable report (SPEC.md §4).

``to_dict``/``to_json`` turn a ``BinContainer`` into the lossless JSON document
(format ``dcf2bin-container``, schema version ``SCHEMA_VERSION``, documented in
docs/dump.md and as ``JSON_SCHEMA`` below); ``from_dict``/``from_json_bytes`` turn it
back into a container whose bytes are exactly the ones that were dumped, for every
container ``container.read`` accepts (odd headers, gaps, any version, a PI parameter
segment of the wrong size). ``report`` renders the readable text report.

Derived fields are never trusted from a JSON document: in the ``canonical`` layout the
header is recomputed from the segments (a stale value is a warning); in the ``stored``
layout the header is used as given and must describe the segments exactly.
"""
from __future__ import annotations

import functools
import json
import re
from dataclasses import dataclass

from dcf2bin import datatypes as dt
from dcf2bin import schema, values
from dcf2bin.layout import table_channel
from dcf2bin.container import BinContainer, ContainerError, read as read_container
from dcf2bin.diagnostics import Diagnostic, Severity

FORMAT = "dcf2bin-container"
SCHEMA_VERSION = 1
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

# JSON Schema (draft 2020-12) of the document ``to_dict`` writes; docs/dump.md explains it.
_HEX = {"type": "string", "pattern": "^([0-9A-Fa-f]{2})*$"}
_U32 = {"type": "integer", "minimum": 0, "maximum": _DWORD}
JSON_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$id": "https://dcf2bin.invalid/schema/dcf2bin-container-1.json",
    "title": "dcf2bin lossless container dump",
    "type": "object",
    "required": ["format", "schema_version", "entries"],
    "additionalProperties": False,
    "properties": {
        "format": {"const": FORMAT},
        "schema_version": {"const": SCHEMA_VERSION},
        "layout": {"enum": [CANONICAL, STORED]},
        "header": {
            "type": "object", "additionalProperties": False,
            "required": HEADER_FIELDS,
            "properties": {name: {"type": "integer", "minimum": 0, "maximum": mx}
                           for name, mx in _HEADER_MAX.items()},
        },
        "entries": {
            "type": "array",
            "items": {
                "type": "object", "additionalProperties": False,
                "required": ["index", "subindex", "data", "attribute"],
                "properties": {
                    "index": {"type": "string", "pattern": "^0x[0-9A-Fa-f]{1,4}$"},
                    "subindex": {"type": "integer", "minimum": 0, "maximum": 255},
                    "data": _HEX,
                    "attribute": {"oneOf": [{"type": "null"}, {
                        "type": "string", "pattern": "^0x[0-9A-Fa-f]{1,2}$"}]},
                },
            },
        },
        "extra_attributes": _HEX,
        "addresses": {"oneOf": [{"type": "null"}, {
            "type": "array", "items": {"type": "integer", "minimum": 0, "maximum": _WORD}}]},
        "pi_parameters": {"oneOf": [
            {"type": "null"},
            {"type": "object", "additionalProperties": False, "required": PIPARAM_FIELDS,
             "properties": {name: _U32 for name in PIPARAM_FIELDS}},
            {"type": "object", "additionalProperties": False, "required": ["raw"],
             "properties": {"raw": _HEX}},
        ]},
        "gaps": {"type": "array", "items": {
            "type": "object", "additionalProperties": False, "required": ["offset", "data"],
            "properties": {"offset": _U32, "data": _HEX}}},
    },
}


# -- reading a container robustly -----------------------------------------------------------

def read_bytes(data: bytes, name: str) -> tuple[BinContainer | None, list[Diagnostic]]:
    """``container.read`` with its error as one diagnostic naming the byte offset."""
    try:
        c, warnings = read_container(data)
    except ContainerError as exc:
        return None, [Diagnostic(Severity.ERROR, str(exc), name, offset=exc.offset,
                                 rule=exc.rule)]
    return c, [Diagnostic(d.severity, d.message, name, d.line, d.column, d.offset, d.rule,
                          d.hint) for d in warnings]


def header_of(c: BinContainer) -> dict[str, int]:
    """The header as stored (odd layouts) or as ``to_bytes`` builds it."""
    return dict(c.header) if c.header is not None else c.canonical_header()


def entry_offsets(c: BinContainer, header: dict[str, int] | None = None) -> list[int]:
    """Byte offset of each index entry (its WORD index) from the container's start."""
    h = header or header_of(c)
    pos = h["index_offset"] + schema.COUNT.size
    head = schema.ENTRY_HEAD.size
    out = []
    append = out.append
    for _, _, data in c.entries:
        append(pos)
        pos += head + len(data)
    return out


# -- container -> JSON ----------------------------------------------------------------------

def to_dict(c: BinContainer) -> dict:
    """The lossless document as Python data (key order is the documented one)."""
    h = header_of(c)
    attrs = c.attributes or b""
    n = len(c.entries)
    entries = []
    for i, (index, sub, data) in enumerate(c.entries):
        entries.append({"index": f"0x{index:04X}", "subindex": sub, "data": data.hex().upper(),
                        "attribute": f"0x{attrs[i]:02X}" if i < len(attrs) else None})
    if c.raw_piparam is not None:
        pi = {"raw": c.raw_piparam.hex().upper()}
    elif c.pi is not None:
        pi = dict(zip(PIPARAM_FIELDS, c.pi))
    else:
        pi = None
    return {
        "format": FORMAT,
        "schema_version": SCHEMA_VERSION,
        "layout": STORED if c.header is not None else CANONICAL,
        "header": {k: h[k] for k in HEADER_FIELDS},
        "entries": entries,
        "extra_attributes": attrs[n:].hex().upper(),
        "addresses": list(c.addresses) if c.addresses is not None else None,
        "pi_parameters": pi,
        "gaps": [{"offset": off, "data": data.hex().upper()} for off, data in c.gaps],
    }


def to_json(c: BinContainer) -> str:
    """``to_dict`` as stable, diff-friendly JSON text: one entry per line."""
    return format_json(to_dict(c))


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
            last = len(value) - 1
            for i, item in enumerate(value):
                out.append(f"    {d(item)}{',' if i < last else ''}")
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


# -- JSON -> container ----------------------------------------------------------------------

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
            raise JsonProblem(path + (key,), f"unknown key '{key}' (expected one of "
                                              f"{', '.join(allowed)})")
    for key in required:
        if key not in value:
            raise JsonProblem(path, f"missing key '{key}'")
    return value


_TOP_KEYS = ["format", "schema_version", "layout", "header", "entries", "extra_attributes",
             "addresses", "pi_parameters", "gaps"]
_ENTRY_KEYS = ["index", "subindex", "data", "attribute"]


@dataclass
class Parsed:
    container: BinContainer
    layout: str
    header: dict[str, int] | None      # as given in the document


def from_dict(doc) -> Parsed:
    """Check a document and turn it into a container model. Raises JsonProblem."""
    doc = _obj(doc, (), _TOP_KEYS, ["format", "schema_version", "entries"])
    if doc["format"] != FORMAT:
        got = json.dumps(doc["format"])[:40]
        raise JsonProblem(("format",), f"expected \"{FORMAT}\", got {got}")
    version = doc["schema_version"]
    if isinstance(version, bool) or not isinstance(version, int):
        raise JsonProblem(("schema_version",), f"expected an integer, got {_kind(version)}")
    if version != SCHEMA_VERSION:
        newer = " (written by a newer dcf2bin?)" if version > SCHEMA_VERSION else ""
        raise JsonProblem(("schema_version",),
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


def build(parsed: Parsed) -> tuple[bytes, list[tuple[tuple, str]]]:
    """The container's bytes, and warnings as (path, message). Raises JsonProblem."""
    c = parsed.container
    warnings: list[tuple[tuple, str]] = []
    if parsed.layout == CANONICAL:
        if len(c.index_bytes()) > _DWORD - schema.HEADER_SIZE:
            raise JsonProblem(("entries",), "the entries do not fit a container (4 GiB)")
        canon = c.canonical_header()
        if parsed.header is not None:
            for k in HEADER_FIELDS:
                if parsed.header[k] != canon[k]:
                    warnings.append((("header", k), f"{parsed.header[k]} is recomputed as "
                                                    f"{canon[k]} (layout \"canonical\")"))
        data = c.to_bytes()
    else:
        data = _build_stored(c)
    return data, warnings


def _build_stored(c: BinContainer) -> bytes:
    h = c.header
    segs = c.segments()
    for name in schema.SEGMENTS:
        size = h[f"{name}_size"]
        if len(segs[name]) != size:
            what = {"index": "entries", "address": "addresses", "extinfo": "entries",
                    "piparam": "pi_parameters"}[name]
            raise JsonProblem(("header", f"{name}_size"),
                              f"{size}, but the {what} make {len(segs[name])} bytes of the "
                              f"{name} segment")
    covered = schema.HEADER_SIZE + sum(len(s) for s in segs.values()) + \
        sum(len(g) for _, g in c.gaps)
    if h["total_size"] != covered:
        # checked before anything is allocated from the document's total_size
        raise JsonProblem(("header", "total_size"),
                          f"{h['total_size']}, but the header, segments and gaps make "
                          f"{covered} bytes")
    spans = []
    for name in schema.SEGMENTS:
        off, size = h[f"{name}_offset"], h[f"{name}_size"]
        if size:
            spans.append((off, off + size, ("header", f"{name}_offset")))
    for i, (off, g) in enumerate(c.gaps):
        if g:
            spans.append((off, off + len(g), ("gaps", i, "offset")))
    spans.sort()
    pos = schema.HEADER_SIZE
    for start, end, path in spans:
        if start < pos:
            raise JsonProblem(path, f"{start}: bytes [{start}, {end}) overlap the header, a "
                                    f"segment or a gap ending at {pos}")
        if start > pos:
            raise JsonProblem(path, f"{start}: bytes [{pos}, {start}) are covered by no "
                                    "segment and no gap")
        pos = end
    try:
        data = c.to_bytes()
    except ContainerError as exc:  # defensive: the checks above should catch everything
        raise JsonProblem(("header",), str(exc)) from None
    try:
        back, _ = read_container(data)
    except ContainerError as exc:
        raise JsonProblem(("header",), f"the stored layout is not a readable container: "
                                       f"{exc} (at byte 0x{exc.offset:X})") from None
    if back.gaps != [g for g in c.gaps if g[1]]:
        raise JsonProblem(("gaps",), "the gaps do not match the bytes between the segments")
    return data


def from_json_bytes(data: bytes, name: str) -> tuple[bytes | None, list[Diagnostic]]:
    """A lossless JSON dump -> the container's bytes (None on errors) and diagnostics."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        return None, [Diagnostic(Severity.ERROR, f"not UTF-8 (byte 0x{data[exc.start]:02X})",
                                 name, line, rule=RULE_JSON_SYNTAX)]
    try:
        doc = json.loads(text, object_pairs_hook=_no_duplicates, parse_constant=_no_constant)
    except json.JSONDecodeError as exc:
        return None, [Diagnostic(Severity.ERROR, f"invalid JSON: {exc.msg}", name, exc.lineno,
                                 exc.colno, rule=RULE_JSON_SYNTAX)]
    except _DuplicateKey as exc:
        return None, [Diagnostic(Severity.ERROR, f"key '{exc.key}' repeated in one object",
                                 name, _line_of_key(text, exc.key), rule=RULE_JSON_SYNTAX)]
    except ValueError as exc:       # NaN/Infinity, or an integer literal too long
        return None, [Diagnostic(Severity.ERROR, f"invalid JSON: {exc}", name,
                                 rule=RULE_JSON_SYNTAX)]
    except RecursionError:
        return None, [Diagnostic(Severity.ERROR, "invalid JSON: nested too deeply", name,
                                 rule=RULE_JSON_SYNTAX)]
    try:
        parsed = from_dict(doc)
        out, warnings = build(parsed)
    except JsonProblem as exc:
        return None, [_json_diag(Severity.ERROR, text, name, exc.path, str(exc))]
    return out, [_json_diag(Severity.WARNING, text, name, p, m, RULE_JSON_HEADER)
                 for p, m in warnings]


class _DuplicateKey(Exception):
    def __init__(self, key: str):
        self.key = key


def _no_duplicates(pairs):
    out = {}
    for k, v in pairs:
        if k in out:
            raise _DuplicateKey(k)
        out[k] = v
    return out


def _no_constant(name: str):
    raise ValueError(f"{name} is not a number here")


def _line_of_key(text: str, key: str) -> int | None:
    needle = json.dumps(key)
    first = text.find(needle)
    second = text.find(needle, first + 1) if first >= 0 else -1
    return text.count("\n", 0, second) + 1 if second >= 0 else None


def _json_diag(severity: Severity, text: str, name: str, path: tuple, message: str,
               rule: str = RULE_JSON) -> Diagnostic:
    pos = locate(text, path)
    line = text.count("\n", 0, pos) + 1 if pos is not None else None
    return Diagnostic(severity, f"{path_text(path)}: {message}", name, line, rule=rule)


# -- where is a JSON path? (only used to report an error) --------------------------------------

_WS_RE = re.compile(r"[ \t\n\r]*")
_ATOM_RE = re.compile(r"-?(?:0|[1-9][0-9]*)(?:\.[0-9]+)?(?:[eE][-+]?[0-9]+)?|true|false|null")


class _Found(Exception):
    def __init__(self, pos: int):
        self.pos = pos


def locate(text: str, path: tuple) -> int | None:
    """Character position of the value at ``path`` in a valid JSON text (None if absent).

    For a missing key the enclosing object's position is returned.
    """
    from json.decoder import scanstring
    best = [None]

    def ws(pos: int) -> int:
        return _WS_RE.match(text, pos).end()

    def value(pos: int, at: tuple) -> int:
        pos = ws(pos)
        if at == path[:len(at)]:
            best[0] = pos
            if at == path:
                raise _Found(pos)
        ch = text[pos]
        if ch == "{":
            pos = ws(pos + 1)
            if text[pos] == "}":
                return pos + 1
            while True:
                key, pos = scanstring(text, ws(pos) + 1)
                pos = ws(pos) + 1              # ':'
                pos = ws(value(pos, at + (key,)))
                if text[pos] == "}":
                    return pos + 1
                pos += 1                       # ','
        if ch == "[":
            pos = ws(pos + 1)
            if text[pos] == "]":
                return pos + 1
            i = 0
            while True:
                pos = ws(value(pos, at + (i,)))
                i += 1
                if text[pos] == "]":
                    return pos + 1
                pos += 1
        if ch == '"':
            return scanstring(text, pos + 1)[1]
        return _ATOM_RE.match(text, pos).end()

    try:
        value(0, ())
    except _Found as f:
        return f.pos
    except (IndexError, ValueError, AttributeError, RecursionError):
        return best[0]
    return best[0]


# -- the readable report ----------------------------------------------------------------------

_SEGMENT_TITLES = {"index": "index segment", "address": "PI address segment",
                   "extinfo": "extended info segment", "piparam": "PI parameter segment"}
_DATA_SHOWN = 16     # bytes of data shown before "..." unless --full


@dataclass
class EdsInfo:
    """Names and exact types from an EDS (``--eds``); see ``load_eds``."""
    entries: dict          # (index, sub) -> model.Entry
    objects: dict          # index -> model.Obj

    def name(self, index: int, sub: int) -> str:
        e = self.entries.get((index, sub))
        if e is not None and e.name:
            return e.name
        o = self.objects.get(index)
        return o.name if o is not None and sub == 0 and o.name else ""

    def dtype(self, index: int, sub: int):
        e = self.entries.get((index, sub))
        return e.dtype if e is not None else None


def load_eds(path: str, data: bytes | None = None) -> tuple[EdsInfo, object, int]:
    """Load an EDS with ``model.load`` -> (EdsInfo, Device, number of errors in it)."""
    from dcf2bin import model
    dev = model.load(path, data=data)
    entries = {}
    for idx, obj in dev.objects.items():
        for sub, e in obj.entries.items():
            entries[(idx, sub)] = e
    errors = sum(1 for p in dev.problems if p.diagnostic.severity is Severity.ERROR)
    return EdsInfo(entries, dev.objects), dev, errors


def eds_warnings(path: str, errors: int) -> list[Diagnostic]:
    """The warning for an ``--eds`` with ``errors`` errors in it (none for none)."""
    if not errors:
        return []
    return [Diagnostic(Severity.WARNING, f"the EDS has {errors} error"
                       f"{'s' if errors != 1 else ''} (see 'dcf2bin validate'); types and "
                       "names are taken where they could be read", path)]


_FLAGS = [dt.attr_flags(a) for a in range(256)]


def nv_type(index: int, sub: int, size: int, eds: EdsInfo | None = None):
    """The DataType of a network variable: the EDS's, else its CiA 405 range's, if the size fits."""
    if not 0xA000 <= index <= 0xAFFF or sub == 0:
        return None
    if eds is not None:
        t = eds.dtype(index, sub)
        if t is not None and t.size == size:
            return t
    return _range_type(index, size)


@functools.lru_cache(maxsize=4096)
def _range_type(index: int, size: int):
    ch = table_channel(index)
    if ch is not None and ch.dtype.size == size:
        return ch.dtype
    return None


def value_text(index: int, sub: int, data: bytes, attr: int | None,
               eds: EdsInfo | None = None, full: bool = False) -> str:
    """The decoded value where the type (EDS, CiA 405 range) or attribute and size say how."""
    size = len(data)
    t = eds.dtype(index, sub) if eds is not None else None
    if t is not None and t.size is not None and t.size != size:
        t = None
    if t is None:
        t = nv_type(index, sub, size)
    if t is None and attr is not None:
        kinds = attr & dt.ATTR_TYPE_MASK
        if kinds == dt.ATTR_BOOLEAN and size == 1:
            t = dt.BOOLEAN
        elif kinds == dt.ATTR_VSTRING:
            t = dt.VISIBLE_STRING
        elif kinds == dt.ATTR_NUMERIC and size in dt.UNSIGNED_BY_SIZE:
            t = dt.UNSIGNED_BY_SIZE[size]
    if t is None:
        return ""
    if t.kind == dt.BOOL:
        return {0: "FALSE", 1: "TRUE"}.get(data[0], f"0x{data[0]:02X}") if size == 1 else ""
    if t.kind in (dt.VSTRING, dt.USTRING):
        text = values.to_python(t, data)
        shown = json.dumps(text, ensure_ascii=False)
        if not full and len(shown) > 34:
            shown = shown[:30] + '..."'
        return shown
    if t.kind in (dt.OSTRING, dt.DOMAIN):
        return ""
    try:
        v = values.to_python(t, data)
    except values.ValueProblem:
        return ""
    if t.kind == dt.REAL:
        return values.decode(t, data) or repr(v)
    if t.kind == dt.SINT or size <= 2:
        return str(v)
    text = f"0x{v:0{2 * size}X}"
    if size == 4 and sub >= 1 and (0x1600 <= index <= 0x17FF or 0x1A00 <= index <= 0x1BFF):
        text += f" = {v >> 16:04X}sub{(v >> 8) & 0xFF:X}, {v & 0xFF} bits"
    elif size == 4 and sub == 1 and (0x1400 <= index <= 0x15FF or 0x1800 <= index <= 0x19FF):
        text += f" = COB-ID 0x{v & 0x1FFFFFFF:X}{', invalid' if v & 0x80000000 else ''}"
    return text


def _short_hex(data: bytes, full: bool) -> str:
    if full or len(data) <= _DATA_SHOWN:
        return data.hex().upper()
    return data[:_DATA_SHOWN - 4].hex().upper() + "..." + data[-2:].hex().upper()


def nv_keys(c: BinContainer) -> list[tuple[int, int]]:
    """Network variables in index-segment order, first occurrence (SPEC §3.4)."""
    seen = set()
    out = []
    for index, sub, _ in c.entries:
        if 0xA000 <= index <= 0xAFFF and sub >= 1 and (index, sub) not in seen:
            seen.add((index, sub))
            out.append((index, sub))
    return out


def header_notes(c: BinContainer, h: dict[str, int], nvs: int) -> dict[str, str]:
    """Where the header disagrees with the segments (or with D-5...D-7): field -> note."""
    notes: dict[str, str] = {}
    if h["version"] != 1:
        notes["version"] = "not the default 1"
    present = sum(1 for name in schema.SEGMENTS if h[f"{name}_size"])
    if h["segment_count"] != present:
        notes["segment_count"] = f"{present} segments are present"
    # read() checked that every segment's bytes are what its header slot says
    canon = schema.HEADER_SIZE + sum(h[f"{name}_size"] for name in schema.SEGMENTS)
    if h["total_size"] != canon:
        notes["total_size"] = f"header + segments = {canon}; {h['total_size'] - canon} bytes " \
                              "belong to no segment"
    spans = sorted((h[f"{n}_offset"], n) for n in schema.SEGMENTS if h[f"{n}_size"])
    order = [n for _, n in spans]
    if order != [n for n in schema.SEGMENTS if n in order]:
        notes["order"] = "segments are not in the header's order"
    for name in schema.SEGMENTS:
        if not h[f"{name}_size"] and h[f"{name}_offset"]:
            notes[f"{name}_offset"] = "an empty segment should have offset 0"
    n = len(c.entries)
    if len(c.attributes or b"") != n:
        notes["extinfo_size"] = f"{_count(len(c.attributes or b''), 'attribute byte')} for " \
                                f"{_count(n, 'entry', 'entries')}"
    if c.raw_piparam is not None:
        notes["piparam_size"] = "a PI parameter segment has 20 bytes"
    n_addr = len(c.addresses or [])
    if n_addr != nvs:
        notes["address_size"] = f"{_count(n_addr, 'address', 'addresses')} for " \
                                f"{_count(nvs, 'network variable')}"
    return notes


def _count(n: int, one: str, many: str | None = None) -> str:
    return f"{n} {one if n == 1 else (many or one + 's')}"


def report(c: BinContainer, name: str, *, eds: EdsInfo | None = None,
           full: bool = False) -> str:
    """The readable text report (``dcf2bin dump --format text``)."""
    h = header_of(c)
    size = h["total_size"]
    nvs = nv_keys(c)
    notes = header_notes(c, h, len(nvs))
    out: list[str] = []
    w = out.append
    layout = "canonical layout" if c.header is None else "stored layout (not canonical)"
    w(f"{name}: binary DCF segment container, {size} bytes, {layout}")
    w("")
    w(f"Header ({schema.HEADER_SIZE} bytes)")

    def note(key: str) -> str:
        return f"  ! {notes[key]}" if key in notes else ""

    w(f"  0x00  total size     {h['total_size']:<10}{note('total_size')}".rstrip())
    w(f"  0x04  version        {h['version']:<10}{note('version')}".rstrip())
    w(f"  0x06  segment count  {h['segment_count']:<10}{note('segment_count')}".rstrip())
    for i, seg in enumerate(schema.SEGMENTS):
        off, sz = h[f"{seg}_offset"], h[f"{seg}_size"]
        msg = note(f"{seg}_offset") or note(f"{seg}_size")
        span = f"bytes {off}..{off + sz - 1}" if sz else "absent"
        w(f"  0x{8 + 8 * i:02X}  {_SEGMENT_TITLES[seg]:<22} offset {off:<6} size {sz:<6} "
          f"{span}{msg}".rstrip())
    if "order" in notes:
        w(f"  ! {notes['order']}")

    # -- index segment
    attrs = c.attributes or b""
    offsets = entry_offsets(c, h)
    n = len(c.entries)
    w("")
    w(f"Index segment: {n} entr{'y' if n == 1 else 'ies'}")
    if n:
        rows = []
        counts: dict[tuple[int, int], int] = {}
        for index, sub, _ in c.entries:
            counts[(index, sub)] = counts.get((index, sub), 0) + 1
        seen: dict[tuple[int, int], int] = {}
        for i, (index, sub, data) in enumerate(c.entries):
            attr = attrs[i] if i < len(attrs) else None
            key = (index, sub)
            seen[key] = seen.get(key, 0) + 1
            rep = f"{seen[key]}/{counts[key]}" if counts[key] > 1 else ""
            rows.append((str(i + 1), f"0x{offsets[i]:X}", f"0x{index:04X}", str(sub),
                         str(len(data)), _short_hex(data, full),
                         value_text(index, sub, data, attr, eds, full),
                         f"0x{attr:02X}" if attr is not None else "-",
                         _FLAGS[attr] if attr is not None else "-", rep))
        head = ("#", "offset", "index", "sub", "size", "data", "value", "attr", "flags", "write")
        out.extend(_table(head, rows, right={0, 3, 4}))
    if len(attrs) > n:
        w(f"  ! {_count(len(attrs) - n, 'attribute byte')} without an entry: "
          f"{_short_hex(attrs[n:], full)}")

    # -- process image
    w("")
    addrs = c.addresses
    if addrs is None:
        w(f"PI address segment: absent ({_count(len(nvs), 'network variable')})")
    else:
        w(f"PI address segment: {_count(len(addrs), 'address', 'addresses')}, "
          f"{_count(len(nvs), 'network variable')}"
          + ("  ! they should match" if "address_size" in notes else ""))
        pi = c.pi
        first: dict[tuple[int, int], bytes] = {}
        for index, sub, d in c.entries:
            first.setdefault((index, sub), d)
        rows = []
        for k in range(max(len(addrs), len(nvs))):
            a = addrs[k] if k < len(addrs) else None
            key = nvs[k] if k < len(nvs) else None
            area, off = _area_of(a, pi) if a is not None else ("", "")
            data = first[key] if key is not None else None
            t = nv_type(key[0], key[1], len(data), eds) if key is not None else None
            rows.append((str(k + 1),
                         f"0x{a:04X}" if a is not None else "-", area, str(off),
                         f"0x{key[0]:04X}" if key else "-", str(key[1]) if key else "-",
                         str(len(data)) if data is not None else "-",
                         t.name if t is not None else "-",
                         eds.name(*key) if eds is not None and key else ""))
        if rows:
            head = ("#", "address", "area", "offset", "index", "sub", "size", "type", "name")
            out.extend(_table(head, rows, right={0, 3, 5, 6}))

    w("")
    if c.raw_piparam is not None:
        w(f"PI parameter segment: {len(c.raw_piparam)} bytes (expected 20): "
          f"{_short_hex(c.raw_piparam, full)}")
    elif c.pi is None:
        w("PI parameter segment: absent")
    else:
        total, in_off, in_size, out_off, out_size = c.pi
        w("PI parameter segment")
        pnotes = _pi_notes(c.pi)
        w(f"  complete size  {total:<8}{pnotes.get('total', '')}".rstrip())
        for label, off, sz, key in (("input area ", in_off, in_size, "input"),
                                    ("output area", out_off, out_size, "output")):
            span = f"bytes {off}..{off + sz - 1}" if sz else "empty"
            w(f"  {label}    offset {off:<6} size {sz:<6} {span}{pnotes.get(key, '')}")

    if c.gaps:
        w("")
        w("Bytes in no segment")
        for off, data in c.gaps:
            w(f"  0x{off:X}  {len(data)} bytes  {_short_hex(data, full)}")
    return "\n".join(out) + "\n"


def _pi_notes(pi) -> dict[str, str]:
    total, in_off, in_size, out_off, out_size = pi
    notes = {}
    end = max(in_off + in_size, out_off + out_size)
    if total < end:
        notes["total"] = f"  ! the areas end at {end}"
    if in_size and out_size and in_off < out_off + out_size and out_off < in_off + in_size:
        notes["output"] = "  ! overlaps the input area"
    elif out_size and out_off % 8 and out_off >= in_off + in_size:
        notes["output"] = "  (not 8-aligned: --pi-align?)"
    return notes


def _area_of(addr: int, pi) -> tuple[str, int | str]:
    if pi is None:
        return "", ""
    _, in_off, in_size, out_off, out_size = pi
    if in_off <= addr < in_off + in_size:
        return "input", addr - in_off
    if out_off <= addr < out_off + out_size:
        return "output", addr - out_off
    return "outside", ""


def _table(head: tuple, rows: list[tuple], right: set[int]) -> list[str]:
    widths = [len(h) for h in head]
    for col, cells in enumerate(zip(*rows)):
        widths[col] = max(widths[col], max(map(len, cells)))
    fmt = "  " + "  ".join(f"{{{i}:{'>' if i in right else '<'}{w}}}"
                           for i, w in enumerate(widths))
    return [fmt.format(*head).rstrip()] + [fmt.format(*r).rstrip() for r in rows]
