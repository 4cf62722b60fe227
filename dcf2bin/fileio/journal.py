"""What a set of outputs being written is doing, on disk, so that a run stopped by
SIGKILL (or a power loss) between two renames is undone by the next one.

Two small files in the output folder, both named ``.dcf2bin-build.*``:

* ``.dcf2bin-build.lock`` -- always there once a recorded set was written into the folder
  (a set written with ``OutputSet(record=False)`` removes it again when it records no set). Its
  ``flock`` is the lock every writer of the folder holds (:class:`FolderLock`); its text
  is the manifest: which files the last complete set wrote (name, and inode, size and
  modification time: an inode number alone is soon given to another file), so that the
  next one can name those it does not write again, and never mistake a user's file for
  one of its own.
* ``.dcf2bin-build.journal`` -- only while a set is written (or after a run was killed):
  the state (``writing``: temporary files being filled; ``renaming``: every temporary
  file complete and synced, the old files linked aside, renames under way; ``done``: the
  set is complete, only the files kept aside are left to remove) and per file its target,
  its temporary file, the name the old file is kept under and the temporary file's
  identity (:func:`file_id`).

:func:`recover` reads a journal left behind and rolls the set back (``writing``,
``renaming``) or finishes its clean-up (``done``), touching only the files the journal
names and, for a target, only when it is still the file the journal says.
"""
from __future__ import annotations

import errno
import json
import os
import stat
from dataclasses import asdict, dataclass

from dcf2bin.fileio.reading import kind_text, read_file
from dcf2bin.fileio.writing import fsync_dir, write_all

LOCK = ".dcf2bin-build.lock"
JOURNAL = ".dcf2bin-build.journal"
_FORMAT = "dcf2bin output set 1"


@dataclass
class Entry:
    """One file of a set: where it goes and what stands in for it meanwhile."""
    target: str                    # the real path the file is renamed to
    temp: str                      # its temporary file, beside the target
    backup: str | None = None      # the old file is kept under this name (None: no old file)
    temp_id: list[int] | None = None   # the temporary file's identity (file_id), once written
    moved: bool = False            # the old file is renamed aside (no hard links here)


def _lstat(path: str | None):
    if path is None:
        return None
    try:
        return os.lstat(path)
    except OSError:
        return None


def _unlink(path: str) -> None:
    try:
        os.unlink(path)
    except FileNotFoundError:
        pass


# -- the journal --------------------------------------------------------------------------

def file_id(st) -> list[int]:
    """What tells a file dcf2bin wrote from another one later at its name: inode, size and
    modification time (the inode number alone is reused as soon as a file is removed)."""
    return [st.st_ino, st.st_size, st.st_mtime_ns]


def _ids(value) -> dict[str, list[int]]:
    """A manifest read back: name -> file_id; anything else raises ValueError."""
    out = {}
    for name, ident in dict(value or {}).items():
        ident = [int(x) for x in ident]
        if len(ident) != 3:
            raise ValueError(name)
        out[str(name)] = ident
    return out


def write(folder: str, state: str, entries: list[Entry],
          manifest: dict[str, list[int]]) -> None:
    """Replace the journal atomically (a temporary file, fsync, rename, fsync of the
    folder), so that it is the old state or the new one, never half of either."""
    text = json.dumps({"format": _FORMAT, "state": state, "pid": os.getpid(),
                       "files": [asdict(e) for e in entries], "manifest": manifest},
                      indent=1) + "\n"
    path = os.path.join(folder, JOURNAL)
    tmp = path + ".tmp"
    _unlink(tmp)                # left by a stopped run; never written through a link
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0)
                 | getattr(os, "O_BINARY", 0), 0o644)
    try:
        write_all(fd, text.encode())
        os.fsync(fd)
    finally:
        os.close(fd)
    os.replace(tmp, path)
    fsync_dir(folder)


def remove(folder: str) -> None:
    _unlink(os.path.join(folder, JOURNAL + ".tmp"))
    _unlink(os.path.join(folder, JOURNAL))
    fsync_dir(folder)


def read(folder: str) -> dict | None:
    """The journal left in ``folder`` (None when there is none). One that cannot be
    understood raises ``OSError``: nothing is touched on a guess."""
    path = os.path.join(folder, JOURNAL)
    try:
        data = read_file(path, limit=1 << 20, descriptors=False)
    except FileNotFoundError:
        return None
    try:
        doc = json.loads(data)
        if doc.get("format") != _FORMAT or doc.get("state") not in ("writing", "renaming",
                                                                    "done"):
            raise ValueError(doc.get("format"))
        doc["files"] = [Entry(**e) for e in doc["files"]]
        doc["manifest"] = _ids(doc.get("manifest"))
    except (ValueError, TypeError, KeyError, AttributeError):
        raise OSError(errno.EINVAL, f"cannot understand {JOURNAL} (left by another "
                      "program or version?); remove it after checking the folder's files",
                      path) from None
    return doc


# -- undoing and finishing ----------------------------------------------------------------

def rollback(entries: list[Entry]) -> tuple[int, int]:
    """Undo a set: each target back to its old file (or removed when the set made it),
    every temporary file removed. Works from what is on disk, so it is right whether a
    rename happened or not, and may be run again. Returns (restored, removed)."""
    restored = removed = 0
    for e in reversed(entries):
        now, old = _lstat(e.target), _lstat(e.backup)
        ours = now is not None and e.temp_id is not None and file_id(now) == e.temp_id
        if old is not None:
            if now is not None and (now.st_dev, now.st_ino) == (old.st_dev, old.st_ino):
                _unlink(e.backup)                       # still in place: drop the link
            elif now is None or ours:
                os.replace(e.backup, e.target)          # the old file back, as it was
                restored += 1
        elif ours:
            os.unlink(e.target)                         # new in this set: gone again
            removed += 1
        _unlink(e.temp)
    return restored, removed


def finish(entries: list[Entry]) -> None:
    """After a complete set: the old files kept aside are removed."""
    for e in entries:
        if e.backup is not None:
            _unlink(e.backup)
        _unlink(e.temp)


def folders(entries: list[Entry]) -> list[str]:
    return sorted({os.path.dirname(e.target) for e in entries})


def recover(folder: str, lock: FolderLock) -> str | None:
    """Finish or undo the set a stopped run left in ``folder`` (``lock`` held); a
    sentence saying what was done, None when there was nothing to undo."""
    doc = read(folder)
    if doc is None:
        _unlink(os.path.join(folder, JOURNAL + ".tmp"))
        return None
    entries = doc["files"]
    if doc["state"] == "done":          # complete: its manifest and clean-up were left
        lock.set_manifest(doc["manifest"])
        finish(entries)
        remove(folder)
        return None
    restored, removed = rollback(entries)
    for f in folders(entries):
        fsync_dir(f)
    remove(folder)
    if doc["state"] == "writing" or not (restored or removed):
        return ("a build stopped while writing its files was cleared away (its temporary "
                "files removed; no file had been replaced)")
    return (f"a build stopped while renaming its files was rolled back ({restored} "
            f"file{'s' if restored != 1 else ''} restored, {removed} removed)")


# -- the lock and the manifest ------------------------------------------------------------

class FolderLock:
    """``flock`` on ``.dcf2bin-build.lock`` in ``folder``: one writer of a set at a time.
    A writer that finds it taken calls ``on_wait()`` once and waits. The lock file is
    never replaced or removed while it may be locked (a lock on a replaced file would
    lock nothing); a lock taken on a file that was removed meanwhile is taken again."""

    def __init__(self, folder: str, on_wait=None):
        self.path = os.path.join(folder, LOCK)
        self.on_wait = on_wait
        self.fd: int | None = None

    def __enter__(self) -> FolderLock:
        try:
            import fcntl
        except ImportError:                 # pragma: no cover - not a POSIX system
            fcntl = None
        waited = False
        while True:
            fd = os.open(self.path, os.O_RDWR | os.O_CREAT | getattr(os, "O_NOFOLLOW", 0)
                         | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0), 0o666)
            try:
                mode = os.fstat(fd).st_mode
                if not stat.S_ISREG(mode):        # a FIFO put there would block a read
                    raise OSError(errno.EINVAL, kind_text(mode), self.path)
                if fcntl is not None:
                    try:
                        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                    except BlockingIOError:
                        if not waited and self.on_wait is not None:
                            self.on_wait()
                        waited = True
                        fcntl.flock(fd, fcntl.LOCK_EX)
                now = _lstat(self.path)
                st = os.fstat(fd)
                if now is not None and (now.st_dev, now.st_ino) == (st.st_dev, st.st_ino):
                    self.fd = fd
                    return self
            except BaseException:
                os.close(fd)
                raise
            os.close(fd)                    # removed while we waited: lock the new one

    def __exit__(self, *exc) -> None:
        if self.fd is not None:
            os.close(self.fd)               # closing releases the flock
            self.fd = None

    def manifest(self) -> dict[str, list[int]]:
        """name -> file_id of each file the last complete set wrote ({} when unknown)."""
        try:
            os.lseek(self.fd, 0, os.SEEK_SET)
            data = os.read(self.fd, 1 << 20)
            doc = json.loads(data) if data.strip() else {}
            return _ids(doc.get("files"))
        except (OSError, ValueError, TypeError, AttributeError):
            return {}                       # torn or foreign: forget, never guess

    def set_manifest(self, files: dict[str, list[int]]) -> None:
        text = json.dumps({"format": _FORMAT, "files": files}, indent=1, sort_keys=True)
        os.ftruncate(self.fd, 0)
        os.lseek(self.fd, 0, os.SEEK_SET)
        write_all(self.fd, (text + "\n").encode())
        os.fsync(self.fd)

    def remove(self) -> None:
        """Remove the lock file (a folder this run made and leaves empty; a set that records
        nothing): done while it is still locked, so a waiter sees it gone and locks the
        next one."""
        _unlink(self.path)
