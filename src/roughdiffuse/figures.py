"""The lecture's figures in one call: :func:`make_figures` writes eleven PNGs and index.html.

Each figure is a function that returns a matplotlib Figure and the caption shown in the
index; the renders use :func:`roughdiffuse.render.render` and the models' own code.
The figures reproduce the pictures and claims of the lecture on diffuse reflection from
rough surfaces (Oren and Nayar, SIGGRAPH 1994), retold in the site's docs/lecture/ pages.
"""

from __future__ import annotations

import html
import math
import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from . import _figure
from ._validate import ParameterError
from .io.atomic import atomic_write
from .models import (
    EON,
    Burley,
    BurleyRenormalized,
    Chan,
    Coated,
    Fujii,
    Hammon,
    Hapke,
    Lambert,
    LambertSphere,
    LommelSeeliger,
    LunarLambert,
    Minnaert,
    Mix,
    OrenNayar,
    TorranceSparrow,
    VCavity,
)
from .plots import (
    ROUGHNESS_SERIES,
    plot_cross_section,
    plot_plane_of_incidence,
    plot_roughness_series,
    radiance_colorbar,
    show_radiance,
)
from .render import (
    DistantLight,
    Moon,
    Sphere,
    SurfaceOfRevolution,
    pixel_coordinates,
    render,
)

__all__ = ["FIGURES", "Figure", "figure_matches", "kept_figures", "make_figures"]

SIZE = 200
"""Pixels across a rendered object in the figures."""

SPP = 9
"""Samples per pixel in the figures."""

CLAY = (0.75, 0.45, 0.30)
"""An RGB albedo for clay."""


@dataclass(frozen=True)
class Figure:
    """One figure of the set: file name, title, caption and the function that draws it."""

    name: str
    title: str
    caption: str
    draw: Callable[[], Any]


def _suptitle(fig: Any, text: str) -> None:
    fig.suptitle(text, fontsize="large")


def _lambert_sphere() -> Any:
    rho = 0.8
    img, mask = render(Lambert(rho), Sphere(), DistantLight(0.0), size=SIZE, samples_per_pixel=SPP)
    fig, (a, b) = _figure.subplots(1, 2, figsize=(9, 4), gridspec_kw={"width_ratios": [1, 1.4]})
    show_radiance(a, img, float(img.max()), "Lambert, ρ = 0.8, light behind the viewer")
    radiance_colorbar(a, float(img.max()))
    xs, _ = pixel_coordinates(Sphere(), None, SIZE)
    plot_cross_section({"rendered": img}, masks={"rendered": mask}, ax=b, x=xs)
    x = np.linspace(-1, 1, 401)
    b.plot(
        x,
        rho / math.pi * np.sqrt(1 - x**2),
        "k--",
        lw=1,
        label="closed form ρ/π E0 n·s = ρ/π √(1 − x²)",
    )
    b.legend(fontsize="small")
    b.set_title("brightness across the middle row")
    _suptitle(fig, "1. A Lambertian sphere lit head-on: the edges are dark (n·s = 0)")
    fig.tight_layout()
    return fig


LUNAR_HAPKE = Hapke(0.12, b0=1.0, h=0.06, xi=-0.25, theta_bar=math.radians(20.0))
"""Hapke with lunar-like parameters (B0 ≈ 1, h ≈ 0.06, backscattering ξ ≈ −0.25, θ̄ ≈ 20°:
the range of Helfenstein & Veverka, Icarus 1987, and Hapke 2012, Table 12.1); w is set by the
moon preset."""


def _full_moon() -> Any:
    light = DistantLight(0.0)
    models = {
        "Lambert": Lambert(),
        "Oren–Nayar full, σ = 0.7 rad": OrenNayar(sigma=0.7, variant="full"),
        "Lommel–Seeliger": LommelSeeliger(),
        "Hapke (lunar parameters)": LUNAR_HAPKE,
        "Minnaert, k = 0.6": Minnaert(k=0.6),
    }
    moon = Moon()
    results = {
        k: render(m, moon, light, size=SIZE, samples_per_pixel=SPP) for k, m in models.items()
    }
    fig = _figure.figure(figsize=(14, 6.6))
    grid = fig.add_gridspec(2, len(models), height_ratios=[1, 0.9])
    for i, (label, (img, _)) in enumerate(results.items()):
        ax = fig.add_subplot(grid[0, i])
        centre = float(img[SIZE // 2, SIZE // 2])
        show_radiance(ax, img / centre, 1.05, label)  # each disc on the scale of its centre
    radiance_colorbar(ax, 1.05, "radiance ÷ the disc centre's")
    ax = fig.add_subplot(grid[1, :])
    plot_cross_section(
        {k: v[0] for k, v in results.items()},
        masks={k: v[1] for k, v in results.items()},
        ax=ax,
        normalize=True,
        x=pixel_coordinates(moon, None, SIZE)[0],
    )
    ax.set_title("brightness across the disc, divided by the centre's")
    _suptitle(
        fig,
        "2. Why does the full moon look flat? Spheres of the moon's albedo (0.12), "
        "lit from behind the viewer",
    )
    fig.tight_layout()
    return fig


def _vase() -> Any:
    vase = SurfaceOfRevolution()
    light = DistantLight(0.0)
    models = {"Lambertian": Lambert(0.8), "Oren–Nayar, σ = 0.3 rad": OrenNayar(0.8, 0.3)}
    results = {
        k: render(m, vase, light, size=SIZE, samples_per_pixel=SPP) for k, m in models.items()
    }
    mask = next(iter(results.values()))[1]
    row = int(np.argmax(mask.sum(axis=1)))  # the widest row: the vase's belly
    vmax = max(float(r[0].max()) for r in results.values())
    fig = _figure.figure(figsize=(11, 4.4))
    grid = fig.add_gridspec(1, 3, width_ratios=[1, 1, 1.6])
    for i, (label, (img, _)) in enumerate(results.items()):
        ax = fig.add_subplot(grid[0, i])
        show_radiance(ax, img, vmax, label)
        ax.axhline(row, color="tab:red", lw=0.8, ls="--")
    radiance_colorbar(ax, vmax)
    ax = fig.add_subplot(grid[0, 2])
    plot_cross_section(
        {k: v[0] for k, v in results.items()},
        masks={k: v[1] for k, v in results.items()},
        row=row,
        ax=ax,
        x=pixel_coordinates(vase, None, SIZE)[0],
    )
    ax.set_title("brightness along the dashed line")
    _suptitle(
        fig, "3. The clay vase lit from the viewing direction (θi = 0), as in the lecture's Fig. 7"
    )
    fig.tight_layout()
    return fig


def _roughness_series() -> Any:
    fig = plot_roughness_series(
        lambda s: OrenNayar(0.8, s),
        ROUGHNESS_SERIES,
        lights=[DistantLight(0.0), DistantLight(math.radians(60.0), 0.0)],
        size=SIZE // 4 * 3,
        samples_per_pixel=SPP,
    )
    _suptitle(fig, "4. Increasing roughness: Oren–Nayar spheres, σ = 0 is Lambert")
    fig.tight_layout()
    return fig


def _view_dependence() -> Any:
    colours = {0.0: "black", 0.25: "tab:blue", 0.5: "tab:orange"}
    models: dict[str, Any] = {"Lambert": Lambert(0.8)}
    styles: dict[str, dict[str, Any]] = {"Lambert": {"color": "black"}}
    for s in (0.25, 0.5):
        for variant, ls in (("qualitative", "-"), ("full", "--")):
            label = f"Oren–Nayar {variant}, σ = {s:g}"
            models[label] = OrenNayar(0.8, s, variant)
            styles[label] = {"color": colours[s], "ls": ls}
    fig = _figure.figure(figsize=(13, 4.2))
    for i, deg in enumerate((30.0, 60.0)):
        ax = fig.add_subplot(1, 3, i + 1)
        plot_plane_of_incidence(models, math.radians(deg), ax=ax, styles=styles)
    ax = fig.add_subplot(1, 3, 3, projection="polar")
    plot_plane_of_incidence(models, math.radians(60.0), ax=ax, polar=True, styles=styles)
    ax.get_legend().remove()
    _suptitle(
        fig,
        "5. View dependence in the plane of incidence (ρ = 0.8): rough surfaces "
        "brighten as the view approaches the source",
    )
    fig.tight_layout()
    return fig


def _blurred_highlights() -> Any:
    sigmas = (0.05, 0.1, 0.2, 0.3, 0.4)
    light = DistantLight(math.radians(30.0), 0.0)
    fig, axes = _figure.subplots(1, len(sigmas), figsize=(2.2 * len(sigmas), 2.9))
    for ax, s in zip(axes, sigmas, strict=True):
        img, mask = render(
            TorranceSparrow(1.5, s), Sphere(), light, size=SIZE // 4 * 3, samples_per_pixel=SPP
        )
        peak = float(img.max())
        show_radiance(ax, img / peak, 1.0, f"σ = {s:g} rad\npeak {peak:.3g} sr⁻¹")
        ax.contour(mask, [0.5], colors="0.45", linewidths=0.8)
    radiance_colorbar(ax, 1.0, "radiance ÷ the image's peak")
    _suptitle(
        fig,
        "6. Blurred highlights: Torrance–Sparrow spheres (η = 1.5), light at "
        "θi = 30°\n(each image scaled to its peak; grey line: the silhouette)",
    )
    fig.tight_layout(rect=(0, 0, 1, 0.97))
    return fig


COAT_PATHS = 256
"""Paths per pixel of the layered truth in figure 7 (its Monte Carlo noise is stated)."""


def _coat_images(size: int) -> tuple[dict[str, np.ndarray], np.ndarray, float]:
    """Figure 7's vase three ways (radiance images (H, W, 3)), the lit mask, and the truth's
    RMS standard error (the same pixel geometry for all: one ray per pixel centre)."""
    from .render.pixels import pixel_cosines
    from .simulate import layered

    base = OrenNayar(CLAY, 0.3)
    coat = {"eta": 1.5, "roughness": 0.2, "distribution": "ggx"}
    models = {
        "Mix, as the lecture draws it": Mix(
            [(1.0, base), (1.0, TorranceSparrow(1.5, 0.15))]),
        "Coated (closed form)": Coated(base, **coat),
    }
    g = pixel_cosines(SurfaceOfRevolution(), DistantLight(math.radians(45.0), math.radians(30.0)),
                      size=size)
    mu_i, mu_o = np.clip(g.mu_i[g.lit], 0.0, 1.0), np.clip(g.mu_o[g.lit], 0.0, 1.0)
    cos_io = g.cos_io[g.lit]
    images = {}
    for label, m in models.items():
        f = np.asarray(m.brdf_cosines(mu_i, mu_o, cos_io), dtype=np.float64)
        images[label] = f * mu_i[:, None]
    s_i, s_o = np.sqrt(1.0 - mu_i**2), np.sqrt(1.0 - mu_o**2)
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_dp = np.where(s_i * s_o > 0, (cos_io - mu_i * mu_o) / (s_i * s_o), 1.0)
    f, se = layered.brdf(np.arccos(mu_i), np.arccos(mu_o), np.arccos(np.clip(cos_dp, -1, 1)),
                         base, **coat, samples=COAT_PATHS, seed=7, return_stderr=True)
    images["layered truth (Monte Carlo)"] = f * mu_i[:, None]
    noise = float(np.sqrt(np.mean((se * mu_i[:, None]) ** 2)))
    full = {}
    for label, values in images.items():
        img = np.zeros((*g.lit.shape, 3))
        img[g.lit] = values
        full[label] = img
    return full, g.lit, noise


def _diffuse_plus_specular() -> Any:
    size = SIZE // 4 * 3
    images, lit, noise = _coat_images(size)
    truth = images["layered truth (Monte Carlo)"]
    scale = float(np.sqrt(np.mean(truth[lit] ** 2)))
    vmax = float(np.percentile(np.concatenate([v[lit].ravel() for v in images.values()]), 99.5))
    fig = _figure.figure(figsize=(12.5, 4.6))
    grid = fig.add_gridspec(1, 4, width_ratios=[1, 1, 1, 1.4])
    row = int(np.argmax(lit.sum(axis=1)))
    for i, (label, img) in enumerate(images.items()):
        ax = fig.add_subplot(grid[0, i])
        if img is truth:
            err = f"its Monte Carlo noise: {noise / scale:.1%} RMS"
        else:
            err = f"RMS error {np.sqrt(np.mean((img[lit] - truth[lit]) ** 2)) / scale:.1%}"
        show_radiance(ax, img, vmax, f"{label}\n{err}")
        ax.axhline(row, color="tab:red", lw=0.8, ls="--")
    radiance_colorbar(ax, vmax, "L/E0 of each of R, G, B (sr⁻¹)")
    ax = fig.add_subplot(grid[0, 3])
    cols = np.flatnonzero(lit[row])
    for (label, img), style in zip(images.items(), ("-", "--", "-"), strict=True):
        ax.plot(cols, img[row, cols].mean(axis=-1), style, label=label.split(",")[0],
                color="black" if img is truth else None, lw=1.0)
    ax.set_xlabel("pixel column along the dashed line")
    ax.set_ylabel("radiance (E0 = 1; mean of R, G, B)")
    ax.legend(fontsize="small", loc="upper left")
    _suptitle(
        fig,
        "7. Diffuse plus surface reflection: the clay vase under a glaze (η = 1.5, "
        "GGX α = 0.2), light at θi = 45°",
    )
    fig.tight_layout()
    return fig


def _models_side_by_side() -> Any:
    sigma = 0.5
    s2 = sigma * sigma
    a = 1.0 - 0.5 * s2 / (s2 + 0.33)  # the qualitative model's A and B (Oren–Nayar Eq. 30)
    b = 0.45 * s2 / (s2 + 0.09)
    r = b / a
    models = {
        "qualitative ON": OrenNayar(0.8, sigma, "qualitative"),
        "full ON": OrenNayar(0.8, sigma, "full"),
        f"Fujii (r = {r:.2f})": Fujii(0.8, r),
        f"EON (r = {r:.2f})": EON(0.8, r),
    }
    light = DistantLight(math.radians(60.0), 0.0)
    imgs = {
        k: render(m, Sphere(), light, size=SIZE // 4 * 3, samples_per_pixel=SPP)[0]
        for k, m in models.items()
    }
    ref = imgs["qualitative ON"]
    vmax = max(float(v.max()) for v in imgs.values())
    dmax = max(float(np.abs(v - ref).max()) for v in imgs.values()) or 1.0
    fig, axes = _figure.subplots(2, 4, figsize=(11, 6), layout="constrained")
    for i, (label, img) in enumerate(imgs.items()):
        show_radiance(axes[0, i], img, vmax, label)
        if i == len(imgs) - 1:
            radiance_colorbar(axes[0, i], vmax)
        ax = axes[1, i]
        if i == 0:
            ax.axis("off")
            ax.text(
                0.5,
                0.5,
                "differences from\nthe qualitative model\n(red: brighter)",
                ha="center",
                va="center",
                transform=ax.transAxes,
            )
            continue
        im = ax.imshow(img - ref, cmap="RdBu_r", vmin=-dmax, vmax=dmax)
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title(f"{label} − qualitative", fontsize="small")
    fig.colorbar(im, ax=axes[1, 1:].tolist(), shrink=0.8, label="difference of L/E0 (sr⁻¹)")
    _suptitle(
        fig,
        f"8. The Oren–Nayar family side by side: ρ = 0.8, σ = {sigma} rad, light at "
        "θi = 60°; Fujii/EON r = B/A of Eq. 30",
    )
    return fig


def _production_models() -> Any:
    models = {
        "Lambert": Lambert(0.8),
        "Burley, r = 0.5": Burley(0.8, 0.5),
        "Frostbite, r = 0.5": BurleyRenormalized(0.8, 0.5),
        "Hammon, α = 0.25": Hammon(0.8, 0.25),
        "Chan, α = 0.25": Chan(0.8, 0.25),
        "EON, r = 0.5": EON(0.8, 0.5),
        "d'Eon spheres": LambertSphere(0.8, "full"),
    }
    light = DistantLight(math.radians(60.0), 0.0)
    size = SIZE // 2
    imgs = {
        k: render(m, Sphere(), light, size=size, samples_per_pixel=SPP)[0]
        for k, m in models.items()
    }
    vmax = max(float(v.max()) for v in imgs.values())
    fig = _figure.figure(figsize=(14, 7.2))
    grid = fig.add_gridspec(2, len(models), height_ratios=[1, 1.5])
    for i, (label, img) in enumerate(imgs.items()):
        ax = show_radiance(fig.add_subplot(grid[0, i]), img, vmax, label)
    radiance_colorbar(ax, vmax)
    half = len(models) // 2 + 1
    styles = {"Lambert": {"color": "k", "ls": "--"}}
    for j, theta_i in enumerate((30.0, 70.0)):
        cols = slice(0, half) if j == 0 else slice(half, len(models))
        ax = fig.add_subplot(grid[1, cols])
        plot_plane_of_incidence(models, math.radians(theta_i), ax=ax, styles=styles)
        ax.set_title(f"plane of incidence, θi = {theta_i:g}°", fontsize="medium")
        ax.legend(fontsize="x-small")
    _suptitle(
        fig,
        "9. What production renderers use: ρ = 0.8, light at θi = 60° (one grey scale); "
        "Burley 2015 equals Burley 2012",
    )
    fig.tight_layout()
    return fig


def furnace_groups() -> dict[str, dict[str, Any]]:
    """Every model at ρ = 1 for the white-furnace figure, a few roughnesses each."""
    deg = math.radians
    return {
        "Lambert": {"ρ = 1": Lambert(1.0)},
        "Oren–Nayar (qualitative)": {f"σ = {s}°": OrenNayar(1.0, deg(s)) for s in (0, 20, 40, 60)},
        "Oren–Nayar (full)": {f"σ = {s}°": OrenNayar(1.0, deg(s), "full") for s in (0, 20, 40, 60)},
        "Fujii (FON)": {f"r = {r}": Fujii(1.0, r) for r in (0.0, 0.5, 1.0)},
        "EON": {f"r = {r}": EON(1.0, r) for r in (0.0, 0.5, 1.0)},
        "Torrance–Sparrow (η = 1.5)": {
            f"σ = {s}°": TorranceSparrow(1.5, deg(s)) for s in (10, 20, 40)
        },
        "Lommel–Seeliger": {"w = 1": LommelSeeliger(1.0)},
        "Lunar-Lambert": {f"L = {x}": LunarLambert(1.0, x) for x in (0.0, 0.5, 1.0)},
        "Minnaert": {f"k = {k}": Minnaert(1.0, k) for k in (0.5, 1.0, 1.5)},
        "Burley 2012 (= 2015)": {f"r = {r}": Burley(1.0, r) for r in (0.0, 0.5, 1.0)},
        "Frostbite": {f"r = {r}": BurleyRenormalized(1.0, r) for r in (0.0, 0.5, 1.0)},
        "Hammon": {f"α = {a}": Hammon(1.0, a) for a in (0.0, 0.5, 1.0)},
        "Chan": {f"α = {a}": Chan(1.0, a) for a in (0.01, 0.25, 1.0)},
        "d'Eon Lambertian spheres": {
            "full": LambertSphere(1.0, "full"),
            "fast": LambertSphere(1.0, "fast"),
        },
        "Hapke (w = 1)": {
            "smooth, isotropic": Hapke(1.0, 0.0, 0.1, 0.0, 0.0),
            "θ̄ = 20°": Hapke(1.0, 0.0, 0.1, 0.0, deg(20)),
            "θ̄ = 20°, B0 = 1, h = 0.06": Hapke(1.0, 1.0, 0.06, 0.0, deg(20)),
        },
    }


def _white_furnace() -> Any:
    from .energy import plot_albedo

    fig = plot_albedo(furnace_groups(), np.radians(np.arange(0.0, 89.6, 2.5)))
    for ax in fig.axes:  # Minnaert k < 1 and Lunar-Lambert diverge at grazing: clip
        ax.set_ylim(0.0, 1.6)
    fig.suptitle(
        "10. White furnace, every model at ρ = 1: ∫ f cos θi dωi against θr "
        "(1 = no energy lost or gained; clipped at 1.6)"
    )
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 0.98))
    return fig


def _eon_fitted_to(truth: VCavity) -> tuple[float, float]:
    """EON's (ρ, r) minimising the RMS relative error against ``truth`` over a grid of
    geometries (θi, θr ∈ 0–80°, Δφ ∈ 0–180°). EON's ρ is not the facet albedo (EON is
    built to conserve energy, the V-cavity's interreflection is not), so both are fitted."""
    from scipy.optimize import minimize

    t = np.radians(np.arange(0.0, 81.0, 10.0))
    ti, tr, dp = np.meshgrid(t, t, np.radians(np.arange(0.0, 181.0, 30.0)), indexing="ij")
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], axis=-1).reshape(-1, 3)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], axis=-1).reshape(
        -1, 3
    )
    f = np.asarray(truth.brdf(wi, wo))

    def cost(x: np.ndarray) -> float:
        m = EON(float(np.clip(x[0], 0.0, 1.0)), float(np.clip(x[1], 0.0, 1.0)))
        return float(np.mean((np.asarray(m.brdf(wi, wo)) / f - 1.0) ** 2))

    x0 = np.array([float(truth.albedo), 0.3])
    res = minimize(cost, x0, method="Nelder-Mead", options={"xatol": 1e-4, "fatol": 1e-10})
    rho, r = (float(np.clip(v, 0.0, 1.0)) for v in res.x)
    return rho, r


def _against_the_truth() -> Any:
    scenes = [
        ("clay vase, ρ = 0.8, σ = 0.3 rad", SurfaceOfRevolution(), 0.8, 0.3),
        ("full moon, ρ = 0.12, σ = 0.7 rad", Moon(), 0.12, 0.7),
    ]
    light = DistantLight(0.0)
    fig = _figure.figure(figsize=(13, 11), layout="constrained")
    grid = fig.add_gridspec(4, 5)
    for k, (label, shape, rho, sigma) in enumerate(scenes):
        truth = VCavity(rho, sigma)
        eon_rho, r = _eon_fitted_to(truth)
        models = {
            "V-cavity (exact)": truth,
            "Lambert": Lambert(rho),
            "qualitative ON": OrenNayar(rho, sigma, "qualitative"),
            "full ON": OrenNayar(rho, sigma, "full"),
            f"EON, ρ = {eon_rho:.3f}, r = {r:.2f} (fitted)": EON(eon_rho, r),
        }
        # SIZE: the same compiled renders as figures 2 and 3
        out = {
            name: render(m, shape, light, size=SIZE, samples_per_pixel=SPP)
            for name, m in models.items()
        }
        ref, mask = out["V-cavity (exact)"]
        row = int(np.argmax(mask.sum(axis=1)))  # the widest row (the vase's belly)
        vmax = max(float(v[0].max()) for v in out.values())
        inside = mask > 0.5
        errors = []
        for i, (name, (img, _)) in enumerate(out.items()):
            ax = fig.add_subplot(grid[2 * k, i])
            show_radiance(ax, img, vmax, name if i < 4 else name.replace(", r", ",\nr"))
            ax.axhline(row, color="tab:red", lw=0.6, ls="--")
            if i == len(out) - 1:
                radiance_colorbar(ax, vmax)
            if i == 0:
                ax.set_ylabel(label, fontsize="small")
                continue
            ax = fig.add_subplot(grid[2 * k + 1, i])
            err = np.where(inside, img / np.where(inside, ref, 1.0) - 1.0, np.nan)
            im = ax.imshow(err, cmap="RdBu_r", vmin=-0.3, vmax=0.3)
            ax.set_xticks([])
            ax.set_yticks([])
            rms = float(np.sqrt(np.nanmean(err**2)))
            ax.set_title(f"error of {name.split(',')[0]}: RMS {100 * rms:.1f}%", fontsize="small")
            errors.append(ax)
        fig.colorbar(im, ax=errors, shrink=0.8, label="(model − exact) / exact")
        ax = fig.add_subplot(grid[2 * k + 1, 0])
        plot_cross_section(
            {n.split(" (")[0].split(",")[0]: v[0] for n, v in out.items()},
            masks={n.split(" (")[0].split(",")[0]: v[1] for n, v in out.items()},
            row=row,
            ax=ax,
            x=pixel_coordinates(shape, None, SIZE)[0],
        )
        ax.legend(fontsize="xx-small")
        ax.set_title("along the dashed line", fontsize="small")
        ax.set_xlabel("x", fontsize="small")
    _suptitle(
        fig,
        "11. Against the exact V-cavity surface (all bounces), lit from the viewer (θi = 0): "
        "the vase and the full moon",
    )
    return fig


FIGURES: tuple[Figure, ...] = (
    Figure(
        "1-lambert-sphere",
        "A Lambertian sphere lit head-on",
        "Radiance ρ/π E0 n·s falls to zero at the limb, where n·s = 0: the rendered profile "
        "(solid) lies on the closed form (dashed); the colour bar gives the image's radiance "
        "per unit irradiance, L/E0, in sr⁻¹.",
        _lambert_sphere,
    ),
    Figure(
        "2-full-moon",
        "The full-moon question",
        "Five spheres lit from behind the viewer: Lambert, Oren–Nayar full (σ = 0.7 rad), "
        "Lommel–Seeliger, Hapke with lunar parameters and Minnaert (k = 0.6). The Lambertian "
        "disc darkens towards its edge; the rough Oren–Nayar disc stays much brighter there, "
        "the Lommel–Seeliger disc is exactly flat, and Hapke's and Minnaert's, the laws "
        "planetary photometry fits to the moon, are nearly flat too. Each disc is divided by "
        "its centre's radiance (the colour bar's scale) and so are the profiles.",
        _full_moon,
    ),
    Figure(
        "3-vase",
        "The clay vase (the lecture's Fig. 7)",
        "The default clay vase lit from the viewing direction: the Lambertian rendering "
        "darkens towards the silhouette, the Oren–Nayar one (σ = 0.3 rad) is flatter, as in "
        "the photograph of the real vase in Oren and Nayar's Fig. 7. Both share one grey "
        "scale.",
        _vase,
    ),
    Figure(
        "4-roughness-series",
        "Increasing roughness",
        "The same sphere (ρ = 0.8) for σ = 0, 0.1, 0.2, 0.3, 0.5 rad, lit head-on (top) and "
        "from θi = 60° (bottom), on one grey scale: roughness flattens the disc and, under "
        "oblique light, brightens the side towards the viewer.",
        _roughness_series,
    ),
    Figure(
        "5-view-dependence",
        "View dependence",
        "Radiance in the plane of incidence against the signed viewing angle θr (positive "
        "on the light's side). Lambert is flat; Oren–Nayar radiance rises as the viewing "
        "direction approaches the source (θr → θi), more for larger σ; dashed lines are the "
        "full model with interreflections.",
        _view_dependence,
    ),
    Figure(
        "6-blurred-highlights",
        "Blurred highlights",
        "Torrance–Sparrow spheres with increasing facet slope deviation σ: the highlight "
        "spreads and its peak falls (each image divided by its peak, stated above it).",
        _blurred_highlights,
    ),
    Figure(
        "7-diffuse-plus-specular",
        "Diffuse plus surface reflection",
        "The clay vase (Oren–Nayar body, σ = 0.3 rad, clay colour) with a glossy surface, "
        "three ways. Left: the lecture's Mix, the body plus a Torrance–Sparrow highlight "
        "(σ = 0.15 rad), each at weight 1. Middle: Coated, a dielectric glaze (η = 1.5, "
        "GGX α = 0.2) over the same body in closed form: light is refracted in and out, "
        "reflected back inside, so the body darkens and saturates and energy is conserved "
        "without a weight. Right: the exact layered reflectance by Monte Carlo "
        "(roughdiffuse.simulate.layered, 256 paths per pixel), the truth both are scored "
        "against: RMS error of the radiance over the lit pixels relative to the truth's RMS "
        "radiance (the truth's own noise is stated). The plot follows the dashed line.",
        _diffuse_plus_specular,
    ),
    Figure(
        "8-models-side-by-side",
        "The Oren–Nayar family",
        "Qualitative and full Oren–Nayar, Fujii's improved model and the energy-preserving "
        "EON at σ = 0.5 rad (Fujii and EON take r, not an angle: r = B/A of the qualitative "
        "model, so that their s/t terms have the same weight). Bottom: differences from the "
        "qualitative model.",
        _models_side_by_side,
    ),
    Figure(
        "9-production-models",
        "What production renderers use",
        "Spheres and plane-of-incidence radiance of the diffuse models production renderers "
        "ship: Burley's Disney diffuse (MaterialX; Unity HDRP's default divided by 1.03571; "
        "compiled out in Filament, which renders Lambert), Frostbite's renormalised version "
        "(Falcor), Hammon's GGX diffuse (opt-in in Unity), Chan's (Unreal), EON (OpenPBR) and "
        "d'Eon's Lambertian spheres, against Lambert (dashed). Burley 2015 (Mitsuba 3's "
        "principled) is Burley 2012 rewritten and coincides with it.",
        _production_models,
    ),
    Figure(
        "10-white-furnace",
        "White furnace for every model",
        "Directional albedo at ρ = 1 against the viewing angle: 1 means the model neither "
        "loses nor creates energy. Lambert and EON are 1; d'Eon's full model stays within "
        "2 %, its fast variant creates up to 25 % at grazing; Burley (r = 1) and Hammon "
        "(α = 1) create energy at grazing angles, at r or α = 0 they lose it; Frostbite loses "
        "up to 30 %; Minnaert with k < 1 and Lunar-Lambert diverge at grazing; Hapke (w = 1) "
        "with roughness loses 13–18 %. docs/developer/energy-and-sampling.md lists the numbers.",
        _white_furnace,
    ),
    Figure(
        "11-against-the-truth",
        "Against the exact surface",
        "The clay vase (ρ = 0.8, σ = 0.3 rad) and the full moon (ρ = 0.12, σ = 0.7 rad) lit "
        "from the viewing direction, rendered with the exact reflectance of the V-cavity "
        "surface the models approximate (roughdiffuse.VCavity, all bounces, solid-angle "
        "slope measure) beside Lambert, qualitative and full Oren–Nayar at the same σ and ρ, "
        "and EON with its r (and its ρ, which is not the facet albedo) fitted to the exact "
        "BRDF (least RMS relative error over θi, θr ≤ 80°), both stated. "
        "Second row of each: each model's relative error against the exact image; the "
        "plot shows all five along the dashed line. Where the lecture compares its models "
        "with a photograph, this compares them with the surface they model.",
        _against_the_truth,
    ),
)


def _write_index(folder: Path) -> Path:
    items = []
    for f in FIGURES:
        if not (folder / f"{f.name}.png").exists():
            continue
        items.append(
            f'<figure id="{f.name}">\n  <img src="{f.name}.png" alt="{html.escape(f.title)}">\n'
            f"  <figcaption><b>{html.escape(f.title)}.</b> {html.escape(f.caption)}"
            "</figcaption>\n</figure>"
        )
    page = (
        '<!doctype html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        "<title>roughdiffuse: figures of the lecture</title>\n<style>\n"
        "body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;}\n"
        "img{max-width:100%;border:1px solid #ddd}figure{margin:2em 0}\n"
        "figcaption{color:#333;margin-top:.5em}\n</style>\n</head>\n<body>\n"
        "<h1>Diffuse reflection from rough surfaces: the figures</h1>\n"
        "<p>Made by <code>roughdiffuse figures</code>. Radiance for irradiance E0 = 1; images "
        "on a linear grey scale.</p>\n" + "\n".join(items) + "\n</body>\n</html>\n"
    )
    return atomic_write(folder / "index.html", lambda tmp: tmp.write_text(page, "utf-8"))


PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def _check_kept(path: Path) -> None:
    """Refuse to keep ``path`` as a figure unless it is a PNG file (not a folder, link or
    other data planted under the figure's name)."""
    if path.is_symlink() or not path.is_file():
        raise ParameterError(f"{str(path)!r} is not a regular file; remove it or use --force")
    with open(path, "rb") as fh:
        head = fh.read(len(PNG_SIGNATURE))
    if head != PNG_SIGNATURE:
        raise ParameterError(
            f"{str(path)!r} is not a PNG image: not kept as a figure; remove it or use --force"
        )


def kept_figures(folder: str | os.PathLike[str], only: list[str] | None = None) -> list[str]:
    """Names of the figures ``make_figures`` (without ``force``) would keep in ``folder``."""
    folder = Path(folder)
    chosen = [f for f in FIGURES if not only or any(figure_matches(f.name, o) for o in only)]
    return [f.name for f in chosen if (folder / f"{f.name}.png").exists()]


def figure_matches(name: str, key: str) -> bool:
    """Whether ``--only`` ``key`` names the figure ``name``: a number is the figure's number
    (``1`` is ``1-lambert-sphere``, not ``10-…``), other text a prefix of the name."""
    if not key:
        return False  # an empty name matches no figure (not every one)
    if key.isdigit():
        return name.split("-", 1)[0] == key
    return name.startswith(key)


def make_figures(
    folder: str | os.PathLike[str] = "figures",
    force: bool = False,
    progress: bool = True,
    only: list[str] | None = None,
) -> list[Path]:
    """Write the eleven figures (PNG, 110 dpi) and ``index.html`` into ``folder``.

    Parameters
    ----------
    folder : path
        Created if missing (its parent must exist).
    force : bool
        Redraw figures whose PNG exists (otherwise they are kept, so an interrupted run
        resumes where it stopped; a kept file must be a PNG, else ``ValueError``).
        ``index.html`` is written last and removed while figures are redrawn: a folder
        without it is unfinished.
    progress : bool
        Show a progress bar (:func:`roughdiffuse.progress.progress`, on standard error).
    only : list of str, optional
        Names (or leading numbers) of the figures to draw.

    Returns
    -------
    list of Path
        The PNG files and index.html.
    """
    from .progress import progress as progress_bar

    folder = Path(folder)
    if not folder.parent.is_dir():
        raise ParameterError(f"parent folder {str(folder.parent)!r} does not exist")
    folder.mkdir(exist_ok=True)
    chosen = [f for f in FIGURES if not only or any(figure_matches(f.name, o) for o in only)]
    if only and not chosen:
        raise ParameterError(
            f"no figure matches {only}; names: {', '.join(f.name for f in FIGURES)}"
        )
    out = []
    kept = [f for f in chosen if (folder / f"{f.name}.png").exists() and not force]
    for f in kept:  # a file under a figure's name that is not a PNG is not kept silently
        _check_kept(folder / f"{f.name}.png")
    if len(kept) < len(chosen):
        # index.html is the folder's completion marker: it is removed while figures are
        # redrawn and written last, so a folder without it is visibly unfinished
        (folder / "index.html").unlink(missing_ok=True)
    bar = progress_bar(len(chosen), "figures", unit="fig", enabled=progress)
    for f in chosen:
        bar.set_postfix_str(f.name)
        bar.update(1)
        path = folder / f"{f.name}.png"
        out.append(path)
        if f in kept:
            continue
        fig = f.draw()
        fig.text(0.995, 0.005, "roughdiffuse", ha="right", va="bottom", fontsize=6, color="0.6")
        atomic_write(path, lambda tmp, fig=fig: fig.savefig(tmp, dpi=110))
        _figure.release(fig)  # drawn by a public plotting function: known to pyplot
    bar.close()
    out.append(_write_index(folder))
    return out
