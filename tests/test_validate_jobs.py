"""validate -j N: files checked in worker processes give the report of -j 1, byte for byte,
in every format, with the same exit code (issue 22). Speed is measured in benchmarks/."""
from __future__ import annotations

import multiprocessing
import sys

import pytest
from click.testing import CliRunner

from conftest import CORPUS, SAMPLES, needs_corpus
from dcf2bin.cli import main
from dcf2bin.lint import Options, parallel, runner

FORMATS = ("text", "json", "sarif", "github")


def validate(*args, input=None):
    res = CliRunner().invoke(main, ["validate", *map(str, args)], input=input)
    assert res.exception is None or isinstance(res.exception, SystemExit), res.output
    return res.exit_code, res.stdout


@needs_corpus
@pytest.mark.parametrize("fmt", FORMATS)
def test_corpus_report_is_the_same_with_two_jobs(fmt):
    serial = validate("-j", "1", "--format", fmt, CORPUS)
    assert serial[0] == 1 and serial[1]           # the corpus has errors: a real report
    assert validate("-j", "2", "--format", fmt, CORPUS) == serial


@needs_corpus
def test_more_jobs_than_cores_and_argument_order():
    # files named one by one, in reverse: the report follows the arguments, not the
    # order in which the workers finish; the text format's per-rule cap and summary line
    # are computed over the merged results
    files = sorted(p for p in CORPUS.rglob("*") if p.suffix.lower() in (".eds", ".dcf"))[::-1]
    serial = validate("-j", "1", *files)
    assert validate("-j", "5", *files) == serial
    assert f"in {len(files)} files" in serial[1].splitlines()[-1]


@pytest.fixture
def always_parallel(monkeypatch):
    """Workers even for a few small files (normally checked in this process alone)."""
    monkeypatch.setattr(parallel, "MIN_PARALLEL_BYTES", 0)


def test_little_input_is_checked_here(monkeypatch):
    def no_workers(*args, **kwargs):
        raise AssertionError("a worker process was started")
    monkeypatch.setattr(parallel, "_context", no_workers)
    files = sorted(str(p) for p in SAMPLES.glob("*.dcf"))
    assert parallel.lint_paths([(p, p) for p in files], Options(), 2, runner.lint_path) == [
        runner.lint_path(p, p, Options()) for p in files]


def test_unreadable_inputs_and_stdin_keep_their_place(tmp_path, always_parallel):
    empty = tmp_path / "empty"
    empty.mkdir()
    args = [SAMPLES / "plc.dcf", tmp_path / "missing.dcf", "-", empty,
            SAMPLES / "plc.dcf", SAMPLES]
    stdin = (SAMPLES / "plc.dcf").read_text()
    for fmt in FORMATS:
        serial = validate("-j", "1", "--format", fmt, *args, input=stdin)
        assert serial[0] == 3                      # IO001: unreadable input
        assert validate("-j", "2", "--format", fmt, *args, input=stdin) == serial


def test_jobs_must_be_positive():
    code, _ = validate("-j", "0", SAMPLES / "plc.dcf")
    assert code == 2


def test_default_is_the_usable_cores():
    import os
    assert parallel.usable_cores() == len(os.sched_getaffinity(0))


def test_worker_lints_every_task_it_takes_and_sends_it_back():
    # the worker loop run in this process: tasks come from the shared counter, results
    # go back tagged with their place in the argument list
    ctx = multiprocessing.get_context("spawn")
    files = [str(SAMPLES / "plc.dcf"), str(SAMPLES / "nonexistent.dcf")]
    tasks = [(1, files[1], "b"), (0, files[0], "a")]
    counter = ctx.Value("q", 0)
    r, w = ctx.Pipe(duplex=False)
    parallel._worker(tasks, Options(), counter, w, runner.lint_path)
    got = dict(r.recv() for _ in tasks)
    assert counter.value == 2
    assert got[0] == runner.lint_path(files[0], "a", Options())
    assert got[1] == runner.lint_path(files[1], "b", Options())
    assert got[1].kind == runner.KIND_UNREADABLE


def test_lint_paths_keeps_the_order_of_its_items(always_parallel):
    files = sorted(str(p) for p in SAMPLES.glob("*.dcf"))
    items = [(p, p) for p in files]
    assert parallel.lint_paths(items, Options(), 2, runner.lint_path) == [
        runner.lint_path(p, p, Options()) for p in files]


@pytest.mark.skipif(sys.platform != "linux", reason="the start methods chosen on Linux")
@pytest.mark.parametrize("threads", [1, 2], ids=["fork", "forkserver"])
def test_both_ways_of_starting_workers_give_the_serial_results(always_parallel, monkeypatch,
                                                              threads):
    # with another thread in the process the workers come from the fork server instead of
    # a fork of this process (on Linux); either way the results are the serial ones
    monkeypatch.setattr(parallel.threading, "active_count", lambda: threads)
    ctx = parallel._context()
    assert ctx.get_start_method() == ("fork" if threads == 1 else "forkserver")
    files = sorted(str(p) for p in SAMPLES.glob("*.*") if p.suffix in (".dcf", ".eds", ".bin"))
    items = [(p, p) for p in files]
    assert parallel.lint_paths(items, Options(), 3, runner.lint_path) == [
        runner.lint_path(p, p, Options()) for p in files]



# -- how the results come back (fork start method, Linux) -------------------------------------

_PARENT = [0]
_THREADS_SEEN: list[int] = []


def _big_result(path: str, shown: str, opts: Options) -> tuple[str, str]:
    """A stand-in for lint_path whose result is larger than a pipe holds (1 MiB): the
    worker must wait until this process reads it, and nothing may be lost or reordered."""
    import os
    import threading
    if os.getpid() == _PARENT[0]:
        _THREADS_SEEN.append(threading.active_count())
    return shown, shown[-1] * (3 << 20)


@pytest.mark.skipif(sys.platform != "linux", reason="the fork start method of Linux")
def test_results_larger_than_the_pipe_arrive_in_order(tmp_path, always_parallel):
    import os
    _PARENT[0] = os.getpid()
    _THREADS_SEEN.clear()
    items = []
    for k in range(6):
        f = tmp_path / f"{k}.dcf"
        f.write_bytes(b"x" * (k + 1))           # different sizes: the largest are taken first
        items.append((str(f), f"file{k}"))
    got = parallel.lint_paths(items, Options(), 2, _big_result)
    assert got == [(shown, shown[-1] * (3 << 20)) for _, shown in items]
    # the results are collected by this thread between its own files: no thread of ours
    # competes with the linting one for the GIL (that made -j 2 slower than -j 1)
    assert _THREADS_SEEN and set(_THREADS_SEEN) == {1}
