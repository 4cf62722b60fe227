"""The bounded reader: every input of every command is read here.

* A regular file (a symbolic link is followed) is read up to :data:`MAX_INPUT` bytes; one
  byte more is refused (:class:`InputTooLarge`), so a file that grows while it is read
  never exhausts memory.
* A path that names one of this process's open descriptors (``/dev/stdin``, ``/dev/fd/N``,
  ``/proc/self/fd/N``: a shell's ``<(...)``) is read like standard input, from a duplicate
  of that descriptor: already open, so nothing is opened that could block (a FIFO whose
  writer is gone blocks a new ``open``), and bounded all the same.
* Anything else that is not a regular file -- a FIFO, a character or block device
  (``/dev/zero`` behind a link), a socket, a directory -- is refused before a byte is read
  (:class:`NotARegularFile`, ``IsADirectoryError``). The file is opened with ``O_NONBLOCK``
  and checked with ``fstat`` on the open descriptor, so a FIFO put in a regular file's
  place between a check and the open cannot block the run either.

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

_CHUNK = 1 << 20
_DESCRIPTOR = re.compile(r"/dev/(?:stdin|fd/(\d+))|/proc/(self|\d+)/fd/(\d+)")


class InputTooLarge(OSError):
    """An input larger than the limit (errno EFBIG)."""


class NotARegularFile(OSError):
    """An input that is a FIFO, a device or a socket (errno EINVAL)."""


def size_text(limit: int) -> str:
    """A limit as a user reads it: ``64 MiB``, ``1000 bytes``."""
    return f"{limit >> 20} MiB" if limit >= 1 << 20 and limit % (1 << 20) == 0 \
        else f"{limit} bytes"


def _too_large(name: str, limit: int) -> InputTooLarge:
    return InputTooLarge(errno.EFBIG, f"larger than {size_text(limit)} (the input limit)", name)


def read_stream(stream, name: str, *, limit: int = MAX_INPUT) -> bytes:
    """At most ``limit`` bytes of a binary stream (standard input); :class:`InputTooLarge`
    when it holds more."""
    data = stream.read(limit + 1)
    if data is None:          # a non-blocking stream with nothing ready
        data = b""
    if len(data) > limit:
        raise _too_large(name, limit)
    return data


def _read_fd(fd: int, first: int, limit: int) -> bytes:
    """Up to ``limit + 1`` bytes: ``first`` in one read (the size fstat gave, plus one to
    see the end), then in pieces of 1 MiB while the file keeps giving more."""
    chunks = [os.read(fd, first)]
    total = len(chunks[0])
    while total <= limit:
        chunk = os.read(fd, min(_CHUNK, limit + 1 - total))
        if not chunk:
            break
        chunks.append(chunk)
        total += len(chunk)
    return chunks[0] if len(chunks) == 1 else b"".join(chunks)


def descriptor_of(path: str) -> int | None:
    """The number of this process's open descriptor that ``path`` names (``/dev/stdin``
    is 0, ``/dev/fd/N``, ``/proc/self/fd/N``, ``/proc/<this pid>/fd/N``), else None."""
    m = _DESCRIPTOR.fullmatch(os.path.normpath(path))
    if m is None:
        return None
    if m.group(2) is not None:
        if m.group(2) != "self" and int(m.group(2)) != os.getpid():
            return None               # another process's descriptor: a path like any
        return int(m.group(3))
    return int(m.group(1)) if m.group(1) is not None else 0


def _os_error(exc: OSError, path: str) -> OSError:
    """``exc`` again, naming ``path`` (the name the user gave, not a resolved one)."""
    return type(exc)(exc.errno, exc.strerror, path)


def _read_descriptor(fd: int, path: str, limit: int) -> bytes:
    try:
        dup = os.dup(fd)
    except OSError as exc:
        raise _os_error(exc, path) from None
    try:
        data = _read_fd(dup, _CHUNK, limit)
    except OSError as exc:
        raise _os_error(exc, path) from None
    finally:
        os.close(dup)
    if len(data) > limit:
        raise _too_large(path, limit)
    return data


def kind_text(mode: int) -> str:
    """What a file that is not a regular one is, for a message."""
    if stat.S_ISFIFO(mode):
        return "a FIFO, not a regular file"
    if stat.S_ISCHR(mode) or stat.S_ISBLK(mode):
        return "a device, not a regular file"
    if stat.S_ISSOCK(mode):
        return "a socket, not a regular file"
    return "not a regular file"


def read_file(path, *, limit: int = MAX_INPUT, descriptors: bool = True) -> bytes:
    """The bytes of the file at ``path``, bounded (see the module's docstring).
    ``descriptors=False``: ``/dev/stdin`` and its kin are paths like any other (for a
    name written inside a file, which must never read this process's input)."""
    path = os.fsdecode(path)
    if "\0" in path:
        raise OSError(errno.EINVAL, "not a valid file name", path)
    fd = descriptor_of(path) if descriptors else None
    if fd is not None:
        return _read_descriptor(fd, path, limit)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0)
                     | getattr(os, "O_NOCTTY", 0) | getattr(os, "O_BINARY", 0))
    except OSError as exc:
        raise _os_error(exc, path) from None
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(errno.EISDIR, "Is a directory", path)
        if not stat.S_ISREG(st.st_mode):
            raise NotARegularFile(errno.EINVAL, kind_text(st.st_mode), path)
        if st.st_size > limit:
            raise _too_large(path, limit)
        try:
            data = _read_fd(fd, min(st.st_size, limit) + 1, limit)
        except OSError as exc:
            raise _os_error(exc, path) from None
    finally:
        os.close(fd)
    if len(data) > limit:
        raise _too_large(path, limit)
    return data
