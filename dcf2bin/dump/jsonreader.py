"""JSON text -> container bytes with diagnostics (``from_json_bytes``): strict JSON (no
repeated key, no NaN), then ``document.from_dict`` and ``rebuild.build`` -- or, for the JSON
form of a concise DCF (``"format": "dcf2bin-concise"``), ``concise_json.from_dict`` and the
concise DCF's bytes; a problem's JSON path is turned into the line it is on (``locate``).
"""
from __future__ import annotations

import json
import re

from dcf2bin import concise
from dcf2bin.diagnostics import Diagnostic, Severity, shorten
from dcf2bin.dump import concise_json
from dcf2bin.dump.document import from_dict
from dcf2bin.dump.jsonform import (JsonProblem, path_text, RULE_JSON, RULE_JSON_HEADER,
                                   RULE_JSON_SYNTAX)
from dcf2bin.dump.rebuild import build


def from_json_bytes(data: bytes, name: str) -> tuple[bytes | None, list[Diagnostic]]:
    """A lossless JSON dump -> the bytes of the container or concise DCF it records (None on
    errors) and diagnostics."""
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
        return None, [Diagnostic(Severity.ERROR, f"key '{shorten(exc.key)}' repeated in one object",
                                 name, _line_of_key(text, exc.key), rule=RULE_JSON_SYNTAX)]
    except ValueError as exc:       # NaN/Infinity, or an integer literal too long
        return None, [Diagnostic(Severity.ERROR, f"invalid JSON: {exc}", name,
                                 rule=RULE_JSON_SYNTAX)]
    except RecursionError:
        return None, [Diagnostic(Severity.ERROR, "invalid JSON: nested too deeply", name,
                                 rule=RULE_JSON_SYNTAX)]
    try:
        if isinstance(doc, dict) and doc.get("format") == concise_json.FORMAT:
            return concise.to_bytes(concise_json.from_dict(doc)), []
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
