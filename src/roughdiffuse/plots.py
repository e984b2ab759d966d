"""Plots of the lecture (matplotlib): cross-sections, the plane of incidence, roughness series.

Every function draws on a matplotlib ``Axes`` (``ax=``) or, without one, on a new figure made
through ``matplotlib.pyplot`` (so ``plt.show()`` and Jupyter show it; no backend is chosen here),
and returns it; nothing is shown or saved here. Images are shown on a *linear* grey scale
from 0 to a common maximum, so that brightness in the picture and in the profiles plotted
beside it agree.

The plane of incidence (Oren and Nayar 1994, Figs. 9–12): the light at θi in the xz-plane,
the viewer in the same plane at a signed angle θr in [−90°, 90°], positive on the light's
side (backscattering, φr = φi) and negative on the mirror side (φr = φi + π).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import matplotlib.ticker
import numpy as np

from ._figure import pyplot_figure, pyplot_subplots
from ._validate import ParameterError
from .models import Model
from .render import DistantLight, OrthographicCamera, Shape, Sphere, render

__all__ = [
    "cross_section",
    "plane_of_incidence",
    "plot_cross_section",
    "plot_plane_of_incidence",
    "plot_roughness_series",
    "radiance_colorbar",
    "show_radiance",
]

ROUGHNESS_SERIES = (0.0, 0.1, 0.2, 0.3, 0.5)
"""σ (radians) of the lecture's roughness series."""


def cross_section(
    image: np.ndarray,
    row: int | None = None,
    mask: np.ndarray | None = None,
    x: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Brightness along image row ``row`` (default: the middle row).

    Parameters
    ----------
    x : array (W,), optional
        Coordinates of the columns (e.g. from :func:`roughdiffuse.render.pixel_coordinates`);
        default: pixel centres mapped to [−1, 1] across the image width.

    Returns
    -------
    x : array (W,)
        The column coordinates.
    values : array (W,) or (W, C)
        The row's radiance; with ``mask`` (the renderer's coverage), the radiance of the
        covered part of each pixel (value / coverage), and NaN where coverage is below 1/2.
    """
    img = np.asarray(image, dtype=np.float64)
    h, w = img.shape[:2]
    row = h // 2 if row is None else int(row)
    if not 0 <= row < h:
        raise ParameterError(f"row must be in [0, {h - 1}] (got {row})")
    if x is None:
        x = (np.arange(w) + 0.5) / w * 2.0 - 1.0
    elif np.shape(x) != (w,):
        raise ParameterError(f"x must have shape ({w},) (got {np.shape(x)})")
    vals = img[row].copy()
    if mask is not None:
        cov = np.asarray(mask, dtype=np.float64)[row]
        off = cov < 0.5
        # the renderer averages over the whole pixel: divide by the covered fraction
        vals = vals / np.where(off, 1.0, cov).reshape(-1, *([1] * (vals.ndim - 1)))
        vals[off] = np.nan
    return x, vals


def plot_cross_section(
    images: Mapping[str, np.ndarray],
    row: int | None = None,
    masks: Mapping[str, np.ndarray] | None = None,
    ax: Any = None,
    normalize: bool = False,
    x: np.ndarray | None = None,
) -> Any:
    """Brightness along one row of several images on one axis (the lecture's Fig. 7(d)).

    Parameters
    ----------
    images : mapping of label -> image (H, W)
        Images of the same size (e.g. the same object under different models).
    row : int, optional
        Image row (default: the middle row).
    masks : mapping of label -> coverage (H, W), optional
        Where coverage < 1/2 the profile is not drawn.
    normalize : bool
        Divide each profile by its value at the middle of the row.
    x : array (W,), optional
        World coordinates of the columns (see :func:`cross_section`).
    """
    if ax is None:
        _, ax = pyplot_subplots(figsize=(5, 3.5))
    for label, img in images.items():
        m = masks.get(label) if masks else None
        xs, v = cross_section(img, row, m, x)
        if v.ndim == 2:
            v = v.mean(axis=1)
        if normalize:
            mid = v[len(v) // 2]
            v = v / mid if np.isfinite(mid) and mid > 0 else v
        ax.plot(xs, v, label=label)
    ax.set_xlabel(
        "position across the image (−1 left edge, 1 right edge)"
        if x is None
        else "x across the image (object units)"
    )
    ax.set_ylabel("radiance / centre radiance" if normalize else "radiance (E0 = 1)")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def plane_of_incidence(
    model: Model, theta_i: float, theta_r: np.ndarray, irradiance: float = 1.0
) -> np.ndarray:
    """Radiance L = f_r E0 cos θi in the plane of incidence at signed viewing angles θr.

    Parameters
    ----------
    theta_i : float
        Incidence angle, radians, in [0, π/2].
    theta_r : array
        Signed viewing angles in radians, [−π/2, π/2]; positive on the light's side.
    """
    if not 0.0 <= theta_i <= math.pi / 2:
        raise ParameterError(f"theta_i must be in [0, π/2] radians (got {theta_i:g})")
    tr = np.asarray(theta_r, dtype=np.float64)
    if np.any(np.abs(tr) > math.pi / 2 + 1e-12):
        raise ParameterError("theta_r must be in [−π/2, π/2] radians")
    wi = np.array([math.sin(theta_i), 0.0, math.cos(theta_i)])
    wo = np.stack([np.sin(tr), np.zeros_like(tr), np.cos(tr)], axis=-1)
    f = np.asarray(model.brdf(wi, wo), dtype=np.float64)
    return f * irradiance * math.cos(theta_i)


def plot_plane_of_incidence(
    models: Mapping[str, Model],
    theta_i: float,
    ax: Any = None,
    polar: bool = False,
    styles: Mapping[str, Mapping[str, Any]] | None = None,
    n: int = 361,
) -> Any:
    """Radiance against the viewing angle θr in the plane of incidence, several models.

    Parameters
    ----------
    models : mapping of label -> Model
    theta_i : float
        Incidence angle, radians.
    ax : matplotlib Axes, optional
        A polar Axes when ``polar`` (created if not given).
    polar : bool
        Polar plot: angle θr from the normal (up), radius the radiance.
    styles : mapping of label -> keyword arguments of ``ax.plot``, optional
    """
    if ax is None:
        fig = pyplot_figure(figsize=(5, 3.5 if not polar else 4))
        ax = fig.add_subplot(projection="polar" if polar else None)
    tr = np.linspace(-math.pi / 2, math.pi / 2, n)
    top = 0.0
    for label, model in models.items():
        values = plane_of_incidence(model, theta_i, tr)
        if values.ndim == 2:
            values = values.mean(axis=1)
        top = max(top, float(np.nanmax(values)))
        kw = dict((styles or {}).get(label, {}))
        if polar:
            ax.plot(tr, values, label=label, **kw)
        else:
            ax.plot(np.degrees(tr), values, label=label, **kw)
    deg = math.degrees(theta_i)
    if polar:
        ax.set_theta_zero_location("N")
        ax.set_theta_direction(-1)
        ax.set_thetamin(-90)
        ax.set_thetamax(90)
        ax.set_rlabel_position(-90)
        ax.yaxis.set_major_locator(matplotlib.ticker.MaxNLocator(3))
        ax.tick_params(axis="y", labelsize="x-small")
        ax.plot([theta_i, theta_i], [0, top * 1.1], color="0.4", lw=1, ls=":")
        ax.annotate("light", (theta_i, top * 1.1), fontsize="small", color="0.3")
        ax.set_xlabel("radiance (radius) against θr (angle from the normal)", fontsize="small")
    else:
        ax.axvline(deg, color="0.4", lw=1, ls=":")
        ax.text(deg, 0.02 * top, " θr = θi", fontsize="small", color="0.3", rotation=90)
        ax.set_xlabel("viewing angle θr (degrees; > 0 on the light's side)")
        ax.set_ylabel("radiance (E0 = 1)")
        ax.set_xlim(-90, 90)
        ax.set_ylim(bottom=0)
        ax.grid(True, alpha=0.3)
    ax.set_title(f"θi = {deg:.0f}°", fontsize="medium")
    ax.legend(fontsize="x-small", loc="best")
    return ax


def show_radiance(ax: Any, image: np.ndarray, vmax: float, title: str = "") -> Any:
    """Show linear radiance on a linear grey (or RGB) scale from 0 to ``vmax``."""
    img = np.asarray(image, dtype=np.float64)
    vmax = vmax if vmax > 0 else 1.0
    if img.ndim == 3:
        ax.imshow(np.clip(img / vmax, 0.0, 1.0), interpolation="lanczos")
    else:
        ax.imshow(img, cmap="gray", vmin=0.0, vmax=vmax, interpolation="lanczos")
    ax.set_xticks([])
    ax.set_yticks([])
    if title:
        ax.set_title(title, fontsize="medium")
    return ax


RADIANCE_LABEL = "radiance L/E0 (sr⁻¹)"
"""The colour bar's label of an image of the renderer's radiance: per unit irradiance E0
(W m⁻² sr⁻¹ per W m⁻²)."""


def radiance_colorbar(ax: Any, vmax: float, label: str = RADIANCE_LABEL) -> Any:
    """A grey colour bar beside ``ax``, from 0 to ``vmax``: the scale :func:`show_radiance`
    draws with. Images that share a scale share one bar, beside the last of them.

    The bar is an inset of ``ax`` (``Axes.inset_axes``), so ``tight_layout`` makes room for it
    and the figure's list of axes is unchanged. Returns the ``Colorbar``.
    """
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    vmax = vmax if vmax > 0 else 1.0
    cax = ax.inset_axes([1.04, 0.0, 0.06, 1.0])
    bar = ax.figure.colorbar(ScalarMappable(Normalize(0.0, vmax), cmap="gray"), cax=cax)
    bar.set_label(label, fontsize="x-small")
    bar.ax.tick_params(labelsize="x-small")
    return bar


def plot_roughness_series(
    make_model: Callable[[float], Model],
    sigmas: Sequence[float] = ROUGHNESS_SERIES,
    shape: Shape | None = None,
    lights: Sequence[DistantLight] | None = None,
    camera: OrthographicCamera | None = None,
    size: int = 160,
    samples_per_pixel: int = 4,
    progress: Callable[[], None] | None = None,
) -> Any:
    """The same object for increasing σ, side by side (one row per light), on one grey scale
    with its colour bar beside each row.

    Parameters
    ----------
    make_model : callable σ -> Model
        For example ``lambda s: OrenNayar(0.8, s)``.
    sigmas : sequence of float
        Roughness values, radians (default 0, 0.1, 0.2, 0.3, 0.5).
    lights : sequence of DistantLight
        One row each (default: head-on, θi = 0).
    progress : callable, optional
        Called once per rendered image.

    Returns
    -------
    matplotlib Figure
    """
    shape = Sphere() if shape is None else shape
    lights = [DistantLight(0.0)] if lights is None else list(lights)
    images = []
    for light in lights:
        row = []
        for s in sigmas:
            row.append(
                render(
                    make_model(s), shape, light, camera, size, samples_per_pixel=samples_per_pixel
                )[0]
            )
            if progress:
                progress()
        images.append(row)
    vmax = max(float(np.max(im)) for row in images for im in row)
    fig, axes = pyplot_subplots(
        len(lights),
        len(sigmas),
        figsize=(2.0 * len(sigmas), 2.1 * len(lights) + 0.4),
        squeeze=False,
    )
    for r, light in enumerate(lights):
        for c, s in enumerate(sigmas):
            show_radiance(axes[r, c], images[r][c], vmax, f"σ = {s:.3g} rad" if r == 0 else "")
        axes[r, 0].set_ylabel(f"light θi = {math.degrees(light.theta):.0f}°")
        radiance_colorbar(axes[r, -1], vmax)  # one scale for every image
    return fig
