"""Signals while outputs are written: SIGINT, SIGTERM and SIGHUP never leave a
half-written file or a temporary one behind.

Two ways, for two kinds of writing:

* :func:`raising` -- while one file is written: a signal raises :class:`Interrupted`
  (SIGINT: ``KeyboardInterrupt``, as Python does) wherever the program is, even inside a
  write that blocks (a FIFO nobody reads); the writer removes its temporary file on the
  way out, and :data:`temporaries` lets the program's last ``finally`` remove any that
  is left.
* :func:`deferred` -- while a set of files is written and renamed (``OutputSet``): a
  signal is only noted, the writer asks :meth:`Deferred.check` between two steps and rolls
  the whole set back, and when the block ends the signal is raised again with the
  handlers that were there before (so a program that lets SIGTERM end it still ends by
  it, and the command line's handler turns it into exit 128 + N). Every step in such a
  block is a write into a new regular file, a rename or an fsync: none can block for
  ever, so a noted signal is always acted on.

Handlers can only be set from the main thread; elsewhere both are no-ops (the signal
does what it did before). A signal that is ignored (``nohup``) stays ignored.
"""
from __future__ import annotations

import contextlib
import os
import signal

CAUGHT = ("SIGTERM", "SIGHUP", "SIGINT")


class Interrupted(BaseException):
    """A caught signal (SIGTERM, SIGHUP) while an output was being written."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


class _Temporaries:
    """Temporary files being written; removed by :meth:`remove_all` when a run stops."""

    def __init__(self):
        self.paths: set[str] = set()

    def add(self, path: str) -> None:
        self.paths.add(path)

    def discard(self, path: str) -> None:
        self.paths.discard(path)

    def remove_all(self) -> None:
        for path in list(self.paths):
            try:
                os.unlink(path)
            except OSError:
                pass
            self.paths.discard(path)


#: every temporary output of this process that is not renamed yet
temporaries = _Temporaries()


def _signals():
    for name in CAUGHT:
        sig = getattr(signal, name, None)
        if sig is not None:
            yield sig


def _install(handler, *, keep_int: bool) -> dict:
    """Set ``handler`` for the caught signals; the handlers replaced (to restore)."""
    old = {}
    for sig in _signals():
        try:
            current = signal.getsignal(sig)
            if current is signal.SIG_IGN:
                continue          # nohup and friends: keep ignoring
            if keep_int and sig == signal.SIGINT and current is signal.default_int_handler:
                continue          # raises KeyboardInterrupt already
            old[sig] = signal.signal(sig, handler)
        except (ValueError, OSError, TypeError):   # not the main thread
            pass
    return old


def _restore(old: dict) -> None:
    for sig, handler in old.items():
        try:
            signal.signal(sig, handler if handler is not None else signal.SIG_DFL)
        except (ValueError, OSError, TypeError):
            pass


def _raise_interrupted(signum, frame):
    raise Interrupted(signum)


@contextlib.contextmanager
def raising():
    """SIGTERM and SIGHUP raise :class:`Interrupted` inside the block (SIGINT raises
    ``KeyboardInterrupt``, or ``Interrupted`` where Python's handler was replaced)."""
    old = _install(_raise_interrupted, keep_int=True)
    try:
        yield
    finally:
        _restore(old)


class Stop(Exception):
    """Raised by :meth:`Deferred.check` when a signal came: roll back, then leave the
    ``deferred`` block, which raises the signal again."""

    def __init__(self, signum: int):
        super().__init__(signum)
        self.signum = signum


class Deferred:
    """The signals noted in a :func:`deferred` block."""

    def __init__(self):
        self.received: list[int] = []

    def note(self, signum, frame) -> None:
        self.received.append(signum)

    def check(self) -> None:
        """Raise :class:`Stop` when a signal came since the block began."""
        if self.received:
            raise Stop(self.received[0])


@contextlib.contextmanager
def deferred():
    """Note SIGINT, SIGTERM and SIGHUP instead of acting on them; the writer calls
    ``check()`` between steps and undoes its work on :class:`Stop`. On leaving the block
    the old handlers come back and the first noted signal is raised again (Python's SIGINT
    handler: ``KeyboardInterrupt``; the default SIGTERM: the process ends by it). When
    that handler returns and the block was stopped, :class:`Interrupted` tells the caller
    that the work was undone."""
    state = Deferred()
    old = _install(state.note, keep_int=False)
    stopped = None
    try:
        yield state
    except Stop as stop:
        stopped = stop.signum
    finally:
        _restore(old)
        if state.received and hasattr(signal, "raise_signal"):
            signal.raise_signal(state.received[0])
    if stopped is not None:
        raise Interrupted(stopped)
