"""Validate many files in worker processes (``dcf2bin validate -j N``).

Each worker reads and lints whole files with the same function the serial run calls
(``runner.lint_path``, passed in: this module does not import the runner), so a file's
diagnostics do not depend on where it was checked; the results are put back in argument
order, and the report, the per-rule cap of the text format, the summary line and the exit
code are computed by the caller over the merged list, as for ``-j 1``.

The design is safe under every start method (the work is a module-level function of
picklable arguments; nothing relies on state inherited from the parent). On Linux, in a
process without other threads (the command line), the workers are forks of this process:
ready in milliseconds, with dcf2bin already imported. Otherwise 'forkserver' where the
platform has it (the server imports dcf2bin's reader and rules once, and each worker is
a fork of that clean process, not of a caller that may hold threads or locks; a worker is
then ready about 0.1 s later), else 'spawn'.
"""
from __future__ import annotations

import os
import signal
import sys
import threading
from typing import Callable, TypeVar

from dcf2bin.lint.context import Options

R = TypeVar("R")
Lint = Callable[[str, str, Options], R]    # (path, shown name, options) -> its result

# Imported once in the fork server, so that each worker it starts has them (dcf2bin.cli
# too: such a worker imports the caller's main module, dcf2bin.__main__). A forked worker
# imports what its first file needs itself, while this process imports the same for its
# own first file: ~7 ms that would otherwise come before the fork, in series.
_PRELOAD = ["dcf2bin.cli", "dcf2bin.lint.runner", "dcf2bin.lint.registry", "dcf2bin.ini",
            "dcf2bin.model", "dcf2bin.layout", "dcf2bin.select", "dcf2bin.compiler",
            "dcf2bin.dynod"]


# Less input than this is checked in this process alone (a pre-commit batch of a few
# files, say). Going parallel costs this process about 12 ms of CPU before its first file
# (the multiprocessing import, the shared counter, the fork; the fork server: about 0.1 s
# more) and both processes some more per file (copy-on-write faults on the shared heap,
# about 4 % at a free core); this process lints about 10 MB/s. Measured on the corpus's
# smallest files, a second core free (-j 2 against -j 1, in-process): 91 KiB 36-45 ms
# against 22 ms, 240 KiB 80-90 against 53 ms, 473 KiB 69 against 79 ms, 961 KiB 88 against
# 121 ms; with the second core busy, -j 2 lost up to 45 % below 0.5 MiB. From 1 MiB on the
# gain is clear and a busy core costs little.
MIN_PARALLEL_BYTES = 1 << 20


def _size(path: str) -> int:
    try:
        return os.stat(path).st_size
    except OSError:
        return 0


def usable_cores() -> int:
    """The CPUs this process may run on (the default of ``--jobs``)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):      # not Linux
        return max(1, os.cpu_count() or 1)


def _context():
    import multiprocessing     # here: a validate of one file only asks usable_cores (5-7 ms)
    methods = multiprocessing.get_all_start_methods()
    if sys.platform == "linux" and "fork" in methods and threading.active_count() == 1:
        # forking a process with one thread is safe (lint_paths starts no thread then)
        return multiprocessing.get_context("fork")
    if "forkserver" in methods:
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload(_PRELOAD)
        return ctx
    return multiprocessing.get_context("spawn")


def _widen(conn) -> None:
    """Make the pipe behind ``conn`` hold 1 MiB (Linux; the most an unprivileged process
    may ask for), where it can: a worker then rarely waits for its results to be read."""
    try:
        import fcntl
        fcntl.fcntl(conn.fileno(), fcntl.F_SETPIPE_SZ, 1 << 20)
    except (ImportError, AttributeError, OSError):
        pass


def _take(counter, n: int) -> int | None:
    """The next position in the task list, or None when every task is taken."""
    with counter.get_lock():
        k = counter.value
        if k >= n:
            return None
        counter.value = k + 1
        return k


def _worker(tasks, opts: Options, counter, conn, lint: Lint) -> None:
    # Ctrl-C reaches the whole process group: the parent stops and reports; the workers
    # must not each print a KeyboardInterrupt traceback.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        while (k := _take(counter, len(tasks))) is not None:
            i, path, shown = tasks[k]
            conn.send((i, lint(path, shown, opts)))
    finally:
        conn.close()


def lint_paths(items: list[tuple[str, str]], opts: Options, jobs: int,
               lint: Lint) -> list[R]:
    """``lint`` every (path, shown name) in ``items``, ``jobs`` files at a time: in this
    process and ``jobs - 1`` worker processes; the results in the order of ``items``.
    ``lint`` is a module-level function (``runner.lint_path``): the workers receive it
    by name.

    The tasks are taken from one shared counter, the largest files first (so that no one
    is left with a big file at the end). This process lints from the start, while the
    workers are still being started; a worker that dies leaves its file to this process,
    which lints whatever has no result at the end (so a crash is reported as with -j 1).
    """
    n = len(items)
    jobs = min(jobs, n)
    sizes = [_size(path) for path, _ in items] if jobs > 1 else []
    if jobs <= 1 or sum(sizes) < MIN_PARALLEL_BYTES:
        return [lint(path, shown, opts) for path, shown in items]
    order = sorted(range(n), key=lambda i: -sizes[i])
    tasks = [(i, items[i][0], items[i][1]) for i in order]
    out: list[R | None] = [None] * n
    try:
        ctx = _context()
        counter = ctx.Value("q", 0)
        pipes = [ctx.Pipe(duplex=False) for _ in range(jobs - 1)]
    except OSError:         # no shared memory or no pipes here (a sandbox): one process
        return [lint(path, shown, opts) for path, shown in items]
    for _, w in pipes:
        _widen(w)
    procs = [ctx.Process(target=_worker, args=(tasks, opts, counter, w, lint), daemon=True)
             for _, w in pipes]
    readers: list = []

    def start() -> None:
        for p, (r, w) in zip(procs, pipes):
            try:
                p.start()
            except Exception:  # noqa: BLE001 - e.g. no more processes: this one does the work
                r.close()
            else:
                readers.append(r)
            w.close()

    from multiprocessing.connection import wait

    def collect(timeout: float | None) -> None:
        # the results that are there (timeout 0), or all of them (None: until every
        # worker has closed its pipe)
        while readers:
            ready = wait(list(readers), timeout)
            if not ready:
                return
            for r in ready:
                try:
                    i, res = r.recv()
                except (EOFError, OSError):
                    readers.remove(r)
                    r.close()
                else:
                    out[i] = res

    starter = None
    if ctx.get_start_method() == "fork":
        for stream in (sys.stdout, sys.stderr):   # a fork must not write them out again
            try:
                stream.flush()
            except (AttributeError, OSError, ValueError):
                pass
        start()
    else:
        # starting a process from the fork server (or spawning it) waits until it is
        # ready: in a thread, while this process lints
        starter = threading.Thread(target=start, name="dcf2bin-validate-jobs", daemon=True)
        starter.start()
    # The results are collected here, between this process's own files, not by a thread:
    # a thread that wakes for each result takes the GIL from the linting one (up to the
    # switch interval each time, longer when the machine is busy and the thread waits for
    # a CPU), with the worker blocked on a full pipe meanwhile. On the corpus, -j 2 in
    # process: 0.27-0.29 -> 0.26-0.29 s on an idle machine, 0.37-0.42 -> 0.37-0.41 s
    # beside one CPU-bound process (-j 1: 0.46 s); 0.40-0.56 -> 0.27 s under other
    # sessions' load. The pipes are widened so that a worker seldom waits for the end of
    # this process's current file.
    while (k := _take(counter, n)) is not None:
        i, path, shown = tasks[k]
        out[i] = lint(path, shown, opts)
        collect(0)
    if starter is not None:
        starter.join()
    collect(None)
    for p in procs:
        if p.pid is not None:
            p.join()
    for i, res in enumerate(out):
        if res is None:                      # its worker died: lint it here
            out[i] = lint(items[i][0], items[i][1], opts)
    return out  # type: ignore[return-value]
