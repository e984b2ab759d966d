"""The generated part of docs/implementations.md: other renderers' diffuse, from their declarations.

Each registry model of :mod:`roughdiffuse.models.renderers` (an id named after its source)
gives a row: its id, label, the other project's file and function (``reference``), and either
the model it equals after a parameter conversion (an
:class:`~roughdiffuse.models.alias.Alias`: ``base`` and the ``to_base`` docstring) or "own
kernel"; then its values at four stated geometries. The page's text between the markers is
replaced when the site is built; ``tests/test_docs_implementations.py`` checks the committed
page is up to date.
"""

from __future__ import annotations

import inspect
import math
from pathlib import Path

import numpy as np

BEGIN = "<!-- generated:variants:begin -->"
END = "<!-- generated:variants:end -->"
GEOMETRIES = {"A": (60, 60, 0), "B": (60, 60, 180), "C": (30, 70, 90), "D": (85, 85, 180)}


def _entries() -> list:
    from roughdiffuse import registry

    return [e for e in registry.entries() if e.cls.__module__ == "roughdiffuse.models.renderers"]


def _formula(entry) -> str:
    from roughdiffuse import registry
    from roughdiffuse.models.alias import Alias

    cls = entry.cls
    if not issubclass(cls, Alias):
        return "own kernel"
    base = next(e.id for e in registry.entries() if e.cls is cls.base)
    if cls.base_fixed:
        base = next(
            e.id for e in registry.entries() if e.cls is cls.base and e.fixed == cls.base_fixed
        )
    elif entry.fixed:  # Mitsuba 0.6: full or fast
        base = "oren-nayar-full" if entry.fixed.get("variant") == "full" else "oren-nayar"
    rule = (inspect.getdoc(cls.to_base) or "").rstrip(".")
    return f"`{base}`, {rule}"


def _cosines(ti: float, tr: float, dp: float) -> tuple[float, float, float]:
    ti, tr, dp = (math.radians(x) for x in (ti, tr, dp))
    return (
        math.cos(ti),
        math.cos(tr),
        math.cos(ti) * math.cos(tr) + math.sin(ti) * math.sin(tr) * math.cos(dp),
    )


def _point(entry) -> dict:
    return {p.name: (0.8 if p.channels else p.example if p.example is not None else p.default)
            for p in entry.parameters if not p.categorical}  # fmt: skip


def section() -> str:
    """The Markdown between the markers."""
    rows = ["| id | renderer | source (file, function) | formula |", "| --- | --- | --- | --- |"]
    values = ["| id | parameters | A | B | C | D |", "| --- | --- | ---: | ---: | ---: | ---: |"]
    for e in _entries():
        rows.append(f"| `{e.id}` | {e.label} | {e.reference} | {_formula(e)} |")
        point = _point(e)
        model = e.create(**point)
        cells = []
        for ti, tr, dp in GEOMETRIES.values():
            mu_i, mu_o, c = _cosines(ti, tr, dp)
            cells.append(f"{float(np.asarray(model.brdf_cosines(mu_i, mu_o, c))):.4f}")
        args = ", ".join(f"{k} = {v:g}" for k, v in point.items())
        values.append(f"| `{e.id}` | {args} | " + " | ".join(cells) + " |")
    return "\n".join(
        [
            "Generated from the declarations in `roughdiffuse/models/renderers.py` (each row is",
            "a registry id: `roughdiffuse eval --model ID`, fits, `compare_models`, the Mitsuba",
            "plugin `roughdiffuse_<id>`). A formula that equals one of roughdiffuse's models after",
            "a change of parameters is declared as that conversion; the others (\"own kernel\")",
            "are new formulas.",
            "",
            *rows,
            "",
            "f in 1/sr at the geometries (θi, θr, Δφ) A = (60°, 60°, 0°), B = (60°, 60°, 180°),",
            "C = (30°, 70°, 90°), D = (85°, 85°, 180°):",
            "",
            *values,
        ]
    )


def render(text: str) -> str:
    """``text`` with the section between the markers regenerated."""
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    return f"{head}{BEGIN}\n{section()}\n{END}{tail}"


def generate(docs: Path) -> None:
    """Rewrite docs/implementations.md's generated section if it changed."""
    page = docs / "implementations.md"
    text = page.read_text(encoding="utf-8")
    new = render(text)
    if new != text:
        page.write_text(new, encoding="utf-8")
