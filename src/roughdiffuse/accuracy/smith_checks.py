"""The accuracy report's sections on the Smith microsurface and the rendered heightfields.

Called by :func:`roughdiffuse.accuracy.report.write_report`; each function returns Markdown
lines (and writes its figures into the report folder).

* :func:`smith_check_lines` — the Smith solver's own checks: white furnace and one bounce by
  the walk against the quadrature;
* :func:`heightfield_lines` — Gaussian heightfields rendered by Mitsuba 3 against the Smith
  solver (same Beckmann α) and the V-cavity solver (at the σ of the same mean square slope
  angle, :func:`matching_sigma`), 1, 2 and all bounces, with the convergence of the renders
  in mesh resolution, patch size and samples; skipped (with a line saying so) without
  Mitsuba.
"""

from __future__ import annotations

import functools
import math
import tempfile
from pathlib import Path

import numpy as np
from scipy import integrate, optimize

from ..io import atomic_write
from ..simulate import smith
from ..simulate.surface import SIGMA_MAX, Settings
from ..simulate.surface import brdf as cavity_brdf

__all__ = ["heightfield_lines", "matching_sigma", "smith_check_lines"]

ALBEDO = 0.8


@functools.lru_cache(maxsize=32)
def matching_sigma(alpha: float) -> float:
    """The V-cavity σ whose slope angles have the mean square of a Beckmann surface of α.

    Beckmann, per unit projected area: tan²θm ~ α² × Exp(1), so
    E[θm²] = ∫ atan(α√x)² e^{−x} dx. V-cavities (``measure="solid-angle"``, the default):
    density ∝ exp(−θa²/2σ²) sin θa on [0, min(π/2, 10σ)] (:mod:`.surface`). Solved for σ.
    """
    target = integrate.quad(lambda x: math.atan(alpha * math.sqrt(x)) ** 2 * math.exp(-x), 0,
                            math.inf)[0]

    def vc(sigma: float) -> float:
        top = min(SIGMA_MAX, 10.0 * sigma)
        w = lambda t: math.exp(-0.5 * (t / sigma) ** 2) * math.sin(t)  # noqa: E731
        return integrate.quad(lambda t: t * t * w(t), 0, top)[0] / integrate.quad(w, 0, top)[0]

    return float(optimize.brentq(lambda s: vc(s) - target, 1e-3, SIGMA_MAX))


def smith_check_lines(quick: bool) -> list[str]:
    """White furnace and walk-against-quadrature tables of the Smith solver."""
    samples = 5_000 if quick else 100_000
    alphas = (0.5,) if quick else (0.1, 0.3, 0.5, 1.0, 2.0)
    thetas = np.radians([0.0, 45.0, 80.0] if quick else [0.0, 30.0, 60.0, 80.0, 89.0])
    lines = [
        "",
        "## The Smith microsurface: checks of the solver",
        "",
        "`roughdiffuse.simulate.smith` (Lambertian facets, uncorrelated heights, isotropic "
        "Beckmann or GGX slopes of roughness α): one bounce by Gauss–Legendre quadrature over "
        "the visible normals with the height-correlated G2 (Heitz 2014; Heitz & Dupuy 2015), "
        "any number of bounces by the height-space random walk of Heitz, Hanika, d'Eon and "
        "Dachsbacher (2016), every value with its standard error.",
        "",
        f"White furnace: directional albedo at ρ = 1, all bounces, {samples:,} paths per "
        "value (ωo drawn uniformly per path), as albedo − 1 in standard errors (z):",
        "",
        "| distribution | α | " + " | ".join(f"θi = {math.degrees(t):.0f}°" for t in thetas)
        + " |",
        "| --- | --- |" + " --- |" * len(thetas),
    ]
    worst = 0.0
    for dist in ("beckmann", "ggx"):
        for a in alphas:
            v, se = smith.directional_albedo(thetas, a, 1.0, "all", dist, samples=samples, seed=1)
            z = (v - 1.0) / se
            worst = max(worst, float(np.max(np.abs(z))))
            cells = " | ".join(f"{x:.4f} (z = {s:+.1f})" for x, s in zip(v, z, strict=True))
            lines.append(f"| {dist} | {a:g} | {cells} |")
    lines += ["", f"Largest |z|: {worst:.1f}.", ""]
    # one bounce: the walk against the quadrature
    rng = np.random.default_rng(0)
    n = 6 if quick else 40
    ti, tr = rng.uniform(0, 1.48, n), rng.uniform(0, 1.48, n)
    dp = rng.uniform(0, 2 * math.pi, n)
    lines += [
        f"One bounce, random walk against quadrature over {n} random geometries "
        f"({samples // 5:,} paths each): z = (walk − quadrature) / s.e.",
        "",
        "| distribution | α | mean z² | max |z| |",
        "| --- | --- | --- | --- |",
    ]
    for dist in ("beckmann", "ggx"):
        for a in (0.3, 1.0):
            q = smith.single_scattering(ti, tr, dp, a, 1.0, dist)
            r = smith.random_walk(ti, tr, dp, a, 1.0, 1, dist, samples=samples // 5, seed=2)
            z = (r.values[0] - q) / r.stderr[0]
            lines.append(f"| {dist} | {a:g} | {np.mean(z * z):.2f} | {np.max(np.abs(z)):.1f} |")
    return lines


HF_GEOMETRIES = ((0, 0, 0), (40, 30, 150), (60, 60, 0), (60, 60, 180), (75, 20, 90), (80, 80, 0))
HF_ALPHAS = (0.3, 0.7)


def _heightfield_rows(alphas, geoms, settings, samples: int, progress: bool) -> list[tuple]:
    """(α, σ, geometry, bounces, heightfield f, its s.e., Smith, its s.e., V-cavity) for every
    α and geometry, and 1, 2 and all bounces."""
    from tqdm import tqdm

    from ..simulate.heightfield import heightfield_brdf

    bounces = (1, 2, "all")
    rows = []
    todo = [(a, g) for a in alphas for g in geoms]
    for alpha, (gi, gr, gp) in tqdm(todo, desc="heightfields", disable=not progress):
        ti, tr, dp = (math.radians(x) for x in (gi, gr, gp))
        sigma = matching_sigma(alpha)
        rendered = heightfield_brdf(ti, tr, dp, alpha, ALBEDO, bounces, settings, seed=7)
        walk = smith.random_walk(ti, tr, dp, alpha, ALBEDO, "all", "beckmann", samples=samples,
                                 seed=3, max_order=2)
        for b in bounces:
            if b == 1:
                s, sse = float(smith.single_scattering(ti, tr, dp, alpha, ALBEDO)), 0.0
            elif b == 2:
                o = walk.orders[:2]
                s = float(ALBEDO * o[0] + ALBEDO**2 * o[1])
                sse = float(math.hypot(ALBEDO * walk.orders_stderr[0],
                                       ALBEDO**2 * walk.orders_stderr[1]))
            else:
                s, sse = float(walk.values[0]), float(walk.stderr[0])
            v = float(cavity_brdf(ti, tr, dp, sigma, ALBEDO, b, Settings()))
            f, se = rendered[b]
            rows.append((alpha, sigma, (gi, gr, gp), b, f, se, s, sse, v))
    return rows


def heightfield_lines(out: Path, quick: bool, progress: bool = True) -> list[str]:
    """Heightfield renders against both solvers; convergence; an image to look at."""
    try:
        import mitsuba  # noqa: F401
    except ImportError:
        return ["", "## Smith and the heightfields", "", "(skipped: Mitsuba 3 is not installed)"]
    from ..simulate.heightfield import HeightfieldSettings

    settings = (
        HeightfieldSettings(n=64, res=64, spp=8, realisations=3) if quick else HeightfieldSettings()
    )
    geoms = HF_GEOMETRIES[1:2] if quick else HF_GEOMETRIES
    alphas = (0.5,) if quick else HF_ALPHAS
    samples = 5_000 if quick else 100_000
    bounces = (1, 2, "all")
    rows = _heightfield_rows(alphas, geoms, settings, samples, progress)
    lines = [
        "",
        "## Smith and the heightfields: a rendered arbiter",
        "",
        "Random Gaussian heightfields (Gaussian heights, Gaussian correlation "
        "exp(−r²/ℓ²)) are Beckmann surfaces: their slopes are Gaussian with E[tan²θm] = α². "
        "`roughdiffuse.simulate.heightfield` builds them by spectral synthesis on a periodic "
        "grid, scales the heights so that the mean tan²θm over the mesh's triangles is exactly "
        "α², and renders the mesh of Lambertian triangles (face normals) with Mitsuba 3: a "
        "directional emitter of unit irradiance, an orthographic camera whose film covers "
        "exactly one period of the surface (so the image mean is the BRDF times cos θi), the "
        "tile repeated 3 × 3 so that light and view rays see surroundings, and the `path` "
        "integrator with `max_depth` 2, 3 and 64 (1, 2 and all bounces). The standard error "
        "is between independent surfaces (it includes the finite patch and the pixel noise).",
        "",
        f"Settings: {settings.n} × {settings.n} grid per tile, {settings.cells_per_length:g} "
        f"cells per ℓ (tile {settings.n / settings.cells_per_length:g} ℓ wide), "
        f"{settings.res}² pixels × {settings.spp} spp, {settings.realisations} surfaces per "
        f"value; ρ = {ALBEDO}. Smith: Beckmann of the same α (one bounce by quadrature, more "
        f"by the walk, {samples:,} paths). V-cavity: `Settings()` at the σ whose "
        "slope-angle mean square equals the surface's (σ = "
        + ", ".join(f"{matching_sigma(a):.3f} for α = {a:g}" for a in alphas)
        + ").",
        "",
        "| α | θi, θr, Δφ | bounces | heightfield | Smith | V-cavity | Smith − hf "
        "| V-cavity − hf |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for alpha, _, g, b, f, se, s, sse, v in rows:
        lines.append(
            f"| {alpha:g} | {g[0]}°, {g[1]}°, {g[2]}° | {b} | {f:.4f} ± {se:.4f} | "
            f"{s:.4f} ± {sse:.4f} | {v:.4f} | {100 * (s - f) / f:+.1f} % "
            f"(z = {(s - f) / math.hypot(se, sse):+.1f}) | {100 * (v - f) / f:+.1f} % |"
        )
    for alpha in alphas:
        for b in bounces:
            sel = [r for r in rows if r[0] == alpha and r[3] == b]
            ds = [abs(r[6] - r[4]) / r[4] for r in sel]
            dv = [abs(r[8] - r[4]) / r[4] for r in sel]
            lines.append("")
            lines.append(
                f"α = {alpha:g}, {b} bounce(s): |Smith − heightfield| max {100 * max(ds):.1f} %,"
                f" mean {100 * np.mean(ds):.1f} %; |V-cavity − heightfield| max "
                f"{100 * max(dv):.1f} %, mean {100 * np.mean(dv):.1f} %."
            )
    if not quick:
        lines += _convergence_lines(settings)
    _heightfield_picture(out, quick)
    lines += ["", "![A rendered heightfield](heightfield.png)", ""]
    return lines


def _convergence_lines(base) -> list[str]:
    """The change of the rendered f with mesh resolution, patch size and samples."""
    from dataclasses import replace

    from ..simulate.heightfield import heightfield_brdf

    ti, tr, dp, alpha = math.radians(60), math.radians(60), math.pi, 0.7
    variants = [
        ("as above", base),
        ("6 cells per ℓ (finer mesh, same patch)", replace(base, n=192, cells_per_length=6.0)),
        ("3 cells per ℓ (coarser mesh)", replace(base, n=96, cells_per_length=3.0)),
        ("patch 64 ℓ (n = 256)", replace(base, n=256)),
        ("2 × the samples per pixel", replace(base, spp=2 * base.spp)),
        ("5 × 5 tiles", replace(base, tiles=5)),
    ]
    lines = [
        "",
        "Convergence of the render at α = 0.7, θi = θr = 60°, Δφ = 180° (the geometry where "
        "the solvers differ most), all bounces:",
        "",
        "| variant | f ± s.e. |",
        "| --- | --- |",
    ]
    for label, s in variants:
        f, se = heightfield_brdf(ti, tr, dp, alpha, ALBEDO, "all", s, seed=11)
        lines.append(f"| {label} | {f:.4f} ± {se:.4f} |")
    return lines


def _heightfield_picture(out: Path, quick: bool) -> None:
    """A close look: one surface lit at 70° from the side, one bounce and all bounces."""
    import mitsuba as mi

    from .._figure import subplots  # Figure objects, no pyplot (see roughdiffuse._figure)
    from ..simulate.heightfield import (
        gaussian_heightfield,
        heightfield_mesh,
        render_heightfield,
        triangle_slopes,
        write_ply,
    )

    n, dx, alpha = 64, 0.25, 0.7
    rng = np.random.default_rng(5)
    h = gaussian_heightfield(n, dx, 1.0, rng)
    g = triangle_slopes(h, dx)
    h *= alpha / math.sqrt(np.mean(np.sum(g * g, axis=1)))
    ti = math.radians(70.0)
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.array([0.0, 0.0, 1.0])
    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    try:
        with tempfile.TemporaryDirectory() as tmp:
            ply = write_ply(Path(tmp) / "hf.ply", *heightfield_mesh(h, dx, 3))
            res, spp = (128, 8) if quick else (384, 32)
            imgs = [render_heightfield(mi, ply, n * dx, ALBEDO, wi, wo, d, res=res, spp=spp)
                    for d in (2, 64)]
    finally:
        if previous is not None:
            mi.set_variant(previous)
    fig, axes = subplots(1, 2, figsize=(9, 4.6))
    top = float(np.percentile(imgs[1], 99.5))
    for ax, img, title in zip(axes, imgs, ("1 bounce", "all bounces"), strict=True):
        ax.imshow(img.T, cmap="gray", vmin=0, vmax=top, origin="lower")
        ax.set_title(f"{title}: mean f = {img.mean() / math.cos(ti):.3f} /sr")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.suptitle(
        f"Gaussian heightfield, α = {alpha}, 16 ℓ × 16 ℓ, ρ = {ALBEDO}, viewed from above;\n"
        "light at θi = 70°, its azimuth along the image's horizontal axis"
    )
    fig.tight_layout()
    atomic_write(out / "heightfield.png", lambda tmp: fig.savefig(tmp, dpi=100, format="png"))
