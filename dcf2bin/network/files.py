"""Reading a node's EDS/DCF for a network: only a regular file, and not without bound.

A network file names its nodes' files, so a hostile or mistaken name (a FIFO, /dev/zero,
a directory) must not hang or exhaust the run: anything but a regular file is refused
before it is opened, and a file larger than any EDS/DCF is refused after MAX_SIZE bytes.
"""
from __future__ import annotations

import errno
import os
import stat

MAX_SIZE = 64 << 20


def read_node_file(path: str) -> bytes:
    """The bytes of the file at ``path``; OSError (with ``strerror``) when it is missing,
    not a regular file, or larger than MAX_SIZE."""
    try:
        st = os.stat(path)
    except ValueError:                 # a NUL in the name
        raise OSError(errno.EINVAL, "not a valid file name", path) from None
    if stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", path)
    if not stat.S_ISREG(st.st_mode):
        raise OSError(errno.EINVAL, "not a regular file", path)
    with open(path, "rb") as f:
        data = f.read(MAX_SIZE + 1)
    if len(data) > MAX_SIZE:
        raise OSError(errno.EFBIG, f"larger than {MAX_SIZE >> 20} MiB", path)
    return data
