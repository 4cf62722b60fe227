"""The bounded reader: every input of every command is read here.

* A regular file (a symbolic link is followed) is read up to :data:`MAX_INPUT` bytes; one
  byte more is refused (:class:`InputTooLarge`), so ``/dev/zero`` behind a link, or a file
  that grows while it is read, never exhausts memory.
* A path that names one of this process's open descriptors (``/dev/stdin``, ``/dev/fd/N``,
  ``/proc/self/fd/N``: a shell's ``<(...)``) is read like standard input: already open, so
  opening it cannot block, and bounded all the same.
* Anything else that is not a regular file -- a FIFO, a character or block device, a
  socket, a directory -- is refused before a byte is read (:class:`NotARegularFile`,
  ``IsADirectoryError``). The file is opened with ``O_NONBLOCK`` and checked with ``fstat``
  on the open descriptor, so a FIFO put in a regular file's place between a check and the
  open cannot block the run either.

Errors are ``OSError`` subclasses with ``strerror`` and ``filename`` set: a command prints
``file: error: cannot read: <strerror>`` and exits 3; the API lets them rise as ``open``
would.
"""
from __future__ import annotations

import errno
import os
import re
import stat

#: the largest input dcf2bin reads (64 MiB): far above any real EDS, DCF, container,
#: network or description file, far below what would exhaust memory
MAX_INPUT = 64 << 20

_DESCRIPTOR = re.compile(r"/dev/(stdin|fd/\d+)|/proc/(self|\d+)/fd/\d+")


class InputTooLarge(OSError):
    """An input larger than the limit (errno EFBIG)."""


class NotARegularFile(OSError):
    """An input that is a FIFO, a device or a socket (errno EINVAL)."""


def _mib(limit: int) -> str:
    return f"{limit >> 20} MiB" if limit >= 1 << 20 and limit % (1 << 20) == 0 else f"{limit} bytes"


def read_stream(stream, name: str, *, limit: int = MAX_INPUT) -> bytes:
    """At most ``limit`` bytes of a binary stream (standard input); :class:`InputTooLarge`
    when it holds more."""
    data = stream.read(limit + 1)
    if data is None:          # a non-blocking stream with nothing ready
        data = b""
    if len(data) > limit:
        raise InputTooLarge(errno.EFBIG, f"larger than {_mib(limit)} (the input limit)", name)
    return data


def _read_fd(fd: int, first: int, limit: int) -> bytes:
    """Up to ``limit + 1`` bytes: ``first`` in one read (the size fstat gave, plus one to
    see the end), then in pieces of 1 MiB while the file keeps giving more."""
    chunks = [os.read(fd, first)]
    total = len(chunks[0])
    while chunks[-1] and total <= limit:
        chunk = os.read(fd, min(1 << 20, limit + 1 - total))
        chunks.append(chunk)
        total += len(chunk)
    return chunks[0] if len(chunks) <= 2 and not chunks[-1] else b"".join(chunks)


def _names_descriptor(path: str) -> bool:
    return bool(_DESCRIPTOR.fullmatch(os.path.normpath(path)))


def read_file(path: str, *, limit: int = MAX_INPUT) -> bytes:
    """The bytes of the file at ``path``, bounded (see the module's docstring)."""
    if "\0" in path:
        raise OSError(errno.EINVAL, "not a valid file name", path)
    if _names_descriptor(path):
        try:
            fd = os.open(path, os.O_RDONLY | getattr(os, "O_NOCTTY", 0))
        except OSError as exc:
            raise OSError(exc.errno, exc.strerror, path) from None
        with os.fdopen(fd, "rb") as f:
            return read_stream(f, path, limit=limit)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)
                     | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_BINARY", 0))
    except IsADirectoryError:
        raise IsADirectoryError(errno.EISDIR, "Is a directory", path) from None
    except OSError as exc:
        raise OSError(exc.errno, exc.strerror, path) from None
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(errno.EISDIR, "Is a directory", path)
        if not stat.S_ISREG(st.st_mode):
            kind = ("a FIFO" if stat.S_ISFIFO(st.st_mode) else
                    "a device" if stat.S_ISCHR(st.st_mode) or stat.S_ISBLK(st.st_mode) else
                    "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
            what = kind if kind.startswith("not") else f"{kind}, not a regular file"
            raise NotARegularFile(errno.EINVAL, what, path)
        if st.st_size > limit:
            raise InputTooLarge(errno.EFBIG, f"larger than {_mib(limit)} (the input limit)",
                                path)
        data = _read_fd(fd, min(st.st_size, limit) + 1, limit)
    finally:
        os.close(fd)
    if len(data) > limit:
        raise InputTooLarge(errno.EFBIG, f"larger than {_mib(limit)} (the input limit)", path)
    return data
