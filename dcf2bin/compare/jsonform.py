"""The JSON form of a comparison (format ``dcf2bin-diff``, schema
``dcf2bin/schemas/diff.json``), in the convention of every dcf2bin JSON output: indexes
``"0x1017"``, sub-indexes integers, data bytes upper-case hex, unknown values null.
"""
from __future__ import annotations

import json

from dcf2bin.compare import show
from dcf2bin.compare.engine import Change, FileDiff, Result
from dcf2bin.compare.scope import Scope
from dcf2bin.compare.side import Item, Side

FORMAT, VERSION = "dcf2bin-diff", 1


def render(result: Result, scope: Scope) -> str:
    doc = {
        "format": FORMAT,
        "version": VERSION,
        "a": result.a,
        "b": result.b,
        "equal": result.equal,
        "scope": {"state_left_out": scope.state, "ignore": [s.text for s in scope.ignore],
                  "values_only": scope.values_only},
        "only_in_a": list(result.only_a),
        "only_in_b": list(result.only_b),
        "not_compared": list(result.not_compared),
        "files": [_file(f) for f in result.files],
    }
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def _side(s: Side, errors: int) -> dict:
    return {"file": s.label, "kind": s.kind, "node_id": s.node_id, "errors": errors}


def _file(f: FileDiff) -> dict:
    return {
        "a": _side(f.a, f.errors_of("a")),
        "b": _side(f.b, f.errors_of("b")),
        "equal": f.equal,
        "compared": f.compared,
        "left_out": {"state": f.left_out.get("state", 0),
                     "ignored": f.left_out.get("ignored", 0),
                     "no_value": f.left_out.get("no_value", 0)},
        "objects_only_in_a": [f"0x{i:04X}" for i in sorted(f.only_a)],
        "objects_only_in_b": [f"0x{i:04X}" for i in sorted(f.only_b)],
        "differences": [_change(c, f) for c in f.changes],
    }


def _change(c: Change, f: FileDiff) -> dict:
    index, sub = c.key
    return {
        "index": f"0x{index:04X}",
        "subindex": sub,
        "change": c.kind,
        "object": show.object_name(index, f.a, f.b) or None,
        "name": show.entry_name(index, sub, f.a, f.b) or None,
        "differs_in": list(c.facets),
        "a": _item(c.a, c.b, f),
        "b": _item(c.b, c.a, f),
    }


def _item(it: Item | None, other: Item | None, f: FileDiff) -> dict | None:
    if it is None:
        return None
    v = it.value
    return {
        "value": show.value_text(it, other) if v.stated else None,
        "data": v.data.hex().upper() if v.data is not None else None,
        "meaning": show.meaning(it, f.a, f.b),
        "datatype": it.dtype.name if it.dtype is not None else None,
        "access": it.access,
        "pdo_mapping": it.pdo_mapping,
        "attribute": f"0x{it.attr:02X}" if it.attr is not None else None,
        "where": it.place or None,
    }
