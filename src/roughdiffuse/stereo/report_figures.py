"""The pictures of the photometric-stereo report: every map with labelled axes and a colour
bar with numbers, the Lambertian and rough results on one scale, the inputs and their lights.

Each function returns a ``matplotlib.figure.Figure`` (not known to pyplot: the report saves
it and lets it go); :func:`report_pngs` draws them all as PNG bytes.
"""

from __future__ import annotations

import io
import math
from typing import Any

import numpy as np

from .inputs import StereoInput

__all__ = ["NORMAL_KEY", "methods_pngs", "report_pngs"]

NORMAL_KEY = "colour = normal direction: red = x (right), green = y (up), blue = z (camera)"

MAX_INPUTS = 8
"""At most this many input images are shown."""


def _png(fig: Any) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=100)
    return buf.getvalue()


def _pixel_axes(ax: Any) -> None:
    ax.set_xlabel("x (pixels)", fontsize=8)
    ax.set_ylabel("y (pixels)", fontsize=8)
    ax.tick_params(labelsize=7)


def _grey(image: np.ndarray) -> np.ndarray:
    return image if image.ndim == 2 else image.mean(axis=-1)  # NaN where a channel is NaN


def light_angles(direction: np.ndarray) -> tuple[float, float]:
    """(θ from the camera axis, azimuth φ from +x) of a unit light direction, degrees."""
    x, y, z = (float(v) for v in direction)
    return math.degrees(math.acos(max(-1.0, min(1.0, z)))), math.degrees(math.atan2(y, x)) % 360


def inputs_figure(data: StereoInput) -> Any:
    """The input images on one grey scale (colour bar: radiance) and the lights' directions."""
    from .._figure import figure

    k = min(data.count, MAX_INPUTS)
    cols = min(k, 4)
    rows = -(-k // cols)
    fig = figure(figsize=(2.6 * cols + 3.4, 2.5 * rows + 0.6), layout="constrained")
    grid = fig.add_gridspec(rows, cols + 1, width_ratios=[1.0] * cols + [1.25])
    imgs = [_grey(data.images[i]) for i in range(k)]
    top = float(max(np.nanpercentile(im[data.mask], 99.5) for im in imgs)) or 1.0
    shown = None
    for i, im in enumerate(imgs):
        ax = fig.add_subplot(grid[i // cols, i % cols])
        shown = ax.imshow(im, cmap="gray", vmin=0.0, vmax=top)
        theta, phi = light_angles(data.directions[i])
        ax.set_title(f"light {i + 1}: θ = {theta:.0f}°, φ = {phi:.0f}°", fontsize=8)
        _pixel_axes(ax)
    fig.colorbar(shown, ax=fig.axes, shrink=0.8, label="radiance (linear)")
    polar = fig.add_subplot(grid[:, cols], projection="polar")
    for i, d in enumerate(data.directions):
        theta, phi = light_angles(d)
        polar.plot(math.radians(phi), theta, "o", color="tab:orange")
        polar.annotate(str(i + 1), (math.radians(phi), theta), fontsize=7,
                       xytext=(3, 3), textcoords="offset points")
    polar.set_rmax(max(90.0, 1.0))
    polar.set_rticks([30, 60, 90])
    polar.set_yticklabels(["30°", "60°", "90°"], fontsize=7)
    polar.tick_params(labelsize=7)
    polar.set_title("light directions\n(angle: azimuth φ, radius: θ from the camera axis)",
                    fontsize=8)
    if data.count > k:
        fig.suptitle(f"the first {k} of {data.count} input images", fontsize=9)
    return fig


def _normal_rgb(normals: np.ndarray) -> np.ndarray:
    valid = np.all(np.isfinite(normals), axis=-1)
    rgb = np.clip(0.5 * (np.nan_to_num(normals) + 1.0), 0.0, 1.0)
    return np.concatenate([rgb, valid[..., None].astype(float)], axis=-1)


def _normal_key(ax: Any) -> None:
    """The colour key of the normal maps: the hemisphere seen from the camera."""
    u = np.linspace(-1.0, 1.0, 101)
    x, y = np.meshgrid(u, -u)
    z = np.sqrt(np.clip(1.0 - x * x - y * y, 0.0, None))
    key = np.stack([x, y, z], axis=-1)
    key[x * x + y * y > 1.0] = np.nan
    ax.imshow(_normal_rgb(key), extent=(-1, 1, -1, 1))
    ax.set_title("key: normal (nx, ny)", fontsize=9)
    ax.set_xlabel("nx", fontsize=8)
    ax.set_ylabel("ny", fontsize=8)
    ax.tick_params(labelsize=7)


def lambert_normals_figure(normals: np.ndarray, label: str = "Lambertian") -> Any:
    """The normal map of Lambertian photometric stereo alone (``label``: which solver), with
    its colour key."""
    from .._figure import figure

    fig = figure(figsize=(6.4, 3.6), layout="constrained")
    axes = fig.subplots(1, 2, width_ratios=[1, 0.75])
    axes[0].imshow(_normal_rgb(normals))
    axes[0].set_title(f"normals, {label}", fontsize=9)
    _pixel_axes(axes[0])
    _normal_key(axes[1])
    return fig


def normals_figure(rough: np.ndarray, lambert: np.ndarray, rough_label: str) -> Any:
    """Both normal maps in one colour encoding, with its key (the hemisphere seen from the
    camera, axes in normal components) and the angle between the two maps (colour bar)."""
    from .._figure import figure

    fig = figure(figsize=(13.0, 3.6), layout="constrained")
    axes = fig.subplots(1, 4, width_ratios=[1, 1, 0.75, 1.2])
    for ax, n, title in ((axes[0], rough, f"normals, {rough_label}"),
                         (axes[1], lambert, "normals, Lambertian")):
        ax.imshow(_normal_rgb(n))
        ax.set_title(title, fontsize=9)
        _pixel_axes(ax)
    _normal_key(axes[2])
    dot = np.clip(np.sum(np.nan_to_num(rough) * np.nan_to_num(lambert), axis=-1), -1.0, 1.0)
    valid = np.all(np.isfinite(rough), axis=-1) & np.all(np.isfinite(lambert), axis=-1)
    angle = np.where(valid, np.degrees(np.arccos(dot)), np.nan)
    im = axes[3].imshow(angle, cmap="magma", vmin=0.0)
    fig.colorbar(im, ax=axes[3], label="angle between the two (degrees)")
    axes[3].set_title(f"{rough_label} against Lambertian normals", fontsize=9)
    _pixel_axes(axes[3])
    return fig


def pair_figure(rough: np.ndarray, lambert: np.ndarray, what: str, unit: str, rough_label: str,
                cmap: str = "viridis", top: float | None = None) -> Any:
    """The same quantity from the rough and the Lambertian fit on one scale, one colour bar."""
    from .._figure import figure

    a, b = _grey(rough), _grey(lambert)
    both = np.concatenate([a[np.isfinite(a)], b[np.isfinite(b)]])
    hi = top if top is not None else (float(np.percentile(both, 99)) if both.size else 1.0)
    lo = min(0.0, float(both.min())) if both.size else 0.0
    fig = figure(figsize=(8.6, 3.6), layout="constrained")
    axes = fig.subplots(1, 2)
    im = None
    for ax, image, title in ((axes[0], a, rough_label), (axes[1], b, "Lambertian")):
        im = ax.imshow(image, cmap=cmap, vmin=lo, vmax=hi if hi > lo else lo + 1.0)
        ax.set_title(f"{what}, {title}", fontsize=9)
        _pixel_axes(ax)
    fig.colorbar(im, ax=axes, label=f"{what} ({unit})", shrink=0.9)
    return fig


def single_figure(image: np.ndarray, what: str, unit: str, cmap: str = "viridis") -> Any:
    """One map with its colour bar."""
    from .._figure import figure

    fig = figure(figsize=(4.6, 3.6), layout="constrained")
    ax = fig.subplots()
    im = ax.imshow(_grey(image), cmap=cmap)
    fig.colorbar(im, ax=ax, label=f"{what} ({unit})")
    ax.set_title(what, fontsize=9)
    _pixel_axes(ax)
    return fig


PARAMETER_UNITS = {"sigma": "radians", "alpha": "GGX α, dimensionless"}
"""The unit of each fitted parameter's map (others: "model units")."""


def value_and_error_figure(value: np.ndarray, se: np.ndarray | None, what: str,
                           unit: str) -> Any:
    """A parameter's per-pixel map and, beside it, its standard error's (each with its own
    colour bar; the error's scale ends at its 99th percentile or 10 times its median,
    whichever is lower, so the pixels the images barely determine, whose errors can be
    10¹² times the others', do not wash out the rest: they show at the scale's end)."""
    from .._figure import figure

    fig = figure(figsize=(9.0, 3.6), layout="constrained")
    axes = fig.subplots(1, 2)
    im = axes[0].imshow(_grey(value), cmap="viridis")
    fig.colorbar(im, ax=axes[0], label=f"{what} ({unit})")
    axes[0].set_title(what, fontsize=9)
    _pixel_axes(axes[0])
    if se is None:
        axes[1].set_axis_off()
        return fig
    e = _grey(se)
    finite = e[np.isfinite(e)]
    top = (min(float(np.percentile(finite, 99)), 10.0 * float(np.median(finite)))
           if finite.size else 1.0)
    top = top if top > 0 else 1.0
    shown = np.where(np.isnan(e), np.nan, np.minimum(e, 2.0 * top))  # ∞: the scale's end
    im = axes[1].imshow(shown, cmap="magma", vmin=0.0, vmax=top)
    fig.colorbar(im, ax=axes[1], label=f"standard error of {what} ({unit})", extend="max")
    axes[1].set_title(f"standard error of {what}", fontsize=9)
    _pixel_axes(axes[1])
    return fig


def report_pngs(
    data: StereoInput,
    maps: dict[str, np.ndarray],
    lambert_maps: dict[str, np.ndarray] | None,
    depth: np.ndarray,
    rough_label: str,
    per_pixel: list[str] | None,
) -> dict[str, bytes]:
    """Every picture of the report, as PNG bytes, by caption.

    With ``lambert_maps=None``, ``maps`` is Lambertian photometric stereo alone: each map
    is drawn once, with no rough model beside it. ``per_pixel`` names the parameters fitted
    per pixel (``sigma``, ``alpha``...): each is drawn beside its standard error
    (``maps[name + "_se"]``).
    """
    from .._figure import release

    figs = {"the input images and their lights": inputs_figure(data)}
    if lambert_maps is None:
        label = "Lambertian" if rough_label == "lambert" else rough_label
        figs["normals"] = lambert_normals_figure(maps["normals"], label)
        figs["albedo"] = single_figure(maps["albedo"], "albedo", "fraction", "gray")
        figs["relative RMS residual"] = single_figure(
            maps["residual"], "relative RMS residual", "fraction of the data", "magma")
    else:
        figs["normals"] = normals_figure(maps["normals"], lambert_maps["normals"], rough_label)
        figs["albedo (one scale for both)"] = pair_figure(
            maps["albedo"], lambert_maps["albedo"], "albedo", "fraction", rough_label,
            cmap="gray", top=1.0)  # a fraction: an even albedo is grey, not the scale's end
        figs["relative RMS residual (one scale for both)"] = pair_figure(
            maps["residual"], lambert_maps["residual"], "relative RMS residual",
            "fraction of the data", rough_label, cmap="magma")
    for name in per_pixel or ():
        if name in maps:
            figs[f"{name} per pixel, with its standard error"] = value_and_error_figure(
                maps[name], maps.get(f"{name}_se"), name, PARAMETER_UNITS.get(name, "model units"))
    if "normal_se_deg" in maps:
        figs["normal standard error"] = single_figure(maps["normal_se_deg"],
                                                      "normal standard error", "degrees", "magma")
    figs["depth"] = single_figure(depth, "depth (z towards the camera)", "pixels", "viridis")
    out = {}
    for name, fig in figs.items():
        out[name] = _png(fig)
        release(fig)
    return out


def methods_figure(maps: dict[str, np.ndarray], what: str, unit: str, cmap: str,
                   top: float | None = None) -> Any:
    """One map per method, side by side on one colour scale from 0, one colour bar.

    ``maps`` is method label -> (H, W) map (NaN outside the object); ``top`` is the end of
    the scale (default: the 99th percentile of every map together).
    """
    from .._figure import figure

    values = np.concatenate([m[np.isfinite(m)] for m in maps.values()] + [np.zeros(1)])
    hi = top if top is not None else float(np.percentile(values, 99))
    hi = hi if hi > 0 else 1.0
    rows = -(-len(maps) // 5)  # at most 5 a row, the rows equally full
    cols = -(-len(maps) // rows)
    fig = figure(figsize=(3.3 * cols + 1.2, 3.2 * rows + 0.3), layout="constrained")
    axes = np.atleast_1d(fig.subplots(rows, cols)).ravel()
    im = None
    for ax, (label, image) in zip(axes, maps.items(), strict=False):
        im = ax.imshow(image, cmap=cmap, vmin=0.0, vmax=hi)
        ax.set_title(label, fontsize=9)
        _pixel_axes(ax)
    for ax in axes[len(maps):]:
        ax.set_axis_off()
    fig.colorbar(im, ax=axes[: len(maps)].tolist(), label=f"{what} ({unit})", shrink=0.85)
    return fig


def methods_pngs(
    mask: np.ndarray,
    results: dict[str, Any],
    truth: np.ndarray | None,
    title: str = "",
) -> dict[str, bytes]:
    """The per-method pictures: the angular error against ``truth`` (H, W, 3; when known)
    and the fraction of each pixel's observations the method left out or rejected."""
    from .._figure import release
    from .synthetic import angular_error

    prefix = f"{title}: " if title else ""
    figs = {}
    if truth is not None:
        err = {}
        for name, r in results.items():
            e = np.full(mask.shape, np.nan)
            e[mask] = angular_error(r.normals, truth[mask])
            err[name] = e
        figs[f"{prefix}angular error against the truth, per method"] = methods_figure(
            err, "angular error", "degrees", "magma")
    rejected = {}
    for name, r in results.items():
        f = np.full(mask.shape, np.nan)
        f[mask] = 1.0 - np.asarray(r.weights).mean(axis=0)
        rejected[name] = f
    figs[f"{prefix}observations left out or rejected (shadows, outliers), per method"] = (
        methods_figure(rejected, "fraction of the pixel's observations", "0 to 1", "viridis",
                       top=1.0))
    out = {}
    for name, fig in figs.items():
        out[name] = _png(fig)
        release(fig)
    return out
