"""The floors of the package: what each part may import, checked on the code's own imports.

Each top-level module or package of ``roughdiffuse`` sits on one floor (:data:`FLOORS`, bottom
first). A module may import its own floor and the floors below, never a floor above; and no
chain of imports between modules comes back to where it started. The import statements are
read with :mod:`ast` (nothing is imported), and every one counts, also those inside
functions (a lazy import still makes the importer depend on the imported), except those under
``if TYPE_CHECKING:``, which never run. Imports by name at run time
(``importlib.import_module`` of a computed name, as ``roughdiffuse.__getattr__`` and the
registry's scan of ``roughdiffuse.models`` do) are not statements and are not read: they go
from the facade down, or from the models' package to its own modules.

docs/developer/index.md draws the same floors.
"""

from __future__ import annotations

import ast
import functools
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "roughdiffuse"

FLOORS: tuple[tuple[str, frozenset[str]], ...] = (
    ("leaves", frozenset(("_array _env _figure _lazy _mitsuba_scene _validate _version "
                          "deprecation frames io "
                          "programs progress quadrature roughness user_config")
                         .split())),  # fmt: skip
    ("engine", frozenset({"engine"})),
    ("solvers", frozenset({"simulate"})),
    ("models", frozenset({"models"})),
    ("registry", frozenset({"registry"})),
    ("services", frozenset(("accuracy data energy figures fit integrations exporters "
                            "planetary plots render stereo").split())),  # fmt: skip
    ("applications", frozenset("roughdiffuse __main__ bench cli commands explorer".split())),
)
"""Bottom first. ``roughdiffuse`` is the package's own ``__init__`` (the facade)."""

FLOOR_OF = {part: k for k, (_, parts) in enumerate(FLOORS) for part in parts}


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in sorted(SRC.rglob("*.py"))}


def _part(module: str) -> str:
    """The top-level part of the package a module belongs to (``roughdiffuse`` for the facade)."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else parts[0]


def _type_checking_only(tree: ast.AST) -> set[int]:
    skip: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and ast.unparse(node.test) in (
            "TYPE_CHECKING",
            "typing.TYPE_CHECKING",
        ):
            for child in node.body:
                skip.update(id(n) for n in ast.walk(child))
    return skip


CALL_TIME_LOOKUPS = {
    ("roughdiffuse.models.coated", "roughdiffuse.registry"): "a coat's base is named by its id",
    ("roughdiffuse.models.mix", "roughdiffuse.registry"): "a mix's parts are made by their ids",
    ("roughdiffuse.engine.glsl", "roughdiffuse.registry"): "uniforms named after an id's params",
    ("roughdiffuse.engine.glsl", "roughdiffuse"): "the package version in a printed header",
}
"""The only imports that run up a floor: inside a function (when called, the registry above
has been built), each for the reason given. At module level they would be refused too."""


def _in_functions(tree: ast.AST) -> set[int]:
    inside: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            for child in node.body:
                inside.update(id(n) for n in ast.walk(child))
    return inside


def _known(name: str) -> str:
    while name not in MODULES and "." in name:
        name = name.rsplit(".", 1)[0]
    return name


def imports(module: str) -> list[tuple[str, int]]:
    """(imported module of roughdiffuse, line) for every import statement of ``module``."""
    path = MODULES[module]
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip = _type_checking_only(tree)
    lazy = _in_functions(tree)
    out = []
    for node in ast.walk(tree):
        if id(node) in skip:
            continue
        if id(node) in lazy and isinstance(node, ast.Import | ast.ImportFrom):
            names = [_known(a.name) for a in node.names] if isinstance(node, ast.Import) else []
            if isinstance(node, ast.ImportFrom):
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
                target = target if node.level else (node.module or "")
                names = [f"{target}.{a.name}" if f"{target}.{a.name}" in MODULES
                         else _known(target) for a in node.names]
            if names and all((module, t) in CALL_TIME_LOOKUPS for t in names):
                continue
        if isinstance(node, ast.Import):
            out += [(_known(a.name), node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            for a in node.names:
                sub = f"{target}.{a.name}"
                out.append((sub if sub in MODULES else _known(target), node.lineno))
    return [(t, line) for t, line in out if t.split(".")[0] == "roughdiffuse" and t != module]


@functools.cache
def graph() -> dict[str, list[tuple[str, int]]]:
    """Every module's imports of the package (parsed when a test first asks, not when the
    tests are collected: every pytest worker collects every file)."""
    return {m: imports(m) for m in MODULES}


def test_every_part_of_the_package_has_a_floor():
    parts = {_part(m) for m in MODULES}
    assert sorted(parts - set(FLOOR_OF)) == []
    assert sorted(set(FLOOR_OF) - parts) == []


def test_no_import_runs_up_a_floor():
    offenders = []
    for module, targets in graph().items():
        mine = FLOOR_OF[_part(module)]
        for target, line in targets:
            theirs = FLOOR_OF[_part(target)]
            if theirs > mine:
                offenders.append(
                    f"{MODULES[module].relative_to(ROOT)}:{line} imports {target} "
                    f"({FLOORS[mine][0]} -> {FLOORS[theirs][0]})"
                )
    assert offenders == []


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan, iterative)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found = []
    counter = 0
    for root in graph:
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter
        counter += 1
        stack.append(root)
        on_stack.add(root)
        while work:
            v, children = work[-1]
            for w in children:
                if w not in index:
                    index[w] = low[w] = counter
                    counter += 1
                    stack.append(w)
                    on_stack.add(w)
                    work.append((w, iter(sorted(graph[w]))))
                    break
                if w in on_stack:
                    low[v] = min(low[v], index[w])
            else:
                work.pop()
                if work:
                    low[work[-1][0]] = min(low[work[-1][0]], low[v])
                if low[v] == index[v]:
                    component = []
                    while True:
                        w = stack.pop()
                        on_stack.discard(w)
                        component.append(w)
                        if w == v:
                            break
                    if len(component) > 1:
                        found.append(sorted(component))
    return found


def test_no_cycle_between_modules():
    edges = {m: {t for t, _ in targets} for m, targets in graph().items()}
    assert _cycles(edges) == []


def test_the_cycle_finder_finds_a_cycle():
    # the check above could not fail if it found nothing in a graph that has a cycle
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _cycles({"a": {"b"}, "b": set()}) == []


def test_the_engine_does_not_import_the_models():
    # the old circle: models/base.py -> _dispatch -> fastpath -> models/base.py
    engine = [m for m in graph() if _part(m) == "engine"]
    assert engine and all(_part(t) != "models" for m in engine for t, _ in graph()[m])
