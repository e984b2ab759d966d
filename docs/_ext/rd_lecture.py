"""Figures of "The lecture, retold" (``docs/lecture/*.md``), drawn when the site is built.

Each figure is a small function of the package's public API (:func:`roughdiffuse.render.render`,
:mod:`roughdiffuse.plots`, :func:`roughdiffuse.simulate.brdf`) at small sizes, so that the
build stays fast; the PNGs go to ``docs/lecture/figures/`` (ignored by git) and are redrawn when
this file or the package version changes.
"""

from __future__ import annotations

import hashlib
import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure

SIZE = 96
"""Pixels across a rendered object (the figures of ``roughdiffuse figures`` use 200)."""

SPP = 4
"""Samples per pixel."""


def _legend_below(fig: Figure, *axes: Any) -> None:
    """One legend for ``axes`` below the figure, in type as large as the axis labels: an
    x-small legend inside a panel is unreadable once the figure is shrunk to the column, and
    covers the curves."""
    handles, labels = [], []
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
        if ax.get_legend() is not None:
            ax.get_legend().remove()
    fig.legend(handles, labels, loc="outside lower center", ncol=min(len(labels), 3),
               fontsize="medium", frameon=False)


def _sphere_row(models: dict[str, Any], light: Any, shape: Any = None, size: int = SIZE,
                scale: str = "shared") -> tuple[Figure, dict[str, tuple[np.ndarray, Any]]]:
    from roughdiffuse.plots import plot_cross_section, show_radiance
    from roughdiffuse.render import Sphere, pixel_coordinates, render

    shape = shape or Sphere()
    out = {k: render(m, shape, light, size=size, samples_per_pixel=SPP) for k, m in models.items()}
    fig = Figure(figsize=(2.3 * len(models) + 3.6, 2.9), layout="constrained")
    grid = fig.add_gridspec(1, len(models) + 1, width_ratios=[1] * len(models) + [1.7])
    vmax = max(float(np.max(img)) for img, _ in out.values())
    for i, (label, (img, _)) in enumerate(out.items()):
        ax = fig.add_subplot(grid[0, i])
        v = vmax if scale == "shared" else float(img[size // 2, size // 2]) * 1.05
        show_radiance(ax, np.asarray(img), v, label)
    ax = fig.add_subplot(grid[0, -1])
    plot_cross_section({k: v[0] for k, v in out.items()}, masks={k: v[1] for k, v in out.items()},
                       ax=ax, normalize=scale != "shared",
                       x=pixel_coordinates(shape, None, size)[0])
    _legend_below(fig, ax)
    ax.set_title("across the middle row" + ("" if scale == "shared" else ", ÷ centre"),
                 fontsize="small")
    return fig, out


def lambert_sphere() -> Figure:
    from roughdiffuse import Lambert
    from roughdiffuse.render import DistantLight

    fig, _ = _sphere_row({"Lambert, ρ = 0.8": Lambert(0.8)}, DistantLight(0.0))
    ax = fig.axes[-1]
    x = np.linspace(-1, 1, 201)
    ax.plot(x, 0.8 / math.pi * np.sqrt(1 - x**2), "k--", lw=1, label="ρ/π √(1 − x²)")
    for legend in list(fig.legends):
        legend.remove()
    _legend_below(fig, ax)
    return fig


def lambert_angles() -> Figure:
    from roughdiffuse import Lambert
    from roughdiffuse.plots import plot_plane_of_incidence

    fig = Figure(figsize=(7.0, 2.9), layout="constrained")
    for i, deg in enumerate((0.0, 60.0)):
        ax = fig.add_subplot(1, 2, i + 1)
        plot_plane_of_incidence({"Lambert, ρ = 0.8": Lambert(0.8)}, math.radians(deg), ax=ax,
                                n=91)
        ax.set_title(f"θi = {deg:.0f}°", fontsize="small")
    _legend_below(fig, *fig.axes)
    return fig


def full_moon() -> Figure:
    from roughdiffuse import Lambert, LommelSeeliger, Minnaert, OrenNayar
    from roughdiffuse.render import DistantLight, Moon

    models = {"Lambert": Lambert(), "Oren–Nayar full, σ = 0.7": OrenNayar(sigma=0.7,
                                                                           variant="full"),
              "Lommel–Seeliger": LommelSeeliger(), "Minnaert, k = 0.6": Minnaert(k=0.6)}
    fig, _ = _sphere_row(models, DistantLight(0.0), Moon(), scale="own")
    return fig


def v_cavity() -> Figure:
    """A V-cavity (shadowed and hidden parts) and its exact BRDF, one bounce and all."""
    from roughdiffuse import OrenNayar
    from roughdiffuse.simulate import brdf

    fig = Figure(figsize=(9.0, 3.0), layout="constrained")
    ax = fig.add_subplot(1, 2, 1)
    ta, ti, tr = math.radians(40.0), math.radians(60.0), math.radians(-25.0)
    w = math.tan(ta)  # facet half-width for a cavity of depth 1
    ax.plot([-2.2 * w, -w, 0, w, 2.2 * w], [0, 0, -1, 0, 0], color="0.3", lw=2)
    # light from the upper right at θi > θa: the right facet faces away from it, and the ray
    # grazing the right rim, (w, 0) − u s, meets the left facet (−w t, −1 + t) at this t
    s = np.array([math.sin(ti), math.cos(ti)])
    t = (math.tan(ti) - w) / (math.tan(ti) + w)
    ax.plot([0, -w * t], [-1, -1 + t], color="tab:blue", lw=5, solid_capstyle="butt",
            label="in shadow")
    ax.plot([0, w], [-1, 0], color="tab:blue", lw=5, solid_capstyle="butt")
    ax.plot([w, -w * t], [0, -1 + t], color="tab:orange", lw=0.8, ls="--")
    for x0 in (0.2 * w, 1.5 * w):
        ax.annotate("", xy=(x0, 0.05), xytext=(x0 + 0.8 * s[0], 0.05 + 0.8 * s[1]),
                    arrowprops={"arrowstyle": "->", "color": "tab:orange"})
    ax.text(1.5 * w + 0.8 * s[0], 0.1 + 0.8 * s[1], "light", color="tab:orange",
            fontsize="small")
    v = np.array([math.sin(tr), math.cos(tr)])
    p0 = np.array([-0.75 * w, -0.25])  # a lit point of the left facet, seen by the viewer
    ax.annotate("", xytext=tuple(p0), xy=tuple(p0 + 1.1 * v),
                arrowprops={"arrowstyle": "->", "color": "tab:green"}, annotation_clip=False)
    ax.text(*(p0 + 1.15 * v), "viewer", color="tab:green", fontsize="small", ha="right")
    ax.text(0.0, -1.2, "facet slope θa = 40°, light at θi = 60°", fontsize="small",
            ha="center")
    ax.set_aspect("equal")
    ax.axis("off")
    ax.set_xlim(-2.2 * w, 2.2 * w)
    ax.set_ylim(-1.3, 1.0)
    left = ax

    ax = fig.add_subplot(1, 2, 2)
    sigma, rho, deg = 0.3, 0.9, 60.0
    tr_deg = np.linspace(-85.0, 85.0, 35)
    tr = np.radians(np.abs(tr_deg))
    dphi = np.where(tr_deg >= 0, 0.0, math.pi)  # θr > 0 on the light's side
    ti = np.full_like(tr, math.radians(deg))
    for bounces, style in ((1, "-"), ("all", "-")):
        f = brdf(ti, tr, dphi, sigma, rho, bounces)
        ax.plot(tr_deg, f * math.cos(math.radians(deg)), style, lw=2 if bounces == "all" else 1,
                label=f"V-cavity surface, {bounces} bounce{'s' if bounces == 'all' else ''}")
    mu_o = np.cos(tr)
    cos_io = math.cos(ti[0]) * mu_o + math.sin(ti[0]) * np.sin(tr) * np.cos(dphi)
    for variant, ls in (("qualitative", ":"), ("full", "--")):
        m = OrenNayar(rho, sigma, variant)
        f = np.asarray(m.brdf_cosines(np.cos(ti), mu_o, cos_io))
        ax.plot(tr_deg, f * math.cos(math.radians(deg)), ls, color="k", lw=1,
                label=f"Oren–Nayar {variant}")
    ax.axhline(rho / math.pi * math.cos(math.radians(deg)), color="0.6", lw=0.8,
               label="Lambert")
    ax.set_xlabel("θr (degrees; > 0 on the light's side)")
    ax.set_ylabel("radiance (E0 = 1)")
    ax.set_title(f"σ = {sigma} rad, ρ = {rho}, θi = {deg:.0f}°", fontsize="small")
    _legend_below(fig, left, ax)
    return fig


def oren_nayar_plane() -> Figure:
    from roughdiffuse import Lambert, OrenNayar
    from roughdiffuse.plots import plot_plane_of_incidence

    models: dict[str, Any] = {"Lambert": Lambert(0.8)}
    styles: dict[str, dict[str, Any]] = {"Lambert": {"color": "black"}}
    for s, colour in ((0.2, "tab:blue"), (0.5, "tab:orange")):
        for variant, ls in (("qualitative", "-"), ("full", "--")):
            label = f"{variant}, σ = {s:g}"
            models[label] = OrenNayar(0.8, s, variant)
            styles[label] = {"color": colour, "ls": ls}
    fig = Figure(figsize=(9.0, 3.0), layout="constrained")
    for i, deg in enumerate((30.0, 70.0)):
        ax = fig.add_subplot(1, 2, i + 1)
        plot_plane_of_incidence(models, math.radians(deg), ax=ax, styles=styles, n=91)
        ax.set_title(f"θi = {deg:.0f}°", fontsize="small")
    _legend_below(fig, *fig.axes)
    return fig


def oren_nayar_series() -> Figure:
    from roughdiffuse import OrenNayar
    from roughdiffuse.plots import plot_roughness_series
    from roughdiffuse.render import DistantLight

    fig = plot_roughness_series(lambda s: OrenNayar(0.8, s), (0.0, 0.2, 0.5),
                                lights=[DistantLight(0.0), DistantLight(math.radians(60.0), 0.0)],
                                size=64, samples_per_pixel=SPP)
    fig.set_size_inches(5.6, 3.8)
    fig.tight_layout()  # room for the colour bars beside the rows
    return fig


def vase() -> Figure:
    from roughdiffuse import Lambert, OrenNayar
    from roughdiffuse.render import DistantLight, SurfaceOfRevolution

    fig, _ = _sphere_row({"Lambert": Lambert(0.8), "Oren–Nayar, σ = 0.3": OrenNayar(0.8, 0.3)},
                         DistantLight(0.0), SurfaceOfRevolution(), size=128)
    return fig


def torrance_sparrow() -> Figure:
    from roughdiffuse import TorranceSparrow
    from roughdiffuse.plots import plot_plane_of_incidence, show_radiance
    from roughdiffuse.render import DistantLight, Sphere, render

    sigmas = (0.05, 0.15, 0.3)
    fig = Figure(figsize=(10.0, 2.9), layout="constrained")
    grid = fig.add_gridspec(1, 4, width_ratios=[1, 1, 1, 1.8])
    for i, s in enumerate(sigmas):
        img, _ = render(TorranceSparrow(1.5, s), Sphere(), DistantLight(math.radians(30.0), 0.0),
                        size=SIZE, samples_per_pixel=SPP)
        ax = fig.add_subplot(grid[0, i])
        show_radiance(ax, np.asarray(img), float(np.max(img)), f"σ = {s:g} rad")
    ax = fig.add_subplot(grid[0, 3])
    plot_plane_of_incidence({f"σ = {s:g}": TorranceSparrow(1.5, s) for s in (0.15, 0.3)},
                            math.radians(60.0), ax=ax, n=181)
    ax.set_title("θi = 60°: the peak lies beyond the mirror direction", fontsize="small")
    ax.axvline(-60.0, color="0.6", lw=0.8, ls=":")
    _legend_below(fig, ax)
    return fig


def mix() -> Figure:
    from roughdiffuse import Mix, OrenNayar, TorranceSparrow
    from roughdiffuse.plots import plot_plane_of_incidence, show_radiance
    from roughdiffuse.render import DistantLight, Sphere, render

    body, coat = OrenNayar((0.75, 0.45, 0.30), 0.3), TorranceSparrow(1.5, 0.15)
    models = {"body: Oren–Nayar": body, "coat: Torrance–Sparrow": coat,
              "Mix, weights 1 and 1": Mix([(1.0, body), (1.0, coat)])}
    light = DistantLight(math.radians(45.0), math.radians(30.0))
    imgs = {k: np.asarray(render(m, Sphere(), light, size=SIZE, samples_per_pixel=SPP)[0])
            for k, m in models.items()}
    vmax = float(np.percentile(imgs["Mix, weights 1 and 1"], 99.5))
    fig = Figure(figsize=(10.0, 2.9), layout="constrained")
    grid = fig.add_gridspec(1, 4, width_ratios=[1, 1, 1, 1.8])
    for i, (label, img) in enumerate(imgs.items()):
        rgb = img if img.ndim == 3 else np.repeat(img[..., None], 3, axis=-1)
        show_radiance(fig.add_subplot(grid[0, i]), rgb, vmax, label)
    ax = fig.add_subplot(grid[0, 3])
    plot_plane_of_incidence(models, math.radians(45.0), ax=ax, n=181)
    ax.set_ylabel("radiance (mean of R, G, B)")
    _legend_below(fig, ax)
    return fig


FIGURES: dict[str, Callable[[], Figure]] = {
    "lambert-sphere": lambert_sphere,
    "lambert-angles": lambert_angles,
    "full-moon": full_moon,
    "v-cavity": v_cavity,
    "oren-nayar-plane": oren_nayar_plane,
    "oren-nayar-series": oren_nayar_series,
    "vase": vase,
    "torrance-sparrow": torrance_sparrow,
    "mix": mix,
}
"""File name (without .png) -> the function that draws it."""


def generate(docs: Path) -> list[Path]:
    """Draw the figures missing from ``docs/lecture/figures/`` or made by another version."""
    import matplotlib.pyplot as plt

    import roughdiffuse

    folder = docs / "lecture" / "figures"
    folder.mkdir(parents=True, exist_ok=True)
    import roughdiffuse.plots

    # the figures change with this file, the version and the plotting functions they call
    sources = Path(__file__).read_bytes() + Path(roughdiffuse.plots.__file__).read_bytes()
    key = hashlib.sha256(sources + roughdiffuse.__version__.encode()).hexdigest()
    stamp = folder / ".cache.json"
    try:
        done = json.loads(stamp.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        done = {}
    out = []
    for name, draw in FIGURES.items():
        path = folder / f"lecture-{name}.png"  # unique among the site's images
        out.append(path)
        if done.get(name) == key and path.is_file():
            continue
        fig = draw()
        fig.savefig(path, dpi=90)
        # a figure of a public plotting function is known to pyplot: forgotten here, or the
        # gallery's first example would show it as its own
        plt.close(fig)
        done[name] = key
    stamp.write_text(json.dumps(done, indent=1), encoding="utf-8")
    return out


if __name__ == "__main__":  # draw them all (python docs/_ext/rd_lecture.py)
    import time

    for name, draw in FIGURES.items():
        t = time.perf_counter()
        draw().savefig(Path("/tmp") / f"lecture-{name}.png", dpi=90)
        print(f"{name}: {time.perf_counter() - t:.1f} s")
