#!/usr/bin/env python3
"""Record, or compare against a record, what the commands that read a container make of
it: ``dump`` (text and JSON), ``bin2dcf``, ``map`` (every format, of the container and of
the DCF it was compiled from) and ``simulate`` (text and JSON). The companion of
``same_output.py`` (compile and validate) for optimisations of these commands.

    python benchmarks/same_views.py record out/views_before.json
    python benchmarks/same_views.py compare out/views_before.json   # exit 1 on a difference
    python benchmarks/same_views.py record out/main.json --repo ../main

Inputs: the files of ``same_output.inputs`` (samples/, tests/fixtures/, the corpus, two
generated 6,000-variable DCFs) and the 1,000/10,000/60,000-variable files that
``table.py`` generates in ``benchmarks/out`` when present. A DCF/EDS/INI is compiled
first (in-process); a file that does not compile gives no container (its ``map`` of the
DCF is still recorded). Each command runs in-process
through click; the record holds a digest of its exit code, standard output and standard
error (paths of the checkout, its corpus and temporary files written as <repo>,
<corpus>, <tmp>).
"""
from __future__ import annotations

import hashlib
import json
import sys
import tempfile
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
OUT = HERE / "out"          # table.py's generated files
MAP_FORMATS = ("text", "csv", "json", "iec", "c", "svg", "html")


def inputs(repo: Path) -> list[tuple[str, Path]]:
    sys.path.insert(0, str(HERE))
    import same_output
    files = same_output.inputs(repo)
    for n in (1000, 10000, 60000):
        p = OUT / f"plc_{n}.dcf"
        if p.is_file():
            files.append((f"out/{p.name}", p))
    return files


def digest(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()[:16]


def views(path: Path, repo: Path, tmp: Path) -> dict:
    from click.testing import CliRunner

    from dcf2bin import compiler
    from dcf2bin.cli import main
    runner = CliRunner()

    corpus = repo.parent / "shared" / "corpus" / "files"

    def clean(b: bytes) -> bytes:
        for path, name in ((tmp, b"<tmp>"), (corpus, b"<corpus>"), (corpus.resolve(), b"<corpus>"),
                           (HERE / "out", b"<out>"), (repo, b"<repo>")):
            b = b.replace(str(path).encode(), name)
        return b

    def run(*args: str) -> str:
        r = runner.invoke(main, list(args))
        if r.exception is not None and not isinstance(r.exception, SystemExit):
            return f"raised {type(r.exception).__name__}: {r.exception}"
        return digest(f"{r.exit_code}\0".encode() + clean(r.stdout_bytes) + b"\0"
                      + clean(r.stderr_bytes))

    rec = {}
    binf = tmp / (path.stem + ".bin")
    if path.suffix.lower() == ".bin":
        binf.write_bytes(path.read_bytes())
    else:
        for fmt in MAP_FORMATS:
            rec[f"map-dcf-{fmt}"] = run("map", str(path), "-f", fmt)
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = compiler.compile_path(str(path))
        except Exception as exc:  # noqa: BLE001 - recorded, compared
            rec["compile"] = f"raised {type(exc).__name__}"
            return rec
        if not res.data:
            return rec
        binf.write_bytes(res.data)
    b = str(binf)
    rec["dump"] = run("dump", b)
    rec["dump-json"] = run("dump", b, "-f", "json")
    rec["bin2dcf"] = run("bin2dcf", b, "-o", "-")
    for fmt in MAP_FORMATS:
        rec[f"map-bin-{fmt}"] = run("map", b, "-f", fmt)
    rec["simulate"] = run("simulate", b)
    rec["simulate-json"] = run("simulate", b, "-f", "json")
    binf.unlink()
    return rec


def main(argv: list[str]) -> int:
    repo = REPO
    if len(argv) == 4 and argv[2] == "--repo":
        repo, argv = Path(argv[3]).resolve(), argv[:2]
    if len(argv) != 2 or argv[0] not in ("record", "compare"):
        print(__doc__)
        return 2
    sys.path.insert(0, str(repo))
    mode, record = argv
    with tempfile.TemporaryDirectory() as t:
        tmp = Path(t)
        got = {name: views(p, repo, tmp) for name, p in inputs(repo)}
    if mode == "record":
        Path(record).write_text(json.dumps(got, indent=1, sort_keys=True))
        print(f"recorded {len(got)} files, {sum(map(len, got.values()))} outputs in {record}")
        return 0
    want = json.loads(Path(record).read_text())
    bad = []
    for k in sorted(set(want) | set(got)):
        w, g = want.get(k) or {}, got.get(k) or {}
        for cmd in sorted(set(w) | set(g)):
            if w.get(cmd) != g.get(cmd):
                bad.append((k, cmd))
                print(f"DIFFERENT: {k} {cmd}: {w.get(cmd)} -> {g.get(cmd)}")
    n = sum(map(len, got.values()))
    print(f"compared {len(got)} files, {n} outputs: {len(bad)} different")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
