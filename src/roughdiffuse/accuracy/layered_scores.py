"""The accuracy report's layered section: closed forms of a coated surface against the walk.

The truth is :func:`roughdiffuse.simulate.layered.brdf` (position-free Monte Carlo through
the coat, its rough interface the exact multiple-scattering microsurface of Heitz et al.
2016). Scored against it, on a grid of geometries, for Lambertian, Oren–Nayar and EON bases
under a smooth and a rough coat, and a V-cavity base (a table, run by the NumPy walk, which
has the exact interface too but is about four times slower) under the smooth coat:

* :class:`~roughdiffuse.models.coated.Coated`, the closed form;
* :class:`~roughdiffuse.models.mix.Mix` of the base and a Torrance–Sparrow (Beckmann) lobe of
  the coat's roughness, at its best-fitting weight (least squares in the relative error);
* Mitsuba 3's own ``plastic`` (smooth, ``nonlinear=true``) and ``roughplastic`` (GGX or
  Beckmann, ``nonlinear=true``) for the Lambertian base, when Mitsuba is installed;
* the walk with the single-scattering interface (``interface="single"``, the behaviour of
  pbrt-v4's ``LayeredBxDF`` and of Mitsuba's ``roughdielectric``), rough coats.

Beside the table, the white furnace (:func:`furnace_figure`): the directional albedo of a
white Lambertian base under the rough coat (GGX and Beckmann side by side), by each of them.

Errors are relative, |f − f_truth| / f_truth, RMS and maximum over the grid; the walk's own
relative standard error is listed beside them (an error below about twice it is noise).

Run ``python -m roughdiffuse.accuracy.layered_scores docs/accuracy/layered.md [SAMPLES]
[CACHE]`` to write the page (about ten CPU-minutes at 40,000 paths; the walks' results are
kept in the folder CACHE, if given, and read from it when run again).
"""

from __future__ import annotations

import hashlib
import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..io.atomic import write_text
from ..models import EON, Lambert, Mix, Model, OrenNayar, TorranceSparrow, VCavity
from ..models.coated import Coated
from ..simulate import layered

__all__ = ["Case", "furnace_figure", "layered_lines", "score_case"]

ETA = 1.5
ALBEDO = 0.8
ROUGH = 0.3
ROUGHS = (0.1, 0.3, 0.5)
"""The rough coats scored; :data:`ROUGH` is the furnace figure's."""
DISTRIBUTIONS = ("ggx", "beckmann")
"""The rough coats' facet distributions scored."""
_ANGLES = np.radians([0.0, 20.0, 40.0, 60.0, 75.0])
_PHIS = np.radians([0.0, 90.0, 180.0])


@dataclass(frozen=True)
class Case:
    """One configuration: a label, the base, the coat's roughness α and distribution."""

    label: str
    base: Model
    roughness: float
    distribution: str = "ggx"


def _cases() -> list[Case]:
    bases = [
        ("Lambert ρ = 0.8", Lambert(ALBEDO)),
        ("Oren–Nayar full ρ = 0.8, σ = 0.3", OrenNayar(ALBEDO, 0.3, "full")),
        ("EON ρ = 0.8, r = 0.5", EON(ALBEDO, 0.5)),
        ("V-cavity ρ = 0.8, σ = 0.3", VCavity(ALBEDO, 0.3)),
    ]
    smooth = [Case(f"{name}, smooth coat", base, 0.0) for name, base in bases]
    rough = [Case(f"{name}, {d.upper() if d == 'ggx' else d.capitalize()} α = {a} coat", base,
                  a, d)
             for d in DISTRIBUTIONS for a in ROUGHS for name, base in bases
             if not isinstance(base, VCavity)]
    return smooth + rough


def _grid() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    ti, tr, dp = np.meshgrid(_ANGLES, _ANGLES, _PHIS, indexing="ij")
    return ti.ravel(), tr.ravel(), dp.ravel()


def _dirs(ti, tr, dp) -> tuple[np.ndarray, np.ndarray]:
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], -1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], -1)
    return wi, wo


def _errors(f: np.ndarray, truth: np.ndarray) -> tuple[float, float]:
    rel = (np.asarray(f) - truth) / truth
    return float(np.sqrt(np.mean(rel * rel))), float(np.max(np.abs(rel)))


def _best_mix(case: Case, wi, wo, truth) -> tuple[float, np.ndarray]:
    """Mix (1 − w) base + w TS-Beckmann(η, α): the w minimising the relative residuals
    (linear in w: closed-form least squares); for a smooth coat the lobe is 0, f = (1 − w) base."""
    b = np.asarray(case.base.brdf(wi, wo))
    if case.roughness > 0:
        s = np.asarray(TorranceSparrow(ETA, None, "beckmann", alpha=case.roughness).brdf(wi, wo))
    else:
        s = np.zeros_like(b)
    d = (s - b) / truth
    r = (truth - b) / truth
    w = float(np.clip(np.sum(d * r) / np.sum(d * d), 0.0, 1.0))
    model = Mix([(1.0 - w, case.base), (w, TorranceSparrow(ETA, None, "beckmann",
                                                             alpha=max(case.roughness, 1e-3)))])
    f = np.asarray(model.brdf(wi, wo)) if case.roughness > 0 else (1 - w) * b
    return w, f


def _mitsuba(case: Case, ti, tr, dp) -> np.ndarray | None:
    if not isinstance(case.base, Lambert):
        return None
    try:
        import mitsuba as mi

        mi.set_variant("scalar_rgb")
    except (ImportError, AttributeError, RuntimeError):
        return None
    spec: dict[str, Any] = {"int_ior": ETA, "ext_ior": 1.0, "nonlinear": True,
                            "diffuse_reflectance": {"type": "rgb", "value": [ALBEDO] * 3}}
    if case.roughness > 0:
        spec.update(type="roughplastic", distribution=case.distribution,
                    alpha=case.roughness)
    else:
        spec.update(type="plastic")
    bsdf = mi.load_dict(spec)
    out = []
    for a, b, c in zip(ti, tr, dp, strict=True):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(math.sin(b) * math.cos(c), math.sin(b) * math.sin(c), math.cos(b))
        v = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(math.sin(a), 0.0, math.cos(a)))
        out.append(float(v[0]) / max(math.cos(a), 1e-12))
    return np.array(out)


def _walk(case: Case, samples: int, seed: int, interface: str,
          cache: Path | None) -> tuple[np.ndarray, np.ndarray]:
    """The walk's f and standard error on the grid, read from ``cache`` if it holds them
    (a file named by the case, its base's parameters, the paths, the seed, the interface)."""
    key = repr((case.label, case.base, case.roughness, case.distribution, samples, seed,
                interface, ETA, tuple(_ANGLES), tuple(_PHIS)))

    def run() -> tuple[np.ndarray, np.ndarray]:
        ti, tr, dp = _grid()
        return layered.brdf(ti, tr, dp, case.base, eta=ETA, roughness=case.roughness,
                            distribution=case.distribution, samples=samples, seed=seed,
                            interface=interface, return_stderr=True)

    return _cached(cache, "layered", key, run)


def _cached(cache: Path | None, prefix: str, key: str,
            run: Any) -> tuple[np.ndarray, np.ndarray]:
    """``run()``'s (value, standard error), kept in the folder ``cache`` (if given) under a
    name made from ``prefix`` and a hash of ``key``, and read from there when it is; each
    file written whole or not at all (an interrupted run leaves no half file to be read)."""
    if cache is None:
        return run()
    from ..io.atomic import atomic_write

    path = cache / f"{prefix}_{hashlib.sha1(key.encode()).hexdigest()[:16]}.npy"
    if path.exists():
        value, se = np.load(path)
        return value, se
    value, se = run()
    cache.mkdir(parents=True, exist_ok=True)

    def write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            np.save(fh, np.stack([value, se]))

    atomic_write(path, write)
    return value, se


def score_case(case: Case, samples: int = 40_000, seed: int = 0,
               cache: Path | None = None) -> dict[str, Any]:
    """The errors of Coated, the best Mix, Mitsuba's plugin and the single-scattering walk
    against the walk with the exact interface (the walks' results kept in ``cache``)."""
    ti, tr, dp = _grid()
    truth, se = _walk(case, samples, seed, "multiple", cache)
    wi, wo = _dirs(ti, tr, dp)
    out: dict[str, Any] = {"case": case.label, "noise": float(np.sqrt(np.mean((se / truth) ** 2)))}
    coated = Coated(case.base, ETA, case.roughness, case.distribution)
    out["coated"] = _errors(coated.brdf(wi, wo), truth)
    w, f_mix = _best_mix(case, wi, wo, truth)
    out["mix_weight"] = w
    out["mix"] = _errors(f_mix, truth)
    mits = _mitsuba(case, ti, tr, dp)
    out["mitsuba"] = None if mits is None else _errors(mits, truth)
    out["single"] = None
    if case.roughness > 0:
        single, _ = _walk(case, samples, seed + 1, "single", cache)
        out["single"] = _errors(single, truth)
    return out


def _mitsuba_albedo(theta: np.ndarray, roughness: float, distribution: str = "ggx",
                    n: int = 24) -> np.ndarray | None:
    """Directional albedo of Mitsuba's ``roughplastic`` over a white base (Gauss–Legendre
    in μ and φ of its ``eval``, which includes the cosine), or None without Mitsuba."""
    try:
        import mitsuba as mi

        mi.set_variant("scalar_rgb")
    except (ImportError, AttributeError, RuntimeError):
        return None
    from ..quadrature import gauss_legendre

    bsdf = mi.load_dict({"type": "roughplastic", "distribution": distribution,
                         "alpha": roughness, "int_ior": ETA, "ext_ior": 1.0, "nonlinear": True,
                         "diffuse_reflectance": {"type": "rgb", "value": [1.0] * 3}})
    mu, wmu = gauss_legendre(n)
    phi, wphi = gauss_legendre(2 * n)
    out = []
    for t in theta:
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(math.sin(t), 0.0, math.cos(t))
        total = 0.0
        for m, wm in zip(mu, wmu, strict=True):
            s = math.sqrt(1.0 - m * m)
            for p, wp in zip(phi, wphi, strict=True):
                a = 2.0 * math.pi * p
                v = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(s * math.cos(a), s * math.sin(a),
                                                                 m))
                total += float(v[0]) * wm * wp * 2.0 * math.pi
        out.append(total)
    return np.array(out)


def _walk_albedo(theta: np.ndarray, distribution: str, samples: int, seed: int, interface: str,
                 cache: Path | None) -> tuple[np.ndarray, np.ndarray]:
    """The walk's directional albedo of a white Lambertian base under the furnace's coat,
    with its standard error, read from ``cache`` if it holds it."""
    key = repr((tuple(theta), distribution, samples, seed, interface, ETA, ROUGH))
    return _cached(cache, "furnace", key, lambda: layered.directional_albedo(
        theta, Lambert(1.0), eta=ETA, roughness=ROUGH, distribution=distribution,
        samples=samples, seed=seed, interface=interface, return_stderr=True))


def furnace_curves(samples: int = 200_000, mix_weights: dict[str, float] | None = None,
                   cache: Path | None = None) -> dict[str, dict[str, np.ndarray]]:
    """The white furnace (Lambert ρ = 1, no absorption, η = 1.5, α = :data:`ROUGH`) under a
    GGX and a Beckmann coat: for each distribution, θi (degrees) and the directional albedo by
    the walk with the exact interface (and its standard error), the walk with the
    single-scattering one, ``Coated``, Mitsuba's ``roughplastic`` (if installed) and the
    ``Mix`` at the weight it takes for the Lambert case (if given)."""
    theta = np.radians(np.arange(0.0, 86.0, 5.0))
    white = Lambert(1.0)
    wo = np.stack([np.sin(theta), 0 * theta, np.cos(theta)], -1)
    curves: dict[str, dict[str, np.ndarray]] = {}
    for dist in DISTRIBUTIONS:
        exact, se = _walk_albedo(theta, dist, samples, 0, "multiple", cache)
        single, _ = _walk_albedo(theta, dist, samples // 4, 1, "single", cache)
        c: dict[str, np.ndarray] = {"theta": np.degrees(theta), "exact": exact, "stderr": se,
                                    "single": single}
        c["coated"] = np.asarray(Coated(white, ETA, ROUGH, dist).directional_albedo(wo))
        mits = _mitsuba_albedo(theta, ROUGH, dist)
        if mits is not None:
            c["mitsuba"] = mits
        if mix_weights is not None:
            w = mix_weights[dist]
            mix = Mix([(1.0 - w, white),
                       (w, TorranceSparrow(ETA, None, "beckmann", alpha=ROUGH))])
            c["mix"] = np.asarray(mix.directional_albedo(wo))
            c["mix_weight"] = np.array(w)
        curves[dist] = c
    return curves


def furnace_figure(path: Path, curves: dict[str, dict[str, np.ndarray]]) -> None:
    """The white furnace curves of :func:`furnace_curves`, one panel per distribution side by
    side, written to ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..io.atomic import atomic_write

    fig, axes = plt.subplots(2, len(curves), figsize=(11.0, 7.0), sharey="row",
                             gridspec_kw={"height_ratios": [3, 2]}, squeeze=False)
    for ax, zoom, (dist, c) in zip(axes[0], axes[1], curves.items(), strict=True):
        deg = c["theta"]
        zoom.errorbar(deg, 100 * (c["exact"] - 1), yerr=400 * c["stderr"], fmt="o-", ms=3,
                      color="k", label="walk, exact interface (±4 s.e.)")
        zoom.plot(deg, 100 * (c["coated"] - 1), "-", color="C1", label="Coated")
        zoom.axhline(0.0, color="0.6", lw=0.8)
        zoom.set_xlabel("θi (degrees)")
        zoom.set_ylim(-3.0, 3.0)
        zoom.legend(fontsize=8, loc="lower left")
        ax.errorbar(deg, c["exact"], yerr=4 * c["stderr"], fmt="o-", ms=3, color="k",
                    label="walk, exact interface (±4 s.e.)")
        ax.plot(deg, c["single"], "s--", ms=3, color="C0",
                label="walk, single-scattering interface (pbrt-v4)")
        ax.plot(deg, c["coated"], "-", color="C1", label="Coated")
        if "mitsuba" in c:
            ax.plot(deg, c["mitsuba"], ":", color="C2", label="Mitsuba 3 roughplastic")
        if "mix" in c:
            ax.plot(deg, c["mix"], "-.", color="C3", label=f"Mix, w = {float(c['mix_weight']):.3f}")
        ax.axhline(1.0, color="0.6", lw=0.8)
        name = "GGX" if dist == "ggx" else "Beckmann"
        ax.set_title(f"Lambert ρ = 1 under {name} α = {ROUGH}, η = {ETA}")
        ax.set_ylim(0.0, 1.1)
        ax.legend(fontsize=8, loc="lower left")
    axes[0, 0].set_ylabel("directional albedo A")
    axes[1, 0].set_ylabel("A − 1 (%)")
    fig.suptitle("White furnace (below: the departure from 1, enlarged)")
    fig.tight_layout()
    atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    plt.close(fig)


def _pct(e: tuple[float, float] | None) -> str:
    return "–" if e is None else f"{100 * e[0]:.1f} % / {100 * e[1]:.1f} %"


def _furnace_rows(curves: dict[str, dict[str, np.ndarray]]) -> list[str]:
    """The furnace curves as a table: for each distribution, the walk's largest |A − 1| and
    the range of A over θi by each of the others."""
    lines = ["| coat | walk, exact: max abs(A − 1) (4 s.e.) | `Coated`: max abs(A − 1) "
             "| `Mix` | Mitsuba 3 `roughplastic` | single-scattering walk |",
             "|---|---|---|---|---|---|"]
    def span(c: dict[str, np.ndarray], k: str) -> str:
        return f"{np.min(c[k]):.3f} – {np.max(c[k]):.3f}" if k in c else "–"

    for dist, c in curves.items():
        name = "GGX" if dist == "ggx" else "Beckmann"
        lines.append(
            f"| {name} α = {ROUGH} | {100 * np.max(np.abs(c['exact'] - 1)):.2f} % "
            f"({400 * np.max(c['stderr']):.2f} %) | "
            f"{100 * np.max(np.abs(c['coated'] - 1)):.2f} % | {span(c, 'mix')} | "
            f"{span(c, 'mitsuba')} | {span(c, 'single')} |")
    return lines


_CLOSING = [
    "The walk with the exact interface gives 1; the single-scattering walk and Mitsuba's",
    "`roughplastic` lose the light a second facet event would return; `Coated`'s",
    "transmittance is the interface's own energy 1 − E(μ) and its internal reflectance",
    "1 − (1 − Ē)/η² (exact for a lossless interface), so it departs from 1 only by how far",
    "its reflection (the single-scattering lobe and the fitted multiple-scattering one)",
    "integrates to other than E(μ): the fit holds that integral to E(μ) from θ = 0 to 89°.",
    "",
    "Mitsuba 3: `plastic` for the smooth coat and `roughplastic` (`nonlinear=true`, the",
    "coat's distribution) for the rough one, their `eval` divided by the cosine. `Mix` is",
    "(1 − w) × base + w × Torrance–Sparrow (Beckmann, α of the coat, η = 1.5); under a",
    "smooth coat its specular lobe is a delta, so it is (1 − w) × base, the tuned weight",
    "standing in for the Fresnel transmittances and the internal reflections.",
    "",
    "Regenerate: `python -m roughdiffuse.accuracy.layered_scores docs/accuracy/layered.md",
    "40000 /tmp/layered_cache` (the last argument, a folder for the walks' results, is",
    "optional).",
    "",
    "Note on Mitsuba's `plastic`: with `nonlinear=false` (its default) its diffuse part is",
    "ρ (1 − F_i)(1 − F_o) / (π η² (1 − F_dr)), which keeps the texture's colour but is not the",
    "sum of the internal reflections for ρ < 1 (74 % too bright at ρ = 0.5, η = 1.5); with",
    "`nonlinear=true` it is ρ (1 − F_i)(1 − F_o) / (π η² (1 − ρ F_dr)), the exact sum, which",
    "the walk matches.",
    "",
]
"""The page's text after the furnace table: what each curve shows, how Mitsuba and `Mix` are
evaluated, how to regenerate the page."""


def layered_lines(samples: int = 40_000, figure: Path | None = None,
                  cache: Path | None = None) -> list[str]:
    """The Markdown of the layered section (and the furnace figure, written to ``figure``
    if given); the walks' results kept in ``cache`` (a folder) if given."""
    rows = [score_case(c, samples, cache=cache) for c in _cases()]
    weights = {d: next(r["mix_weight"] for r in rows if r["case"].startswith("Lambert")
                       and f"{d.upper() if d == 'ggx' else d.capitalize()} α = {ROUGH}"
                       in r["case"]) for d in DISTRIBUTIONS}
    curves = furnace_curves(mix_weights=weights, cache=cache)
    if figure is not None:
        furnace_figure(figure, curves)
    lines = [
        "# A coat over a rough-diffuse base: closed forms against the layered walk",
        "",
        "The truth: `roughdiffuse.simulate.layered.brdf`, the position-free Monte Carlo walk",
        "through a dielectric coat of η = 1.5 (Guo, Hašan and Zhao 2018). A rough coat's",
        "interface is the exact multiple-scattering dielectric microsurface of Heitz, Hanika,",
        "d'Eon and Dachsbacher 2016 (a random walk on the Smith microsurface, reflection or",
        "refraction at each facet event, from above and from below): it loses no light.",
        "",
        "What is exact, and what is not:",
        "",
        "* The walk is the exact BRDF of this layer (a Smith microsurface over the base, no",
        "  lateral extent) up to its Monte Carlo noise: it matches Mitsuba 3's own `plastic`",
        "  for a smooth coat, the white furnace gives 1 within 0.2 % up to α = 1 for GGX and",
        "  Beckmann (`bench/coat_furnace.py`), and it is reciprocal, tends to the smooth walk",
        "  as α → 0 and to the base as η → 1 (`tests/test_simulate_layered*.py`).",
        "* `Coated` is a closed form fitted in part to that walk. Exact: a smooth coat over a",
        "  Lambertian base (Mitsuba's `plastic`, `nonlinear=true`), and, for any coat, its",
        "  single-scattering lobe (Walter et al. 2007 with height-correlated masking) and the",
        "  sum of the internal reflections given the coat's energy. Fitted to the walk's",
        "  interface alone (a black base): its directional reflectance with multiple",
        "  scattering, E(μ) = E_ss (1 + c(μ)) (`models.coated.ms_ratio`, from",
        "  `data/coat_interface.npz`), whose complement is the light that enters, and the",
        "  reflection by two or more facet events resolved in direction, a sum of",
        "  single-scattering lobes of roughness 0.7 α, α and 2 α with weights polynomial in",
        "  η and the two cosines, piecewise linear in α (`models.coated.ms_lobe`, from",
        "  `data/coat_lobe.npz`,",
        "  `scripts/coat_lobe_tables.py`). Approximate: a non-Lambertian base is evaluated",
        "  at the directions refracted by a smooth interface, and the light it receives",
        "  after an internal reflection is taken as diffuse.",
        "",
        "Grid: θi, θr in {0, 20, 40, 60, 75}°, Δφ in {0, 90, 180}° (75 geometries), "
        f"{samples:,} paths per geometry. Errors relative, RMS / max over the grid. The rough",
        f"coats are GGX and Beckmann with α in {ROUGHS}. The walk runs compiled",
        "(`engine=\"auto\"`: `simulate/layered_walk_numba.py`); the V-cavity base (a table) runs",
        "on the NumPy walk, about four times slower, so it is scored under the smooth coat. The",
        "last column is the walk with the single-scattering interface",
        "(`interface=\"single\"`: pbrt-v4's `LayeredBxDF`, Mitsuba's `roughdielectric`).",
        "",
        "| case | walk noise | `Coated` | `Mix`, best weight (w) | Mitsuba 3 (Lambert only) "
        "| single-scattering walk |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {100 * r['noise']:.2f} % | {_pct(r['coated'])} | "
            f"{_pct(r['mix'])} (w = {r['mix_weight']:.3f}) | {_pct(r['mitsuba'])} | "
            f"{_pct(r['single'])} |"
        )
    lines += [
        "",
        "![White furnace under a GGX and a Beckmann coat](layered_furnace.png)",
        "",
        f"The white furnace (Lambert ρ = 1, no absorption, α = {ROUGH}, η = {ETA}), θi from 0",
        "to 85° in steps of 5°, the directional albedo A by each:",
        "",
        *_furnace_rows(curves),
        "",
        *_CLOSING,
    ]
    return lines


def main(argv: list[str] | None = None) -> int:
    """Write the layered page to the path given (default docs/accuracy/layered.md), with the
    paths per geometry (default 40,000) and a folder for the walks' results (optional)."""
    args = sys.argv[1:] if argv is None else argv
    path = Path(args[0] if args else "docs/accuracy/layered.md")
    samples = int(args[1]) if len(args) > 1 else 40_000
    cache = Path(args[2]) if len(args) > 2 else None
    text = "\n".join(layered_lines(samples, figure=path.with_name("layered_furnace.png"),
                                   cache=cache))
    write_text(path, text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
