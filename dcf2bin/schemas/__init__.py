"""The JSON Schemas (draft 2020-12) of every JSON document dcf2bin writes, shipped as package
data: ``dump.json`` (``dump -f json``, also compile's JSON input), ``dump-concise.json``
(``dump -f json`` of a concise DCF, and compile's), ``map.json``,
``simulate.json``, ``validate.json`` (also ``network check -f json``), ``rules.json``
(``validate --list-rules -f json``), ``network-show.json``, ``network-scan.json``,
``lss.json`` (``network lss`` and ``lss set -f json``), ``lss-scan.json``,
``diff.json`` (``diff -f json``).

Every document starts with ``"format": "dcf2bin-<what>"`` and ``"version": <int>``; CANopen
object indexes are ``"0x%04X"`` strings, COB-IDs ``"0x%08X"`` strings, and sub-indexes,
sizes, offsets, addresses and counts JSON integers (docs/options.md, "JSON outputs").

    >>> load("map")["properties"]["format"]
    {'const': 'dcf2bin-map'}

Imports nothing from dcf2bin: any package may use it.
"""
from __future__ import annotations

import json
from functools import lru_cache
from importlib import resources

# output -> (schema file, format name). The schema file is ``<key>.json`` in this package.
FORMATS = {
    "dump": "dcf2bin-container",
    "dump-concise": "dcf2bin-concise",
    "map": "dcf2bin-map",
    "simulate": "dcf2bin-simulate",
    "validate": "dcf2bin-validate",
    "rules": "dcf2bin-rules",
    "network-show": "dcf2bin-network-show",
    "network-scan": "dcf2bin-network-scan",
    "lss": "dcf2bin-lss",
    "lss-scan": "dcf2bin-lss-scan",
    "diff": "dcf2bin-diff",
}


@lru_cache(maxsize=None)
def _text(name: str) -> str:
    if name not in FORMATS:
        raise KeyError(f"no JSON Schema named {name!r} (known: {', '.join(FORMATS)})")
    return resources.files(__name__).joinpath(f"{name}.json").read_text(encoding="utf-8")


def load(name: str) -> dict:
    """The schema of output ``name`` (a key of ``FORMATS``) as a fresh dict."""
    return json.loads(_text(name))


__all__ = ["FORMATS", "load"]
