"""The accuracy report's scoreboard: every registry model against three all-bounce truths.

Truths (all bounces, facet albedo ρ = 0.5 and 0.9), on one grid of (θi, θr, Δφ):

* the V-cavity surface (:mod:`.surface`, ``Settings()``), at the σ whose mean square slope
  angle equals that of the Beckmann surface of each α (:func:`.smith_checks.matching_sigma`);
* the Smith microsurface with Lambertian facets, Beckmann slopes of roughness α;
* the same with GGX slopes (:mod:`.smith`, random walk; the Monte Carlo error is printed).

Models: every registry entry with a diffuse lobe that is a formula (``traceable``), the Mix
left out (a blend, not a surface). Each model gets albedo = ρ and its one roughness
parameter (the numeric parameter other than the albedo) by the best fit: the value in its
declared range that minimises the RMS relative error against each truth (a 41-point scan,
refined by a bounded scalar minimisation); where a published mapping exists it is scored too
(Oren–Nayar's σ is the V-cavity σ by construction; Hammon's α is the GGX α). Models without
a roughness parameter are scored as they are.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy import optimize

from .. import registry
from ..io.atomic import write_text
from ..io.jsonfile import dumps
from ..simulate import smith
from ..simulate.surface import Settings
from ..simulate.surface import brdf as cavity_brdf
from .smith_checks import matching_sigma

__all__ = ["SCORES_FILE", "model_score_lines"]

SCORES_FILE = "model_scores.json"
"""The scoreboard as data, written beside the report (the model pages of the site read it)."""

ALPHAS = (0.2, 0.5, 1.0)
ALBEDOS = (0.5, 0.9)
TRUTHS = ("V-cavity", "Smith-Beckmann", "Smith-GGX")
PUBLISHED = {
    ("oren-nayar", "V-cavity"): "sigma",
    ("oren-nayar-full", "V-cavity"): "sigma",
    ("hammon", "Smith-GGX"): "alpha",
}
"""(model id, truth) -> the parameter whose published value is the truth's σ or α."""


def _grid(quick: bool):
    ang = np.radians([0.0, 40.0, 75.0] if quick else [0.0, 15.0, 30.0, 45.0, 60.0, 75.0])
    dps = np.radians([0.0, 180.0] if quick else [0.0, 60.0, 120.0, 180.0])
    g = np.meshgrid(ang, ang, dps, indexing="ij")
    return tuple(x.ravel() for x in g)


def _truths(quick: bool, progress: bool):
    """{(truth, α, ρ): (values, standard errors)} on the grid, and the largest relative s.e."""
    from tqdm import tqdm

    ti, tr, dp = _grid(quick)
    alphas = (0.5,) if quick else ALPHAS
    samples = 2_000 if quick else 100_000
    out = {}
    jobs = [(t, a) for t in TRUTHS for a in alphas]
    for truth, a in tqdm(jobs, desc="truths", disable=not progress):
        if truth == "V-cavity":
            s = matching_sigma(a)
            for rho in ALBEDOS:
                out[truth, a, rho] = (cavity_brdf(ti, tr, dp, s, rho, "all", Settings()), None)
        else:
            dist = "beckmann" if truth == "Smith-Beckmann" else "ggx"
            r = smith.random_walk(ti, tr, dp, a, ALBEDOS, "all", dist, samples=samples, seed=17)
            for k, rho in enumerate(ALBEDOS):
                out[truth, a, rho] = (r.values[k], r.stderr[k])
    rel = max(float(np.max(se / v)) for v, se in out.values() if se is not None)
    return out, rel, alphas, samples


def _entries():
    chosen = []
    for e in registry.entries():
        if e.lobe != "diffuse" or not e.cls.closed_form or e.id == "mix":
            continue
        numeric = [p for p in e.parameters if not p.categorical and p.name != "albedo"]
        if len(numeric) > 1:
            continue
        chosen.append((e, numeric[0] if numeric else None))
    return chosen


def _rms_and_max(entry, param, value, rho, cosines, truth):
    kw = {"albedo": rho}
    if param is not None:
        kw[param.name] = value
    f = np.asarray(entry.create(**kw).brdf_cosines(*cosines), dtype=np.float64)
    e = (f - truth) / truth
    return float(np.sqrt(np.mean(e * e))), float(np.max(np.abs(e)))


def _best(entry, param, rho, cosines, truth, quick=False):
    lo, hi = param.bounds
    xs = np.linspace(lo, hi, 11 if quick else 41)
    rms = [_rms_and_max(entry, param, x, rho, cosines, truth)[0] for x in xs]
    k = int(np.argmin(rms))
    if quick:  # the scan only
        return float(xs[k]), *_rms_and_max(entry, param, xs[k], rho, cosines, truth)
    a, b = xs[max(k - 1, 0)], xs[min(k + 1, len(xs) - 1)]
    res = optimize.minimize_scalar(
        lambda x: _rms_and_max(entry, param, x, rho, cosines, truth)[0],
        bounds=(a, b),
        method="bounded",
        options={"xatol": 1e-4 * (hi - lo)},
    )
    x = float(res.x) if res.fun <= rms[k] else float(xs[k])
    return x, *_rms_and_max(entry, param, x, rho, cosines, truth)


def _score_cells(entry, param, truth, alphas, truths, cosines, quick):
    """One model against one truth over every α and ρ: the table cells (best fit, and
    published value where there is one), the RMS errors, and the JSON records."""
    cells, pub_cells, rms_all, rows = [], [], [], []
    for a in alphas:
        for rho in ALBEDOS:
            values = truths[truth, a, rho][0]
            if param is None:
                rms, mx = _rms_and_max(entry, None, None, rho, cosines, values)
                cells.append(f"{rms:.3f} (max {mx:.2f})")
                x, how = None, "none"
            else:
                x, rms, mx = _best(entry, param, rho, cosines, values, quick)
                cells.append(f"{rms:.3f} (max {mx:.2f}) [{x:.2f}]")
                how = "best fit"
            rows.append({"alpha": a, "rho": rho, "mapping": how, "value": x,
                         "rms": rms, "max": mx})  # fmt: skip
            rms_all.append(rms)
            pname = PUBLISHED.get((entry.id, truth))
            if pname is not None and param is not None and param.name == pname:
                value = matching_sigma(a) if pname == "sigma" else a
                value = min(value, param.bounds[1])
                prms, pmx = _rms_and_max(entry, param, value, rho, cosines, values)
                pub_cells.append(f"{prms:.3f} (max {pmx:.2f})")
                rows.append({"alpha": a, "rho": rho, "mapping": "published",
                             "value": value, "rms": prms, "max": pmx})  # fmt: skip
    return cells, pub_cells, rms_all, rows


def _intro_lines(ti, dp, alphas, samples, rel_se) -> list[str]:
    """The section's heading and what its tables compare."""
    return [
        "",
        "## Every model against three surfaces",
        "",
        f"All bounces, ρ ∈ {{{', '.join(f'{r:g}' for r in ALBEDOS)}}}, α ∈ "
        f"{{{', '.join(f'{a:g}' for a in alphas)}}}, on {ti.size} geometries (θi, θr ∈ "
        f"{{{', '.join(f'{math.degrees(x):.0f}' for x in np.unique(ti))}}}°, Δφ ∈ "
        f"{{{', '.join(f'{math.degrees(x):.0f}' for x in np.unique(dp))}}}°). Truths: the "
        "V-cavity surface at the σ of the same mean square slope angle ("
        + ", ".join(f"σ = {matching_sigma(a):.3f} for α = {a:g}" for a in alphas)
        + f"), and the Smith Lambertian microsurface with Beckmann and GGX slopes "
        f"({samples:,} paths per geometry; largest relative standard error "
        f"{100 * rel_se:.1f} %, so RMS errors below about {100 * rel_se:.0f} % are at the "
        "noise level). Error = (model − truth) / truth; RMS and maximum over the grid. Each "
        "model's roughness parameter is fitted per truth, α and ρ (value in brackets); "
        "'published' rows use the truth's own σ or α.",
        "",
    ]


def _write_scores(out, data, ti, dp, alphas, samples, rel_se, quick) -> None:
    """The scoreboard as JSON, ``out / SCORES_FILE``."""
    settings = {
        "albedos": list(ALBEDOS),
        "alphas": list(alphas),
        "sigmas": {f"{a:g}": matching_sigma(a) for a in alphas},
        "theta_deg": [round(math.degrees(x), 6) for x in np.unique(ti)],
        "delta_phi_deg": [round(math.degrees(x), 6) for x in np.unique(dp)],
        "geometries": ti.size,
        "smith_samples": samples,
        "largest_relative_stderr": rel_se,
        "quick": quick,
    }
    payload = {"settings": settings, "models": data}
    write_text(Path(out) / SCORES_FILE, dumps(payload, indent=1) + "\n")


def model_score_lines(quick: bool, progress: bool = True, out: Path | None = None) -> list[str]:
    """The scoreboard section: tables per truth, and which model for which surface.

    With ``out``, the same numbers are also written to ``out / SCORES_FILE`` as JSON:
    ``{"settings": {...}, "models": {id: {truth: [{"alpha", "rho", "mapping", "value",
    "rms", "max"}, ...]}}}`` (``value`` is the roughness used, ``None`` without one).
    """
    ti, tr, dp = _grid(quick)
    cosines = (
        np.cos(ti),
        np.cos(tr),
        np.cos(ti) * np.cos(tr) + np.sin(ti) * np.sin(tr) * np.cos(dp),
    )
    truths, rel_se, alphas, samples = _truths(quick, progress)
    entries = _entries()
    lines = _intro_lines(ti, dp, alphas, samples, rel_se)
    summary: dict[str, dict[str, list[float]]] = {t: {} for t in TRUTHS}
    data: dict[str, dict[str, list[dict]]] = {}
    for truth in TRUTHS:
        lines += [
            f"### Against the {truth} surface",
            "",
            "| model | mapping | "
            + " | ".join(f"α = {a:g}, ρ = {r:g}" for a in alphas for r in ALBEDOS)
            + " |",
            "| --- | --- |" + " --- |" * (len(alphas) * len(ALBEDOS)),
        ]
        for entry, param in entries:
            cells, pub_cells, rms_all, rows = _score_cells(
                entry, param, truth, alphas, truths, cosines, quick
            )
            data.setdefault(entry.id, {}).setdefault(truth, []).extend(rows)
            summary[truth][entry.label] = rms_all
            mapping = "none" if param is None else f"{param.name}: best fit"
            lines.append(f"| {entry.label} | {mapping} | " + " | ".join(cells) + " |")
            if pub_cells:
                lines.append(
                    f"| {entry.label} | {PUBLISHED[entry.id, truth]}: published | "
                    + " | ".join(pub_cells)
                    + " |"
                )
        lines.append("")
    lines += [
        "### Which model for which surface",
        "",
        "Mean RMS relative error over the α and ρ above (each model at its best-fit "
        "roughness), best first:",
        "",
    ]
    for truth in TRUTHS:
        ranked = sorted(summary[truth].items(), key=lambda kv: float(np.mean(kv[1])))
        best = ", ".join(f"{name} {np.mean(v):.3f}" for name, v in ranked[:4])
        lines.append(f"* **{truth}**: {best}.")
    if out is not None:
        _write_scores(out, data, ti, dp, alphas, samples, rel_se, quick)
    return lines
