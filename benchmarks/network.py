"""Time `dcf2bin network build` against lely's `dcfgen -r` (PyPI: dcf-tools) on one
generated network per size: a PLC and N slaves, each with 4 TPDOs and 4 RPDOs of 4
objects (at 126 slaves: 1,008 links, 4,032 PLC variables).

    python benchmarks/network.py                    # 8, 32, 126 slaves, 5 runs each
    python benchmarks/network.py --sizes 126 --repeat 9
    python benchmarks/network.py --no-dcfgen        # dcf2bin only
    python benchmarks/network.py --sizes 126 --lely # a lely master (D-21) on both sides

Both tools run as a fresh process on the same YAML (dcfgen ignores the master's dcf: and
the mapping's name:), so each time includes its start-up and its writing of the files, as
a user sees them; the commands run in turn (dcf2bin build, dcf2bin check, dcfgen, again),
so that each sees the machine as the others do, and the table gives the medians. dcf2bin
runs with its bytecode cache, as an installed package does (see ``_env``). `check` is the
CPU time of `dcf2bin network check` on the same file (issue 20: no slower than the build);
`build` is the CPU time of `dcf2bin.network.build_network` alone, whose time per node
shows how the work grows. The ratio is given on wall time (issue 27's measure: what a user
waits for) and on CPU time (user + system of the process), which other jobs on a shared
machine disturb less. The load average is printed before and after. Files go to
benchmarks/out/network_N/.

With ``--lely`` the master has no ``dcf:`` (``bus_lely.yml``): both tools then make the
same files -- a lely master's master.dcf and the slaves' concise DCFs (SPEC §10.2a,
D-21) -- and the table compares like with like.
"""
from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
OUT = os.path.join(HERE, "out")


def _var(sec, name, dtype, access, default, pdo=0):
    return (f"[{sec}]\nParameterName={name}\nObjectType=0x7\nDataType={dtype}\n"
            f"AccessType={access}\nDefaultValue={default}\nPDOMapping={pdo}\n\n")


def _rec(index, name, subs, ot="0x9"):
    return f"[{index:04X}]\nParameterName={name}\nObjectType={ot}\nSubNumber={subs}\n\n"


def _compact(index, name, n=127):
    return (f"[{index:04X}]\nParameterName={name}\nObjectType=0x8\nDataType=0x0007\n"
            f"AccessType=rw\nDefaultValue=0\nPDOMapping=0\nCompactSubObj={n}\n\n")


def _mapping(index: int, pdo: str) -> str:
    """A PDO mapping record with 8 empty subs (nothing mapped)."""
    return (_rec(index, f"{pdo} mapping", 9) + _var(f"{index:04X}sub0", "n", "0x0005", "rw", "0")
            + "".join(_var(f"{index:04X}sub{s}", f"Mapped object {s}", "0x0007", "rw", "0")
                      for s in range(1, 9)))


def plc_dcf(n_rx: int, n_tx: int) -> str:
    """A PLC with n_rx RPDOs, n_tx TPDOs (8 mapping subs each) and the NMT master objects."""
    out = [f"[FileInfo]\nFileName=plc.dcf\nEDSVersion=4.0\n\n[DeviceInfo]\nVendorNumber=0x3F\n"
           f"ProductNumber=0x1302\nNrOfRXPDO={n_rx}\nNrOfTXPDO={n_tx}\n\n"
           "[DeviceComissioning]\nNodeID=1\n\n"]
    out.append(_var("1000", "Device type", "0x0007", "ro", "0x195"))
    out.append(_var("1001", "Error register", "0x0005", "ro", "0"))
    out.append(_var("1005", "COB-ID SYNC", "0x0007", "rw", "0x80"))
    out.append(_var("1006", "Cycle period", "0x0007", "rw", "0"))
    out.append(_compact(0x1016, "Consumer heartbeat time"))
    out.append(_var("1017", "Producer heartbeat time", "0x0006", "rw", "0"))
    out.append(_rec(0x1018, "Identity", 2))
    out.append(_var("1018sub0", "n", "0x0005", "ro", "1"))
    out.append(_var("1018sub1", "Vendor-ID", "0x0007", "ro", "0x3F"))
    for kind, base, n in (("RPDO", 0x1400, n_rx), ("TPDO", 0x1800, n_tx)):
        subs = [1, 2, 5] if kind == "RPDO" else [1, 2, 3, 5]
        for i in range(n):
            c = base + i
            out.append(_rec(c, f"{kind}{i + 1} communication", len(subs) + 1))
            out.append(_var(f"{c:04X}sub0", "n", "0x0005", "ro", str(max(subs))))
            out.append(_var(f"{c:04X}sub1", "COB-ID", "0x0007", "rw", "0x80000000"))
            out.append(_var(f"{c:04X}sub2", "Transmission type", "0x0005", "rw", "255"))
            if kind == "TPDO":
                out.append(_var(f"{c:04X}sub3", "Inhibit time", "0x0006", "rw", "0"))
            out.append(_var(f"{c:04X}sub5", "Event timer", "0x0006", "rw", "0"))
            out.append(_mapping(c + 0x200, f"{kind}{i + 1}"))
    for index, name in ((0x1F81, "Slave assignment"), (0x1F84, "Device type"),
                        (0x1F85, "Vendor"), (0x1F86, "Product"), (0x1F87, "Revision"),
                        (0x1F88, "Serial")):
        out.append(_compact(index, name))
    return "".join(out)


def slave_eds() -> str:
    """A slave with 4 TPDOs and 4 RPDOs (8 mapping subs each) and 16 UNSIGNED16 inputs
    (0x6000) and outputs (0x6200)."""
    out = ["[FileInfo]\nFileName=slave.eds\nEDSVersion=4.0\n\n[DeviceInfo]\n"
           "VendorNumber=0x42\nProductNumber=0x7\nNrOfRXPDO=4\nNrOfTXPDO=4\n\n"]
    out.append(_var("1000", "Device type", "0x0007", "ro", "0x191"))
    out.append(_var("1001", "Error register", "0x0005", "ro", "0"))
    out.append(_var("1017", "Producer heartbeat time", "0x0006", "rw", "0"))
    out.append(_rec(0x1018, "Identity", 3))
    out.append(_var("1018sub0", "n", "0x0005", "ro", "2"))
    out.append(_var("1018sub1", "Vendor-ID", "0x0007", "ro", "0x42"))
    out.append(_var("1018sub2", "Product code", "0x0007", "ro", "0x7"))
    for kind, base, cob in (("RPDO", 0x1400, 0x200), ("TPDO", 0x1800, 0x180)):
        for i in range(4):
            c = base + i
            out.append(_rec(c, f"{kind}{i + 1} communication", 4))
            out.append(_var(f"{c:04X}sub0", "n", "0x0005", "ro", "5"))
            out.append(_var(f"{c:04X}sub1", "COB-ID", "0x0007", "rw",
                            f"$NODEID+0x{cob + 0x100 * i:X}"))
            out.append(_var(f"{c:04X}sub2", "Transmission type", "0x0005", "rw", "255"))
            out.append(_var(f"{c:04X}sub5", "Event timer", "0x0006", "rw", "0"))
            out.append(_mapping(c + 0x200, f"{kind}{i + 1}"))
    for index, access in ((0x6000, "ro"), (0x6200, "rw")):
        out.append(_rec(index, "inputs" if access == "ro" else "outputs", 17, "0x8"))
        out.append(_var(f"{index:04X}sub0", "n", "0x0005", "ro", "16"))
        for s in range(1, 17):
            out.append(_var(f"{index:04X}sub{s:X}", f"value {s}", "0x0006", access, "0", 1))
    optional = ([0x1017] + list(range(0x1400, 0x1404)) + list(range(0x1600, 0x1604))
                + list(range(0x1800, 0x1804)) + list(range(0x1A00, 0x1A04)) + [0x6000, 0x6200])
    out.append("[MandatoryObjects]\nSupportedObjects=3\n1=0x1000\n2=0x1001\n3=0x1018\n\n")
    out.append(f"[OptionalObjects]\nSupportedObjects={len(optional)}\n"
               + "".join(f"{k}=0x{x:04X}\n" for k, x in enumerate(optional, 1)) + "\n")
    out.append("[ManufacturerObjects]\nSupportedObjects=0\n")
    return "".join(out)


def bus_yml(n: int, plc: bool = True) -> str:
    """N slaves x 8 PDOs (4 TPDOs, 4 RPDOs of 4 objects, cob_id auto); the master a PLC
    (its dcf:) or, without ``plc``, a lely master."""
    out = [f"master:\n  node_id: 1\n{'  dcf: plc.dcf' + chr(10) if plc else ''}"
           "  heartbeat_producer: 100\n  sync_period: 10000\n"]
    for k in range(n):
        nid = 2 + k
        out.append(f"s{nid}:\n  dcf: slave.eds\n  node_id: {nid}\n  heartbeat_producer: 50\n")
        for kind, index in (("tpdo", 0x6000), ("rpdo", 0x6200)):
            out.append(f"  {kind}:\n")
            for p in range(1, 5):
                out.append(f"    {p}:\n      cob_id: auto\n      transmission: 1\n"
                           "      mapping:\n")
                for s in range(4 * (p - 1) + 1, 4 * p + 1):
                    out.append(f"        - {{index: 0x{index:04X}, sub_index: {s}}}\n")
    return "".join(out)


def generate(n: int) -> str:
    folder = os.path.join(OUT, f"network_{n}")
    os.makedirs(folder, exist_ok=True)
    links = 4 * n
    with open(os.path.join(folder, "plc.dcf"), "w") as f:
        f.write(plc_dcf(links, links))
    with open(os.path.join(folder, "slave.eds"), "w") as f:
        f.write(slave_eds())
    with open(os.path.join(folder, "bus.yml"), "w") as f:
        f.write(bus_yml(n))
    with open(os.path.join(folder, "bus_lely.yml"), "w") as f:
        f.write(bus_yml(n, plc=False))
    return folder


def _env() -> dict:
    """The environment of every process timed: dcf2bin from this checkout, with its
    bytecode cache (``pip install`` compiles a package's modules, and dcfgen's are; a
    session that sets PYTHONDONTWRITEBYTECODE would otherwise time dcf2bin compiling its
    80 modules on every run: 0.1 s), kept in benchmarks/out/pycache."""
    env = dict(os.environ, PYTHONPATH=ROOT, PYTHONPYCACHEPREFIX=os.path.join(OUT, "pycache"))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def _run(cmd: list[str], cwd: str, outdir: str) -> tuple[float, float]:
    """(wall seconds, CPU seconds: user + system of the process) of one run of ``cmd``
    as a fresh process, into an empty ``outdir``."""
    import resource
    shutil.rmtree(outdir, ignore_errors=True)
    os.makedirs(outdir)
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    r = subprocess.run(cmd, cwd=cwd, env=_env(), capture_output=True, text=True)
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if r.returncode != 0:
        raise SystemExit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr[-2000:]}")
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def _interleaved(commands: dict, cwd: str, repeat: int) -> dict:
    """name -> (median wall, median CPU, best wall, best CPU) of each command of
    ``commands`` (name -> (argv, output folder)), run in turn ``repeat`` times after one
    run of each that is not counted (bytecode and page caches): every tool sees the
    machine as the others do."""
    for cmd, outdir in commands.values():
        _run(cmd, cwd, outdir)
    times: dict = {name: [] for name in commands}
    for _ in range(repeat):
        for name, (cmd, outdir) in commands.items():
            times[name].append(_run(cmd, cwd, outdir))
    return {name: (statistics.median(w for w, _ in got), statistics.median(c for _, c in got),
                   min(w for w, _ in got), min(c for _, c in got))
            for name, got in times.items()}


def _in_process(folder: str, repeat: int, name: str = "bus.yml") -> float:
    """Best CPU seconds of ``dcf2bin.network.build_network`` alone (no start-up, no
    writing): how the work itself grows with the network."""
    sys.path.insert(0, ROOT)
    from dcf2bin.network import build_network
    best = float("inf")
    for _ in range(repeat):
        t = time.process_time()
        res = build_network(os.path.join(folder, name))
        best = min(best, time.process_time() - t)
        assert res.ok, [d.format() for d in res.diagnostics if d.severity.value == "error"]
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", default="8,32,126", help="numbers of slaves (max 126)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-dcfgen", action="store_true")
    ap.add_argument("--lely", action="store_true",
                    help="a lely master (no dcf:) on both sides instead of a PLC")
    args = ap.parse_args()
    dcfgen = None if args.no_dcfgen else shutil.which("dcfgen")
    if dcfgen is None and not args.no_dcfgen:
        print("dcfgen not found (pip install dcf-tools): dcf2bin only")
    load_before = os.getloadavg()
    rows = []
    for n in (int(s) for s in args.sizes.split(",")):
        if not 1 <= n <= 126:
            raise SystemExit("sizes are 1..126 slaves")
        folder = generate(n)
        bus = "bus_lely.yml" if args.lely else "bus.yml"
        commands = {
            "build": ([sys.executable, "-m", "dcf2bin", "network", "build", bus, "-o",
                       "out_dcf2bin", "-q"], os.path.join(folder, "out_dcf2bin")),
            "check": ([sys.executable, "-m", "dcf2bin", "network", "check", bus, "-q"],
                      os.path.join(folder, "out_check"))}
        if dcfgen:
            commands["dcfgen"] = ([dcfgen, "-r", "-d", "out_dcfgen", bus],
                                  os.path.join(folder, "out_dcfgen"))
        got = _interleaved(commands, folder, args.repeat)
        inproc = _in_process(folder, args.repeat, bus)
        rows.append((n, got, inproc))
    print("a lely master (no dcf:) on both sides" if args.lely else
          "a PLC master (dcf:) for dcf2bin; dcfgen builds its lely master")
    print(f"{'slaves':>6} {'links':>6} {'vars':>6} | {'dcf2bin':>8} {'cpu':>6} {'check':>6} "
          f"{'build':>6} {'ms/node':>8} | {'dcfgen -r':>9} {'cpu':>6} {'ms/node':>8} | "
          f"{'ratio wall':>10} {'cpu':>5}")
    for n, got, inproc in rows:
        wall, cpu = got["build"][:2]
        line = (f"{n:>6} {8 * n:>6} {32 * n:>6} | {wall:>8.3f} {cpu:>6.3f} "
                f"{got['check'][1]:>6.3f} {inproc:>6.3f} {1000 * inproc / n:>8.2f} |")
        if "dcfgen" in got:
            twall, tcpu = got["dcfgen"][:2]
            line += (f" {twall:>9.3f} {tcpu:>6.3f} {1000 * tcpu / n:>8.2f} | "
                     f"{twall / wall:>10.1f} {tcpu / cpu:>5.1f}")
        print(line)
    print(f"seconds, medians of {args.repeat} runs of each command in turn (after one "
          "run of each not counted). dcf2bin/dcfgen -r: the whole process, wall and cpu "
          "(user + system) time; check: cpu time of 'network check' on the same file; "
          "build: cpu time of build_network alone (best), ms/node its share per slave; "
          "ratio: dcfgen / dcf2bin")
    for n, got, _ in rows:
        if "dcfgen" in got:
            print(f"{n} slaves: best wall dcf2bin {got['build'][2]:.3f} s, dcfgen "
                  f"{got['dcfgen'][2]:.3f} s ({got['dcfgen'][2] / got['build'][2]:.1f}x)")
    print(f"load average before: {' '.join(f'{x:.2f}' for x in load_before)}; after: "
          f"{' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    if args.lely and any("dcfgen" in got for _, got, _ in rows):
        n, got, _ = rows[-1]
        ratio = got["dcfgen"][0] / got["build"][0]
        print(f"issue 27 (at least 10x dcfgen's wall time, {n} slaves, lely mode): "
              f"{ratio:.1f}x, {'met' if ratio >= 10 else 'NOT met'}")


if __name__ == "__main__":
    main()
