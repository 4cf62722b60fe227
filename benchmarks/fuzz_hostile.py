#!/usr/bin/env python3
"""Issue 26's fuzz benchmark: every kind of hostile input through every command that reads it.

    python benchmarks/fuzz_hostile.py                    # seed 26, 300 runs
    python benchmarks/fuzz_hostile.py --runs 1000 --seed 7 --timeout 20
    python benchmarks/fuzz_hostile.py --only fifo,devzero --runs 20 -v
    python benchmarks/fuzz_hostile.py --keep DIR         # keep the input of every bad run

Inputs, each run one of them (the case), made from real files where there are some:

* network files (YAML): tests/fixtures/network, tests/golden/network and tests/fixtures/
  network_show, mutated -- a value of the wrong type, a huge integer (``0x`` and 4,000
  ``F``, 5,000 binary or decimal digits, a long sexagesimal), a node's ``dcf:`` naming a
  FIFO, a ``/dev/zero`` link, a directory, random bytes, a missing file or the network file
  itself, truncation, flipped bytes, repeated lines, 1,000 unknown keys, deep nesting, an
  alias bomb -- and the 3 MB shapes of hostile_shapes.py, random bytes;
* EDS/DCF: samples/, tests/fixtures/network and ../shared/corpus/files, mutated --
  flipped bytes, truncation, a huge integer, a repeated section, 100 KiB of comments, a
  1 MB value, mixed line ends -- and the shapes of hostile_shapes.py at 3 MB, random bytes;
* ``.cpj`` projects: tests/fixtures/network/check/network.cpj mutated (node numbers and
  values of thousands of digits, NodeXDCFName naming the hostile files), the 3 MB .cpj
  shapes, random bytes;
* the input itself a FIFO, a link to ``/dev/zero`` or a directory, named as each kind;
* a network that builds (the golden ones, check/bus.yml, one whose slave's file is
  ``io.dcf``), built into a folder where an output cannot go: a directory at an output's
  name, or the inputs' folder (``-o .``, where ``io.dcf`` would be written over its input).

Commands: a network file (YAML or .cpj) through ``network check``, ``network show``,
``network build -o DIR`` (an empty folder, one with directories at output names, or the
inputs' folder) and ``network download --dry-run``; an EDS through ``validate``, ``compile
-o DIR/x.bin`` and ``download --dry-run -n 5``.

Each run is ``python -m dcf2bin`` of this checkout in a folder of its own (the node files
copied there), in a session of its own, killed with its children after ``--timeout``
seconds, its address space limited to 3 GiB. Printed: runs, tracebacks, exit-70s, runs
killed at the limit, runs over 2 s (wall and CPU), runs over the memory bound (4x the
input plus 60 MiB), the peak memory (max RSS of one run), leftover files (a temporary in
the output folder, or in the input's; a file in ``-o`` after a failed build; compile's
output after a failure; not the lock and manifest ``.dcf2bin-build.lock`` that every
build leaves in its folder by design) -- per case, then each finding with its run number, case and
command, so that ``--only CASE --first N --runs 1`` runs it again.
"""
from __future__ import annotations

import argparse
import os
import random
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter, defaultdict
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

NET = ROOT / "tests" / "fixtures" / "network"
CORPUS = ROOT.parent / "shared" / "corpus" / "files"
MIB = 1 << 20
LIMIT_S = 2.0
MEMORY_LIMIT = 3 << 30

HUGE = ["0x" + "F" * 4000, "9" * 5000, "0b" + "1" * 5000, "1" + ":30" * 2000,
        "-0x" + "F" * 4400, "0" + "7" * 4500, "!!int " + "9" * 4400, '"0x' + "F" * 4000 + '"']
WRONG = HUGE + ["[1, 2]", "{a: 1}", "~", "1.5", "-1", "true", "'x'", "2001-01-01",
                "!!binary AAAA", "1e309", ".nan", "auto", "''", "[]", "*nowhere", "4294967296",
                '"$NODEID+1"', "{index: 0x6000}", "[{index: 1, sub_index: 300}]"]
HOSTILE = ["fifo", "zero.eds", "adir", "random.eds", "empty.eds", "missing.eds", "NETWORK"]


# -- the folder of one run -----------------------------------------------------------------

def setup(folder: Path, rng: random.Random) -> None:
    """The node files the seeds name, and what hostile names point at."""
    for p in NET.glob("*.eds"):
        shutil.copy(p, folder / p.name)
    shutil.copy(NET / "plc.dcf", folder / "plc.dcf")
    shutil.copy(ROOT / "samples" / "device.eds", folder / "device.eds")
    shutil.copytree(NET / "check", folder / "check",
                    ignore=shutil.ignore_patterns("*.py", "*.yml"))
    for where in (folder, folder / "check"):          # the node file of the shapes
        shutil.copy(NET / "canopennode.eds", where / "node.eds")
    shutil.copy(NET / "check" / "io.dcf", folder / "io.dcf")
    for where in (folder, folder / "check"):
        os.mkfifo(where / "fifo")
        os.symlink("/dev/zero", where / "zero.eds")
        (where / "adir").mkdir()
        (where / "random.eds").write_bytes(rng.randbytes(3000))
        (where / "empty.eds").write_bytes(b"")


def yaml_seeds() -> list[tuple[str, bytes]]:
    files = sorted(NET.glob("*.yml")) + sorted((ROOT / "tests" / "golden" / "network").glob(
        "*/bus.yml")) + [NET / "check" / "bus.yml", ROOT / "tests" / "fixtures" /
                         "network_show" / "bus.yml"]
    out = []
    for p in files:
        if p.exists():
            # every dcf: named as it lies in the run's folder
            text = re.sub(rb'(dcf:\s*"?)[^"\n]*?(check/)?([\w.]+\.(?:eds|dcf))',
                          lambda m: m.group(1) + (m.group(2) or b"") + m.group(3),
                          p.read_bytes())
            out.append((p.relative_to(ROOT).as_posix(), text))
    out.append(("builtin", b"master:\n  node_id: 1\n  dcf: plc.dcf\nio:\n  node_id: 5\n"
                           b"  dcf: canopennode.eds\n  heartbeat_producer: 100\n"))
    # a slave whose file has the name of its output (io.dcf): ``build -o .`` must not
    # write over it, nor leave the outputs it wrote before it noticed
    out.append(("builtin-io", b"master:\n  node_id: 1\n  dcf: plc.dcf\n  sync_period: 10000\n"
                              b"  heartbeat_producer: 100\nio:\n  node_id: 2\n  dcf: io.dcf\n"))
    return out


def eds_seeds() -> list[tuple[str, Path]]:
    files = sorted(p for p in (ROOT / "samples").iterdir() if p.suffix in (".eds", ".dcf"))
    files += sorted(NET.glob("*.eds"))
    if CORPUS.is_dir():
        files += sorted(p for p in CORPUS.rglob("*") if p.suffix.lower() in (".eds", ".dcf"))
    return [(os.path.relpath(p, ROOT), p) for p in files]


# -- mutations ------------------------------------------------------------------------------

_VALUE = re.compile(rb"(?m)^(\s*-?\s*[A-Za-z_][\w]*:)[ \t]*(\S.*)$")
_NUMBER = re.compile(rb"(?<=[\s:,\[{-])(?:0[xX][0-9A-Fa-f]+|[0-9]+)(?=[\s,\]}]|$)")
_DCF = re.compile(rb'(dcf:\s*)("?[^"\n]*"?)')


def flip(rng, data: bytes) -> bytes:
    out = bytearray(data)
    for _ in range(rng.randint(1, 8)):
        if out:
            out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def truncate(rng, data: bytes) -> bytes:
    return data[:rng.randrange(len(data) + 1)]


def repeat_line(rng, data: bytes) -> bytes:
    lines = data.split(b"\n")
    k = rng.randrange(len(lines))
    return b"\n".join(lines[:k] + [lines[k]] * rng.choice([2, 100, 20000]) + lines[k + 1:])


def y_value(rng, data):
    spots = list(_VALUE.finditer(data))
    if not spots:
        return data + b"\nx: " + rng.choice(WRONG).encode()
    m = rng.choice(spots)
    return data[:m.start(2)] + rng.choice(WRONG).encode() + data[m.end(2):]


def y_huge(rng, data):
    spots = [m.span() for m in _NUMBER.finditer(data)]
    if not spots:
        return y_value(rng, data)
    a, b = rng.choice(spots)
    return data[:a] + rng.choice(HUGE).encode() + data[b:]


def y_dcf(rng, data):
    spots = list(_DCF.finditer(data))
    name = rng.choice(HOSTILE)
    if not spots:
        return data + f"\nio9:\n  node_id: 9\n  dcf: {name}\n".encode()
    m = rng.choice(spots)
    return data[:m.start(2)] + name.encode() + data[m.end(2):]


def y_keys(rng, data):
    keys = "".join(f"  {rng.choice(['unknown_', 'heartbeat_prodcuer', 'node_idd', 'x'])}"
                   f"{k}: 1\n" for k in range(1000))
    return data.replace(b"\nmaster:\n", b"\nmaster:\n" + keys.encode(), 1) + b"\n"


def y_deep(rng, data):
    depth = rng.choice([63, 65, 1000, 50000])
    return data + f"\ndeep: {'[' * depth}1{']' * depth}\n".encode()


def y_bomb(rng, data):
    width, levels = rng.choice([(10, 9), (30, 6), (9, 12)])
    text = "lol0: &lol0 [1" + ",1" * (width - 1) + "]\n" + "".join(
        f"lol{n}: &lol{n} [" + ",".join([f"*lol{n - 1}"] * width) + "]\n"
        for n in range(1, levels))
    return text.encode() + data + f"\nbomb: *lol{levels - 1}\n".encode()


YAML_MUTATIONS = [y_value, y_huge, y_dcf, y_keys, y_deep, y_bomb, flip, truncate, repeat_line]


def e_huge(rng, data):
    keys = [m.span(1) for m in re.finditer(rb"(?mi)^(?:DefaultValue|ParameterValue|SubNumber|"
                                           rb"DataType|LowLimit|HighLimit|NodeID)=(.*)$", data)]
    if not keys:
        return data + b"\n[2000]\nDefaultValue=" + rng.choice(HUGE).encode() + b"\n"
    a, b = rng.choice(keys)
    return data[:a] + rng.choice(HUGE).strip('"').encode() + data[b:]


def e_section(rng, data):
    heads = [m.start() for m in re.finditer(rb"(?m)^\[", data)]
    if not heads:
        return data + data
    a = rng.choice(heads)
    b = data.find(b"\n[", a + 1)
    return data + b"\n" + data[a:b if b > 0 else len(data)]


def e_comments(rng, data):
    at = rng.randrange(len(data) + 1)
    at = data.rfind(b"\n", 0, at) + 1
    return data[:at] + b"".join(b"; " + b"c" * 1021 + b"\n" for _ in range(100)) + data[at:]


def e_value(rng, data):
    return data + (b"\n[2FFF]\nParameterName=Blob\nObjectType=0x7\nDataType=0x000F\n"
                   b"AccessType=rw\nDefaultValue=" + b"AB" * (512 * 1024) + b"\n")


def e_line_ends(rng, data):
    return data.replace(b"\r\n", b"\n").replace(b"\n", b"\r\n", rng.randint(1, 50))


EDS_MUTATIONS = [flip, truncate, repeat_line, e_huge, e_section, e_comments, e_value,
                 e_line_ends]


def c_node(rng, data):
    what = rng.choice(["Node" + "9" * 5000 + "Present=1", "Node2Present=" + HUGE[0],
                       "Nodes=" + HUGE[1], "Node" + "0" * 70 + "2Present=1",
                       f"Node2DCFName={rng.choice(HOSTILE[:-1])}", "Node128Present=1"])
    return data.replace(b"[Topology]\n", b"[Topology]\n" + what.encode() + b"\n", 1)


CPJ_MUTATIONS = [c_node, flip, truncate, repeat_line]


# -- the cases ------------------------------------------------------------------------------
# Each makes the input in ``folder`` and returns (its path, its kind: yaml, cpj or eds).

def case_yaml(rng, folder, seeds):
    name, data = rng.choice(seeds["yaml"])
    for mutate in rng.sample(YAML_MUTATIONS, rng.randint(1, 3)):
        data = mutate(rng, data)
    p = folder / "bus.yml"
    p.write_bytes(data.replace(b"dcf: NETWORK", b"dcf: bus.yml"))
    return p, "yaml"


def case_eds(rng, folder, seeds):
    name, src = rng.choice(seeds["eds"])
    data = src.read_bytes()
    for mutate in rng.sample(EDS_MUTATIONS, rng.randint(1, 3)):
        data = mutate(rng, data)
    p = folder / ("x.dcf" if src.suffix.lower() == ".dcf" else "x.eds")
    p.write_bytes(data)
    return p, "eds"


def case_cpj(rng, folder, seeds):
    data = (NET / "check" / "network.cpj").read_bytes()
    for mutate in rng.sample(CPJ_MUTATIONS, rng.randint(1, 2)):
        data = mutate(rng, data)
    p = folder / "check" / "net.cpj"
    p.write_bytes(data)
    return p, "cpj"


def case_huge(rng, folder, seeds):
    """A huge integer where a network file, a .cpj or an EDS has an integer."""
    kind = rng.choice(["yaml", "cpj", "eds"])
    if kind == "yaml":
        _, data = rng.choice(seeds["yaml"])
        p = folder / "bus.yml"
        p.write_bytes(y_huge(rng, data))
    elif kind == "cpj":
        p = folder / "check" / "net.cpj"
        p.write_bytes(c_node(rng, (NET / "check" / "network.cpj").read_bytes()))
    else:
        _, src = rng.choice(seeds["eds"])
        p = folder / "x.eds"
        p.write_bytes(e_huge(rng, src.read_bytes()))
    return p, kind


def case_shape(rng, folder, seeds):
    """A shape of hostile_shapes.py at 3 MB (made once per fuzz run, copied)."""
    name = rng.choice(sorted(seeds["shapes"]))
    kind, src = seeds["shapes"][name]
    p = folder / src.name if kind != "cpj" else folder / "check" / src.name
    shutil.copy(src, p)
    return p, kind


def case_random(rng, folder, seeds):
    kind = rng.choice(["yaml", "cpj", "eds"])
    p = {"yaml": folder / "bus.yml", "cpj": folder / "check" / "net.cpj",
         "eds": folder / "x.eds"}[kind]
    p.write_bytes(rng.randbytes(rng.choice([0, 1, 100, 3000, 1 << 20])))
    return p, kind


def case_nesting(rng, folder, seeds):
    _, data = rng.choice(seeds["yaml"])
    p = folder / "bus.yml"
    p.write_bytes(rng.choice([y_deep, y_bomb])(rng, data))
    return p, "yaml"


def case_build(rng, folder, seeds):
    """A network that builds, into a folder where an output cannot go (see OUTPUTS):
    nothing may be left of a build that failed."""
    good = [d for name, d in seeds["yaml"] if name.startswith(("builtin", "tests/golden"))
            or name.endswith("check/bus.yml")]
    p = folder / "bus.yml"
    p.write_bytes(rng.choice(good))
    return p, "build"


def _special(make):
    def case(rng, folder, seeds):
        kind = rng.choice(["yaml", "cpj", "eds"])
        p = {"yaml": folder / "n.yml", "cpj": folder / "check" / "n.cpj",
             "eds": folder / "n.eds"}[kind]
        make(p)
        return p, kind
    return case


CASES = {
    "yaml": case_yaml, "eds": case_eds, "cpj": case_cpj, "huge-integer": case_huge,
    "shape-3mb": case_shape, "random-bytes": case_random, "nesting": case_nesting,
    "build-output": case_build,
    "fifo": _special(os.mkfifo),
    "devzero": _special(lambda p: os.symlink("/dev/zero", p)),
    "directory": _special(lambda p: p.mkdir()),
}
WEIGHTS = {"yaml": 26, "eds": 20, "cpj": 10, "huge-integer": 10, "shape-3mb": 10,
           "random-bytes": 6, "nesting": 6, "build-output": 8, "fifo": 3, "devzero": 3,
           "directory": 2}


# the output folder of network build: empty, with a directory where an output goes, or
# the folder of the inputs (-o .)
OUTPUTS = ["empty", "blocked", "inputs"]
BLOCKING = ["plc.dcf", "master.dcf", "io.bin", "io.dcf", "io1.bin", "cia402_device_1.dcf"]


def commands(kind: str, path: Path, out: Path) -> list[list[str]]:
    if kind == "build":
        return [["network", "build", str(path), "-o", str(out)]]
    if kind == "eds":
        return [["validate", str(path)], ["compile", str(path), "-o", str(out / "x.bin")],
                ["download", "--dry-run", "-n", "5", str(path)]]
    return [["network", "check", str(path)], ["network", "show", str(path)],
            ["network", "build", str(path), "-o", str(out)],
            ["network", "download", "--dry-run", str(path)]]


def output_folder(rng, folder: Path, path: Path, out: Path, cmd: list[str]) -> list[str]:
    """The command with its build folder chosen (``OUTPUTS``)."""
    if cmd[:2] != ["network", "build"]:
        return cmd
    how = rng.choice(OUTPUTS)
    if how == "blocked":
        for name in BLOCKING:
            (out / name).mkdir()
    elif how == "inputs":
        return cmd[:-1] + [str(path.parent)]
    return cmd


# -- one run --------------------------------------------------------------------------------

def _limits():
    os.setsid()
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def run(args: list[str], cwd: Path, timeout: float) -> dict:
    """One process: exit code, wall and CPU seconds and peak RSS (``os.wait4``: of that
    process alone; this process stays small, since a child's peak starts at its
    parent's when forked), whether it was killed at ``timeout``, its output."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), NO_COLOR="1")
    env.pop("DCF2BIN_DEBUG", None)
    keep = cwd.parent / f"{cwd.name}.out", cwd.parent / f"{cwd.name}.err"   # not in cwd
    with open(keep[0], "w+b") as out, open(keep[1], "w+b") as err:
        t0 = time.perf_counter()
        proc = subprocess.Popen([sys.executable, "-m", "dcf2bin", *args], cwd=cwd, env=env,
                                stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                preexec_fn=_limits)
        killed = False
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - t0 > timeout:
                killed = True
                os.killpg(proc.pid, signal.SIGKILL)
                _, status, usage = os.wait4(proc.pid, 0)
                break
            time.sleep(0.01)
        wall = time.perf_counter() - t0
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        text_out = out.read().decode("utf-8", "replace")
        text_err = err.read().decode("utf-8", "replace")
    keep[0].unlink()
    keep[1].unlink()
    return {"code": proc.returncode, "wall": wall, "killed": killed,
            "cpu": usage.ru_utime + usage.ru_stime, "rss": usage.ru_maxrss / 1024,
            "out": text_out, "err": text_err}


# network build's lock and manifest of the files it wrote: there after every build into
# the folder, by design (dcf2bin.fileio.journal, man dcf2bin-network-build); after a failed
# run it counts like any file the run made or changed
BUILD_LOCK = ".dcf2bin-build.lock"


def leftovers(folder: Path, out: Path, before: dict, code: int) -> list[str]:
    """Temporaries in the input's and the output's folder (a journal of a build, a
    ``.dcf2bin-*.tmp``); after a failure, the files made or changed in the output folder."""
    found = []
    for where in {folder, folder / "check", out}:
        if where.is_dir():
            found += [str(p.relative_to(folder)) for p in where.iterdir()
                      if p.name != BUILD_LOCK and (p.name.startswith(".dcf2bin")
                                                   or p.name.endswith(".tmp"))]
    if code != 0 and out.is_dir():
        found += [f"{p.relative_to(folder)} (after exit {code})" for p in out.iterdir()
                  if p.name not in before or (p.is_file() and not p.is_symlink()
                                              and p.stat().st_mtime_ns != before[p.name])]
    return found


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--runs", type=int, default=300)
    ap.add_argument("--seed", type=int, default=26)
    ap.add_argument("--timeout", type=float, default=10.0,
                    help="seconds before a run is killed (a hang)")
    ap.add_argument("--only", help="comma-separated cases: " + ", ".join(CASES))
    ap.add_argument("--first", type=int, default=1, help="number of the first run")
    ap.add_argument("--keep", metavar="DIR", help="keep the folder of every bad run here")
    ap.add_argument("-v", "--verbose", action="store_true", help="one line per run")
    args = ap.parse_args()
    cases = args.only.split(",") if args.only else list(CASES)
    work = Path(tempfile.mkdtemp(prefix="fuzz-hostile-"))
    # the 3 MB shapes, made by a process of their own (this one stays small: see run)
    listing = subprocess.run([sys.executable, str(HERE / "hostile_shapes.py"), "--write",
                              str(work / "shapes"), "--network-mib", "3", "--eds-mib", "3"],
                             check=True, capture_output=True, text=True).stdout
    shapes = {}
    for line in listing.splitlines():
        _, name, _, path = line.split(None, 3)
        ext = Path(path).suffix
        shapes[name] = ("cpj" if ext == ".cpj" else "yaml" if ext == ".yml" else "eds",
                        Path(path))
    seeds = {"yaml": yaml_seeds(), "eds": eds_seeds(), "shapes": shapes}
    stats: dict[str, Counter] = defaultdict(Counter)
    peak: dict[str, tuple[float, str]] = {}
    findings: list[tuple[str, int, str, str, str]] = []
    t_start = time.perf_counter()
    try:
        for n in range(args.first, args.first + args.runs):
            rng = random.Random(f"{args.seed}:{n}")
            case = rng.choices(cases, [WEIGHTS[c] for c in cases])[0]
            folder = work / f"run{n}"
            folder.mkdir()
            setup(folder, rng)
            path, kind = CASES[case](rng, folder, seeds)
            out = folder / "out"
            out.mkdir()
            cmd = output_folder(rng, folder, path, out, rng.choice(commands(kind, path, out)))
            target = Path(cmd[-1]) if cmd[:2] == ["network", "build"] else out
            before = {p.name: p.stat().st_mtime_ns for p in target.iterdir()}
            size = path.stat().st_size if path.is_file() and not path.is_symlink() else 0
            r = run(cmd, folder, args.timeout)
            shown = " ".join(a if len(a) < 60 else a[:57] + "..." for a in cmd)
            shown = shown.replace(str(folder) + "/", "").replace(str(folder), ".")
            s = stats[case]
            s["runs"] += 1
            s[f"code {r['code']}"] += 1
            bad = []
            if "Traceback (most recent call last)" in r["out"] + r["err"]:
                s["tracebacks"] += 1
                bad.append("traceback")
            if r["code"] == 70:
                s["exit 70"] += 1
                bad.append("exit 70")
            if r["killed"]:
                s["killed"] += 1
                bad.append(f"killed after {args.timeout:g} s")
            if r["wall"] > LIMIT_S:
                s["over 2 s wall"] += 1
            if r["cpu"] > LIMIT_S:
                s["over 2 s CPU"] += 1
                bad.append(f"{r['cpu']:.1f} s CPU")
            if r["rss"] > 4 * size / MIB + 60:
                s["over memory bound"] += 1
                bad.append(f"{r['rss']:.0f} MiB RSS for {size / MIB:.1f} MiB")
            if r["rss"] > peak.get(case, (0, ""))[0]:
                peak[case] = (r["rss"], f"run {n}: {shown}")
            left = leftovers(folder, target, before, r["code"])
            if left:
                s["leftovers"] += 1
                bad.append("left " + ", ".join(left[:3]))
            if bad:
                last = (r["err"].strip().splitlines() or [""])[-1][:160]
                findings.append((case, n, shown, "; ".join(bad), last))
                if args.keep:
                    shutil.copytree(folder, Path(args.keep) / f"run{n}", symlinks=True,
                                    ignore=shutil.ignore_patterns("fifo", "n.yml", "n.eds",
                                                                  "n.cpj"))
            if args.verbose:
                print(f"{n:5} {case:13} exit {r['code']:3} {r['wall']:6.2f} s "
                      f"{r['rss']:6.0f} MiB  {shown}  {'; '.join(bad)}", flush=True)
            shutil.rmtree(folder, ignore_errors=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    report(stats, peak, findings, args, time.perf_counter() - t_start)
    return 1 if any(s["tracebacks"] or s["exit 70"] for s in stats.values()) else 0


COLUMNS = ["runs", "tracebacks", "exit 70", "killed", "over 2 s wall", "over 2 s CPU",
           "over memory bound", "leftovers"]


def report(stats, peak, findings, args, elapsed) -> None:
    total = Counter()
    for s in stats.values():
        total.update(s)
    print(f"seed {args.seed}, runs {args.first}..{args.first + args.runs - 1}, "
          f"timeout {args.timeout:g} s, {elapsed:.0f} s\n")
    print("| case | " + " | ".join(COLUMNS) + " | peak RSS MiB | exit codes |")
    print("|---" * (len(COLUMNS) + 3) + "|")
    for case in [c for c in CASES if c in stats] + ["all"]:
        s = total if case == "all" else stats[case]
        rss = max((v[0] for v in peak.values()), default=0) if case == "all" else peak[case][0]
        codes = ", ".join(f"{k[5:]}: {v}" for k, v in sorted(
            s.items(), key=lambda kv: int(kv[0][5:]) if kv[0].startswith("code ") else 0)
            if k.startswith("code ")) or "-"
        print(f"| {case} | " + " | ".join(str(s[c]) for c in COLUMNS) +
              f" | {rss:.0f} | {codes} |")
    if peak:
        rss, where = max(peak.values())
        print(f"\npeak memory: {rss:.0f} MiB ({where})")
    load = os.getloadavg()
    print(f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f} on {os.cpu_count()} CPUs")
    if findings:
        print(f"\n{len(findings)} run(s) with a finding (case, run, command: what; last line "
              "of stderr):")
        for case, n, shown, bad, last in findings:
            print(f"  {case} run {n}: {shown}: {bad}" + (f"  [{last}]" if last else ""))


if __name__ == "__main__":
    sys.exit(main())
