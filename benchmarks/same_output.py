#!/usr/bin/env python3
"""Record, or compare against a record, what dcf2bin makes of many files: the proof that
an optimisation changed nothing a user sees.

    python benchmarks/same_output.py record out/before.json   # before the change
    python benchmarks/same_output.py compare out/before.json  # after it: exit 1 on a difference
    python benchmarks/same_output.py record out/main.json --repo ../main   # another checkout

Files: every DCF/EDS/INI/BIN under samples/, tests/fixtures/ and ../shared/corpus/files
(when present), and generated DCFs of 6,000 variables (plain and with Denotation=). Per file:
the compile result (container bytes, SHA-256, and every diagnostic as the command line
prints it; containers are dumped instead) and validate's JSON report (every rule, as
``dcf2bin validate --format json FILE``). The record holds digests only.
"""
from __future__ import annotations

import hashlib
import json
import sys
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
REPO = HERE.parent
CORPUS = REPO.parent / "shared" / "corpus" / "files"
SUFFIXES = (".dcf", ".eds", ".ini", ".bin")


def inputs(repo: Path) -> list[tuple[str, Path]]:
    """(name in the record, path): the same names for any checkout."""
    roots = [("samples", repo / "samples"), ("fixtures", repo / "tests" / "fixtures"),
             ("corpus", CORPUS)]
    files = []
    for name, root in roots:
        if root.is_dir():
            files += sorted((f"{name}/{p.relative_to(root)}", p) for p in root.rglob("*")
                            if p.is_file() and p.suffix.lower() in SUFFIXES)
    out = HERE / "out"
    out.mkdir(exist_ok=True)
    sys.path.insert(0, str(HERE))
    import gen_dcf
    for denot in (False, True):
        p = out / f"same_6000{'_denotations' if denot else ''}.dcf"
        if not p.exists():
            p.write_bytes(gen_dcf.generate(6000, denotations=denot).encode("ascii"))
        files.append((f"generated/{p.name}", p))
    return files


def digest(data: bytes | str) -> str:
    if isinstance(data, str):
        data = data.encode("utf-8")
    return hashlib.sha256(data).hexdigest()[:16]


def one(path: Path, repo: Path) -> dict:
    """The digests of what compile and validate make of ``path`` (the checkout's own path
    in them written as <repo>, so that two checkouts compare)."""
    from dcf2bin import __version__, compiler, report
    from dcf2bin.lint import Options, all_rules, run
    rec = {}
    if path.suffix.lower() != ".bin":
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                res = compiler.compile_path(str(path))
            rec["compile"] = digest((res.data or b"") + "\0".join(
                d.format() for d in res.diagnostics).replace(str(HERE / "out"), "<out>")
                .replace(str(repo), "<repo>").encode())
        except Exception as exc:  # noqa: BLE001 - recorded, compared
            rec["compile"] = f"raised {type(exc).__name__}: {exc}"
    result = run([str(path)], Options())
    table = {r.id: r.as_dict() for r in all_rules()}
    text = report.json_report(result.diagnostics, [(f.path, f.kind) for f in result.files],
                              table, exit_code=int(result.exit_code()),
                              tool_version=__version__)
    rec["validate"] = digest(text.replace(str(HERE / "out"), "<out>").replace(str(repo),
                                                                               "<repo>"))
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
    got = {name: one(p, repo) for name, p in inputs(repo)}
    if mode == "record":
        Path(record).write_text(json.dumps(got, indent=1, sort_keys=True))
        print(f"recorded {len(got)} files in {record}")
        return 0
    want = json.loads(Path(record).read_text())
    bad = [k for k in sorted(set(want) | set(got)) if want.get(k) != got.get(k)]
    for k in bad:
        print(f"DIFFERENT: {k}: {want.get(k)} -> {got.get(k)}")
    print(f"compared {len(got)} files: {len(bad)} different")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
