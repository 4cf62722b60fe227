"""JSON Schema (draft 2020-12) of ``dcf2bin validate --format json`` (format version 1)
and of ``--list-rules --format json``: the files ``dcf2bin/schemas/validate.json`` and
``rules.json`` (kept here as names for the code and tests that import them).

Stable contract: keys are never removed or renamed within a format version; every key
is always present (null where unknown). New keys may be added.
"""
from __future__ import annotations

from dcf2bin.schemas import load

REPORT_SCHEMA = load("validate")
RULES_SCHEMA = load("rules")

__all__ = ["REPORT_SCHEMA", "RULES_SCHEMA"]
