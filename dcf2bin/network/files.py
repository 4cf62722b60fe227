"""Reading a node's EDS/DCF for a network: through the one bounded reader of every input
(:mod:`dcf2bin.fileio`): only a regular file, never more than 64 MiB; and only DCF/EDS
text (issue 26: a binary container, its JSON form, is refused by its content as every
command tells it; binary junk is the INI reader's DCF008, as ``validate`` says it)."""
from __future__ import annotations

from dcf2bin.fileio import MAX_INPUT as MAX_SIZE, read_file


def read_node_file(path: str) -> bytes:
    """The bytes of the file at ``path``; OSError (with ``strerror``) when it is missing,
    not a regular file, or larger than MAX_SIZE."""
    return read_file(path)


def wrong_kind(path: str, data: bytes) -> str | None:
    """Why ``data`` cannot be a node's file (NET011): it is a container or the JSON form
    of one, by its content; None for DCF/EDS text (and for what only looks like none of
    them: the INI reader words that)."""
    from dcf2bin import filekind
    return filekind.mismatch(path, filekind.detect(data, path), filekind.DCF)
