"""Reading a node's EDS/DCF for a network: through the one bounded reader of every input
(:mod:`dcf2bin.fileio`): only a regular file, never more than 64 MiB."""
from __future__ import annotations

from dcf2bin.fileio import MAX_INPUT as MAX_SIZE, read_file


def read_node_file(path: str) -> bytes:
    """The bytes of the file at ``path``; OSError (with ``strerror``) when it is missing,
    not a regular file, or larger than MAX_SIZE."""
    return read_file(path)
