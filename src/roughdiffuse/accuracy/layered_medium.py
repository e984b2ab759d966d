"""A scattering coat against a real renderer: the layered walk and Mitsuba 3's ``volpath``.

The walk (:func:`roughdiffuse.simulate.layered.directional_albedo` with ``medium_albedo``
and ``medium_g``) against Mitsuba 3 rendering the same layer as geometry
(:func:`render_slab`): a plane-parallel slab (a thin, wide box, thickness d, half-width
200 d) with a smooth ``dielectric`` boundary of index η and a ``homogeneous`` medium inside
(albedo ω, extinction τ/d, ``hg`` phase function of asymmetry g), over a ``diffuse`` plane
of albedo ρ lying inside it (a shape without a medium of its own keeps the medium the light
travels in), seen at θ by an ``orthographic`` sensor at the slab's centre.

The light is a uniform ``constant`` environment of radiance 1, not a directional emitter:
a directional emitter is a Dirac delta in direction, and neither Mitsuba's path tracers
(``volpath``: the shadow ray towards it stops at the dielectric boundary, and no sampled
direction hits a delta) nor its light tracer (``ptracer``: the orthographic sensor is a
delta too) can carry its light through a smooth dielectric boundary. Under the uniform
environment the pixel's radiance is ∫ f cos θi dωi, the directional albedo at θ (by
reciprocity, the walk's ``directional_albedo(θ)``), the coat's mirror reflection F(μ, η)
included in both. Each channel of the image is the same (grey parameters); the render's
standard error is that of the mean over its pixels (independent samples per pixel).

Run ``python -m roughdiffuse.accuracy.layered_medium docs/accuracy/layered_medium.md`` to
write the page (about a CPU-minute).
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..io.atomic import write_text
from ..models import Lambert
from ..simulate import layered

__all__ = ["CASES", "MediumCase", "compare", "medium_lines", "render_slab"]


@dataclass(frozen=True)
class MediumCase:
    """One layer: the view θ (degrees), the base's albedo ρ, the coat's η, the medium's
    optical thickness τ, single-scattering albedo ω and Henyey–Greenstein g, and the coat's
    GGX roughness α (0: smooth; rough: Mitsuba's ``roughdielectric`` against the walk's
    single-scattering interface, ``interface="single"``, which is its behaviour)."""

    theta_deg: float
    rho: float
    eta: float
    tau: float
    omega: float
    g: float
    alpha: float = 0.0


CASES = (
    MediumCase(0.0, 0.5, 1.5, 1.0, 0.8, 0.5),
    MediumCase(45.0, 0.5, 1.5, 1.0, 0.8, 0.5),
    MediumCase(70.0, 0.5, 1.5, 1.0, 0.8, 0.5),
    MediumCase(30.0, 0.8, 1.33, 3.0, 0.95, -0.3),
    MediumCase(60.0, 0.2, 1.8, 0.3, 0.6, 0.8),
    MediumCase(30.0, 0.0, 1.5, 2.0, 1.0, 0.0),
    MediumCase(45.0, 0.5, 1.5, 1.0, 0.8, 0.5, 0.3),
)
"""The layers compared: a glaze-like medium at three views; a thick, nearly conservative,
back-scattering one over a bright base; a thin forward-scattering one over a dark base; a
conservative medium over a black base (all its light from the medium); the glaze under a
rough GGX coat (α = 0.3)."""


def render_slab(mi: Any, case: MediumCase, *, spp: int = 256, res: int = 32,
                seed: int = 0) -> tuple[float, float]:
    """Mitsuba 3's ``volpath`` render of the slab of ``case`` (module docstring; ``mi``
    with an RGB variant set): the mean radiance of the pixels and its standard error."""
    d, half = 1.0, 200.0
    theta = math.radians(case.theta_deg)
    wo = np.array([math.sin(theta), 0.0, math.cos(theta)])
    top = np.array([0.0, 0.0, d])
    t4 = mi.ScalarTransform4f
    up = [0.0, 0.0, 1.0] if theta > 1e-3 else [0.0, 1.0, 0.0]
    sensor = t4().look_at(origin=(top + 50.0 * wo).tolist(), target=top.tolist(),
                          up=up) @ t4().scale([0.5, 0.5, 1.0])
    grey = {"type": "rgb", "value": [case.omega] * 3}
    scene = mi.load_dict({
        "type": "scene",
        # no Russian roulette: every path runs until it leaves or its 10,000 bounces end
        "integrator": {"type": "volpath", "max_depth": 10_000, "rr_depth": 10_000},
        "sensor": {
            "type": "orthographic",
            "to_world": sensor,
            "film": {"type": "hdrfilm", "width": res, "height": res,
                     "rfilter": {"type": "box"}, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": spp},
        },
        "emitter": {"type": "constant", "radiance": {"type": "rgb", "value": [1.0] * 3}},
        "slab": {
            "type": "cube",
            "to_world": t4().translate([0.0, 0.0, 0.5 * d]) @ t4().scale([half, half, 0.5 * d]),
            "bsdf": ({"type": "dielectric", "int_ior": case.eta, "ext_ior": 1.0}
                     if case.alpha == 0 else
                     {"type": "roughdielectric", "distribution": "ggx", "alpha": case.alpha,
                      "int_ior": case.eta, "ext_ior": 1.0}),
            "interior": {"type": "homogeneous", "albedo": grey, "sigma_t": case.tau / d,
                         "phase": {"type": "hg", "g": case.g}},
        },
        "base": {  # just above the slab's floor, inside the medium
            "type": "rectangle",
            "to_world": t4().translate([0.0, 0.0, 1e-4 * d]) @ t4().scale([0.99 * half,
                                                                            0.99 * half, 1.0]),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [case.rho] * 3}},
        },
    })
    img = np.asarray(mi.render(scene, seed=seed), dtype=np.float64)[..., 0]
    return float(img.mean()), float(img.std(ddof=1) / math.sqrt(img.size))


def walk_albedo(case: MediumCase, samples: int = 100_000,
                seed: int = 0) -> tuple[float, float]:
    """The layered walk's directional albedo of ``case`` and its standard error (a rough
    coat with the single-scattering interface, Mitsuba's ``roughdielectric``'s)."""
    value, se = layered.directional_albedo(
        math.radians(case.theta_deg), Lambert(case.rho), case.eta, case.alpha,
        absorption=case.tau, medium_albedo=case.omega, medium_g=case.g, samples=samples,
        seed=seed, return_stderr=True, interface="single" if case.alpha > 0 else "multiple")
    return float(value), float(se)


def compare(mi: Any, case: MediumCase, *, samples: int = 100_000, spp: int = 256,
            res: int = 32) -> dict[str, float]:
    """The walk and the render of ``case``: their values, standard errors and relative
    difference."""
    walk, walk_se = walk_albedo(case, samples)
    render, render_se = render_slab(mi, case, spp=spp, res=res)
    return {"walk": walk, "walk_se": walk_se, "render": render, "render_se": render_se,
            "rel": (walk - render) / render}


def medium_lines(mi: Any, samples: int = 100_000, spp: int = 256) -> list[str]:
    """The page: the comparison table of :data:`CASES` and what it shows."""
    lines = [
        "# A scattering coat: the layered walk against Mitsuba 3's volpath",
        "",
        "The layered walk with a homogeneous medium in the coat (`medium_albedo` ω,",
        "`medium_g` g, the optical thickness τ as `absorption`; the slab of pbrt-v4's",
        "`coateddiffuse`) against Mitsuba 3 rendering the layer as geometry: a thin, wide box",
        "(half-width 200 thicknesses) with a smooth `dielectric` boundary of index η and a",
        "`homogeneous` medium with an `hg` phase function inside, over a `diffuse` plane of",
        "albedo ρ inside the box, seen by an orthographic sensor (`volpath`, no Russian",
        "roulette). The light is a uniform `constant` environment of radiance 1, so each",
        "pixel is the directional albedo at the view θ (by reciprocity, the walk's",
        "`directional_albedo(θ)`), the coat's mirror reflection included in both. A",
        "rough coat (α > 0, GGX) is Mitsuba's `roughdielectric`, against the walk with the",
        "single-scattering interface (`interface=\"single\"`, one facet event per crossing,",
        "as `roughdielectric` has). A",
        "directional emitter cannot be used: its light is a delta in direction, which neither",
        "Mitsuba's path tracer (the shadow ray stops at the dielectric) nor its light tracer",
        "(the orthographic sensor is a delta too) carries through a smooth dielectric.",
        "",
        f"Walk: {samples:,} paths; render: 32 × 32 pixels × {spp} samples, the standard",
        "error that of the pixels' mean. Relative difference (walk − render) / render, and",
        "that difference in combined standard errors:",
        "",
        "| θ | ρ | η | α | τ | ω | g | walk | render | difference | in s.e. |",
        "| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |",
    ]
    for case in CASES:
        r = compare(mi, case, samples=samples, spp=spp)
        se = math.hypot(r["walk_se"], r["render_se"])
        lines.append(
            f"| {case.theta_deg:g}° | {case.rho:g} | {case.eta:g} | {case.alpha:g} | "
            f"{case.tau:g} | "
            f"{case.omega:g} | {case.g:g} | {r['walk']:.5f} ± {r['walk_se']:.5f} | "
            f"{r['render']:.5f} ± {r['render_se']:.5f} | {100 * r['rel']:+.2f} % | "
            f"{(r['walk'] - r['render']) / se:+.1f} |")
    lines += [
        "",
        "Regenerate: `python -m roughdiffuse.accuracy.layered_medium "
        "docs/accuracy/layered_medium.md` (Mitsuba 3; its LLVM variant where libLLVM 19 is "
        "found, else scalar).",
        "",
    ]
    return lines


def main(argv: list[str] | None = None) -> int:
    """Write the page to the path given (default docs/accuracy/layered_medium.md)."""
    import mitsuba as mi

    from ..integrations.drjit_llvm import llvm_problem

    args = sys.argv[1:] if argv is None else argv
    path = Path(args[0] if args else "docs/accuracy/layered_medium.md")
    llvm = "llvm_ad_rgb" in mi.variants() and llvm_problem() is None
    mi.set_variant("llvm_ad_rgb" if llvm else "scalar_rgb")
    text = "\n".join(medium_lines(mi))
    write_text(path, text)
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
