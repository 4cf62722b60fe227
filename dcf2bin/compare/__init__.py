"""``dcf2bin diff``'s library: two configurations compared by meaning, not by text.

Every input -- a DCF/EDS, CiA 311 XML, a container, its JSON form, a concise DCF, a live
node -- is read into one comparable form (``side``: a ``Side`` of ``Item``s, one per
entry) by ``readers`` (files) and ``node`` (SDO); ``scope`` says which entries are
compared (the node's state left out, ``--ignore``); ``engine`` compares two sides;
``folders`` pairs the files of two folders; ``show`` words a value, ``text`` and
``jsonform`` render a ``Result``.

    >>> from dcf2bin import compare
    >>> a = compare.load(data_a, "a.dcf", "dcf")                    # doctest: +SKIP
    >>> b = compare.load(data_b, "b.xdc", "xdd")                    # doctest: +SKIP
    >>> diff, warnings = compare.compare_sources(a, b)              # doctest: +SKIP
    >>> diff.equal                                                  # doctest: +SKIP

No click here, and nothing heavy is imported by this package until it is used.
"""
from __future__ import annotations

from dcf2bin.compare.engine import (ADDED, CHANGED, REMOVED, Change, FileDiff, Result,
                                    compare)
from dcf2bin.compare.readers import KINDS, Source, Unreadable, load, side
from dcf2bin.compare.scope import BadIgnore, Scope, parse_ignore

__all__ = ["ADDED", "CHANGED", "KINDS", "REMOVED", "BadIgnore", "Change", "FileDiff",
           "Result", "Scope", "Source", "Unreadable", "compare", "compare_sources",
           "load", "parse_ignore", "side", "sides"]


def sides(a: Source, b: Source):
    """Both comparable forms: a description without a node-ID of its own takes the other
    input's (-n gives both one). Returns (side a, side b, diagnostics: each input's
    warnings and errors; ``Side.errors`` counts the errors)."""
    sa, ea = side(a, b.node_id)
    sb, eb = side(b, a.node_id)
    return sa, sb, a.warnings + ea + b.warnings + eb


def compare_sources(a: Source, b: Source, scope: Scope | None = None):
    """Compare two inputs read by ``load``: (FileDiff, diagnostics: the inputs' and those
    of values that cannot be encoded)."""
    sa, sb, diags = sides(a, b)
    diff = compare(sa, sb, scope)
    return diff, diags + diff.diagnostics()
