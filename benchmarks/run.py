#!/usr/bin/env python3
"""Benchmark dcf2bin against canopen and configparser on large generated DCFs.

    python benchmarks/run.py [--sizes 6000,60000] [--repeat 3]

For every size N, benchmarks/gen_dcf.py writes benchmarks/out/plc_N.dcf (a PLC
with N CiA 405 network variables), then three tools read that file:

  dcf2bin       dcf2bin.compiler.compile_file(path, CompileOptions()) -> bytes
  canopen       canopen.import_od(path)
  configparser  ConfigParser(strict=False, interpolation=None), optionxform=str
  simulate      dcf2bin.dynod.emulate_bytes(container) -- DynBuildOd's model on the
                container compiled from that file (compiled once, not timed), as
                ``dcf2bin simulate FILE.bin`` does; the report gives simulate/dcf2bin,
                which should stay within 2x
  validate      dcf2bin.lint.lint_bytes(name, data): every validate rule on the file
                (what ``dcf2bin validate FILE`` does); the report gives validate/dcf2bin
  map-F         the same compile, then the variable map in format F (text, csv,
                json, iec, c, svg, html): what ``dcf2bin map FILE --format F``
                does but for writing the file; its child also times compile_file,
                alternating call for call, and the report gives map/compile from
                those (target: within 2x; svg/html within 5 s)

Each (tool, size) pair runs in a fresh subprocess (this script re-invoked as
``run.py --one TOOL PATH``), so imports, caches and memory of one tool do not
affect another.  That subprocess imports the tool first (not timed), times
``--repeat`` calls with time.perf_counter (best of them is reported), then
makes one more call under tracemalloc for the peak traced memory of a call,
and prints one JSON line.  ``--no-memory`` skips that traced call (the
traced call takes several times as long as a timed one); ``--gc-off``
disables the cyclic GC during the timed calls (its full collections make all
three tools look worse than linear on big files); ``--tools`` picks a subset.

The report has the best times, peak MiB, the ratios canopen/dcf2bin and
configparser/dcf2bin, and the linearity of each tool:
(time at largest N / time at smallest N) / (largest N / smallest N), where
~1.0 means linear.  Raw results also go to benchmarks/out/results.json.

Standard library only, plus canopen and dcf2bin (taken from this working
tree, whether or not it is installed).
"""
from __future__ import annotations

import argparse
import gc
import json
import os
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
TOOLS = ("dcf2bin", "canopen", "configparser", "simulate", "validate")
# dcf2bin map FILE --format F, in process: compile + the variable map in that format
MAP_FORMATS = ("text", "csv", "json", "iec", "c", "svg", "html")
MAP_TOOLS = tuple(f"map-{f}" for f in MAP_FORMATS)
# issue 11: every map format within 2x of compile's time; svg/html within 5 s
MAP_PICTURE_LIMIT_S = 5.0
MAP_RATIO_LIMIT = 2.0
MIB = 1024 * 1024


# --------------------------------------------------------------------------
# Child mode: measure one tool on one file.
# --------------------------------------------------------------------------

class Unavailable(Exception):
    """The tool cannot be run (e.g. dcf2bin's compiler API does not exist yet)."""


def load_tool(tool: str):
    """Import the tool and return ``(call, describe)``.

    call(path) does the work; describe(result) gives a short sanity summary
    (so a tool that silently reads nothing is noticed).
    """
    if tool == "dcf2bin":
        sys.path.insert(0, str(REPO))          # the working tree's dcf2bin
        try:
            from dcf2bin.compiler import CompileOptions, compile_file
        except ImportError as e:
            raise Unavailable(
                "dcf2bin.compiler.compile_file / CompileOptions not available "
                f"yet ({e})") from None

        def call(path: Path):
            return compile_file(str(path), CompileOptions())

        def describe(result) -> str:
            return f"{len(result)} bytes container"
        return call, describe

    if tool == "simulate":
        sys.path.insert(0, str(REPO))
        try:
            from dcf2bin.compiler import CompileOptions, compile_file
            from dcf2bin.dynod import emulate_bytes
        except ImportError as e:
            raise Unavailable(f"dcf2bin.dynod not available yet ({e})") from None
        containers: dict = {}

        def call(path: Path):
            return emulate_bytes(containers[path])

        def prepare(path: Path) -> None:      # not timed
            containers[path] = compile_file(str(path), CompileOptions())

        def describe(out) -> str:
            return f"0x{out.code:02X} {out.name}, {len(out.pdos)} PDOs"
        call.prepare = prepare
        return call, describe

    if tool == "validate":
        sys.path.insert(0, str(REPO))
        try:
            from dcf2bin.lint import lint_bytes
        except ImportError as e:
            raise Unavailable(f"dcf2bin.lint not available ({e})") from None

        def call(path: Path):
            return lint_bytes(path.name, path.read_bytes())

        def describe(res) -> str:
            errors = sum(1 for d in res.diagnostics if d.severity.value == "error")
            return f"{len(res.diagnostics)} findings, {errors} errors"
        return call, describe

    if tool in MAP_TOOLS:
        fmt = tool[len("map-"):]
        sys.path.insert(0, str(REPO))
        try:
            from dcf2bin.compiler import CompileOptions, compile_path
            from dcf2bin.plc import varmap
            from dcf2bin.cli.map import render
        except ImportError as e:
            raise Unavailable(f"dcf2bin map not available yet ({e})") from None

        def call(path: Path):
            # what 'dcf2bin map PATH --format FMT' does, but for writing the file
            res = compile_path(str(path), CompileOptions())
            if not res.ok:
                raise RuntimeError(f"{path}: the DCF does not compile")
            was = gc.isenabled()
            gc.disable()
            try:
                vm = varmap.from_result(res, path.name)
                return render(vm, fmt, "byte", "DCF_")
            finally:
                if was:
                    gc.enable()

        def describe(text) -> str:
            return f"{len(text)} characters of {fmt}"
        return call, describe

    if tool == "canopen":
        import canopen

        def call(path: Path):
            return canopen.import_od(str(path))

        def describe(od) -> str:
            return f"{len(od)} objects"
        return call, describe

    if tool == "configparser":
        import configparser

        def call(path: Path):
            cp = configparser.ConfigParser(strict=False, interpolation=None)
            cp.optionxform = str               # keep key case, like canopen
            with open(path, encoding="utf-8") as f:
                cp.read_file(f)
            return cp

        def describe(cp) -> str:
            return f"{len(cp.sections())} sections"
        return call, describe

    raise SystemExit(f"unknown tool {tool!r} (choose from {', '.join(TOOLS + MAP_TOOLS)})")


def measure_one(tool: str, path: Path, repeat: int, memory: bool = True,
                gc_on: bool = True) -> dict:
    """Time ``repeat`` calls, then (if memory) one traced call for the peak.

    gc_on=False disables the cyclic garbage collector during each call: its
    full collections rescan the whole growing heap, which makes every
    pure-Python reader look worse than linear on big files.
    """
    result: dict = {"tool": tool, "path": str(path), "ok": False}
    try:
        call, describe = load_tool(tool)
    except Unavailable as e:
        result["error"] = str(e)
        return result

    times = []
    # a map is compared with a compile timed in the same process, call for call
    # alternating, so that both see the same load of a shared machine
    pair = load_tool("dcf2bin")[0] if tool in MAP_TOOLS else None
    pair_times = []
    try:
        if hasattr(call, "prepare"):
            call.prepare(path)
        for _ in range(repeat):
            if pair is not None:
                gc.collect()
                t0 = time.perf_counter()
                pair(path)
                pair_times.append(time.perf_counter() - t0)
            gc.collect()
            if not gc_on:
                gc.disable()
            t0 = time.perf_counter()
            out = call(path)
            times.append(time.perf_counter() - t0)
            gc.enable()
            summary = describe(out)
            del out

        # Peak of one call, traced separately: tracemalloc slows the call
        # down a lot, so it must not be part of the timed runs.
        peak = None
        if memory:
            gc.collect()
            tracemalloc.start()
            tracemalloc.reset_peak()
            out = call(path)
            peak = tracemalloc.get_traced_memory()[1]
            tracemalloc.stop()
            del out
    except Exception as e:                      # report, don't crash the suite
        result["error"] = _short_error(e)
        result["times"] = times
        return result

    if pair_times:
        result["compile_best"] = min(pair_times)
    result.update(ok=True, times=times, best=min(times), peak_bytes=peak,
                  summary=summary, max_rss_mib=_max_rss_mib())
    return result


def _short_error(e: Exception) -> str:
    """First line of an exception (a CompileError can list thousands)."""
    lines = str(e).strip().splitlines() or [""]
    more = f" (+{len(lines) - 1} more lines)" if len(lines) > 1 else ""
    return f"{type(e).__name__}: {lines[0][:300]}{more}"


def _max_rss_mib() -> float | None:
    """Whole-process peak RSS (interpreter and imports included), if known."""
    try:
        import resource
    except ImportError:                         # not on Windows
        return None
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    # Linux reports KiB, macOS bytes.
    return rss / MIB if sys.platform == "darwin" else rss / 1024


# --------------------------------------------------------------------------
# Parent mode: generate files, run every (size, tool) in a subprocess, report.
# --------------------------------------------------------------------------

def run_child(tool: str, path: Path, repeat: int, memory: bool,
              gc_on: bool) -> dict:
    cmd = [sys.executable, str(Path(__file__).resolve()), "--one", tool,
           str(path), "--repeat", str(repeat)]
    if not memory:
        cmd.append("--no-memory")
    if not gc_on:
        cmd.append("--gc-off")
    proc = subprocess.run(cmd, capture_output=True, text=True)
    lines = proc.stdout.strip().splitlines()
    if proc.returncode != 0 or not lines:
        tail = (proc.stderr.strip().splitlines() or ["(no output)"])[-1]
        return {"tool": tool, "path": str(path), "ok": False,
                "error": f"child exited with {proc.returncode}: {tail}"}
    return json.loads(lines[-1])


def generate_file(n: int, out_dir: Path, denotations: bool = False) -> Path:
    """Write plc_N.dcf, or plc_N_denotations.dcf (skipped when an identical file is
    already there)."""
    from gen_dcf import generate                # HERE is on sys.path (main)

    data = generate(n, denotations).encode("ascii")
    path = out_dir / (f"plc_{n}_denotations.dcf" if denotations else f"plc_{n}.dcf")
    if not (path.exists() and path.read_bytes() == data):
        path.write_bytes(data)
    return path


def _loadavg() -> list[float] | None:
    try:
        return [round(x, 2) for x in os.getloadavg()]
    except (AttributeError, OSError):           # not available on Windows
        return None


def _ratio(a: float | None, b: float | None) -> str:
    return f"{a / b:.2f}x" if a is not None and b else "n/a"


def _table(headers: list[str], rows: list[list[str]]) -> str:
    widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]

    def fmt(cells: list[str]) -> str:
        return "  ".join(c.rjust(w) for c, w in zip(cells, widths))
    return "\n".join([fmt(headers), fmt(["-" * w for w in widths]),
                      *(fmt(r) for r in rows)])


def report(sizes: list[int], file_sizes: dict[int, int],
           results: dict[tuple[int, str], dict], repeat: int,
           memory: bool = True, gc_on: bool = True) -> str:
    def value(n: int, tool: str, key: str) -> float | None:
        r = results.get((n, tool))
        if not r or not r.get("ok"):
            return None
        if key == "time":
            return r["best"]
        return None if r["peak_bytes"] is None else r["peak_bytes"] / MIB

    out = []
    gc_note = "" if gc_on else ", cyclic GC off"
    tables = [("time", f"Wall time, best of {repeat}{gc_note}", "s")]
    if memory:
        tables.append(("peak", "Peak traced memory of one call (tracemalloc)", "MiB"))
    for key, title, unit in tables:
        headers = ["N", "file MiB", *(f"{t} {unit}" for t in TOOLS),
                   "canopen/dcf2bin", "configparser/dcf2bin", "simulate/dcf2bin",
                   "validate/dcf2bin"]
        rows = []
        for n in sizes:
            v = {t: value(n, t, key) for t in TOOLS}
            rows.append([str(n), f"{file_sizes[n] / MIB:.2f}",
                         *("n/a" if v[t] is None else
                           f"{v[t]:.3f}" if key == "time" else f"{v[t]:.1f}"
                           for t in TOOLS),
                         _ratio(v["canopen"], v["dcf2bin"]),
                         _ratio(v["configparser"], v["dcf2bin"]),
                         _ratio(v["simulate"], v["dcf2bin"]),
                         _ratio(v["validate"], v["dcf2bin"])])
        out += [title, _table(headers, rows), ""]

    # Linearity: how time grows from the smallest to the largest size,
    # relative to how the size grows (1.0 = linear, 2.0 = twice as bad).
    lo, hi = min(sizes), max(sizes)
    if lo != hi:
        out.append(f"Linearity, N {lo} -> {hi} (size factor {hi / lo:.1f}); "
                   "time growth / size growth, ~1.0 = linear:")
        for t in TOOLS:
            a, b = value(lo, t, "time"), value(hi, t, "time")
            text = f"{(b / a) / (hi / lo):.2f}" if a and b else "n/a"
            out.append(f"  {t:<13} {text}")
        out.append("")

    map_rows = []
    for n in sizes:
        for fmt in MAP_FORMATS:
            t = value(n, f"map-{fmt}", "time")
            if t is None:
                continue
            base = results[(n, f"map-{fmt}")].get("compile_best")
            if fmt in ("svg", "html"):
                ok = t <= MAP_PICTURE_LIMIT_S
                goal = f"<= {MAP_PICTURE_LIMIT_S:.0f} s"
            else:
                ok = base is not None and t <= MAP_RATIO_LIMIT * base
                goal = f"<= {MAP_RATIO_LIMIT:.0f}x compile"
            map_rows.append([str(n), fmt, f"{base:.3f}" if base else "n/a", f"{t:.3f}",
                             _ratio(t, base), goal,
                             "ok" if ok else "MISSED"])
    if map_rows:
        out += ["dcf2bin map FILE --format F (compile + map, in process), "
                f"best of {repeat}{gc_note}; compile timed in the same process, "
                "alternating with the map",
                _table(["N", "format", "compile s", "map s", "map/compile", "target", ""],
                       map_rows), ""]

    problems = [f"  N={n} {t}: {r['error']}" for (n, t), r in results.items()
                if not r.get("ok")]
    if problems:
        out += ["Not measured:", *sorted(set(problems)), ""]
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description="Time and measure dcf2bin vs. canopen vs. configparser "
                    "on generated CiA 405 PLC DCFs.")
    ap.add_argument("--sizes", default="6000,60000",
                    help="comma-separated numbers of network variables "
                         "(default: 6000,60000)")
    ap.add_argument("--repeat", type=int, default=3,
                    help="timed calls per tool and size; the best counts (default: 3)")
    ap.add_argument("--tools", default=",".join(TOOLS + MAP_TOOLS),
                    help=f"comma-separated subset of {','.join(TOOLS + MAP_TOOLS)} "
                         "(map-F: dcf2bin map --format F)")
    ap.add_argument("--out-dir", type=Path, default=HERE / "out",
                    help="where the DCFs and results.json go (default: benchmarks/out)")
    ap.add_argument("--no-memory", dest="memory", action="store_false",
                    help="skip the tracemalloc run (much faster; no MiB columns)")
    ap.add_argument("--gc-off", dest="gc_on", action="store_false",
                    help="disable the cyclic GC during timed calls, to see the "
                         "scaling of the code itself")
    ap.add_argument("--denotations", action="store_true",
                    help="give every variable a Denotation= of its own, so that no two "
                         "variable sections share their text beyond ParameterName "
                         "(dcf2bin's slower path)")
    ap.add_argument("--one", nargs=2, metavar=("TOOL", "PATH"),
                    help=argparse.SUPPRESS)   # internal: child mode
    args = ap.parse_args(argv)
    if args.repeat < 1:
        ap.error("--repeat must be >= 1")

    if args.one:
        tool, path = args.one
        print(json.dumps(measure_one(tool, Path(path), args.repeat, args.memory,
                                     args.gc_on)))
        return 0

    try:
        sizes = sorted({int(s) for s in args.sizes.split(",") if s.strip()})
    except ValueError:
        ap.error(f"--sizes must be comma-separated integers, got {args.sizes!r}")
    if not sizes or min(sizes) < 1:
        ap.error("--sizes needs at least one positive number")
    sys.path.insert(0, str(HERE))
    from gen_dcf import MAX_VARS
    if max(sizes) > MAX_VARS:
        ap.error(f"--sizes: at most {MAX_VARS} network variables fit the 16-bit "
                 "PI addresses with the generator's type mix (see gen_dcf.py)")
    tools = [t.strip() for t in args.tools.split(",") if t.strip()]
    if unknown := set(tools) - set(TOOLS + MAP_TOOLS):
        ap.error(f"unknown tool(s): {', '.join(sorted(unknown))}")

    args.out_dir.mkdir(parents=True, exist_ok=True)
    results: dict[tuple[int, str], dict] = {}
    file_sizes: dict[int, int] = {}
    for n in sizes:
        path = generate_file(n, args.out_dir, args.denotations)
        file_sizes[n] = path.stat().st_size
        print(f"N={n}: {path} ({file_sizes[n] / MIB:.2f} MiB)", file=sys.stderr)
        for tool in tools:
            r = run_child(tool, path, args.repeat, args.memory, args.gc_on)
            results[(n, tool)] = r
            if r.get("ok"):
                mem = ("" if r["peak_bytes"] is None
                       else f"{r['peak_bytes'] / MIB:7.1f} MiB  ")
                print(f"  {tool:<13} {r['best']:8.3f} s  {mem}({r['summary']})",
                      file=sys.stderr)
            else:
                print(f"  {tool:<13} not measured: {r['error']}", file=sys.stderr)

    print(report(sizes, file_sizes, results, args.repeat, args.memory,
                 args.gc_on))
    machine = {"python": sys.version.split()[0], "platform": sys.platform,
               "cpus": os.cpu_count(), "loadavg": _loadavg()}
    print(f"Python {machine['python']}, {machine['cpus']} CPUs, load average "
          f"{machine['loadavg'] or 'n/a'} at the end (timings on a busy machine are noisy)")
    (args.out_dir / "results.json").write_text(json.dumps(
        {"repeat": args.repeat, "gc": args.gc_on, "denotations": args.denotations,
         "machine": machine,
         "files": {str(n): file_sizes[n] for n in sizes},
         "results": [results[k] | {"n": k[0]} for k in sorted(results)]},
        indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
