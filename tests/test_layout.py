"""One place for each shared thing: one atomic writer, one Gauss–Legendre helper, no
module reaching into another package's private names. Checked on the source, so a new copy or
a new private import fails here."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "src" / "roughdiffuse"
PY = sorted(SRC.rglob("*.py"))

# the private hooks of a model, used only inside roughdiffuse/models/
MODEL_PRIVATE = {"_kernel", "_xp", "_validate", "_should_jit", "_coerce_channels"}


def _module(path: Path) -> tuple[str, str]:
    """(module name, its package) of a source file."""
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    if parts[-1] == "__init__":
        return ".".join(parts[:-1]), ".".join(parts[:-1])
    return ".".join(parts), ".".join(parts[:-1])


def _target(node: ast.ImportFrom, package: str) -> str:
    if not node.level:
        return node.module or ""
    base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def test_no_private_name_is_imported_from_another_package():
    offenders = []
    for path in PY:
        _, package = _module(path)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.ImportFrom):
                continue
            target = _target(node, package)
            target_package = target.rsplit(".", 1)[0] if "." in target else target
            for alias in node.names:
                private = alias.name.startswith("_") and not alias.name.startswith("__")
                if private and target_package != package and target != package:
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} {alias.name}")
    assert offenders == []


def test_models_private_hooks_are_not_used_outside_the_models_package():
    offenders = []
    for path in PY:
        if path.parent.name == "models":
            continue
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Attribute) and node.attr in MODEL_PRIVATE:
                if not (isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")):
                    offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} .{node.attr}")
    assert offenders == []


def test_models_built_of_models_use_the_public_model_interface():
    """Mix and Coated reach their components and base through the public interface
    (``evaluate``, ``parameter_arrays``, ``parameter_values``, ``channel``...), never a private
    name of another object."""
    offenders = []
    for path in (SRC / "models" / "mix.py", SRC / "models" / "coated.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Attribute) or not node.attr.startswith("_"):
                continue
            if node.attr.startswith("__") or (
                isinstance(node.value, ast.Name) and node.value.id in ("self", "cls")
            ):
                continue
            offenders.append(f"{path.relative_to(ROOT)}:{node.lineno} .{node.attr}")
    assert offenders == []


def _calls(name: str, owner: str | None = None) -> list[str]:
    """Files under src/ and bench/ that call ``name`` (``owner.name`` if ``owner`` is given)."""
    found = []
    for path in [*PY, *sorted((ROOT / "bench").glob("*.py"))]:
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.Call):
                continue
            f = node.func
            if isinstance(f, ast.Attribute):
                who = f.value.id if isinstance(f.value, ast.Name) else None
                hit = f.attr == name and (owner is None or who == owner)
            else:
                hit = owner is None and getattr(f, "id", None) == name
            if hit:
                found.append(str(path.relative_to(ROOT)))
    return sorted(set(found))


def test_one_atomic_writer_and_one_gauss_legendre_helper():
    assert _calls("replace", "os") == ["src/roughdiffuse/io/atomic.py"]
    assert _calls("rename", "os") == []
    assert _calls("leggauss") == ["src/roughdiffuse/quadrature.py"]


def test_the_public_entry_points_give_what_the_private_hooks_give():
    import numpy as np

    import roughdiffuse as rd

    m = rd.OrenNayar(0.6, 0.4)
    p = m.parameter_arrays(np)
    assert set(p) == {"albedo", "sigma"} and float(p["sigma"]) == 0.4
    mu_i, mu_o, c = np.array([0.8]), np.array([0.5]), np.array([0.3])
    np.testing.assert_array_equal(m.kernel(np, mu_i, mu_o, c, **p), m.brdf_cosines(mu_i, mu_o, c))
