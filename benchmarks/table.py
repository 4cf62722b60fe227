#!/usr/bin/env python3
"""The table of issue 22: whole processes, as a user runs them, against the alternatives.

    python benchmarks/table.py                  # median of 5 per row
    python benchmarks/table.py --repeat 9 --json out/table.json
    python benchmarks/table.py --skip-alternatives   # dcf2bin rows only (fast)

Every row is a fresh process started from here (``python -m dcf2bin ...`` of this working
tree, or the alternative's own command), timed from start to exit, all with one
interpreter: by default a virtual environment made as README.md installs dcf2bin
(``benchmarks/out/venv``: dcf2bin's dependencies, canopen among them, and dcf-tools for
dcfchk; ``--python system`` for this interpreter, with whatever its site runs at start); the figure is the median
of ``--repeat`` runs, and the memory the largest peak resident set (``ru_maxrss`` of that
process, from ``os.wait4``) over those runs. Each command runs once before it is timed, so
the byte-code caches exist (as for an installed package; they go to
``benchmarks/out/pycache``, not into the tree).

Rows, on the 60,000-variable DCF of ``gen_dcf.py`` (a distinct ParameterName per variable):

  compile     ``dcf2bin compile F -o F.bin``  vs  ``canopen.import_od(F)`` in a process
  validate    ``dcf2bin validate F``          vs  lely's ``dcfchk F`` (PyPI dcf-tools)
  corpus      ``dcf2bin validate -j 1`` vs ``-j 2`` over ../shared/corpus/files
  floor       a process that reads F, decodes it and splits it into lines
  dump, bin2dcf, map, simulate of the same file, against compile (target: within 2x)
  startup     ``dcf2bin --version``, and compile of samples/plc.dcf (target < 0.1 s)

Then the scaling rows: compile and validate in one process (imports not timed, best of
``--repeat``) at 1,000, 10,000 and 60,000 variables, and the time per 1,000 entries (the
targets: within 25 % of each other). The load average is printed with the results.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
OUT = HERE / "out"
CORPUS = REPO.parent / "shared" / "corpus" / "files"
MIB = 1024 * 1024

# issue 22's targets
COMPILE_RATIO, COMPILE_MIB = 20.0, 80.0
VALIDATE_RATIO, VALIDATE_MIB = 15.0, 120.0
JOBS_RATIO = 1.5
SIBLING_RATIO = 2.0
SMALL_COMPILE_S = 0.1
SCALING_SPREAD = 0.25


def child_env(repo: Path) -> dict[str, str]:
    env = dict(os.environ)
    # only the checkout measured (python -m puts the working directory first on the path:
    # the children run in benchmarks/out, which has no dcf2bin package)
    env["PYTHONPATH"] = str(repo)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = str(OUT / "pycache")
    env.pop("DCF2BIN_DEBUG", None)
    return env


def run_once(cmd: list[str], env: dict[str, str]) -> tuple[float, float, int]:
    """(seconds, peak RSS in MiB, exit code) of one process."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                            cwd=OUT)
    _, status, usage = os.wait4(proc.pid, 0)
    elapsed = time.perf_counter() - t0
    proc.returncode = os.waitstatus_to_exitcode(status)
    return elapsed, usage.ru_maxrss / 1024, proc.returncode


def measure(cmd: list[str], repeat: int, env: dict[str, str], ok=(0,)) -> dict:
    _, _, code = run_once(cmd, env)          # warm-up: byte-code caches, page cache
    if code not in ok:
        raise SystemExit(f"{' '.join(cmd)}: exit {code} (expected {ok})")
    times, peaks = [], []
    for _ in range(repeat):
        t, rss, code = run_once(cmd, env)
        times.append(t)
        peaks.append(rss)
    return {"cmd": cmd, "median_s": statistics.median(times), "min_s": min(times),
            "max_s": max(times), "peak_mib": max(peaks), "exit": code}


# The interpreter of the timed processes: a virtual environment made as README.md installs
# dcf2bin (``python3 -m venv``, ``pip install .``), with dcf-tools for dcfchk, so that
# dcf2bin, canopen and dcfchk all start as they do on a user's machine. This machine's own
# Python runs .pth hooks at every start (a sandbox's CA injection that imports certifi, the
# editable install's finder of /work/main): 15-35 ms per process, which is noise beside
# canopen's seconds but a tenth of a compile. ``--python system`` measures with it anyway.
VENV = OUT / "venv"
PYTHON = sys.executable


def ensure_venv(repo: Path, rebuild: bool = False) -> str:
    python = VENV / "bin" / "python"
    if rebuild and VENV.exists():
        shutil.rmtree(VENV)
    if not python.exists():
        print(f"making {VENV} (python -m venv; pip install {repo.name} dcf-tools) ...",
              file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
        subprocess.run([str(python), "-m", "pip", "install", "-q", str(repo), "dcf-tools"],
                       check=True)
    return str(python)


def py(*args: str) -> list[str]:
    return [PYTHON, *args]


def dcf2bin(*args: str) -> list[str]:
    return py("-m", "dcf2bin", *args)


def dcfchk_command() -> list[str] | None:
    here = Path(PYTHON).parent / "dcfchk"    # not a shell shim (pyenv)
    exe = str(here) if here.exists() else shutil.which("dcfchk")
    return [exe] if exe else None


def ensure_file(n: int) -> Path:
    # in a child process: this one stays small, and a child's peak RSS (counted from the
    # fork, before the exec) is its own
    OUT.mkdir(exist_ok=True)
    path = OUT / f"plc_{n}.dcf"
    if not path.exists():
        subprocess.run([sys.executable, str(HERE / "gen_dcf.py"), str(n), "-o", str(path)],
                       check=True)
    return path


# -- scaling, in one process ---------------------------------------------------------------------

def scaling(sizes: list[int], repeat: int, repo: Path) -> list[dict]:
    """In this process (imports done first): compile_path and lint_bytes per size."""
    sys.path.insert(0, str(repo))
    import gc

    from dcf2bin.compiler import compile_path
    from dcf2bin.lint import Options, lint_bytes
    rows = []
    for n in sizes:
        path = ensure_file(n)
        data = path.read_bytes()
        entries = None
        row = {"variables": n}
        for what, call in (("compile", lambda: compile_path(str(path), data=data)),
                           ("validate", lambda: lint_bytes(str(path), data, Options()))):
            best = None
            for _ in range(repeat):
                gc.collect()
                t0 = time.perf_counter()
                res = call()
                t = time.perf_counter() - t0
                best = t if best is None else min(best, t)
                if what == "compile":
                    assert res.ok, [d.format() for d in res.diagnostics][:3]
                    entries = len(res.container.entries)
                del res
            row[what] = best
        row["entries"] = entries
        rows.append(row)
    return rows


# -- the report ----------------------------------------------------------------------------------

def verdict(ok: bool) -> str:
    return "met" if ok else "NOT met"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=5, help="runs per row (median; default 5)")
    ap.add_argument("--size", type=int, default=60000, help="variables of the big file")
    ap.add_argument("--scaling", default="1000,10000,60000",
                    help="sizes of the scaling rows (default 1000,10000,60000)")
    ap.add_argument("--skip-alternatives", action="store_true",
                    help="do not run canopen and dcfchk")
    ap.add_argument("--json", metavar="FILE", help="also write the figures as JSON")
    ap.add_argument("--repo", type=Path, default=REPO,
                    help="the dcf2bin checkout to measure (default: this one; e.g. ../main "
                         "for the figures before a change)")
    ap.add_argument("--python", default="venv",
                    help="interpreter of the timed processes: 'venv' (default: "
                         "benchmarks/out/venv, made on first use), 'system' (this one), "
                         "or a path")
    ap.add_argument("--rebuild-venv", action="store_true",
                    help="make benchmarks/out/venv again (after a dependency changed)")
    args = ap.parse_args(argv)
    repo = args.repo.resolve()
    global PYTHON
    if args.python == "venv":
        OUT.mkdir(exist_ok=True)
        PYTHON = ensure_venv(repo, args.rebuild_venv)
    elif args.python != "system":
        PYTHON = args.python
    env = child_env(repo)
    big = ensure_file(args.size)
    binf = OUT / f"plc_{args.size}.bin"
    r = args.repeat
    res: dict[str, dict] = {}
    res["compile"] = measure(dcf2bin("compile", str(big), "-o", str(binf)), r, env)
    res["validate"] = measure(dcf2bin("validate", str(big)), r, env, ok=(0, 1))
    if not args.skip_alternatives:
        res["canopen"] = measure(py("-c", "import sys, canopen; canopen.import_od(sys.argv[1])",
                                    str(big)), r, env)
        chk = dcfchk_command()
        if chk:
            # dcfchk warns about [DynamicChannels] (CiA 306-3) and exits 1: still a full check
            res["dcfchk"] = measure(chk + [str(big)], r, env, ok=(0, 1))
    help_text = subprocess.run(dcf2bin("validate", "--help"), env=env, capture_output=True,
                               text=True, cwd=OUT).stdout
    if CORPUS.is_dir() and "--jobs" in help_text:
        res["corpus-j1"] = measure(dcf2bin("validate", "-j", "1", str(CORPUS)), r, env,
                                   ok=(0, 1))
        res["corpus-j2"] = measure(dcf2bin("validate", "-j", "2", str(CORPUS)), r, env,
                                   ok=(0, 1))
    res["floor"] = measure(py("-c", "import sys; open(sys.argv[1], 'rb').read().decode()"
                                    ".split('\\n')", str(big)), r, env)
    res["dump"] = measure(dcf2bin("dump", str(binf)), r, env)
    res["bin2dcf"] = measure(dcf2bin("bin2dcf", str(binf), "-o", str(OUT / "back.dcf")), r, env)
    res["map"] = measure(dcf2bin("map", str(big)), r, env)
    res["simulate"] = measure(dcf2bin("simulate", str(binf)), r, env)
    res["version"] = measure(dcf2bin("--version"), r, env)
    res["compile-small"] = measure(dcf2bin("compile", str(repo / "samples" / "plc.dcf"), "-o",
                                           str(OUT / "plc_small.bin")), r, env)
    sizes = [int(s) for s in args.scaling.split(",") if s]
    rows = scaling(sizes, max(3, r), repo)

    c, v = res["compile"], res["validate"]
    print(f"\nissue 22, whole processes, median of {r}, {args.size:,} variables "
          f"({big.stat().st_size / MIB:.2f} MiB), dcf2bin from {repo}, "
          f"interpreter {PYTHON}\n")
    print("| command | dcf2bin | alternative | ratio | target |")
    print("|---|---|---|---|---|")

    def fig(m):
        return f"{m['median_s']:.3f} s, {m['peak_mib']:.0f} MiB"

    if "canopen" in res:
        ratio = res["canopen"]["median_s"] / c["median_s"]
        print(f"| `compile` | {fig(c)} | `canopen.import_od` {fig(res['canopen'])} | "
              f"**{ratio:.1f}x** | 20x, 80 MiB: {verdict(ratio >= COMPILE_RATIO)}, "
              f"{verdict(c['peak_mib'] <= COMPILE_MIB)} |")
    else:
        print(f"| `compile` | {fig(c)} | - | - | 80 MiB: {verdict(c['peak_mib'] <= COMPILE_MIB)} |")
    if "dcfchk" in res:
        ratio = res["dcfchk"]["median_s"] / v["median_s"]
        print(f"| `validate` | {fig(v)} | lely `dcfchk` {fig(res['dcfchk'])} | "
              f"**{ratio:.1f}x** | 15x, 120 MiB: {verdict(ratio >= VALIDATE_RATIO)}, "
              f"{verdict(v['peak_mib'] <= VALIDATE_MIB)} |")
    else:
        print(f"| `validate` | {fig(v)} | - | - | 120 MiB: "
              f"{verdict(v['peak_mib'] <= VALIDATE_MIB)} |")
    if "corpus-j1" in res:
        j1, j2 = res["corpus-j1"], res["corpus-j2"]
        ratio = j1["median_s"] / j2["median_s"]
        print(f"| `validate -j 2` of the corpus | {fig(j2)} | `-j 1` {fig(j1)} | "
              f"**{ratio:.2f}x** | 1.5x: {verdict(ratio >= JOBS_RATIO)} |")
    print(f"| reading and splitting the file alone (the floor) | {fig(res['floor'])} | | | |")
    for name in ("dump", "bin2dcf", "map", "simulate"):
        ratio = res[name]["median_s"] / c["median_s"]
        print(f"| `{name}` | {fig(res[name])} | `compile` {c['median_s']:.3f} s | "
              f"{ratio:.2f}x of compile | within 2x: {verdict(ratio <= SIBLING_RATIO)} |")
    small = res["compile-small"]
    print(f"| `--version` | {fig(res['version'])} | | | |")
    print(f"| `compile samples/plc.dcf` | {fig(small)} | | | < 0.1 s: "
          f"{verdict(small['median_s'] < SMALL_COMPILE_S)} |")

    print(f"\nscaling, in one process (imports not timed), best of {max(3, r)}\n")
    print("| variables | entries | compile | per 1,000 entries | validate | per 1,000 entries |")
    print("|---|---|---|---|---|---|")
    per = {"compile": [], "validate": []}
    for row in rows:
        k = row["entries"] / 1000
        per["compile"].append(row["compile"] / k)
        per["validate"].append(row["validate"] / k)
        print(f"| {row['variables']:,} | {row['entries']:,} | {row['compile']:.3f} s | "
              f"{row['compile'] / k * 1000:.2f} ms | {row['validate']:.3f} s | "
              f"{row['validate'] / k * 1000:.2f} ms |")
    for what, xs in per.items():
        spread = max(xs) / min(xs) - 1
        print(f"{what}: per-1,000 figures within {spread * 100:.0f} % of each other "
              f"(target 25 %: {verdict(spread <= SCALING_SPREAD)})")
    # what each step up in size costs per 1,000 more entries: a fixed part of every file
    # (its device sections, the same in each) drops out here, a cost growing faster than
    # the file does not (information beside the target, not a verdict)
    for what in per:
        steps = [(b[what] - a[what]) / (b["entries"] - a["entries"]) * 1e6
                 for a, b in zip(rows, rows[1:])]
        if steps and min(steps) > 0:
            print(f"{what}: each further 1,000 entries cost "
                  + " / ".join(f"{x:.2f} ms" for x in steps)
                  + f" ({max(steps) / min(steps) - 1:.0%} apart)")
    load = os.getloadavg()
    print(f"\nload average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on "
          f"{os.cpu_count()} CPUs; Python {sys.version.split()[0]}")
    if args.json:
        Path(args.json).write_text(json.dumps({"processes": res, "scaling": rows,
                                               "load": load}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
