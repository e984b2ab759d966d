"""Plots and an HTML report of a fit: data against model, residuals, the fit table.

The plane-of-incidence plot shows the samples whose light and view directions lie (within
about 18°) in one plane with the normal (Δφ = 0: backward side, signed θr > 0; Δφ = π:
forward side, θr < 0), the data as dots and the fitted model at the same geometry as lines
per θi band. For image data the residual image (data − model)/model is shown in the image's
own frame.
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
from .compare import Comparison
from .least_squares import FitResult
from .measurements import Measurements

__all__ = ["plot_fit", "residual_image", "write_report"]

MAX_POINTS = 6000


def _channel(a: np.ndarray) -> np.ndarray:
    return a if a.ndim == 1 else a.mean(axis=-1)


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


def plot_fit(data: Measurements, results: Sequence[FitResult]) -> Any:
    """A matplotlib Figure: plane of incidence, data vs model, residual image (images)."""
    from matplotlib.figure import Figure

    panels = 3 if data.image_shape is not None else 2
    fig = Figure(figsize=(5.2 * panels, 4.4), layout="constrained")
    axes = fig.subplots(1, panels)
    rng = np.random.default_rng(0)
    sel = np.arange(data.size)
    if data.size > 4 * MAX_POINTS:
        sel = np.sort(rng.choice(data.size, 4 * MAX_POINTS, replace=False))
    sub = data.subset(sel)
    ti, tr, dp = sub.angles()
    f_data = _channel(sub.brdf_value)
    preds = []
    for r in results:
        assert r.predict is not None
        p = _channel(r.predict(sub))
        s = sub.scale
        preds.append(np.where(s > 0, p / np.where(s > 0, s, 1.0), 0.0))

    ax = axes[0]
    in_plane = (np.abs(np.cos(dp)) > 0.95) | (np.sin(tr) < 0.05) | (np.sin(ti) < 0.05)
    idx = np.flatnonzero(in_plane)
    if idx.size > MAX_POINTS:
        idx = np.sort(rng.choice(idx, MAX_POINTS, replace=False))
    x = np.degrees(np.where(np.cos(dp) >= 0, tr, -tr))[idx]
    bands = np.linspace(0, 90, 7)
    cmap = __import__("matplotlib").colormaps["viridis"]
    for b in range(len(bands) - 1):
        m = (np.degrees(ti[idx]) >= bands[b]) & (np.degrees(ti[idx]) < bands[b + 1])
        if not np.any(m):
            continue
        color = cmap(b / (len(bands) - 2))
        order = np.argsort(x[m])
        ax.plot(
            x[m],
            f_data[idx][m],
            ".",
            ms=3,
            color=color,
            alpha=0.6,
            label=f"θi {bands[b]:.0f}–{bands[b + 1]:.0f}°",
        )
        xs, ys = x[m][order], preds[0][idx][m][order]
        gap = np.flatnonzero(np.diff(xs) > 3.0) + 1  # do not join separate runs
        ax.plot(np.insert(xs, gap, np.nan), np.insert(ys, gap, np.nan), "-", lw=1.0, color=color)
    ax.set_xlabel("signed θr (degrees; < 0: forward side, Δφ = π)")
    ax.set_ylabel("BRDF (1/sr)")
    ax.set_title(f"plane of incidence: data (dots), {results[0].model_name} (lines)", fontsize=9)
    if idx.size:
        ax.legend(fontsize=7)
    else:
        ax.text(
            0.5, 0.5, "no samples near the plane of incidence", ha="center", transform=ax.transAxes
        )

    ax = axes[1]
    pick = np.arange(sub.size)
    if pick.size > MAX_POINTS:
        pick = np.sort(rng.choice(pick, MAX_POINTS, replace=False))
    top = float(max(np.max(f_data[pick]), max(np.max(p[pick]) for p in preds))) * 1.05
    for r, p in zip(results, preds, strict=True):
        ax.plot(
            p[pick],
            f_data[pick],
            ".",
            ms=2,
            alpha=0.5,
            label=f"{r.model_name} (RMS {100 * r.rms_relative:.2g}%)",
        )
    ax.plot([0, top], [0, top], "k-", lw=0.8)
    ax.set_xlabel("model BRDF (1/sr)")
    ax.set_ylabel("data BRDF (1/sr)")
    ax.set_title("every sample: data against model", fontsize=9)
    ax.legend(fontsize=7)

    if panels == 3:
        ax = axes[2]
        res = residual_image(data, results[0])
        lim = float(np.nanpercentile(np.abs(res), 99)) if np.any(np.isfinite(res)) else 1.0
        im = ax.imshow(res, cmap="RdBu_r", vmin=-lim, vmax=lim)
        fig.colorbar(im, ax=ax, shrink=0.8, label="(data − model)/model")
        ax.set_title(f"residual image, {results[0].model_name}", fontsize=9)
        ax.set_axis_off()
    return fig


def _fig_png(fig: Any) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def _result_table(r: FitResult) -> str:
    rows = []
    for k, name in enumerate(r.names):
        err = r.errors[k]
        err_s = f"{err:.3g}" if math.isfinite(err) else "∞ (not identifiable)"
        extra = f" ({math.degrees(r.values[k]):.2f}°)" if name.startswith("sigma") else ""
        flag = "on bound" if r.on_bound[k] else ""
        rows.append(
            f"<tr><td>{html.escape(name)}</td><td>{r.values[k]:.6g}{extra}</td>"
            f"<td>{err_s}</td><td>{flag}</td></tr>"
        )
    notes = "".join(f"<li>{html.escape(w)}</li>" for w in r.warnings)
    return (
        f"<h2>{html.escape(r.model_name)}</h2>"
        f"<p>{r.n_samples} values; RMS residual {r.rms:.4g} ({100 * r.rms_relative:.3g}% of "
        f"the data); AIC {r.aic:.1f}; BIC {r.bic:.1f}</p>"
        "<table><tr><th>parameter</th><th>value</th><th>std. error (1σ)</th><th></th></tr>"
        + "".join(rows)
        + "</table>"
        + (f"<ul class=warn>{notes}</ul>" if notes else "")
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
        "<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto}"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 8px}"
        ".warn{color:#a40}pre{background:#f6f6f6;padding:8px}</style></head><body>",
        f"<h1>Fit of {html.escape(data.source or 'data')}</h1>",
        f"<p>{data.size} samples ({data.kind}{chans}{img}).</p>",
    ]
    if comparison is not None:
        parts.append(
            "<h2>Models ranked by BIC</h2><pre>" + html.escape(comparison.table()) + "</pre>"
        )
    parts.extend(_result_table(r) for r in results)
    parts.append(f"<h2>Data and model</h2><img alt='fit plots' src='data:image/png;base64,{png}'>")
    parts.append("</body></html>")
    write_text(path, "\n".join(parts))
