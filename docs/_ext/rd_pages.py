"""Pages generated when the site is built: one per registry model, and the API reference.

Nothing here lists models or modules by hand: the model pages come from
:func:`roughdiffuse.registry.entries` (so models added by other packages or branches appear
once they are registered), the API pages from walking the installed ``roughdiffuse`` package.
Generated files go to ``docs/models/`` and ``docs/api/`` (both ignored by git).
"""

from __future__ import annotations

import hashlib
import importlib
import inspect
import json
import math
import pkgutil
import re
import textwrap
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROUGHNESS_NAMES = ("sigma", "roughness", "alpha")


def _write(path: Path, text: str) -> None:
    """Write ``text`` only if it differs (Sphinx then re-reads only changed pages)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


# ------------------------------------------------------------------------------ models
def _varied(entry: Any) -> tuple[Any | None, list[float]]:
    """The roughness-like parameter of ``entry`` and three values across its fit range."""
    numeric = [p for p in entry.parameters if p.choices is None and not p.channels]
    pick = next((p for n in ROUGHNESS_NAMES for p in numeric if p.name == n), None)
    if pick is None:
        pick = next((p for p in numeric if p.unit == "radians"), None)
    if pick is None and numeric:
        pick = numeric[0]
    if pick is None:
        return None, []
    lo, hi = pick.fit_range or (pick.min, pick.max)
    lo = 0.0 if lo is None else lo
    hi = lo + 1.0 if hi is None else hi
    return pick, [lo + (hi - lo) * t for t in (0.2, 0.5, 0.8)]


def _fmt_value(p: Any, v: float) -> str:
    if p.unit == "radians":
        return f"{p.name} = {v:.2f} rad ({math.degrees(v):.0f}°)"
    return f"{p.name} = {v:.3g}"


def _title(entry: Any, values: dict[str, Any]) -> str:
    """``label: name = value, ...`` with numbers rounded (σ = 0.349 rad (20°), not its repr)."""
    parts = []
    for p in entry.parameters:
        if p.name in values and p.name not in entry.fixed:
            v = values[p.name]
            parts.append(f"{p.name} = {v}" if isinstance(v, str) else _fmt_value(p, v))
    return f"{entry.label}: " + ", ".join(parts) if parts else entry.label


def _start(entry: Any) -> dict[str, Any]:
    """Parameters the pictures use: each one's example value (else its default), those that
    exist for the default choices (Coated: its default base's)."""
    out = {}
    for p in entry.parameters:
        value = p.example if p.example is not None else p.default
        if value is not None:
            out[p.name] = value
    return {p.name: out[p.name] for p in entry.applicable(out) if p.name in out}


def _figures(entry: Any, folder: Path) -> dict[str, str]:
    """The sphere, plane-of-incidence and white-furnace pictures of ``entry``."""
    from roughdiffuse.energy import plot_albedo
    from roughdiffuse.plots import plot_plane_of_incidence, radiance_colorbar, show_radiance
    from roughdiffuse.render import DistantLight, Sphere, render

    names = {}
    start = _start(entry)
    model = entry.create(**start)

    fig, axes = plt.subplots(1, 2, figsize=(6.4, 3.4))
    for ax, theta in zip(axes, (0.0, math.radians(60.0)), strict=True):
        image, _ = render(model, Sphere(), DistantLight(theta), size=128)
        image = np.asarray(image, dtype=np.float64)
        vmax = float(np.nanmax(image)) or 1.0
        show_radiance(ax, image, vmax, f"light at θ = {math.degrees(theta):.0f}°")
        radiance_colorbar(ax, vmax)  # each image on its own scale
    fig.suptitle(_title(entry, start), fontsize="small")
    fig.tight_layout()
    names["sphere"] = f"{entry.id}-sphere.png"
    fig.savefig(folder / names["sphere"], dpi=90)
    plt.close(fig)

    pick, values = _varied(entry)
    curves = {"defaults": model} if pick is None else {
        _fmt_value(pick, v): entry.create(**{**start, pick.name: v}) for v in values
    }
    fig, axes = plt.subplots(1, 2, figsize=(9.0, 3.4))
    for ax, deg in zip(axes, (30.0, 60.0), strict=True):
        plot_plane_of_incidence(curves, math.radians(deg), ax=ax, n=181)
    fig.tight_layout()
    names["plane"] = f"{entry.id}-plane.png"
    fig.savefig(folder / names["plane"], dpi=90)
    plt.close(fig)

    white = {"albedo": 1.0} if any(p.name == "albedo" for p in entry.parameters) else {}
    furnace = {label: entry.create(**{**start, **white, **({pick.name: v} if pick else {})})
               for label, v in zip(curves, values or [None], strict=True)}
    fig = plot_albedo({entry.label: furnace}, np.radians(np.arange(0.0, 89.0, 4.0)))
    names["furnace"] = f"{entry.id}-furnace.png"
    fig.savefig(folder / names["furnace"], dpi=90)
    plt.close(fig)
    return names


def _speed(root: Path) -> list[dict[str, Any]]:
    for candidate in (root / "bench" / "results.json",):
        if candidate.is_file():
            try:
                return list(json.loads(candidate.read_text(encoding="utf-8")).get("results", []))
            except (ValueError, AttributeError):
                return []
    return []


def _speed_rows(entry: Any, results: list[dict[str, Any]]) -> list[str]:
    """Rows of ``bench/results.json`` measured on this entry's model."""
    import roughdiffuse
    from roughdiffuse import registry

    namespace = {name: getattr(roughdiffuse, name) for name in dir(roughdiffuse)}
    namespace[entry.cls.__name__] = entry.cls
    rows = []
    for r in results:
        try:
            model = eval(r.get("repr", ""), namespace)  # noqa: S307 - the project's own file
        except Exception:  # noqa: BLE001 - a record of a model this build does not have
            continue
        if registry.id_of(model) != entry.id:
            continue
        cells = [f"2^{r.get('log2_rows', '?')}"]
        for key in ("fast", "c", "numpy"):
            stats = r.get(key) or {}
            cells.append(f"{stats['median']:.0f}" if "median" in stats else "–")
        ratio = r.get("fast_over_numpy")
        cells.append(f"{ratio:.1f}" if ratio else "–")
        rows.append("| " + " | ".join(cells) + " |")
    return rows


def _scores(docs: Path) -> dict[str, Any]:
    """The accuracy report's scoreboard as committed (``docs/accuracy/model_scores.json``,
    written by ``roughdiffuse simulate --report``): the build reads it, never recomputes it."""
    from roughdiffuse.accuracy.model_scores import SCORES_FILE

    try:
        return json.loads((docs / "accuracy" / SCORES_FILE).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}


def _accuracy_lines(entry: Any, scores: dict[str, Any]) -> list[str]:
    """This model's RMS and maximum relative errors against the three all-bounce truths."""
    per_truth = scores.get("models", {}).get(entry.id)
    if not per_truth:
        return [
            "This model is not in the accuracy report's scoreboard (it scores the diffuse "
            "models that are formulas with at most one roughness parameter); how the models "
            "compare with the exact V-cavity surface: {doc}`/accuracy`.",
        ]
    settings = scores.get("settings", {})
    sig = settings.get("sigmas", {})
    published = any(r["mapping"] == "published" for rows in per_truth.values() for r in rows)
    pick = next((r for rows in per_truth.values() for r in rows if r["value"] is not None), None)
    pname = next((p.name for p in entry.parameters if pick is not None and p.name != "albedo"
                  and p.choices is None), None)
    lines = [
        "Relative error (model − truth) / truth against three exact surfaces, all bounces "
        f"(RMS and maximum over {settings.get('geometries', '?')} geometries, θi, θr ∈ "
        + ", ".join(f"{t:g}" for t in settings.get("theta_deg", []))
        + "°, Δφ ∈ " + ", ".join(f"{t:g}" for t in settings.get("delta_phi_deg", []))
        + "°), as measured by the accuracy report (`roughdiffuse simulate --report`, "
        "{mod}`roughdiffuse.accuracy.model_scores`; numbers from "
        "`docs/accuracy/model_scores.json`). The V-cavity surface has the σ of the same mean "
        "square slope as the Beckmann surface of α ("
        + ", ".join(f"α = {a} → σ = {v:.3f}" for a, v in sig.items())
        + "); the Smith surfaces are Monte Carlo, with errors below about "
        f"{100 * settings.get('largest_relative_stderr', 0):.0f} % at the noise level. "
        + (f"`{pname}` is fitted per row (least RMS); the 'published' columns use the "
           "truth's own σ or α instead." if pname else
           "The model has no roughness parameter: it is scored as it is."),
        "",
        "| truth | α | facet ρ | "
        + (f"`{pname}` (best fit) | " if pname else "")
        + "RMS | max |"
        + (" published σ or α: RMS | its max |" if published else ""),
        "| --- | --- | --- | " + ("--- | " if pname else "") + "--- | --- |"
        + (" --- | --- |" if published else ""),
    ]
    for truth, rows in per_truth.items():
        pub = {(r["alpha"], r["rho"]): r for r in rows if r["mapping"] == "published"}
        for r in rows:
            if r["mapping"] == "published":
                continue
            cells = [truth, f"{r['alpha']:g}", f"{r['rho']:g}"]
            if pname:
                cells.append(f"{r['value']:.3f}")
            cells += [f"{r['rms']:.3f}", f"{r['max']:.2f}"]
            if published:
                p = pub.get((r["alpha"], r["rho"]))
                cells += [f"{p['rms']:.3f}", f"{p['max']:.2f}"] if p else ["–", "–"]
            lines.append("| " + " | ".join(cells) + " |")
    lines += ["", "The whole report, with every model side by side: {doc}`/accuracy/index`."]
    return lines


def _param_table(entry: Any) -> list[str]:
    from roughdiffuse.models.declaration import format_interval

    lines = ["| parameter | meaning | unit | accepted | default | per channel |",
             "| --- | --- | --- | --- | --- | --- |"]
    for p in entry.parameters:
        if p.choices is not None:
            accepted = ", ".join(f"`{c}`" for c in p.choices)
        else:
            accepted = format_interval(p.min, p.max, p.min_open)
        default = f"`{p.default}`" if isinstance(p.default, str) else f"{p.default:g}"
        only = "" if p.applies(entry.fixed) else f" (only with {p.when_text()})"
        lines.append(
            f"| `{p.name}` | {p.description}{only} | {p.unit} | {accepted} | {default} | "
            f"{'yes' if p.channels else 'no'} |"
        )
    if len(lines) == 2:
        lines.append("| (none) | | | | | |")
    return lines


NOTATION = (
    "{math}`\\theta_i, \\theta_r`: angles of the light and the viewer from the normal "
    "({math}`\\mu_i = \\cos\\theta_i`, {math}`\\mu_o = \\cos\\theta_r`); "
    "{math}`\\phi_r - \\phi_i`: their azimuth difference; {math}`\\omega_i, \\omega_o`: "
    "the unit vectors towards them, n the normal, h the half vector; {math}`f_r` in 1/sr, the "
    "radiance {math}`L = f_r E_0 \\cos\\theta_i` for irradiance {math}`E_0` (the package's "
    "{mod}`roughdiffuse.frames`)."
)


def formula_of(entry: Any) -> str:
    """The formula text a registry entry's class declares (``Model.formula``), dedented."""
    text = entry.cls.formula
    if isinstance(text, dict):
        text = text.get(entry.id, "")
    return textwrap.dedent(text).strip()


EQUATION_NUMBER = re.compile(
    r"\bEqs?\.\s*\d+(?:\.\d+)?[a-z]?(?:\s*(?:[–,-]|and)\s*\d+(?:\.\d+)?[a-z]?)*"
)
"""An equation number a formula cites ("Eq. 27", "Eq. 9.40, 12.55", "Eq. 28 and 37")."""

CHECKED_EQUATION_NUMBERS: dict[str, str] = {
    "hapke-legendre": (
        "the book's text was not at hand; two independent programs that transcribe the 2nd "
        "edition (2012) give this number to the whole rough-surface reflectance (porosity K, "
        "effective cosines, shadow-hiding term, H functions, shadowing S): Marc W. Buie's IDL "
        "routine `bidr4.pro` (\"combined model, eqn. 12.55, p. 323\") and the IDL routine "
        "`HAPKE_CS` (\"computes Equation 12.55 in the Hapke (2012) Book\")."
    ),
    "lambert-sphere": (
        "the paper's text was not at hand; the paper's author cites the same numbers in his "
        "own implementation (eugenedeon/mitsuba, `src/bsdfs/lambert_sphere.cpp`): `c_from_kd` "
        "\"[d'Eon 2021, Eq.(46)]\", `H0` \"Eq.(37)\" and `H1` \"Eq.(28)\"."
    ),
}
"""Model id -> how the equation numbers its formula cites were checked against the paper's
own numbering (the text the page then shows). A model is listed only when every number its
formula cites was found in the paper's text, in two independent sources that quote the paper,
or in the paper's author's own implementation;
a model not here gets the note that its numbers are not checked: they are carried over from the
sources the implementation was written from, and no copy of the paper was at hand to compare
them with."""


def equation_note(entry: Any) -> str:
    """The sentence a model page shows under its formula about the equation numbers it cites
    (empty when it cites none)."""
    found = EQUATION_NUMBER.finditer(formula_of(entry))
    cited = list(dict.fromkeys(" ".join(m.group(0).split()) for m in found))
    if not cited:
        return ""
    how = CHECKED_EQUATION_NUMBERS.get(entry.id)
    if how:
        return f"Equation numbers ({'; '.join(cited)}): {how}"
    return (f"Equation numbers ({'; '.join(cited)}): as the sources this implementation was "
            "written from cite them; **not checked** against the papers' own numbering.")


def _formula_section(entry: Any) -> list[str]:
    """"The formula" of a model page: the declared LaTeX, the symbols of the declared
    parameters, whether the equation numbers it cites were checked, the common notation."""
    text = formula_of(entry)
    if not text:
        return ["## The formula", "", "This model declares no formula (`Model.formula`).", ""]
    note = equation_note(entry)
    rows = ["| symbol | parameter | meaning |", "| --- | --- | --- |"]
    for p in entry.parameters:
        symbol = entry.cls.symbols.get(p.name)
        if symbol and p.name not in entry.fixed:
            rows.append(f"| {{math}}`{symbol}` | `{p.name}` | {p.description} |")
    return ["## The formula", "", text, "", *([note, ""] if note else []),
            *(rows if len(rows) > 2 else []), "", NOTATION, ""]


def _model_page(entry: Any, names: dict[str, str] | None, speed: list[str],
                accuracy: list[str]) -> str:
    """The Markdown of ``docs/models/<id>.md``: header and parameters, pictures, accuracy and
    speed."""
    lines = _header_lines(entry)
    lines += _picture_lines(entry, names)
    lines += ["## Accuracy", "", *accuracy, "", "## Speed", ""]
    lines += _speed_lines(speed)
    lines.append("")
    return "\n".join(lines)


def _header_lines(entry: Any) -> list[str]:
    """Title, id, class, paper, the class docstring and the parameter table."""
    cls = entry.cls
    qual = f"{cls.__module__}.{cls.__qualname__}"
    fixed = ", ".join(f"{k}={v!r}" for k, v in entry.fixed.items())
    create = f'registry.create("{entry.id}")'
    return [
        f"# {entry.label}",
        "",
        f"`{entry.id}` · {entry.lobe} · class {{py:class}}`{qual}`"
        + (f" with `{fixed}`" if fixed else "")
        + f" · from `{entry.source}`"
        + (" · also in the explorer's GLSL" if entry.glsl else ""),
        "",
        f"**Paper:** {entry.reference}",
        "",
        *_formula_section(entry),
        "## The model",
        "",
        "```{eval-rst}",
        f".. autoclass:: {qual}",
        "   :no-index:",
        "   :no-members:",
        "```",
        "",
        "```python",
        "from roughdiffuse import registry",
        f"model = {create}  # defaults; keyword arguments set parameters",
        "```",
        "",
        "## Parameters",
        "",
        *_param_table(entry),
        "",
        "On the command line: `--model " + entry.id
        + " --param NAME=VALUE` (angles in degrees there).",
        "",
    ]


def _picture_lines(entry: Any, names: dict[str, str] | None) -> list[str]:
    """The sphere, the plane of incidence and the white furnace (none for a simulation)."""
    if names is None:  # a Monte Carlo simulation: no images at build time
        return [
            "## Pictures",
            "",
            "This model is a Monte Carlo simulation on concrete values (it cannot be traced "
            "by the renderer's `jax.jit`), so this page shows no rendered sphere or curves; "
            "its values against the other surfaces are in {doc}`/accuracy`.",
            "",
        ]
    pick, _ = _varied(entry)
    return [
        "## A sphere",
        "",
        f"![{entry.label}: rendered sphere]({names['sphere']})",
        "",
        "## Plane of incidence",
        "",
        "Radiance against the signed viewing angle θr in the plane of incidence "
        "(E0 = 1; {func}`roughdiffuse.plots.plot_plane_of_incidence`)"
        + (f", for three values of `{pick.name}`." if pick else "."),
        "",
        f"![{entry.label}: plane of incidence]({names['plane']})",
        "",
        "## White furnace",
        "",
        "Directional albedo ∫ f cos θi dωi against the viewing angle "
        "({func}`roughdiffuse.energy.plot_albedo`"
        + (", albedo 1" if any(p.name == "albedo" for p in entry.parameters) else "")
        + "): 1 means no energy lost or gained.",
        "",
        f"![{entry.label}: white furnace]({names['furnace']})",
        "",
    ]


def _speed_lines(speed: list[str]) -> list[str]:
    """The benchmark rows of this model, or a note that there are none."""
    if not speed:
        return ["Not in `bench/results.json` (run `python bench/run.py`)."]
    return [
        "Million evaluations per second from `bench/results.json` "
        "({doc}`/benchmarks`; `fast` is {func}`roughdiffuse.engine.fastpath.evaluate`, `C` "
        "the hand-written reference kernel, `NumPy` `model.radiance`):",
        "",
        "| N | fast | C | NumPy | fast/NumPy |",
        "| --- | --- | --- | --- | --- |",
        *speed,
    ]


def generate_models(docs: Path) -> list[str]:
    """Write ``docs/models/<id>.md`` and its pictures for every registry entry."""
    from roughdiffuse import registry

    folder = docs / "models"
    folder.mkdir(exist_ok=True)
    results = _speed(docs.parent)
    scores = _scores(docs)
    ids = []
    cache_file = folder / ".cache.json"
    try:
        cache = json.loads(cache_file.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        cache = {}
    # the pictures are redrawn when what draws them changes, not on any edit of this file
    drawing = (_figures, _title, _fmt_value, _varied, _start)
    generator = hashlib.sha256(
        "".join(inspect.getsource(fn) for fn in drawing).encode()
    ).hexdigest()
    for entry in registry.entries():
        source = inspect.getsource(inspect.getmodule(entry.cls))
        key = hashlib.sha256(
            f"{generator}{entry.to_json()}{source}".encode()
        ).hexdigest()
        names = {k: f"{entry.id}-{k}.png" for k in ("sphere", "plane", "furnace")}
        if not entry.cls.traceable:
            names = None
        elif cache.get(entry.id) != key or not all((folder / n).is_file() for n in names.values()):
            names = _figures(entry, folder)
            cache[entry.id] = key
        _write(folder / f"{entry.id}.md", _model_page(entry, names, _speed_rows(entry, results),
                                                       _accuracy_lines(entry, scores)))
        ids.append(entry.id)
    cache_file.write_text(json.dumps(cache, indent=1), encoding="utf-8")
    rows = ["| id | model | lobe | parameters | paper |", "| --- | --- | --- | --- | --- |"]
    for entry in registry.entries():
        params = ", ".join(p.name for p in entry.parameters) or "–"
        rows.append(f"| {{doc}}`{entry.id} <{entry.id}>` | {entry.label} | {entry.lobe} | "
                    f"{params} | {entry.reference} |")
    index = [
        "# Models",
        "",
        "Every model of {mod}`roughdiffuse.registry` (what `roughdiffuse models` lists), one page "
        "each, generated when this site is built: a model registered by another package "
        "(entry point `roughdiffuse.models`) appears here too.",
        "",
        *rows,
        "",
        "```{toctree}",
        ":hidden:",
        "",
        *ids,
        "```",
        "",
    ]
    _write(folder / "index.md", "\n".join(index))
    return ids


# ------------------------------------------------------------------------------ API
def public_modules(package: str = "roughdiffuse") -> list[str]:
    """Every importable public module of ``package`` (no ``_private`` part, no ``__main__``)."""
    pkg = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(pkg.__path__, prefix=f"{package}."):
        parts = info.name.split(".")
        if any(part.startswith("_") for part in parts):
            continue
        try:
            importlib.import_module(info.name)
        except Exception:  # noqa: BLE001 - an optional backend (Mitsuba, torch) not installed
            continue
        names.append(info.name)
    return sorted(names)


def _exports(module: Any) -> list[tuple[str, str]]:
    """(name, canonical path) of what a module re-exports from elsewhere in the package."""
    out = []
    for name in getattr(module, "__all__", []):
        obj = getattr(module, name, None)
        home = getattr(obj, "__module__", None)
        if inspect.ismodule(obj):
            out.append((name, obj.__name__))
        elif home and home != module.__name__ and home.startswith("roughdiffuse"):
            out.append((name, f"{home}.{getattr(obj, '__qualname__', name)}"))
    return out


TASKS: tuple[tuple[str, str, tuple[str, ...]], ...] = (
    ("Models", "The reflectance models and the registry that lists them: "
     "{func}`roughdiffuse.registry.create`, {class}`roughdiffuse.OrenNayar` and the others.",
     ("roughdiffuse.registry", "roughdiffuse.models")),
    ("Evaluation", "Evaluating a model: directions and angles, the compiled fast path, "
     "directional albedo and the white furnace, sampling, quadrature, roughness conversions.",
     ("roughdiffuse", "roughdiffuse.frames", "roughdiffuse.fastpath",
      "roughdiffuse.engine.fastpath",
      "roughdiffuse.energy", "roughdiffuse.quadrature", "roughdiffuse.roughness",
      "roughdiffuse.models.sampling", "roughdiffuse.models.photometry",
      "roughdiffuse.models.microfacet", "roughdiffuse.models.declaration",
      "roughdiffuse.models.base")),
    ("Rendering and plots", "Images of shapes under distant lights, and the lecture's plots "
     "and figures.", ("roughdiffuse.render", "roughdiffuse.plots", "roughdiffuse.figures")),
    ("Fitting", "Fitting models to BRDF samples, MERL files and images: "
     "{func}`roughdiffuse.fit.fit`, {func}`roughdiffuse.fit.compare_models`, the shipped "
     "data.", ("roughdiffuse.fit", "roughdiffuse.data")),
    ("Ground truth", "Exact surfaces the models approximate: V-cavities, Smith walks, "
     "heightfields, their tables and accuracy reports.",
     ("roughdiffuse.simulate", "roughdiffuse.accuracy", "roughdiffuse.models.vcavity",
      "roughdiffuse.models.smith_diffuse")),
    ("Photometric stereo", "Normals, albedo and roughness from images under several lights.",
     ("roughdiffuse.stereo",)),
    ("Integrations", "Mitsuba 3 plugins, the browser explorer, reading and writing files.",
     ("roughdiffuse.integrations", "roughdiffuse.explorer", "roughdiffuse.io")),
)
"""The API reference's sections: title, what it is for, module prefixes (longest match wins)."""

INTERNALS = ("roughdiffuse.bench", "roughdiffuse.commands", "roughdiffuse.cli",
             "roughdiffuse.engine",
             "roughdiffuse.deprecation", "roughdiffuse.io.atomic",
             "roughdiffuse.integrations.drjit_namespace", "roughdiffuse.simulate.smith_walk_numba")
"""Modules for the package's own commands and machinery: on the internals page only."""


def task_of(module: str) -> str:
    """The API section of ``module``: the task whose longest prefix matches, or "Internals"."""
    best, length = "Internals", -1
    for title, _, prefixes in (*TASKS, ("Internals", "", INTERNALS)):
        for prefix in prefixes:
            matches = module == prefix or (prefix != "roughdiffuse"
                                           and module.startswith(prefix + "."))
            if matches and len(prefix) > length:
                best, length = title, len(prefix)
    return best


def _module_page(name: str) -> list[str]:
    module = importlib.import_module(name)
    title = f"``{name}``"
    lines = [title, "=" * len(title), "", f".. automodule:: {name}", "   :members:",
             "   :ignore-module-all:", "   :show-inheritance:", ""]
    exports = _exports(module)
    if not exports:
        return lines
    if hasattr(module, "__path__") and name != "roughdiffuse":
        # a subpackage documents what it offers in full (``roughdiffuse.fit.fit`` here, not
        # only a link): :no-index: keeps the home page as the target of cross-references
        lines += ["What it offers", "-" * 14, ""]
        for short, full in exports:
            obj = getattr(module, short, None)
            if inspect.isclass(obj):
                directive = "autoclass"
            elif callable(obj):
                directive = "autofunction"
            else:
                continue
            lines += [f".. {directive}:: {full}", "   :no-index:", ""]
    lines += ["Also available here", "-" * 19, "",
              "Defined in another module and importable from this one:", ""]
    for short, full in exports:
        obj = getattr(module, short, None)
        role = "mod" if inspect.ismodule(obj) else "obj"
        lines.append(f"- ``{short}``: :py:{role}:`{full}`")
    lines.append("")
    return lines


def generate_api(docs: Path) -> list[str]:
    """Write ``docs/api/<module>.rst`` (autodoc of what each module defines), the index by
    task and the internals page."""
    folder = docs / "api"
    folder.mkdir(exist_ok=True)
    modules = public_modules()
    for name in modules:
        old = folder / f"{name}.md"
        if old.exists():
            old.unlink()
        _write(folder / f"{name}.rst", "\n".join(_module_page(name)))
    by_task: dict[str, list[str]] = {}
    for name in modules:
        by_task.setdefault(task_of(name), []).append(name)
    summary = [
        "# API reference",
        "",
        "The package by task (generated from the docstrings when the site is built; a module "
        "that imports an optional backend, e.g. Mitsuba, appears when that backend is "
        "installed). The modules behind the command line and the benchmarks are on "
        "{doc}`internals`.",
        "",
    ]
    for title, blurb, _ in TASKS:
        if not by_task.get(title):
            continue
        summary += [f"## {title}", "", blurb, "", "```{eval-rst}", ".. autosummary::", "",
                    *[f"   {name}" for name in by_task[title]], "```", ""]
    summary += ["```{toctree}", ":hidden:", "", *[n for n in modules
                                                   if task_of(n) != "Internals"],
                "internals", "```", ""]
    _write(folder / "index.md", "\n".join(summary))
    internals = [
        "# Internals",
        "",
        "Modules of the command line (`roughdiffuse ...`), the benchmarks and the package's "
        "own machinery: public in name, not meant to be imported by users.",
        "",
        "```{eval-rst}",
        ".. autosummary::",
        "",
        *[f"   {name}" for name in by_task.get("Internals", [])],
        "```",
        "",
        "```{toctree}",
        ":hidden:",
        "",
        *by_task.get("Internals", []),
        "```",
        "",
    ]
    _write(folder / "internals.md", "\n".join(internals))
    return modules


def generate(docs: Path) -> None:
    generate_models(docs)
    generate_api(docs)


__all__ = ["CHECKED_EQUATION_NUMBERS", "EQUATION_NUMBER", "TASKS", "equation_note", "formula_of",
           "generate", "generate_api", "generate_models", "public_modules", "task_of"]
