"""JSON Schema (draft 2020-12) of ``dcf2bin validate --format json`` (format version 1)
and of ``--list-rules --format json``.

Stable contract: keys are never removed or renamed within a format version; every key
is always present (null where unknown). New keys may be added.
"""
from __future__ import annotations

_SEVERITY = {"enum": ["error", "warning", "info"]}
_COUNT = {"type": "integer", "minimum": 0}
_OPT_INT = {"type": ["integer", "null"], "minimum": 0}

REPORT_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "$id": "https://dcf2bin.example/schemas/validate-report-1.json",
    "title": "dcf2bin validate report",
    "type": "object",
    "required": ["format", "version", "tool", "files", "diagnostics", "summary"],
    "additionalProperties": False,
    "properties": {
        "format": {"const": "dcf2bin-validate"},
        "version": {"const": 1},
        "tool": {
            "type": "object", "required": ["name", "version"],
            "properties": {"name": {"const": "dcf2bin"}, "version": {"type": "string"}},
        },
        "files": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["path", "kind", "errors", "warnings", "infos"],
                "additionalProperties": False,
                "properties": {
                    "path": {"type": "string"},
                    "kind": {"enum": ["dcf", "container", "unreadable", "yaml", "cpj"]},
                    "errors": _COUNT, "warnings": _COUNT, "infos": _COUNT,
                },
            },
        },
        "diagnostics": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["rule", "name", "severity", "file", "line", "column", "offset",
                             "message", "hint"],
                "additionalProperties": False,
                "properties": {
                    "rule": {"type": "string", "pattern": "^(DCF|CNT|NET)[0-9]{3}$|^TGT0[0-9A-F]{2}$|^(IO|INT)[0-9]{3}$"},
                    "name": {"type": "string"},
                    "severity": _SEVERITY,
                    "file": {"type": "string"},
                    "line": {"type": ["integer", "null"], "minimum": 1},
                    "column": {"type": ["integer", "null"], "minimum": 1},
                    "offset": _OPT_INT,
                    "message": {"type": "string", "minLength": 1},
                    "hint": {"type": "string"},
                },
            },
        },
        "summary": {
            "type": "object",
            "required": ["files", "errors", "warnings", "infos", "exit_code"],
            "additionalProperties": False,
            "properties": {
                "files": _COUNT, "errors": _COUNT, "warnings": _COUNT, "infos": _COUNT,
                "exit_code": {"enum": [0, 1, 2, 3, 70]},
            },
        },
    },
}

RULES_SCHEMA = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "title": "dcf2bin validate rule list",
    "type": "object",
    "required": ["format", "version", "rules"],
    "properties": {
        "format": {"const": "dcf2bin-rules"},
        "version": {"const": 1},
        "rules": {
            "type": "array",
            "items": {
                "type": "object",
                "required": ["id", "name", "severity", "family", "description", "hint"],
                "additionalProperties": False,
                "properties": {
                    "id": {"type": "string"}, "name": {"type": "string",
                                                      "pattern": "^[a-z0-9]+(-[a-z0-9]+)*$"},
                    "severity": _SEVERITY, "family": {"type": "string"},
                    "description": {"type": "string"}, "hint": {"type": "string"},
                },
            },
        },
    },
}
