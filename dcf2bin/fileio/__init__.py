"""Reading inputs and writing outputs: the one place every command and the API share.

``reading`` is the bounded reader (every input of every command goes through it: a regular
file or an open descriptor, never more than :data:`MAX_INPUT` bytes, never a FIFO or a
device that would block or never end). Nothing here imports click or prints: problems are
raised as ``OSError`` with a ``strerror`` a command turns into one ``file: error:`` line.
"""
from __future__ import annotations

from dcf2bin.fileio.reading import MAX_INPUT, InputTooLarge, NotARegularFile, read_file, read_stream

__all__ = ["MAX_INPUT", "InputTooLarge", "NotARegularFile", "read_file", "read_stream"]
