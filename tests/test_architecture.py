"""The package's structure, checked from its source (docs/architecture.md states the rules).

- Layering: a module imports only modules of a lower layer or of its own group; ``planners``,
  ``control`` and ``sim`` share a layer and never import each other. Every import counts, including
  those inside functions and under ``TYPE_CHECKING``.
- No import cycle between modules.
- No function longer than 100 lines.
- Every module declares ``__all__``; the package ships ``py.typed`` and stubs for its compiled modules.
- ``tests/`` mirrors the package: a test file per module (the notebook tests are apart, in ``notebooks/``).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "python" / "lipmpcc"

#: (layer, group) by module prefix, most specific prefix first; lower layers never import higher ones
LAYERS: list[tuple[str, int, str]] = [
    ("lipmpcc.exceptions", 0, "core"),
    ("lipmpcc.config", 0, "core"),
    ("lipmpcc.resources", 0, "core"),
    ("lipmpcc.metrics", 0, "core"),
    ("lipmpcc.conventions", 0, "core"),
    ("lipmpcc.rotations", 0, "core"),
    ("lipmpcc.push", 0, "core"),
    ("lipmpcc._deprecated", 0, "core"),
    ("lipmpcc._lazy", 0, "core"),
    ("lipmpcc.validation", 0, "core"),
    ("lipmpcc.exclusive", 0, "core"),
    ("lipmpcc._wbc", 0, "compiled"),
    ("lipmpcc._mjtick", 0, "compiled"),
    ("lipmpcc._sqp", 0, "compiled"),
    ("lipmpcc.paths", 1, "geometry"),
    ("lipmpcc.contouring", 1, "geometry"),
    ("lipmpcc.obstacles", 1, "geometry"),
    ("lipmpcc.terrain", 1, "geometry"),
    ("lipmpcc.stone_field", 1, "geometry"),
    ("lipmpcc.models", 1, "geometry"),
    ("lipmpcc.robots", 2, "robots"),
    ("lipmpcc.solvers", 3, "solvers"),
    ("lipmpcc.planners", 4, "planners"),
    ("lipmpcc.control", 4, "control"),
    ("lipmpcc.sim", 4, "sim"),
    ("lipmpcc.loops", 5, "loops"),
    ("lipmpcc.plots", 6, "plots"),
    ("lipmpcc.studies", 7, "studies"),
    ("lipmpcc.report", 8, "app"),
    ("lipmpcc.reproduce", 8, "app"),
    ("lipmpcc.sweep", 8, "sweep"),
    ("lipmpcc.course", 8, "course"),
    ("lipmpcc.cli", 9, "cli"),
    ("lipmpcc.__main__", 9, "cli"),
    ("lipmpcc._entry", 9, "cli"),
]

def _is_shim(path: Path) -> bool:
    """An old import path kept for one release: its docstring starts with "Deprecated:"."""
    doc = ast.get_docstring(ast.parse(path.read_text())) or ""
    return doc.startswith("Deprecated:")


def _module_name(path: Path) -> str:
    rel = path.relative_to(PKG.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in sorted(PKG.rglob("*.py"))}


MODULES = _modules()
#: old import paths kept for one release (lipmpcc._deprecated.forward): the top floor, imported by nothing
DEPRECATED = {m for m, p in MODULES.items() if _is_shim(p)}
KNOWN = set(MODULES) | {"lipmpcc._wbc", "lipmpcc._mjtick", "lipmpcc._sqp"}


def _resolve(mod: str, is_pkg: bool, node: ast.ImportFrom | ast.Import) -> list[str]:
    """The lipmpcc modules an import statement reaches."""
    out: list[str] = []
    if isinstance(node, ast.Import):
        for a in node.names:
            if a.name.startswith("lipmpcc"):
                out.append(_existing(a.name))
        return out
    if node.level:
        base = mod.split(".") if is_pkg else mod.split(".")[:-1]
        base = base[: len(base) - (node.level - 1)]
        target = ".".join(base + ([node.module] if node.module else []))
    else:
        target = node.module or ""
    if not target.startswith("lipmpcc"):
        return out
    for a in node.names:
        sub = f"{target}.{a.name}"
        out.append(sub if sub in KNOWN else _existing(target))
    return out


def _existing(name: str) -> str:
    while name not in KNOWN and "." in name:
        name = name.rsplit(".", 1)[0]
    return name


def _imports() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for mod, path in MODULES.items():
        tree = ast.parse(path.read_text(), filename=str(path))
        deps: set[str] = set()
        for node in ast.walk(tree):
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                deps.update(_resolve(mod, path.name == "__init__.py", node))
        deps.discard(mod)
        graph[mod] = deps
    return graph


GRAPH = _imports()


def _layer(mod: str) -> tuple[int, str]:
    if mod in DEPRECATED:
        return (99, "deprecated")
    for prefix, layer, group in LAYERS:
        if mod == prefix or mod.startswith(prefix + "."):
            return (layer, group)
    raise AssertionError(f"module {mod} has no layer: add it to LAYERS (and to docs/architecture.md)")


def test_every_module_has_a_layer() -> None:
    for mod in MODULES:
        if mod == "lipmpcc":
            continue
        _layer(mod)


def test_lower_layers_never_import_higher_ones() -> None:
    bad = []
    for mod, deps in GRAPH.items():
        if mod == "lipmpcc":  # the package root re-exports the public API
            continue
        layer, group = _layer(mod)
        for dep in deps:
            if dep == "lipmpcc" or dep.split(".")[:len(mod.split("."))] == mod.split(".") and MODULES.get(mod, Path()).name == "__init__.py":
                continue  # a package re-exporting its own modules
            dl, dg = _layer(dep)
            if dg == group:
                continue
            if dl >= layer:
                bad.append(f"{mod} (layer {layer}, {group}) imports {dep} (layer {dl}, {dg})")
    assert not bad, "\n".join(sorted(bad))


def test_no_import_cycles() -> None:
    graph = {m: {d for d in deps if d != "lipmpcc"} for m, deps in GRAPH.items() if m != "lipmpcc"}
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    cycles: list[list[str]] = []
    counter = [0]

    def visit(v: str) -> None:  # Tarjan's strongly connected components
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in list(graph):
        if v not in index:
            visit(v)
    # a package __init__ that re-exports its modules forms a harmless cycle with them only
    real = [c for c in cycles if not all(m.startswith(c[0]) for m in c)]
    assert not real, f"import cycles: {real}"


def _functions() -> list[tuple[int, str]]:
    out = []
    for mod, path in MODULES.items():
        tree = ast.parse(path.read_text(), filename=str(path))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                out.append((node.end_lineno - node.lineno + 1, f"{mod}.{node.name} (line {node.lineno})"))
    return sorted(out, reverse=True)


def test_no_function_over_100_lines() -> None:
    long = [f"{name}: {n} lines" for n, name in _functions() if n > 100]
    assert not long, "\n".join(long)


@pytest.mark.parametrize("mod", sorted(m for m in MODULES if m not in DEPRECATED))
def test_every_module_declares_all(mod: str) -> None:
    tree = ast.parse(MODULES[mod].read_text())
    names = {t.id for node in tree.body if isinstance(node, (ast.Assign, ast.AnnAssign))
             for t in (node.targets if isinstance(node, ast.Assign) else [node.target]) if isinstance(t, ast.Name)}
    assert "__all__" in names, f"{mod} has no __all__"


TESTS = Path(__file__).resolve().parent


def _test_file(mod: str) -> Path:
    """``tests/<package path>/test_<module>.py`` of ``lipmpcc.<package path>.<module>`` (a leading
    underscore dropped: ``lipmpcc.sim._tick`` -> ``tests/sim/test_tick.py``)."""
    parts = mod.split(".")[1:]
    return TESTS.joinpath(*parts[:-1], f"test_{parts[-1].lstrip('_')}.py")


def test_tests_mirror_the_package() -> None:
    """Every module but a package's ``__init__``, ``__main__`` and the deprecated shims has its test file;
    every test folder is a package (the tests import their helpers relatively)."""
    missing = []
    for mod, path in MODULES.items():
        if path.name in ("__init__.py", "__main__.py") or mod in DEPRECATED:
            continue
        if not _test_file(mod).is_file():
            missing.append(f"{mod}: {_test_file(mod).relative_to(TESTS.parent)}")
    assert not missing, "modules without a test file:\n" + "\n".join(missing)
    folders = {p.parent for p in TESTS.rglob("test_*.py")}
    assert not [str(d) for d in folders if not (d / "__init__.py").is_file()]
