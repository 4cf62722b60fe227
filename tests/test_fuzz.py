"""A short deterministic run of benchmarks/fuzz.py: mutated DCFs and containers through
compile (bin and C), validate, export, dump, bin2dcf, simulate and map, and mutated
allocate CSVs through allocate (alone and --into samples/plc.dcf), end without an internal
error or a hang.

The long runs and their figures are in benchmarks/README.md ("The long runs"); rerun with
``python benchmarks/fuzz.py --seed 7 --iterations 12000``.
"""
from __future__ import annotations

import importlib.util
import random
import re
import sys

import pytest

from conftest import ROOT


@pytest.fixture(scope="module")
def fuzz():
    spec = importlib.util.spec_from_file_location("dcf2bin_fuzz", ROOT / "benchmarks" / "fuzz.py")
    mod = importlib.util.module_from_spec(spec)
    sys.modules["dcf2bin_fuzz"] = mod      # its dataclasses look themselves up there
    spec.loader.exec_module(mod)
    return mod


def test_short_run_finds_no_crash(fuzz):
    # samples and fixtures only (no corpus), so the run is the same on every checkout
    report = fuzz.fuzz(seed=1, iterations=300, kind="all", corpus=None, timeout=60)
    assert report.variants == 300
    assert report.by_kind == {"dcf": 100, "container": 100, "csv": 100}
    assert [(c.key, c.variant, c.command) for c in report.crashes] == []
    assert set(report.exit_codes) <= {0, 1, 3}
    assert report.exit_codes.get(1, 0) > 0 and report.exit_codes.get(0, 0) > 0
    assert report.slowest[1] is not None and report.peak_rss_mib > 0


def test_the_new_commands_are_run(fuzz, monkeypatch):
    """simulate and map on DCFs and containers, compile --format c, allocate alone and
    --into samples/plc.dcf: each is among the commands of a short run."""
    seen = []
    real = fuzz.Runner.invoke

    def spy(self, args):
        seen.append(tuple(args))
        return real(self, args)

    monkeypatch.setattr(fuzz.Runner, "invoke", spy)
    report = fuzz.fuzz(seed=2, iterations=30, kind="all", corpus=None)
    assert report.crashes == []

    def ran(pred):
        return any(pred(a) for a in seen)

    assert ran(lambda a: a[0] == "simulate" and a[1].endswith((".dcf", ".eds")))
    assert ran(lambda a: a[0] == "simulate" and a[1].endswith(".bin"))
    assert ran(lambda a: a[0] == "simulate" and "json" in a)
    assert ran(lambda a: a[0] == "map" and a[4].endswith((".dcf", ".eds")))
    assert ran(lambda a: a[0] == "map" and a[4].endswith(".bin"))
    assert ran(lambda a: a[:4] == ("compile", "-q", "--format", "c"))
    assert ran(lambda a: a[0] == "allocate" and "--into" not in a)
    assert ran(lambda a: a[0] == "allocate" and "--into" in a
               and a[a.index("--into") + 1].endswith("plc.dcf"))


def test_a_csv_variant_is_the_same_bytes_every_time_and_below_1_mb(fuzz):
    blobs = [p.read_bytes() for p in fuzz.seed_files("csv", None)] + fuzz.CSV_SEEDS

    def variant(i):
        rng = random.Random(f"5:{i}")
        j = rng.randrange(len(blobs))
        return fuzz.mutate(rng, blobs[j], rng.choice(blobs), "csv")

    first = [variant(i) for i in range(200)]
    assert first == [variant(i) for i in range(200)]
    assert max(len(data) for data, ops in first) < fuzz.MAX_CSV
    assert any(op.startswith("many-rows") for data, ops in first for op in ops)


def test_a_variant_is_the_same_bytes_every_time(fuzz):
    files = fuzz.seed_files("dcf", None)
    blobs = [p.read_bytes() for p in files]

    def variant(i):
        rng = random.Random(f"5:{i}")
        j = rng.randrange(len(files))
        return fuzz.mutate(rng, blobs[j], rng.choice(blobs), "dcf")

    assert [variant(i) for i in range(20)] == [variant(i) for i in range(20)]


def test_a_crash_is_reported_with_where_it_happened(fuzz, monkeypatch):
    from dcf2bin import compiler

    def broken(*args, **kwargs):
        raise RuntimeError("planted")

    monkeypatch.setattr(compiler, "compile_path", broken)
    report = fuzz.fuzz(seed=1, iterations=2, kind="dcf", corpus=None)
    # simulate and map compile a DCF too: each crash is named by its own command's frame
    keys = {c.command[0]: c.key for c in report.crashes}
    # the innermost frame inside the dcf2bin package: the command that called it
    assert re.fullmatch(r"RuntimeError at compile\.py:\d+ in compile_cmd", keys.pop("compile"))
    assert set(keys) <= {"simulate", "map"}
    assert "planted" in report.crashes[0].detail


def test_command_line_exit_status(fuzz, capsys):
    assert fuzz.main(["--seed", "3", "--iterations", "4", "--no-corpus"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("seed 3: 4 variants (container 1, csv 1, dcf 2), ")
    assert "crashes: 0 (0 distinct)\n" in out


@pytest.mark.skipif(not hasattr(__import__("signal"), "setitimer"), reason="needs SIGALRM")
def test_a_hang_is_reported_with_its_command(fuzz, monkeypatch):
    import time

    from dcf2bin import compiler

    def stuck(*args, **kwargs):
        time.sleep(30)

    monkeypatch.setattr(compiler, "compile_path", stuck)
    report = fuzz.fuzz(seed=1, iterations=1, kind="dcf", corpus=None, timeout=0.5)
    assert [(c.key, c.command[0]) for c in report.crashes] == [("Hang", "compile")]


def test_the_network_kinds_find_no_crash(fuzz, monkeypatch):
    """Mutated bus.yml files and .cpj projects through network check (and build): no
    internal error, no hang; every YAML and .cpj mutation is among a short run's."""
    seen = []
    real = fuzz.Runner.invoke

    def spy(self, args):
        seen.append(tuple(args))
        return real(self, args)

    monkeypatch.setattr(fuzz.Runner, "invoke", spy)
    report = fuzz.fuzz(seed=1, iterations=40, kind="network", corpus=None, timeout=60)
    assert report.by_kind == {"yaml": 20, "cpj": 20}
    assert [(c.key, c.variant, c.command) for c in report.crashes] == []
    assert set(report.exit_codes) <= {0, 1, 3} and report.exit_codes.get(1, 0) > 0
    assert any(a[:2] == ("network", "check") and a[2].endswith(".yml") for a in seen)
    assert any(a[:2] == ("network", "check") and a[2].endswith(".cpj") for a in seen)
    assert any(a[:2] == ("network", "build") for a in seen)


def test_the_hostile_network_inputs_end_quickly(fuzz, tmp_path):
    """The cases the issue names, each through network check once: an alias bomb, deep
    nesting, 10,000 slaves, a directory / FIFO / /dev/zero as a node's file."""
    net = fuzz._network()
    folder = net.setup(tmp_path)
    base = net._local((ROOT / "tests/fixtures/network/check/bus.yml").read_bytes())
    rng = random.Random(0)
    variants = [net.y_bomb(rng, base, base)[0], net.y_deep(rng, base, base)[0],
                base + b"".join(b"s%d:\n  dcf: IoX4_8AI.eds\n  node_id: %d\n" % (i, i % 127 + 1)
                                for i in range(10000))]
    for name in ("adir", "fifo", "/dev/zero"):
        variants.append(base.replace(b"dcf: IoX4_8AI.eds", b"dcf: " + name.encode()))
    from click.testing import CliRunner

    from dcf2bin.cli import main
    codes = []
    for data in variants:
        (folder / "v.yml").write_bytes(data)
        res = CliRunner().invoke(main, ["network", "check", str(folder / "v.yml")])
        assert isinstance(res.exception, (SystemExit, type(None))), res.output
        codes.append(res.exit_code)
    # the bomb, the nesting and the repeated node-IDs are errors; the files cannot be read
    assert codes == [1, 1, 1, 3, 3, 3]
