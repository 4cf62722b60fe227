"""All or nothing: a set of files written into one folder (``network build``).

``OutputSet(folder, [(name, bytes), ...], inputs=...)``:

1. :meth:`OutputSet.check` -- every output before the first byte: a plain file name, not
   an input of the run (:class:`OutputIsInput`), nothing but a regular file (or nothing)
   at its name, a folder that exists or can be made and can be written (``OSError``
   naming the path). ``write`` checks again under the lock.
2. :meth:`OutputSet.write` -- under the folder's lock (:class:`journal.FolderLock`; a
   second writer waits), after undoing what a stopped run left (:func:`journal.recover`):
   every file is written as a temporary file beside its target and synced; the files it
   replaces are linked aside (hard links: the old file itself, untouched); the journal
   says so; then the renames; then the journal says ``done``, the manifest names the new
   set and the old files are let go. Any error, SIGINT, SIGTERM or SIGHUP before ``done``
   rolls everything back: none of the new files remain, the old ones are where they were
   (the same inodes), and the error or the signal goes on to the caller. A SIGKILL is
   undone by the next ``write`` in that folder.

A file the last complete set wrote that this set does not (a slave removed from the
network) is left alone and named in :attr:`SetReport.stale`; a file dcf2bin did not write
is never removed.

``record=False`` (``export -f canopennode``: OD.h and OD.c into a firmware's source
folder) writes the set the same way but records nothing: the lock file's manifest is left
as it was (no stale files are named), and a lock file that records no set is removed once
the set is complete (:meth:`OutputSet._let_go`), so that the folder holds the outputs and
nothing else. A ``network build``'s lock file in that folder stays.
"""
from __future__ import annotations

import errno
import os
import stat
from dataclasses import dataclass, field

from dcf2bin.fileio import journal
from dcf2bin.fileio.reading import kind_text
from dcf2bin.fileio.signals import deferred
from dcf2bin.fileio.journal import Entry
from dcf2bin.fileio.writing import OutputIsInput, fill, fsync_dir, is_input, stat_or_none


@dataclass
class SetReport:
    """What :meth:`OutputSet.write` did."""
    written: list[str] = field(default_factory=list)     # the paths, in the given order
    stale: list[str] = field(default_factory=list)       # an earlier set's, kept
    recovered: str | None = None                         # a stopped run undone first


def _plain_name(name: str) -> bool:
    return (bool(name) and name not in (".", "..") and "/" not in name and "\0" not in name
            and os.sep not in name and not name.startswith(".dcf2bin-"))


def _nearest_folder(folder: str) -> str:
    """The folder itself, or its nearest ancestor that exists (where it will be made)."""
    path = os.path.abspath(folder)
    while not os.path.lexists(path) and os.path.dirname(path) != path:
        path = os.path.dirname(path)
    return path


class OutputSet:
    """Files written into ``folder`` all together or not at all (see the module)."""

    def __init__(self, folder: str, files, *, inputs=(), on_wait=None, record: bool = True):
        self.folder = folder
        self.record = record
        self.files = [(name, bytes(data)) for name, data in files]
        self.inputs = [p for p in inputs if p and p != "-"]
        self.on_wait = on_wait
        names = [name for name, _ in self.files]
        bad = [n for n in names if not _plain_name(n)]
        if bad:
            raise ValueError(f"not a plain file name for an output: {bad[0]!r}")
        if len(set(names)) != len(names):
            raise ValueError("an output name is given twice")

    def path(self, name: str) -> str:
        return os.path.join(self.folder, name)

    # -- 1. before the first byte ---------------------------------------------------------

    def check(self) -> None:
        """Raise for the first output that cannot be written (see the module)."""
        if self.folder == "":
            raise FileNotFoundError(errno.ENOENT, "No such file or directory", self.folder)
        st = stat_or_none(self.folder)
        if st is not None and not stat.S_ISDIR(st.st_mode):
            raise NotADirectoryError(errno.ENOTDIR, "Not a directory", self.folder)
        base = _nearest_folder(self.folder)
        if not stat.S_ISDIR(os.stat(base).st_mode):
            raise NotADirectoryError(errno.ENOTDIR, "Not a directory", self.folder)
        if not os.access(base, os.W_OK | os.X_OK):
            raise PermissionError(errno.EACCES, "Permission denied", self.folder)
        targets: dict[str, str] = {}
        for name, _ in self.files:
            target, _ = self._target(name)
            if target in targets:
                raise OSError(errno.EEXIST, f"the same file as {targets[target]} (a "
                              "symbolic link?)", self.path(name))
            targets[target] = self.path(name)

    def _target(self, name: str):
        """(the real path ``name`` is written to, the regular file there or None);
        raises when it cannot be one of the set."""
        path = self.path(name)
        st = stat_or_none(path)
        if is_input(path, st, self.inputs):
            raise OutputIsInput(path)
        if st is not None and stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(errno.EISDIR, "Is a directory", path)
        if st is not None and not stat.S_ISREG(st.st_mode):
            raise OSError(errno.EINVAL, kind_text(st.st_mode), path)
        target = os.path.realpath(path)
        where = os.path.dirname(target)
        if os.path.isdir(where) and not os.access(where, os.W_OK | os.X_OK):
            raise PermissionError(errno.EACCES, "Permission denied", path)
        return target, st

    # -- 2. the writing -------------------------------------------------------------------

    def write(self) -> SetReport:
        """Write the set (see the module); raises as :meth:`check` does, ``OSError``
        naming the output (a full disk), or the signal that stopped it."""
        self.check()
        made = self._make_folder()
        report = SetReport()
        try:
            with journal.FolderLock(self.folder, self.on_wait) as lock:
                try:
                    report.recovered = journal.recover(self.folder, lock)
                    self.check()
                    report.stale = self._commit(lock)
                except BaseException:
                    if made:
                        lock.remove()
                    raise
                finally:
                    self._let_go(lock)
        except BaseException:
            for folder in reversed(made):
                try:
                    os.rmdir(folder)
                except OSError:
                    pass
            raise
        report.written = [self.path(name) for name, _ in self.files]
        return report

    def _make_folder(self) -> list[str]:
        """Make the folder and its missing parents; the ones made, outermost first."""
        made = []
        path = os.path.abspath(self.folder)
        while not os.path.lexists(path):
            made.append(path)
            path = os.path.dirname(path)
        made.reverse()
        for folder in made:
            try:
                os.mkdir(folder)
            except FileExistsError:
                pass
            except OSError as exc:
                raise OSError(exc.errno, exc.strerror, self.folder) from None
        return made

    def _plan(self) -> list[tuple[Entry, bytes, object]]:
        run = os.urandom(6).hex()
        plan = []
        for i, (name, data) in enumerate(self.files):
            target, st = self._target(name)
            stem = os.path.join(os.path.dirname(target), f".dcf2bin-{run}-{i}")
            plan.append((Entry(target, stem + ".tmp", stem + ".old" if st else None), data, st))
        return plan

    def _commit(self, lock: journal.FolderLock) -> list[str]:
        previous = lock.manifest()
        plan = self._plan()
        entries = [e for e, _, _ in plan]
        with deferred() as signals:
            try:
                journal.write(self.folder, "writing", entries, previous)
                for (e, data, st), (name, _) in zip(plan, self.files):
                    signals.check()
                    self._fill(e, data, st, self.path(name))
                for e in entries:
                    self._keep_aside(e)
                self._sync(entries)
                signals.check()
                journal.write(self.folder, "renaming", entries, previous)
                for e, (name, _) in zip(entries, self.files):
                    signals.check()
                    self._rename(e, self.path(name))
                self._sync(entries)
                files = {name: e.temp_id for e, (name, _) in zip(entries, self.files)}
                stale = self._stale(previous, files)
                files.update({name: previous[name] for name in stale})
                files = files if self.record else previous
                signals.check()
                journal.write(self.folder, "done", entries, files)   # the set is complete
            except BaseException:
                self._undo(entries)
                raise
            try:
                lock.set_manifest(files)
                journal.finish(entries)
                journal.remove(self.folder)
            except OSError:
                pass         # the journal says "done": the next run finishes the clean-up
        return [self.path(name) for name in stale]

    def _fill(self, e: Entry, data: bytes, st, shown: str) -> None:
        try:
            fd = os.open(e.temp, os.O_WRONLY | os.O_CREAT | os.O_EXCL
                         | getattr(os, "O_BINARY", 0), 0o600)
        except OSError as exc:
            raise OSError(exc.errno, exc.strerror, shown) from None
        try:
            fill(fd, data, st)
            e.temp_id = journal.file_id(os.fstat(fd))
        except OSError as exc:
            raise OSError(exc.errno, exc.strerror, shown) from None
        finally:
            os.close(fd)

    @staticmethod
    def _keep_aside(e: Entry) -> None:
        """A hard link to the old file, so that it can come back as it was; where the
        file system has none, it is renamed aside just before its replacement."""
        if e.backup is None:
            return
        try:
            os.link(e.target, e.backup, follow_symlinks=False)
        except FileExistsError:
            raise
        except OSError:
            e.moved = True

    @staticmethod
    def _rename(e: Entry, shown: str) -> None:
        try:
            if e.moved:
                os.replace(e.target, e.backup)
            os.replace(e.temp, e.target)
        except OSError as exc:
            raise OSError(exc.errno, exc.strerror, shown) from None

    @staticmethod
    def _sync(entries: list[Entry]) -> None:
        for folder in journal.folders(entries):
            fsync_dir(folder)

    def _undo(self, entries: list[Entry]) -> None:
        """Roll back after an error or a signal; the journal stays when that fails too,
        for the next run to finish."""
        try:
            journal.rollback(entries)
            self._sync(entries)
            journal.remove(self.folder)
        except OSError:
            pass

    def _let_go(self, lock: journal.FolderLock) -> None:
        """``record=False``, the set complete or rolled back: remove the lock file when it
        records no set -- unlinked while its flock is held, so that a writer waiting for
        it finds its path names another file and locks that one (FolderLock checks). A
        lock file that cannot be removed stays: it holds nothing the next run needs."""
        if self.record or lock.manifest():
            return
        try:
            lock.remove()
        except OSError:
            pass

    def _stale(self, previous: dict, files: dict) -> list[str]:
        """The earlier set's files this one does not write that are still the files it
        wrote (the same file_id): kept, and named (none without ``record``: the earlier
        set is another command's)."""
        if not self.record:
            return []
        stale = []
        for name, ident in sorted(previous.items()):
            if name in files:
                continue
            st = stat_or_none(self.path(name))
            if st is not None and stat.S_ISREG(st.st_mode) and journal.file_id(st) == ident:
                stale.append(name)
        return stale


__all__ = ["OutputIsInput", "OutputSet", "SetReport"]
