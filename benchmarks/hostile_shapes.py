#!/usr/bin/env python3
"""Issue 26 items 4 and 5: the cost of a hostile input grows with its size, no faster.

    python benchmarks/hostile_shapes.py                  # every shape, median of 3
    python benchmarks/hostile_shapes.py --only unknown-slave,deep --repeat 5
    python benchmarks/hostile_shapes.py --network-mib 3 --eds-mib 60
    python benchmarks/hostile_shapes.py --write DIR      # only the files

Network files (YAML, ``--network-mib``, 3 MiB by default), one per shape: many unknown
keys (under ``options:``, in a slave, in a PDO, at the top of a ``nodes:`` layout), near
misses of known keys, many slaves, long lists (a PDO mapping, ``sdo:``, a 990,000-element
list), deep nesting, a long text and a long key, many anchors and aliases, an alias bomb;
and ``.cpj`` projects of as many unknown keys, repeated keys or ``[TopologyN]`` sections.
Each goes through ``dcf2bin network check`` and ``network show`` (verdict: under 2 s of CPU
time, and the memory bound below; ``--network-mib 60`` shows the memory of the largest).

EDS files (``--eds-mib``, 60 MiB by default, under the 64 MiB input cap): a valid EDS with
60,000 comment lines of 1 KiB (at its start, inside a section, at its end; after a repeated
section, which the exact line-by-line reader reads), one huge DOMAIN value, many sections
(arrays of 254 sub-objects), 5 million short unknown keys (``Key0000001=1``; also after a
repeated section, read by the exact reader), one key repeated 10 million times, 5.7 million
11-byte sections, long lines of unknown keys. Each goes through ``dcf2bin validate`` and
``compile`` (verdict: peak resident memory within 4x the file's size plus 60 MiB, the bound
of every input).

Every row is a fresh process (``python -m dcf2bin`` of this checkout), timed from start to
exit; the figures are the medians of ``--repeat`` runs of its wall time and of its CPU time
(user + system, from ``os.wait4``; the verdict of the network rows is taken on CPU time,
which other jobs on a shared machine disturb far less), the memory the largest peak
resident set of those runs (``ru_maxrss``: the whole process, interpreter and imports
included). Files go to ``benchmarks/out/hostile/``.
"""
from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
OUT = HERE / "out" / "hostile"
MIB = 1 << 20
NODE_EDS = REPO / "tests" / "fixtures" / "network" / "canopennode.eds"
BASE_EDS = REPO / "samples" / "device.eds"
TIME_LIMIT = 2.0             # item 4: a 3 MB network file of any shape, under 2 s
MEMORY_FACTOR, MEMORY_EXTRA = 4, 60   # item 5: peak RSS within 4x the size + 60 MiB

HEAD = "master:\n  node_id: 1\n"
SLAVE = "io:\n  node_id: 5\n  dcf: node.eds\n"


def _fill(size: int, head: str, line, tail: str = "") -> str:
    """``head``, then ``line(i)`` for i = 0, 1, ... until the text has ``size`` bytes."""
    parts, n, i = [head], len(head) + len(tail), 0
    while n < size:
        s = line(i)
        parts.append(s)
        n += len(s)
        i += 1
    parts.append(tail)
    return "".join(parts)


def _near_misses():
    """Keys one edit away from a slave's keys (a letter dropped, doubled or swapped), then
    longer ones (a key with a number after it), endlessly and each once."""
    from itertools import count
    keys = ("heartbeat_producer", "heartbeat_consumer", "reset_communication",
            "life_time_factor", "revision_number", "software_version", "serial_number")
    seen = set()
    for k in keys:
        for i in range(len(k)):
            for v in (k[:i] + k[i + 1:], k[:i] + k[i] + k[i:],
                      k[:i] + k[i + 1:i + 2] + k[i:i + 1] + k[i + 2:]):
                if v not in seen and v != k:
                    seen.add(v)
                    yield v
    for n in count():
        yield f"{keys[n % len(keys)]}_{n}"


def network_shapes(size: int) -> dict[str, str]:
    """name -> YAML text of about ``size`` bytes."""
    near = _near_misses()
    depth = 60
    nested = "[" * depth + "1" + "]" * depth
    return {
        "unknown-options": _fill(size, "options:\n", lambda i: f"  option_key_{i:07d}: 1\n",
                                 HEAD + SLAVE),
        "unknown-slave": _fill(size, HEAD + SLAVE, lambda i: f"  unknown_key_{i:07d}: 1\n"),
        "unknown-pdo": _fill(size, HEAD + SLAVE + "  tpdo:\n    1:\n",
                             lambda i: f"      pdo_key_{i:07d}: 1\n"),
        "unknown-top": _fill(size, HEAD + "nodes:\n  io:\n    node_id: 5\n    dcf: node.eds\n",
                             lambda i: f"top_key_{i:07d}: 1\n"),
        "near-misses": _fill(size, HEAD + SLAVE, lambda i: f"  {next(near)}: 1\n"),
        "slaves": _fill(size, HEAD, lambda i: f"s{i}:\n  node_id: {i % 126 + 2}\n"
                                              "  dcf: node.eds\n"),
        "mapping-list": _fill(size, HEAD + SLAVE + "  tpdo:\n    1:\n      mapping:\n",
                              lambda i: "        - {index: 0x2000, sub_index: 1}\n"),
        "sdo-list": _fill(size, HEAD + SLAVE + "  sdo:\n",
                          lambda i: f"    - {{index: 0x1017, sub_index: 0, value: {i}}}\n"),
        "long-list": _fill(size, HEAD + SLAVE + "  driver: [", lambda i: "1,", "1]\n"),
        "deep": _fill(size, HEAD + SLAVE, lambda i: f"  deep_{i:07d}: {nested}\n"),
        "long-text": HEAD + SLAVE + "  package: " + "x" * size + "\n",
        "long-key": HEAD + SLAVE + "  ? " + "k" * size + "\n  : 1\n",
        "anchors": _fill(size, HEAD + SLAVE,
                         lambda i: f"  a{i}: &a{i} {{x: 1}}\n  b{i}: *a{i}\n"),
        "aliased-sdo": (HEAD + SLAVE + "  sdo: &s [" + ", ".join(
            ["{index: 0x1017, sub_index: 0, value: 1}"] * 1000) + "]\n"
            + "".join(f"s{n}:\n  node_id: {n}\n  dcf: node.eds\n  sdo: *s\n"
                      for n in range(6, 128))),
        "defaults-sdo": _fill(size, HEAD + "defaults:\n  dcf: node.eds\n  sdo:\n",
                              lambda i: f"    - {{index: 0x1017, sub_index: 0, value: {i}}}\n",
                              "nodes:\n" + "".join(f"  s{n}: {{node_id: {n}}}\n"
                                                   for n in range(2, 128))),
        "alias-bomb": HEAD + SLAVE + "  driver: " + "".join(
            f"\n    - &l{k} [" + ", ".join([f"*l{k - 1}" if k else "1"] * 10) + "]"
            for k in range(12)) + "\n",
    }


def cpj_shapes(size: int) -> dict[str, str]:
    """name -> .cpj text of about ``size`` bytes (the node file: node.eds)."""
    head = "[Topology]\nNetName=n\nNodes=1\nNode2Present=1\nNode2DCFName=node.eds\n"
    return {
        "cpj-unknown-keys": _fill(size, head, lambda i: f"Key{i:07d}=1\n"),
        "cpj-repeats": _fill(size, head, lambda i: f"Node{'0' * (i % 50 + 1)}2Name=n{i}\n"),
        "cpj-topologies": _fill(size, head, lambda i: f"[Topology{i + 2}]\nNetName=n\n"),
    }


def _with_objects(base: bytes, indexes: list[int]) -> bytes:
    """``base`` with ``indexes`` added to its [ManufacturerObjects] list."""
    start = base.index(b"[ManufacturerObjects]")
    end = base.index(b"\n[", start) + 1
    listed = [int(line.split(b"=")[1], 16) for line in base[start:end].splitlines()[2:]
              if b"=" in line] + indexes
    section = (b"[ManufacturerObjects]\nSupportedObjects=%d\n" % len(listed)
               + b"".join(b"%d=0x%04X\n" % (k + 1, x) for k, x in enumerate(listed)) + b"\n")
    return base[:start] + section + base[end:]


def eds_shapes(size: int) -> dict[str, bytes]:
    """name -> EDS bytes of about ``size`` bytes, each a valid EDS plus the bulk."""
    base = BASE_EDS.read_bytes()
    first = base.index(b"\n", base.index(b"[DeviceInfo]")) + 1     # a section's first line
    comment = b"; " + b"x" * 1021 + b"\n"            # 1 KiB lines
    comments = comment * (size // len(comment))
    line = b"Unknown_%07d=" + b"v" * (64 * 1024 - 17) + b"\n"       # 64 KiB, each its key
    n_subs = 254

    def array(index: int) -> bytes:
        out = [b"[%04X]\nParameterName=Array %04X\nObjectType=0x8\nSubNumber=%d\n\n"
               % (index, index, n_subs + 1),
               b"[%04Xsub0]\nParameterName=n\nObjectType=0x7\nDataType=0x0005\n"
               b"AccessType=ro\nDefaultValue=%d\n\n" % (index, n_subs)]
        out += [b"[%04Xsub%X]\nParameterName=Value %d\nObjectType=0x7\nDataType=0x0007\n"
                b"AccessType=rw\nDefaultValue=%d\n\n" % (index, s, s, s)
                for s in range(1, n_subs + 1)]
        return b"".join(out)

    sections, index = [], 0x3000
    total = len(base)
    while total < size and index < 0x6000:
        sections.append(array(index))
        total += len(sections[-1])
        index += 1
    domain = (b"[3000]\nParameterName=Blob\nObjectType=0x7\nDataType=0x000F\nAccessType=rw\n"
              b"DefaultValue=" + b"AB" * (size // 2) + b"\n\n")
    return {
        "comments-at-start": comments + base,
        "comments-at-end": base + comments,
        "comments-in-section": base[:first] + comments + base[first:],
        "huge-value": _with_objects(base, [0x3000]) + b"\n" + domain,
        "many-sections": _with_objects(base, list(range(0x3000, index))) + b"\n"
        + b"".join(sections),
        "comments-exact": base + b"\n[FileInfo]\nFileName=again.eds\n" + comments,
        "many-keys": base[:first] + b"".join(b"Key%07d=1\n" % k for k in range(size // 13))
        + base[first:],
        # the same after a repeated section: the exact line-by-line reader's
        "many-keys-exact": base + b"\n[FileInfo]\nFileName=again.eds\n[Keys]\n"
        + b"".join(b"Key%07d=1\n" % k for k in range(size // 13)),
        # one key repeated on every line (each a DCF010 finding, the first 1,000 kept)
        "repeated-key": base[:first] + b"Key=1\n" * (size // 6) + base[first:],
        # 5.7 million sections of 11 bytes: the first 1,048,576 read (DCF015)
        "tiny-sections": base + b"".join(b"[K%07d]\n" % k for k in range(size // 11)),
        "long-lines": base[:first] + b"".join(line % k for k in range(size // len(line)))
        + base[first:],
    }


def write(folder: Path, network_size: int, eds_size: int, only=None) -> list[tuple]:
    """Write every shape (``only``: those names) -> [(kind, name, path)]."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "node.eds").write_bytes(NODE_EDS.read_bytes())
    out = []
    for name, text in network_shapes(network_size).items():
        if only is None or name in only:
            p = folder / f"{name}.yml"
            p.write_text(text)
            out.append(("network", name, p))
    for name, text in cpj_shapes(network_size).items():
        if only is None or name in only:
            p = folder / f"{name}.cpj"
            p.write_text(text)
            out.append(("network", name, p))
    for name, data in eds_shapes(eds_size).items():
        if only is None or name in only:
            p = folder / f"{name}.eds"
            p.write_bytes(data)
            out.append(("eds", name, p))
    return out


def _limit():
    # a shape that is not met must not take the machine with it: 4 GiB of address space
    # (a MemoryError is exit 70, which the table shows)
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))


def run_once(cmd: list[str], env: dict, cwd: Path) -> tuple[float, float, float, int]:
    """(wall seconds, CPU seconds, peak RSS in MiB, exit code) of one process."""
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env=env, cwd=cwd, preexec_fn=_limit)
    _, status, usage = os.wait4(proc.pid, 0)
    return (time.perf_counter() - t0, usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024,
            os.waitstatus_to_exitcode(status))


def commands(kind: str, path: Path) -> list[tuple[str, list[str]]]:
    if kind == "network":
        return [("network check", ["network", "check", str(path)]),
                ("network show", ["network", "show", str(path)])]
    return [("validate", ["validate", str(path)]),
            ("compile", ["compile", str(path), "-o", os.devnull])]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--network-mib", type=float, default=3.0)
    ap.add_argument("--eds-mib", type=float, default=60.0)
    ap.add_argument("--only", help="comma-separated shape names")
    ap.add_argument("--write", metavar="DIR", help="only write the files to DIR")
    args = ap.parse_args()
    only = set(args.only.split(",")) if args.only else None
    if args.write:
        files = write(Path(args.write), int(args.network_mib * MIB), int(args.eds_mib * MIB),
                      only)
        for kind, name, p in files:
            print(f"{kind:8} {name:20} {p.stat().st_size:>10} {p}")
        return 0
    # The files are made by a process of their own: a child's peak RSS (ru_maxrss) starts
    # at its parent's when it is forked, so this process must never hold them.
    folder = OUT
    listing = subprocess.run([sys.executable, __file__, "--write", str(folder),
                              "--network-mib", str(args.network_mib), "--eds-mib",
                              str(args.eds_mib)] + (["--only", args.only] if args.only else []),
                             check=True, capture_output=True, text=True).stdout
    files = [(kind, name, Path(path)) for kind, name, _, path in
             (line.split(None, 3) for line in listing.splitlines())]
    env = dict(os.environ, PYTHONPATH=str(REPO), NO_COLOR="1")
    env.pop("DCF2BIN_DEBUG", None)
    py = [sys.executable, "-m", "dcf2bin"]
    print("| shape | file | command | exit | wall s | CPU s | max RSS MiB | verdict |")
    print("|---|---|---|---|---|---|---|---|")
    failed = 0
    for kind, name, p in files:
        size = p.stat().st_size
        for label, args_ in commands(kind, p):
            run_once(py + args_, env, folder)              # warm-up: byte-code caches
            runs = [run_once(py + args_, env, folder) for _ in range(args.repeat)]
            secs = statistics.median(r[0] for r in runs)
            cpu = statistics.median(r[1] for r in runs)
            rss = max(r[2] for r in runs)
            codes = sorted({r[3] for r in runs})
            bound = MEMORY_FACTOR * size / MIB + MEMORY_EXTRA
            ok_rss = rss <= bound
            verdict = f"{'met' if ok_rss else 'NOT met'} (<= {bound:.0f} MiB)"
            ok = ok_rss and 70 not in codes
            if kind == "network":
                # CPU time: on a machine shared with other jobs, wall time measures them
                ok_cpu = cpu < TIME_LIMIT
                ok = ok and ok_cpu
                verdict = f"{'met' if ok_cpu else 'NOT met'} (CPU < {TIME_LIMIT:g} s), " \
                          + verdict
            failed += not ok
            print(f"| {name} | {size / MIB:.1f} MiB | `{label}` | "
                  f"{','.join(map(str, codes))} | {secs:.2f} | {cpu:.2f} | {rss:.0f} | "
                  f"{verdict} |", flush=True)
    load = os.getloadavg() if hasattr(os, "getloadavg") else ()
    print(f"\nload average {' '.join(f'{x:.2f}' for x in load)} on {os.cpu_count()} CPUs; "
          f"Python {sys.version.split()[0]}; {failed} row(s) not met")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
