"""The values an argument may take, declared once for the command line and the Python API.

Each spec says what an option of a command (``--node-id``, ``--pi-align``, ...) and the
API argument of the same meaning (``node_id=``, ``pi_align=``) accept, and words a wrong
value in one sentence. ``cli.common`` builds its click types from these specs, the API
(``CompileOptions``, ``dcf2bin.api``) checks its arguments with them, so the two cannot
drift apart and say the same words::

    $ dcf2bin compile plc.dcf --node-id 200
    Error: Invalid value for '-n' / '--node-id': 200 is not in the range 1<=x<=127
    >>> dcf2bin.compile_path("plc.dcf", node_id=200)
    ValueError: node_id: 200 is not in the range 1<=x<=127

No click here, nothing but the profile names imported: a leaf every layer may use.
"""
from __future__ import annotations

import os
from dataclasses import dataclass

from dcf2bin.profiles import NAMES as _PROFILE_NAMES


@dataclass(frozen=True)
class Range:
    """A whole number (``kind=int``) or a number (``kind=float``) in ``min..max``; either
    end may be open (None). Words as click's ranges: '200 is not in the range 1<=x<=127'
    (a float range ends its sentence with a full stop, as click.FloatRange does)."""
    min: float | None = None
    max: float | None = None
    kind: type = int

    def text(self) -> str:
        if self.max is None:
            return f"x>={self.min}"
        if self.min is None:
            return f"x<={self.max}"
        return f"{self.min}<=x<={self.max}"

    def problem(self, value, shown: str | None = None) -> str | None:
        """The sentence for a number outside the range (None inside); ``shown`` is the
        value as the user wrote it (the command line's '0x80')."""
        if (self.min is not None and value < self.min) or \
                (self.max is not None and value > self.max):
            stop = "." if self.kind is float else ""
            if shown is None:
                shown = str(float(value) if self.kind is float else value)
            return f"{shown} is not in the range {self.text()}{stop}"
        return None

    def type_problem(self, value) -> str | None:
        if self.kind is int:
            ok = isinstance(value, int) and not isinstance(value, bool)
            return None if ok else "an int"
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        return None if ok else "a number"


@dataclass(frozen=True)
class Choice:
    """One of ``values`` (all str or all int). Words as click.Choice's:
    "'x' is not one of 'image', 'area'." -- an int choice shown as a number."""
    values: tuple

    def parse(self, text):
        """A command-line text as the choice's type ('8' -> 8), else the text itself."""
        if isinstance(self.values[0], int) and isinstance(text, str):
            try:
                return int(text.strip(), 10)
            except ValueError:
                return text
        return text

    def problem(self, value) -> str | None:
        if self.type_problem(value) is None and value in self.values:
            return None
        return f"{_show(value)} is not one of {', '.join(map(_show, self.values))}."

    def type_problem(self, value) -> str | None:
        if isinstance(self.values[0], int):
            ok = isinstance(value, int) and not isinstance(value, bool)
            return None if ok else "an int"
        return None if isinstance(value, str) else "a str"


@dataclass(frozen=True)
class Flag:
    """True or False (a command-line flag)."""

    def type_problem(self, value) -> str | None:
        return None if isinstance(value, bool) else "a bool"


@dataclass(frozen=True)
class Path:
    """A file name: ``str`` or ``os.PathLike``."""

    def type_problem(self, value) -> str | None:
        return None if isinstance(value, (str, os.PathLike)) else "a path (str or os.PathLike)"


@dataclass(frozen=True)
class Paths:
    """Several file names: a list or tuple of paths (a repeatable option)."""

    def type_problem(self, value) -> str | None:
        if isinstance(value, (list, tuple)) and all(isinstance(p, (str, os.PathLike))
                                                    for p in value):
            return None
        return "a list or tuple of paths"


@dataclass(frozen=True)
class Text:
    """A name or a text: ``str``."""

    def type_problem(self, value) -> str | None:
        return None if isinstance(value, str) else "a str"


@dataclass(frozen=True)
class Bytes:
    """A file's content: ``bytes``, ``bytearray`` or ``memoryview``."""

    def type_problem(self, value) -> str | None:
        return None if isinstance(value, (bytes, bytearray, memoryview)) else "bytes"


def _show(value) -> str:
    """A value as a sentence quotes it: a user's long text cut in the middle (``shorten``)."""
    from dcf2bin.diagnostics import shorten
    return repr(shorten(value)) if isinstance(value, str) else str(value)


# -- the table: one spec per meaning, used by every command and the API ------------------------

NODE_ID = Range(1, 127)                          # -n/--node-id
COUNT = Range(0)                                 # --pi-size, --tx-cobs, --rx-cobs
CONTAINER_VERSION = Range(0, 0xFFFF)             # --container-version (a header WORD)
NET = Range(1)                                   # network --net (a .cpj's [TopologyN])
MAX_LOAD = Range(0, 100, float)                  # network check --max-load, percent
ENTRIES = Choice(("auto", "all"))                # --entries
PDO_SEQUENCE = Choice(("cia301", "none"))        # --pdo-sequence
PROFILE = Choice(_PROFILE_NAMES)                 # --profile
PI_ALIGN = Choice((1, 2, 4, 8))                  # --pi-align
ADDRESS_BASE = Choice(("image", "area"))         # --address-base
GRANULARITY = Choice((8, 64))                    # --granularity
TARGET_CHECK = Choice(("error", "warning", "off"))   # --no-target-check, API target_check
LIMIT_CHECK = Choice(("error", "warning"))       # --limit-check
FLAG, PATH, PATHS, TEXT, BYTES = Flag(), Path(), Paths(), Text(), Bytes()


def check(name: str, value, spec, *, optional: bool = False) -> None:
    """Check one API argument against its spec: ``TypeError`` for a value of the wrong
    type ('node_id must be an int or None, not str'), ``ValueError`` for one the command
    line would refuse, in its words ('node_id: 200 is not in the range 1<=x<=127')."""
    if optional and value is None:
        return
    wanted = spec.type_problem(value)
    if wanted is not None:
        raise TypeError(f"{name} must be {wanted}{' or None' if optional else ''}, "
                        f"not {type(value).__name__}")
    problem = getattr(spec, "problem", None)
    message = problem(value) if problem is not None else None
    if message is not None:
        raise ValueError(f"{name}: {message}")


def check_all(args: dict, table: dict) -> None:
    """``check`` for each ``name: value`` of ``args`` whose name is in ``table``
    (name -> (spec, optional))."""
    for name, value in args.items():
        spec, optional = table[name]
        check(name, value, spec, optional=optional)


__all__ = ["ADDRESS_BASE", "BYTES", "Bytes", "CONTAINER_VERSION", "COUNT", "Choice", "ENTRIES",
           "FLAG", "Flag", "GRANULARITY", "LIMIT_CHECK", "MAX_LOAD", "NET", "NODE_ID", "PATH",
           "PATHS", "PDO_SEQUENCE", "PI_ALIGN", "PROFILE", "Path", "Paths",
           "Range", "TARGET_CHECK", "TEXT", "Text", "check", "check_all"]
