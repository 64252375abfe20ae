"""The layers of DESIGN.md section 1: no import circle, no import from a lower layer to a higher one.

Layers, lowest first: models <- invariants <- reference_impl <- checkers <- swarmproof (a module
may import its own layer or lower ones).  The import graph is read from the source with ``ast``
(nothing is imported; about a second, read once per session): every ``import`` and
``from ... import``, at module level or inside a function, relative ones resolved against the
module's package; ``from pkg import name`` is an edge to ``pkg`` (its ``__init__`` runs) and to
``pkg.name`` when that is a module; ``swarmproof.models.x`` and ``models.x`` name one module.
These are the rules of ``shared/tools/layers`` (issue 28).

What pending work is about to remove may be listed, narrowly, in :data:`PENDING_CIRCLES` and
:data:`PENDING_UPWARD` (both empty now), so any other circle or upward import fails here; an
entry that no longer occurs fails too (remove it).
"""

from __future__ import annotations

import ast
import collections
import functools
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: Each top-level folder and its layer (higher may import lower, never the other way).
LAYERS = {"models": 1, "invariants": 2, "reference_impl": 3, "checkers": 4, "swarmproof": 5}

#: Import circles that are allowed for now, each exactly as it stands (a circle that grows, or a
#: new one, fails), with a comment naming the change that removes it.  Empty: the per-paper
#: packages change removed the last ones (invariants.premises <-> invariants.properties,
#: reference_impl.wang2020 <-> wang2020_fast, checkers.leechong_checks <-> reference_impl.leechong,
#: checkers.proofs <-> checkers.proofs_wang2020).
PENDING_CIRCLES: tuple[frozenset, ...] = ()

#: Imports from a lower layer to a higher one that are allowed for now, each with a comment naming
#: the change that removes it.  Empty: the per-paper packages change removed the last ones
#: (reference_impl.jiang_experiments -> checkers.runs, reference_impl.leechong ->
#: checkers.leechong_checks).
PENDING_UPWARD: tuple[tuple[str, str], ...] = ()


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _modules() -> dict[str, Path]:
    return {_module_name(f): f for top in LAYERS for f in sorted((ROOT / top).rglob("*.py"))}


def _imported_names(module: str, path: Path, node: ast.Import | ast.ImportFrom) -> list[str]:
    """The dotted names an import statement loads: ``from pkg import a`` loads ``pkg`` and
    ``pkg.a`` (the latter may be a name inside ``pkg``, not a module)."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names]
    if node.level:
        package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
        package = package[:len(package) - node.level + 1]
        head = ".".join(package + ([node.module] if node.module else []))
    else:
        head = node.module or ""
    return [head] + [f"{head}.{a.name}" for a in node.names]


def _resolve(name: str, modules: dict[str, Path]) -> str | None:
    """The project module ``name`` names (its longest prefix that is a module), or None."""
    parts = name.split(".")
    if len(parts) > 1 and parts[0] == "swarmproof" and parts[1] in LAYERS:
        name = ".".join(parts[1:])
    while name and name not in modules:
        name = name.rpartition(".")[0]
    return name or None


def _import_statements(node: ast.AST):
    """Every ``import`` statement under ``node``, at any depth (functions, classes, ``if``,
    ``try``...).  Only statements are visited: an import is never inside an expression."""
    for _, value in ast.iter_fields(node):
        if isinstance(value, list):
            for child in value:
                if isinstance(child, (ast.Import, ast.ImportFrom)):
                    yield child
                elif isinstance(child, (ast.stmt, ast.excepthandler, ast.match_case)):
                    yield from _import_statements(child)


@functools.lru_cache(maxsize=None)
def import_graph() -> dict[tuple[str, str], list[str]]:
    """Every edge ``(importer, imported)`` between project modules, with where it is imported
    (``path:line``).  Read once per session."""
    modules = _modules()
    edges: dict[tuple[str, str], list[str]] = collections.defaultdict(list)
    for module, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in _import_statements(tree):
            for name in _imported_names(module, path, node):
                target = _resolve(name, modules)
                if target is not None and target != module:
                    where = f"{path.relative_to(ROOT)}:{node.lineno}"
                    if where not in edges[(module, target)]:
                        edges[(module, target)].append(where)
    return dict(edges)


def circles(edges) -> list[frozenset]:
    """The strongly connected components of more than one module (Tarjan, iterative)."""
    graph = collections.defaultdict(list)
    for a, b in sorted(edges):
        graph[a].append(b)
    nodes = sorted({m for edge in edges for m in edge})
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    for root in nodes:
        if root in index:
            continue
        work = [(root, iter(graph[root]))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(graph[child])))
                elif child in on_stack:
                    low[v] = min(low[v], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[v])
            if low[v] == index[v]:
                component = set()
                while True:
                    w = stack.pop()
                    on_stack.discard(w)
                    component.add(w)
                    if w == v:
                        break
                if len(component) > 1:
                    found.append(frozenset(component))
    return found


def upward_imports(edges) -> list[tuple[str, str]]:
    """Edges from a module of a lower layer to one of a higher layer."""
    return sorted((a, b) for a, b in edges if LAYERS[a.split(".")[0]] < LAYERS[b.split(".")[0]])


def _circle_text(circle, edges) -> str:
    inner = sorted((a, b) for a, b in edges if a in circle and b in circle)
    return " <-> ".join(sorted(circle)) + "".join(
        f"\n    {a} -> {b} ({', '.join(edges[(a, b)])})" for a, b in inner)


def test_no_import_circle():
    edges = import_graph()
    new = [c for c in circles(edges) if c not in PENDING_CIRCLES]
    assert not new, "import circles (break them: move the shared piece down, or invert the import):\n" + \
        "\n".join(_circle_text(c, edges) for c in sorted(new, key=sorted))


def test_no_import_from_a_lower_layer_to_a_higher_one():
    edges = import_graph()
    new = [e for e in upward_imports(edges) if e not in PENDING_UPWARD]
    assert not new, "imports from a lower layer to a higher one (DESIGN.md section 1):\n" + \
        "\n".join(f"    {a} -> {b} ({', '.join(edges[(a, b)])})" for a, b in new)


def test_every_pending_entry_still_occurs():
    """An allowed circle or upward import that is gone must leave the lists, so it cannot come back."""
    edges = import_graph()
    gone = [sorted(c) for c in PENDING_CIRCLES if c not in circles(edges)]
    gone += [e for e in PENDING_UPWARD if e not in edges]
    assert not gone, f"remove these entries from PENDING_CIRCLES / PENDING_UPWARD: {gone}"


def test_the_graph_sees_relative_package_and_function_level_imports():
    """The reading itself: a relative ``from . import x`` is an edge to the package and to
    ``x``; an import inside a function counts; ``swarmproof.models.x`` is ``models.x``."""
    edges = import_graph()
    assert ("models.targets", "models") in edges               # from . import library
    assert ("models.targets", "models.library") in edges
    assert ("checkers.runs", "checkers.algorithm_spec") in edges     # inside run_and_check
    assert ("swarmproof.listeners", "checkers.listeners") in edges   # swarmproof.checkers.listeners
    assert circles({("a.x", "a.y"): [], ("a.y", "a.z"): [], ("a.z", "a.x"): [], ("a.z", "a.w"): []}) \
        == [frozenset({"a.x", "a.y", "a.z"})]
