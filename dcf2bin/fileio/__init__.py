"""Reading inputs and writing outputs: the one place every command and the API share.

* ``reading`` -- the bounded reader: every input of every command goes through
  :func:`read_file` (or :func:`read_stream` for standard input): a regular file or an
  open descriptor, never more than :data:`MAX_INPUT` bytes, never a FIFO or a device that
  would block or never end.
* ``writing`` -- one output file: :func:`check_output` before any work, :func:`write_file`
  atomically (never half-written, never over an input).
* ``outputset`` and ``journal`` -- a set of files written all or none
  (:class:`OutputSet`, ``network build``), under a lock, undone after a SIGKILL.
* ``signals`` -- SIGINT, SIGTERM and SIGHUP while writing (:func:`signals.raising`,
  :func:`signals.deferred`).

The bottom layer: it imports nothing from dcf2bin, never click, and prints nothing;
problems are raised (``OSError`` with ``strerror`` and ``filename``,
:class:`OutputIsInput`) for a command to turn into one ``file: error:`` line.
"""
from __future__ import annotations

import importlib

# name -> module; imported when first asked for, so that reading a file does not load
# the writers (json, the journal) and a command's start stays quick
_WHERE = {
    "MAX_INPUT": "reading", "InputTooLarge": "reading", "NotARegularFile": "reading",
    "read_file": "reading", "read_stream": "reading",
    "OutputIsInput": "writing", "check_output": "writing", "write_file": "writing",
    "OutputSet": "outputset", "SetReport": "outputset",
    "Interrupted": "signals",
}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name not in _WHERE:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(importlib.import_module(f"{__name__}.{_WHERE[name]}"), name)
