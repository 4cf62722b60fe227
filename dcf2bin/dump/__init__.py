"""Containers as text: the lossless JSON form and the readable report (SPEC.md §4).

``to_dict``/``to_json`` turn a ``BinContainer`` into the lossless JSON document
(format ``dcf2bin-container``, schema version ``SCHEMA_VERSION``, documented in
docs/dump.md and as ``JSON_SCHEMA``); ``from_dict``/``from_json_bytes`` turn it
back into a container whose bytes are exactly the ones that were dumped, for every
container ``container.read`` accepts (odd headers, gaps, any version, a PI parameter
segment of the wrong size). ``report`` renders the readable text report.

Derived fields are never trusted from a JSON document: in the ``canonical`` layout the
header is recomputed from the segments (a stale value is a warning); in the ``stored``
layout the header is used as given and must describe the segments exactly.

The package has one module per step; this ``__init__`` re-exports every name other modules,
tests and docs use, so ``from dcf2bin.dump import X`` keeps working:

* ``jsonform``   -- constants, rule ids, ``JSON_SCHEMA``, container -> document, ``JsonProblem``
* ``binary``     -- ``read_bytes`` (a container, its error as a diagnostic), ``header_of``,
                    ``entry_offsets``
* ``document``   -- document -> ``BinContainer`` (``from_dict``), every field checked
* ``rebuild``    -- ``build``: the bytes of a parsed document, canonical or stored layout
* ``jsonreader`` -- ``from_json_bytes``: JSON text -> bytes and ``file:line`` diagnostics
* ``eds``        -- ``EdsInfo``/``load_eds``: names and exact types from ``--eds``
* ``text``       -- ``report``: the readable text report

and the same for a CiA 302-3 concise DCF (read and written by ``dcf2bin.concise``):

* ``concise_json``  -- its lossless JSON form (``dcf2bin-concise``): ``to_json``, ``from_dict``
                       (``from_json_bytes`` turns it back into bytes too)
* ``concise_types`` -- ``entry_type``: an entry's type from the EDS, CiA 301, a CiA 405 range,
                       or guessed from its size
* ``concise_text``  -- ``concise_report``: the readable text report
"""
from __future__ import annotations

from dcf2bin.dump.binary import entry_offsets, header_of, read_bytes
from dcf2bin.dump.document import Parsed, from_dict
from dcf2bin.dump.eds import EdsInfo, eds_warnings, load_eds
from dcf2bin.dump.jsonform import (CANONICAL, FORMAT, HEADER_FIELDS, JSON_SCHEMA,
                                   PIPARAM_FIELDS, RULE_JSON, RULE_JSON_HEADER,
                                   RULE_JSON_SYNTAX, SCHEMA_VERSION, STORED, JsonProblem,
                                   format_json, path_text, to_dict, to_json)
from dcf2bin.dump.jsonreader import from_json_bytes, locate
from dcf2bin.dump.rebuild import build
from dcf2bin.dump.text import header_notes, nv_keys, nv_type, report, value_text
from dcf2bin.dump import concise_json
from dcf2bin.dump.concise_json import FORMAT as CONCISE_FORMAT
from dcf2bin.dump.concise_text import report as concise_report
from dcf2bin.dump.concise_types import entry_type

__all__ = ["CANONICAL", "CONCISE_FORMAT", "FORMAT", "HEADER_FIELDS", "JSON_SCHEMA",
           "PIPARAM_FIELDS", "RULE_JSON", "RULE_JSON_HEADER", "RULE_JSON_SYNTAX", "SCHEMA_VERSION",
           "STORED", "EdsInfo", "JsonProblem", "Parsed", "build", "concise_json",
           "concise_report", "eds_warnings", "entry_offsets", "entry_type", "format_json",
           "from_dict", "from_json_bytes", "header_notes", "header_of", "load_eds", "locate",
           "nv_keys", "nv_type", "path_text", "read_bytes", "report", "to_dict", "to_json",
           "value_text"]
