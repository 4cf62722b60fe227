"""The shape of the code (docs/architecture.md): no import cycle, no oversized class.

The import graph has one node per module of ``dcf2bin/`` (a package is its ``__init__``) and
one edge per import statement that names a ``dcf2bin`` module, absolute (``import
dcf2bin.x``, ``from dcf2bin.x import y``, ``from dcf2bin import x``) or relative (``from .x
import y``, ``from . import x``). Imports at module level AND inside functions both count:
a lazy import keeps ``dcf2bin --help`` fast, but a cycle through it is still a cycle for a
reader. Imports under ``if TYPE_CHECKING:`` count too. ``from pkg import name`` is an edge to
``pkg.name`` when that is a module, else to ``pkg``. Importing ``a.b`` makes Python run
``a/__init__`` first; that implicit edge is NOT counted (a package ``__init__`` may list and
re-export its own modules, as ``dcf2bin.lint`` and ``dcf2bin.dump`` do).
"""
from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "dcf2bin"
MAX_CLASS_LINES = 250

# Edges left out of the graph, each with its reason. Keep this list short; the test below
# fails when an edge listed here no longer exists, so that it is removed with the code.
ALLOWED_EDGES: dict[tuple[str, str], str] = {
    # (importer, imported): why a cycle through this edge is accepted. Empty: none is.
}


def _modules(root: Path = PACKAGE) -> dict[str, Path]:
    out = {}
    for path in sorted(root.rglob("*.py")):
        parts = list(path.relative_to(root.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts.pop()
        out[".".join(parts)] = path
    return out


def _resolve(name: str, modules: dict[str, Path]) -> str | None:
    """The longest module prefix of a dotted name (``dcf2bin.a.b.func`` -> ``dcf2bin.a.b``)."""
    while name:
        if name in modules:
            return name
        name = name.rpartition(".")[0]
    return None


def import_graph(root: Path = PACKAGE, allowed=()) -> dict[str, set[str]]:
    modules = _modules(root)
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for mod, path in modules.items():
        is_pkg = path.name == "__init__.py"
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in ast.walk(tree):          # every level: module, class, function
            targets: list[str] = []
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base = mod.split(".") if is_pkg else mod.split(".")[:-1]
                    base = base[:len(base) - (node.level - 1)]
                    prefix = ".".join(base + ([node.module] if node.module else []))
                else:
                    prefix = node.module or ""
                targets = [f"{prefix}.{a.name}" for a in node.names] + [prefix]
                # `from pkg import name`: the submodule if it is one, else pkg itself
                sub = [t for t in targets[:-1] if t in modules]
                targets = sub if len(sub) == len(targets) - 1 else sub + [prefix]
            for t in targets:
                hit = _resolve(t, modules) if t.startswith("dcf2bin") else None
                if hit and hit != mod and (mod, hit) not in allowed:
                    graph[mod].add(hit)
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One cycle as ``[a, b, ..., a]``, or None (iterative DFS, deterministic order)."""
    WHITE, GREY, BLACK = 0, 1, 2
    colour = dict.fromkeys(graph, WHITE)
    for start in sorted(graph):
        if colour[start] != WHITE:
            continue
        stack = [(start, iter(sorted(graph[start])))]
        path = [start]
        colour[start] = GREY
        while stack:
            node, it = stack[-1]
            nxt = next(it, None)
            if nxt is None:
                colour[node] = BLACK
                stack.pop()
                path.pop()
            elif colour[nxt] == GREY:
                return path[path.index(nxt):] + [nxt]
            elif colour[nxt] == WHITE:
                colour[nxt] = GREY
                stack.append((nxt, iter(sorted(graph[nxt]))))
                path.append(nxt)
    return None


def test_the_graph_sees_the_imports_it_should():
    # guards the walker itself: a graph with no edges would pass the cycle test trivially
    g = import_graph()
    assert "dcf2bin.diagnostics" in g["dcf2bin.report"]               # absolute, module level
    assert "dcf2bin.compiler" in g["dcf2bin.lint.runner"]             # inside a method
    assert "dcf2bin.lint.registry" in g["dcf2bin.lint.rules_od"]
    assert {"dcf2bin.lint.rules_od", "dcf2bin.lint.runner"} <= g["dcf2bin.lint"]
    assert sum(map(len, g.values())) > 100


def test_no_import_cycle():
    cycle = find_cycle(import_graph(allowed=ALLOWED_EDGES))
    assert cycle is None, "import cycle: " + " -> ".join(cycle or [])


def test_every_allowed_edge_still_exists():
    g = import_graph()
    assert [e for e in ALLOWED_EDGES if e[1] not in g.get(e[0], ())] == []


def test_find_cycle_names_a_cycle(tmp_path):
    pkg = tmp_path / "dcf2bin"
    (pkg / "sub").mkdir(parents=True)
    (pkg / "__init__.py").write_text("")
    (pkg / "a.py").write_text("from dcf2bin import b\n")
    (pkg / "b.py").write_text("def f():\n    from .sub import c\n")
    (pkg / "sub" / "__init__.py").write_text("")
    (pkg / "sub" / "c.py").write_text("from ..a import thing\n")
    assert find_cycle(import_graph(pkg)) == ["dcf2bin.a", "dcf2bin.b", "dcf2bin.sub.c",
                                             "dcf2bin.a"]
    (pkg / "sub" / "c.py").write_text("import os\n")
    assert find_cycle(import_graph(pkg)) is None


def class_lengths(root: Path = PACKAGE) -> list[tuple[int, str]]:
    out = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                where = f"{path.relative_to(root.parent)}:{node.lineno} {node.name}"
                out.append((node.end_lineno - node.lineno + 1, where))
    return sorted(out, reverse=True)


def test_no_class_over_the_limit():
    lengths = class_lengths()
    assert lengths, "no class found: the walker is broken"
    too_long = [f"{where} ({n} lines)" for n, where in lengths if n > MAX_CLASS_LINES]
    assert not too_long, f"classes over {MAX_CLASS_LINES} lines: " + "; ".join(too_long)
