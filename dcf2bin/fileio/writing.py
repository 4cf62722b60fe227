"""Writing one output file, the one way every command and the API do it.

* :func:`check_output` says, before any work, whether a path can be written: not an
  input (the same file through a link or a hard link too: :class:`OutputIsInput`), not a
  directory, in a folder that exists and can be written (``OSError`` naming the path).
* :func:`write_file` writes a regular file atomically -- a temporary file beside the real
  target (a symbolic link is followed, the link stays), fsync, rename, fsync of the
  folder; a new file gets ``0666 & ~umask``, an overwritten one keeps its mode (and owner
  where allowed) -- and a character or block device, a FIFO or one of this process's open
  descriptors (``/dev/stdout``, ``/dev/fd/N``) directly. The temporary file is removed on
  any error, and by :data:`signals.temporaries` when a signal stops the run.

A set of files that must be written all or none is :class:`dcf2bin.fileio.OutputSet`.
"""
from __future__ import annotations

import errno
import os
import re
import stat

from dcf2bin.fileio.signals import temporaries

_OWN_DESCRIPTOR = re.compile(r"/dev/(stdout|stderr|fd/\d+)|/proc/(self|\d+)/fd/\d+")


class OutputIsInput(ValueError):
    """An output that would be written over one of the run's inputs."""

    def __init__(self, path: str):
        super().__init__(f"{path}: the output is the input file; refusing to overwrite it")
        self.path = path
        self.reason = "the output is the input file; refusing to overwrite it"


def names_descriptor(path: str) -> bool:
    """/dev/stdout, /dev/fd/N, /proc/self/fd/N: an open file of this process, whatever
    it is (a pipe, a terminal, a file the shell opened with '>'): written directly."""
    return bool(_OWN_DESCRIPTOR.fullmatch(os.path.normpath(path)))


def umask() -> int:
    old = os.umask(0o022)
    os.umask(old)
    return old


def stat_or_none(path: str, *, follow: bool = True):
    try:
        return os.stat(path) if follow else os.lstat(path)
    except (OSError, ValueError):
        return None


def is_input(target: str, st, inputs) -> bool:
    """Whether the file ``target`` (its ``st``, None when it does not exist) is one of
    ``inputs``: the same device and inode, or the same real path."""
    real = None
    for inp in inputs:
        if not inp or inp == "-":
            continue
        ist = stat_or_none(inp)
        if ist is not None and st is not None:
            if (ist.st_dev, ist.st_ino) == (st.st_dev, st.st_ino):
                return True
            continue
        if real is None:
            real = os.path.realpath(target)
        if os.path.realpath(inp) == real:
            return True
    return False


def _folder_problem(folder: str, path: str) -> OSError | None:
    """Why no new file can be made in ``folder`` (None when it can)."""
    st = stat_or_none(folder)
    if st is None:
        return FileNotFoundError(errno.ENOENT, "No such file or directory", path)
    if not stat.S_ISDIR(st.st_mode):
        return NotADirectoryError(errno.ENOTDIR, "Not a directory", path)
    if not os.access(folder, os.W_OK | os.X_OK):
        return PermissionError(errno.EACCES, "Permission denied", path)
    return None


def check_output(path: str, inputs=()) -> None:
    """Raise when ``path`` cannot be written: :class:`OutputIsInput` over an input,
    ``OSError`` (naming ``path``) for a directory there, or a missing or read-only folder.
    Writing may still fail later (a full disk); this catches what can be known before."""
    if path == "":
        raise OSError(errno.ENOENT, "No such file or directory", path)
    if "\0" in path:
        raise OSError(errno.EINVAL, "not a valid file name", path)
    st = stat_or_none(path)
    if is_input(path, st, inputs):
        raise OutputIsInput(path)
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", path)
    if st is not None and not stat.S_ISREG(st.st_mode) or names_descriptor(path):
        if st is not None and not os.access(path, os.W_OK):
            raise PermissionError(errno.EACCES, "Permission denied", path)
        return                      # a device, a FIFO, an open descriptor: written directly
    problem = _folder_problem(os.path.dirname(os.path.realpath(path)) or ".", path)
    if problem is not None:
        raise problem


def fsync_dir(folder: str) -> None:
    """Make a rename in ``folder`` durable (where the system allows a folder's fsync)."""
    try:
        fd = os.open(folder, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def write_all(fd: int, data: bytes) -> None:
    """All of ``data`` to ``fd`` (os.write may write less than asked)."""
    view = memoryview(data)
    while view:
        n = os.write(fd, view)
        view = view[n:]


def new_temporary(folder: str, suffix: str = ".tmp") -> tuple[str, int]:
    """A new file ``.dcf2bin-<random><suffix>`` in ``folder``, mode 0600 (path, descriptor);
    registered in :data:`temporaries` until the caller renames or removes it."""
    for _ in range(100):
        tmp = os.path.join(folder, f".dcf2bin-{os.urandom(6).hex()}{suffix}")
        temporaries.add(tmp)
        try:
            return tmp, os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL
                                | getattr(os, "O_BINARY", 0), 0o600)
        except FileExistsError:
            temporaries.discard(tmp)
        except BaseException:
            temporaries.discard(tmp)
            raise
    raise FileExistsError(errno.EEXIST, "File exists", folder)  # pragma: no cover


def fill(fd: int, data: bytes, st) -> None:
    """Write a temporary file's bytes: the mode (and owner, where allowed) of the file it
    replaces (``st``), else ``0666 & ~umask``; then fsync."""
    os.fchmod(fd, stat.S_IMODE(st.st_mode) if st is not None else 0o666 & ~umask())
    if st is not None and hasattr(os, "fchown"):
        try:
            os.fchown(fd, st.st_uid, st.st_gid)
        except OSError:
            pass               # not ours to give away: the new owner is us
    write_all(fd, data)
    os.fsync(fd)


def write_file(path: str, data: bytes, inputs=()) -> None:
    """Write ``data`` to ``path`` as the module's docstring says; raises
    :class:`OutputIsInput` or ``OSError`` (with ``filename`` = ``path``)."""
    check_output(path, inputs)
    st = stat_or_none(path)
    try:
        if (st is not None and not stat.S_ISREG(st.st_mode)) or names_descriptor(path):
            _write_direct(path, data)
        else:
            _write_atomic(os.path.realpath(path), data, st)
    except OSError as exc:
        if exc.filename == path:
            raise
        raise OSError(exc.errno, exc.strerror, path) from None


def _write_direct(path: str, data: bytes) -> None:
    with open(path, "wb") as f:
        f.write(data)
        f.flush()


def _write_atomic(target: str, data: bytes, st) -> None:
    folder = os.path.dirname(target) or "."
    tmp, fd = new_temporary(folder)
    try:
        try:
            fill(fd, data, st)
        finally:
            os.close(fd)
        os.replace(tmp, target)
        temporaries.discard(tmp)
        fsync_dir(folder)
    finally:
        if tmp in temporaries.paths:
            temporaries.discard(tmp)
            try:
                os.unlink(tmp)
            except OSError:
                pass
