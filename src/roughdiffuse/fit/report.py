"""Plots and an HTML report of a fit: data against model, residuals, the fit table.

The plane-of-incidence plot (:func:`plot_plane_fit`) shows the samples whose light and view
directions lie (within about 18°) in one plane with the normal (Δφ = 0: the light's side,
signed θr > 0; Δφ = π: the mirror side, θr < 0), grouped by θi: each group's data as dots and
the fitted model as a curve at that group's θi along the whole θr range, in the same colour.
The data-against-model scatter gives each of the best few models its own panel. For image
data the residual image (data − model)/model is shown in the image's own frame.
"""

from __future__ import annotations

import base64
import html
import io
import math
import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..io.atomic import check_output_path, write_text
from .compare import Comparison, fitted_row
from .least_squares import FitResult
from .measurements import Measurements
from .summary import row_name

__all__ = ["model_heading", "plot_fit", "plot_plane_fit", "residual_image", "write_report"]

MAX_POINTS = 6000
MAX_GROUPS = 10
"""At most this many θi groups in the plane-of-incidence plot (bands when θi varies more)."""
MAX_PANELS = 3
"""At most this many models (the best) get a data-against-model panel."""


def _channel(a: np.ndarray) -> np.ndarray:
    return a if a.ndim == 1 else a.mean(axis=-1)


def model_heading(result: FitResult) -> str:
    """``"oren-nayar-full (Oren–Nayar full)"``: the registry id and label of a fitted model,
    its ranking row's name for a model ranked per choice (``"coated base=eon (Coated: …)"``,
    :func:`~roughdiffuse.fit.summary.row_name`); its class name when the registry does not
    describe it."""
    from .. import registry

    row = fitted_row(result.model)
    if row is None:
        return result.model_name or type(result.model).__name__
    label = registry.get(row[0]).label
    name = row_name(*row)
    return name if label == row[0] else f"{name} ({label})"


def residual_image(data: Measurements, result: FitResult) -> np.ndarray:
    """(H, W) relative residual (data − model)/model (channel mean), NaN off the samples."""
    if data.image_shape is None or data.pixels is None:
        raise ParameterError("residual_image needs image data (Measurements.from_image)")
    assert result.predict is not None
    model = _channel(result.predict(data))
    val = _channel(data.value)
    out = np.full(data.image_shape[0] * data.image_shape[1], np.nan)
    out[data.pixels] = np.where(model > 0, (val - model) / np.where(model > 0, model, 1.0), 0.0)
    return out.reshape(data.image_shape)


def _theta_groups(theta_i_deg: np.ndarray) -> list[tuple[np.ndarray, float, str]]:
    """(mask, θi of the model curve in degrees, legend label) per group of samples: one group
    per distinct θi (to 0.5°), or up to MAX_GROUPS bands of equal counts when there are more."""
    key = np.round(theta_i_deg * 2.0) / 2.0
    values = np.unique(key)
    if values.size <= MAX_GROUPS:
        return [(key == v, float(v), f"θi = {v:g}°") for v in values]
    edges = np.unique(np.quantile(theta_i_deg, np.linspace(0.0, 1.0, MAX_GROUPS + 1)))
    out = []
    for k, (lo, hi) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        m = (theta_i_deg >= lo) & ((theta_i_deg < hi) if k < edges.size - 2 else True)
        if np.any(m):
            mid = float(np.median(theta_i_deg[m]))
            out.append((m, mid, f"θi {lo:.0f}–{hi:.0f}° (curve {mid:.0f}°)"))
    return out


def plot_plane_fit(data: Measurements, result: FitResult, ax: Any = None) -> Any:
    """Data near the plane of incidence against the fitted model, grouped by θi.

    Each group's samples are dots; the model is a curve at the group's θi over signed
    θr ∈ [−89.5°, 89.5°] (> 0 on the light's side), in the group's colour.

    Parameters
    ----------
    data : Measurements
    result : FitResult
        The fit whose ``model`` is drawn.
    ax : matplotlib Axes, optional
        Drawn on; default a new figure made through ``matplotlib.pyplot``.

    Returns
    -------
    matplotlib Axes
    """
    from .._figure import colormap, pyplot_subplots

    if ax is None:
        _, ax = pyplot_subplots(figsize=(6.0, 4.2), layout="constrained")
    rng = np.random.default_rng(0)
    ti, tr, dp = data.angles()
    in_plane = (np.abs(np.cos(dp)) > 0.95) | (np.sin(tr) < 0.05) | (np.sin(ti) < 0.05)
    idx = np.flatnonzero(in_plane)
    if idx.size > MAX_POINTS:
        idx = np.sort(rng.choice(idx, MAX_POINTS, replace=False))
    if idx.size == 0:
        ax.text(0.5, 0.5, "no samples near the plane of incidence", ha="center",
                transform=ax.transAxes)
        ax.set_axis_off()
        return ax
    sub = data.subset(idx)
    ti, tr, dp = ti[idx], tr[idx], dp[idx]
    x = np.degrees(np.where(np.cos(dp) >= 0, tr, -tr))
    f_data = _channel(sub.brdf_value)
    groups = _theta_groups(np.degrees(ti))
    cmap = colormap("viridis")
    curve_tr = np.radians(np.linspace(-89.5, 89.5, 359))
    wo = np.stack([np.sin(curve_tr), np.zeros_like(curve_tr), np.cos(curve_tr)], axis=-1)
    for k, (m, theta_deg, label) in enumerate(groups):
        color = cmap(0.9 * k / max(len(groups) - 1, 1))
        ax.plot(x[m], f_data[m], "o", ms=3, color=color, alpha=0.7, label=label)
        t = math.radians(theta_deg)
        wi = np.array([math.sin(t), 0.0, math.cos(t)])
        curve = np.asarray(result.model.brdf(wi, wo), dtype=np.float64)
        ax.plot(np.degrees(curve_tr), _channel(curve), "-", lw=1.3, color=color)
    ax.set_xlabel("signed viewing angle θr (degrees; < 0: mirror side, Δφ = 180°)")
    ax.set_ylabel("BRDF (1/sr)")
    ax.set_xlim(-90, 90)
    ax.set_title(f"plane of incidence: data (dots) and {model_heading(result)} (curves)",
                 fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), title="θi",
              title_fontsize=7)
    return ax


def _scatter(ax: Any, model: np.ndarray, data: np.ndarray, result: FitResult) -> None:
    top = float(max(np.max(data), np.max(model))) * 1.05
    ax.plot(model, data, ".", ms=3, alpha=0.5, color="tab:blue")
    ax.plot([0, top], [0, top], "k-", lw=0.8)
    ax.set_xlim(0, top)
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    ax.set_xlabel("model BRDF (1/sr)")
    ax.set_ylabel("data BRDF (1/sr)")
    ax.set_title(f"{model_heading(result)}\nRMS {100 * result.rms_relative:.2g} % of the data",
                 fontsize=8)
    ax.grid(alpha=0.3)


def plot_fit(data: Measurements, results: Sequence[FitResult], fig: Any = None) -> Any:
    """A matplotlib Figure: the plane of incidence (:func:`plot_plane_fit`) of the first
    result, the residual image (image data), and data against model for each of the best
    ``MAX_PANELS`` results in its own panel.

    ``fig``: drawn on (default: a new ``matplotlib.figure.Figure``, not known to pyplot).
    """
    from .._figure import figure

    best = list(results[:MAX_PANELS])
    has_image = data.image_shape is not None
    if fig is None:
        fig = figure(figsize=(11.0, 8.4), layout="constrained")
    top, bottom = fig.subfigures(2, 1, height_ratios=[1.1, 1.0])
    upper = top.subplots(1, 2 if has_image else 1, squeeze=False)[0]
    plot_plane_fit(data, results[0], ax=upper[0])
    if has_image:
        ax = upper[1]
        res = residual_image(data, results[0])
        lim = float(np.nanpercentile(np.abs(res), 99)) if np.any(np.isfinite(res)) else 1.0
        im = ax.imshow(res, cmap="RdBu_r", vmin=-lim, vmax=lim)
        top.colorbar(im, ax=ax, shrink=0.8, label="(data − model)/model")
        ax.set_title(f"residual image, {model_heading(results[0])}", fontsize=9)
        ax.set_xlabel("pixel column")
        ax.set_ylabel("pixel row")

    rng = np.random.default_rng(0)
    pick = np.arange(data.size)
    if pick.size > MAX_POINTS:
        pick = np.sort(rng.choice(pick, MAX_POINTS, replace=False))
    sub = data.subset(pick)
    f_data = _channel(sub.brdf_value)
    scale = sub.scale
    axes = bottom.subplots(1, len(best), squeeze=False)[0]
    for ax, r in zip(axes, best, strict=True):
        assert r.predict is not None
        p = _channel(r.predict(sub))
        p = np.where(scale > 0, p / np.where(scale > 0, scale, 1.0), 0.0)
        _scatter(ax, p, f_data, r)
    if len(results) > len(best):
        bottom.suptitle(f"every sample, data against model: the best {len(best)} of "
                        f"{len(results)} models (ranking in the table)", fontsize=9)
    else:
        bottom.suptitle("every sample, data against model", fontsize=9)
    return fig


def _fig_png(fig: Any) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _result_table(r: FitResult) -> str:
    flagged = bool(np.any(r.on_bound)) or not bool(np.all(np.isfinite(r.errors)))
    rows = []
    for k, name in enumerate(r.names):
        err = r.errors[k]
        err_s = f"{err:.3g}" if math.isfinite(err) and not r.on_bound[k] else "not determined"
        extra = f" ({math.degrees(r.values[k]):.2f}°)" if name.startswith("sigma") else ""
        note = ("stopped at its bound" if r.on_bound[k]
                else "" if math.isfinite(err) else "not identifiable from these data")
        rows.append(
            f"<tr><td>{html.escape(name)}</td><td>{r.values[k]:.6g}{extra}</td>"
            f"<td>{err_s}</td>" + (f"<td>{note}</td>" if flagged else "") + "</tr>"
        )
    notes = "".join(f"<li>{html.escape(w)}</li>" for w in r.warnings)
    return (
        f"<h2>{html.escape(model_heading(r))}</h2>"
        f"<p>{r.n_samples} values; RMS residual {r.rms:.4g} ({100 * r.rms_relative:.3g}% of "
        f"the data); AIC {r.aic:.1f}; BIC {r.bic:.1f}</p>"
        "<table><tr><th>parameter</th><th>value</th><th>std. error (1σ)</th>"
        + ("<th>note</th>" if flagged else "") + "</tr>"
        + "".join(rows)
        + "</table>"
        + (f"<ul class=warn>{notes}</ul>" if notes else "")
    )


def _ranking_table(comparison: Comparison) -> str:
    """The ranking of :meth:`Comparison.table` as an HTML table."""
    b0 = comparison.results[0].bic
    a0 = min(r.aic for r in comparison.results)
    rows = []
    for k, r in enumerate(comparison.results, start=1):
        params = ", ".join(
            f"{p} = {v:.4g} ± {e:.2g}" if math.isfinite(e) and not b else f"{p} = {v:.4g}"
            + (" (at bound)" if b else " (not determined)")
            for p, v, e, b in zip(r.names, r.values, r.errors, r.on_bound, strict=True)
        )
        rows.append(
            f"<tr><td>{k}</td><td>{html.escape(model_heading(r))}</td>"
            f"<td class=num>{r.rms:.4g}</td><td class=num>{100 * r.rms_relative:.3g}</td>"
            f"<td class=num>{r.aic - a0:.1f}</td><td class=num>{r.bic - b0:.1f}</td>"
            f"<td>{html.escape(params)}</td></tr>"
        )
    return (
        "<h2>Models ranked by BIC (lower is better)</h2>"
        "<table class=ranking><tr><th>rank</th><th>model</th><th>RMS (1/sr)</th>"
        "<th>RMS %</th><th>ΔAIC</th><th>ΔBIC</th><th>parameters</th></tr>"
        + "".join(rows) + "</table>"
    )


def write_report(
    path: str | os.PathLike[str],
    data: Measurements,
    results: Sequence[FitResult],
    comparison: Comparison | None = None,
) -> None:
    """Write a self-contained HTML report (tables and embedded PNG plot), atomically."""
    if not results:
        raise ParameterError("write_report needs at least one fit result")
    path = check_output_path(path, "report")
    fig = plot_fit(data, results)
    png = _fig_png(fig)
    chans = f", {data.channels} channels" if data.channels else ""
    img = f", image {data.image_shape[0]} × {data.image_shape[1]}" if data.image_shape else ""
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'><title>roughdiffuse fit</title>",
        "<style>body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em}"
        "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #ccc;"
        "padding:3px 8px;text-align:left}td.num{text-align:right}"
        ".warn{color:#a40}img{max-width:100%}</style></head><body>",
        f"<h1>Fit of {html.escape(data.source or 'data')}</h1>",
        f"<p>{data.size} samples ({data.kind}{chans}{img}).</p>",
    ]
    if comparison is not None:
        parts.append(_ranking_table(comparison))
    parts.extend(_result_table(r) for r in results[: (MAX_PANELS if comparison else None)])
    parts.append(f"<h2>Data and model</h2><img alt='fit plots' src='data:image/png;base64,{png}'>")
    parts.append("</body></html>")
    write_text(path, "\n".join(parts))
