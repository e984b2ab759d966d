"""The accuracy report's layered section: closed forms of a coated surface against the walk.

The truth is :func:`roughdiffuse.simulate.layered.brdf` (position-free Monte Carlo through
the coat). Scored against it, on a grid of geometries, for Lambertian, Oren–Nayar and
V-cavity bases under a smooth and a rough coat:

* :class:`~roughdiffuse.models.coated.Coated`, the closed form;
* :class:`~roughdiffuse.models.mix.Mix` of the base and a Torrance–Sparrow (Beckmann) lobe of
  the coat's roughness, at its best-fitting weight (least squares in the relative error);
* Mitsuba 3's own ``plastic`` (smooth, ``nonlinear=true``) and ``roughplastic`` (GGX,
  ``nonlinear=true``) for the Lambertian base, when Mitsuba is installed.

Errors are relative, |f − f_truth| / f_truth, RMS and maximum over the grid; the walk's own
relative standard error is listed beside them (an error below about twice it is noise).

Run ``python -m roughdiffuse.accuracy.layered_scores docs/accuracy/layered.md`` to write the
page (a few CPU-minutes).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..io.atomic import write_text
from ..models import Lambert, Mix, Model, OrenNayar, TorranceSparrow, VCavity
from ..models.coated import Coated
from ..simulate import layered

__all__ = ["Case", "layered_lines", "score_case"]

ETA = 1.5
ALBEDO = 0.8
ROUGH = 0.3
_ANGLES = np.radians([0.0, 20.0, 40.0, 60.0, 75.0])
_PHIS = np.radians([0.0, 90.0, 180.0])


@dataclass(frozen=True)
class Case:
    """One configuration: a label, the base, the coat's roughness α (GGX)."""

    label: str
    base: Model
    roughness: float


def _cases() -> list[Case]:
    bases = [
        ("Lambert ρ = 0.8", Lambert(ALBEDO)),
        ("Oren–Nayar full ρ = 0.8, σ = 0.3", OrenNayar(ALBEDO, 0.3, "full")),
        ("V-cavity ρ = 0.8, σ = 0.3", VCavity(ALBEDO, 0.3)),
    ]
    return [Case(f"{name}, {'smooth' if a == 0 else f'α = {a}'} coat", base, a)
            for a in (0.0, ROUGH) for name, base in bases]


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
        spec.update(type="roughplastic", distribution="ggx", alpha=case.roughness)
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


def score_case(case: Case, samples: int = 20_000, seed: int = 0) -> dict[str, Any]:
    """The errors of Coated, the best Mix and Mitsuba's plugin against the walk."""
    ti, tr, dp = _grid()
    truth, se = layered.brdf(ti, tr, dp, case.base, eta=ETA, roughness=case.roughness,
                             samples=samples, seed=seed, return_stderr=True)
    wi, wo = _dirs(ti, tr, dp)
    out: dict[str, Any] = {"case": case.label, "noise": float(np.sqrt(np.mean((se / truth) ** 2)))}
    coated = Coated(case.base, ETA, case.roughness)
    out["coated"] = _errors(coated.brdf(wi, wo), truth)
    w, f_mix = _best_mix(case, wi, wo, truth)
    out["mix_weight"] = w
    out["mix"] = _errors(f_mix, truth)
    mits = _mitsuba(case, ti, tr, dp)
    out["mitsuba"] = None if mits is None else _errors(mits, truth)
    return out


def _pct(e: tuple[float, float] | None) -> str:
    return "–" if e is None else f"{100 * e[0]:.1f} % / {100 * e[1]:.1f} %"


def layered_lines(samples: int = 20_000) -> list[str]:
    """The Markdown of the layered section."""
    rows = [score_case(c, samples) for c in _cases()]
    lines = [
        "# A coat over a rough-diffuse base: closed forms against the layered walk",
        "",
        "The truth: `roughdiffuse.simulate.layered.brdf`, the position-free Monte Carlo walk",
        "through a dielectric coat of η = 1.5 (Guo, Hašan and Zhao 2018), checked against",
        "Mitsuba 3's own `plastic` plugin, the white furnace, the η → 1 and ρ = 0 limits and",
        "reciprocity (`tests/test_simulate_layered.py`). Grid: θi, θr in {0, 20, 40, 60, 75}°,",
        "Δφ in {0, 90, 180}° (75 geometries), "
        f"{samples} paths per geometry. Errors relative, RMS / max over the grid. The rough",
        f"coat is GGX with α = {ROUGH}; its walk uses a single-scattering microfacet interface",
        "(Walter et al. 2007), so light masked or reflected upwards inside the coat is lost, as",
        "in every single-scattering microfacet model. The walk runs compiled",
        "(`engine=\"auto\"`: `simulate/layered_walk_numba.py`) for the closed-form bases and",
        "on NumPy for the V-cavity, a table.",
        "",
        "| case | walk noise | `Coated` | `Mix`, best weight (w) | Mitsuba 3 (Lambert only) |",
        "|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {100 * r['noise']:.2f} % | {_pct(r['coated'])} | "
            f"{_pct(r['mix'])} (w = {r['mix_weight']:.3f}) | {_pct(r['mitsuba'])} |"
        )
    lines += [
        "",
        "Mitsuba 3: `plastic` for the smooth coat and `roughplastic` (GGX, `nonlinear=true`)",
        "for the rough one, their `eval` divided by the cosine. `Mix` is (1 − w) × base +",
        "w × Torrance–Sparrow (Beckmann, α of the coat, η = 1.5); under a smooth coat its",
        "specular lobe is a delta, so it is (1 − w) × base, the tuned weight standing in for",
        "the Fresnel transmittances and the internal reflections.",
        "",
        "Regenerate: `python -m roughdiffuse.accuracy.layered_scores docs/accuracy/layered.md`.",
        "",
        "Note on Mitsuba's `plastic`: with `nonlinear=false` (its default) its diffuse part is",
        "ρ (1 − F_i)(1 − F_o) / (π η² (1 − F_dr)), which keeps the texture's colour but is not the",
        "sum of the internal reflections for ρ < 1 (74 % too bright at ρ = 0.5, η = 1.5); with",
        "`nonlinear=true` it is ρ (1 − F_i)(1 − F_o) / (π η² (1 − ρ F_dr)), the exact sum, which",
        "the walk matches.",
        "",
    ]
    return lines


def main(argv: list[str] | None = None) -> int:
    """Write the layered page to the path given (default docs/accuracy/layered.md)."""
    args = sys.argv[1:] if argv is None else argv
    path = Path(args[0] if args else "docs/accuracy/layered.md")
    samples = int(args[1]) if len(args) > 1 else 20_000
    text = "\n".join(layered_lines(samples))
    write_text(path, text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
