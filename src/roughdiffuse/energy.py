"""Energy and sampling reports: white-furnace albedo tables and plots, sample-weight variance.

White furnace: with facet albedo ρ = 1 a surface that loses no energy reflects all of it,
so its directional albedo ∫ f cos θi dωi is 1 at every viewing angle θr. The qualitative
Oren–Nayar model and Fujii's model keep only single scattering and fall below 1 as σ (or r)
grows; EON adds the multiple-scattering lobe and stays at 1 (Portsmouth, Kutz, Hill, JCGT
2025, arXiv 2410.18026, Fig. 3). The full Oren–Nayar model's interreflection term L2 is a
fit, not a conservation law: it can go above or below 1.

Sampling: the weight f cos θi / pdf of a sampled direction has mean equal to the directional
albedo whatever the strategy; its variance measures the strategy (0 for a perfect sampler).
:func:`variance_table` compares each model's own strategy with cosine sampling.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ._validate import ParameterError
from .deprecation import renamed_parameter
from .frames import spherical_to_vector
from .io.atomic import write_text
from .models import Model
from .models.sampling import COSINE, strategy_for, weight_variance

__all__ = ["albedo_curves", "plot_albedo", "variance_table", "write_albedo_csv"]


@renamed_parameter("theta_o", "theta_r", since="0.2")
def albedo_curves(
    models: Mapping[str, Model], theta_r: Sequence[float], progress: bool = False
) -> dict[str, np.ndarray]:
    """Directional albedo of each model at viewing angles ``theta_r`` (radians).

    Colour models give channel 0. Returns label -> array of len(theta_r). ``progress`` shows
    a tqdm bar of the models on stderr (on a terminal only): a model without a closed-form
    albedo (e.g. ``smith-diffuse-*`` at large α) can take minutes.
    """
    from tqdm.auto import tqdm

    th = np.asarray(theta_r, dtype=np.float64)
    if th.ndim != 1 or np.any(~np.isfinite(th)) or np.any(th < 0) or np.any(th > math.pi / 2):
        raise ParameterError("theta_r must be a 1-D array of angles in [0, π/2] radians")
    wo = spherical_to_vector(th, 0.0)
    out = {}
    items = tqdm(
        models.items(), desc="albedo", unit="curve", disable=None if progress else True
    )
    for label, model in items:
        a = np.asarray(model.directional_albedo(wo), dtype=np.float64)
        out[label] = a[..., 0] if a.ndim == 2 else a
    return out


@renamed_parameter("theta_o", "theta_r", since="0.2")
def write_albedo_csv(path: Any, theta_r: Sequence[float], curves: Mapping[str, np.ndarray]) -> None:
    """Write the table: one row per θr (degrees), one column per curve (atomically)."""
    labels = list(curves)
    rows = ["theta_r_deg," + ",".join(f'"{label}"' for label in labels)]
    for i, t in enumerate(theta_r):
        vals = ",".join(f"{curves[label][i]:.7f}" for label in labels)
        rows.append(f"{math.degrees(t):.4f},{vals}")
    write_text(path, "\n".join(rows) + "\n")


@renamed_parameter("theta_o", "theta_r", since="0.2")
def plot_albedo(
    groups: Mapping[str, Mapping[str, Model]],
    theta_r: Sequence[float] | None = None,
    fig: Any = None,
    curves: Mapping[str, Mapping[str, np.ndarray]] | None = None,
) -> Any:
    """White-furnace plot: one panel per model family, one curve per roughness.

    Parameters
    ----------
    groups : {title: {curve label: model}}
        Models of each panel (ρ should be 1 for a white-furnace test).
    theta_r : angles in radians, default 0 to 89.5° every 0.5°.
    fig : matplotlib Figure, optional
        Drawn on; default a new figure made through ``matplotlib.pyplot`` (so ``plt.show()``
        shows it).
    curves : {title: {curve label: albedo array}}, optional
        The :func:`albedo_curves` of each panel at ``theta_r``, if already computed.

    Returns
    -------
    matplotlib Figure
    """
    from ._figure import colormap, pyplot_figure

    th = np.radians(np.arange(0.0, 89.75, 0.5)) if theta_r is None else np.asarray(theta_r)
    n = len(groups)
    ncols = n if n <= 3 else (2 if n == 4 else 3)
    nrows = -(-n // ncols)
    if fig is None:
        fig = pyplot_figure(figsize=(3.8 * ncols + 0.6, 3.3 * nrows + 0.5))
    axes = fig.subplots(nrows, ncols, sharey=True, squeeze=False).ravel()
    for ax in axes[n:]:
        ax.set_visible(False)
    lo = 1.0
    hi = 1.0
    for ax, (title, models) in zip(axes[:n], groups.items(), strict=True):
        panel = albedo_curves(models, th) if curves is None else curves[title]
        colors = colormap("viridis")(np.linspace(0.0, 0.9, max(len(panel), 1)))
        for color, (label, a) in zip(colors, panel.items(), strict=True):
            ax.plot(np.degrees(th), a, color=color, label=label)
            lo, hi = min(lo, float(a.min())), max(hi, float(a.max()))
        ax.axhline(1.0, color="0.5", lw=0.8, ls="--")
        ax.set_title(title, fontsize="medium")
        ax.set_xlabel("viewing angle θr (degrees)")
        ax.set_xlim(0, 90)
        ax.legend(fontsize="small", loc="lower left")
    for ax in axes[::ncols]:
        ax.set_ylabel("directional albedo")
    pad = 0.05 * (hi - lo + 1e-3)
    axes[0].set_ylim(lo - pad, hi + pad)
    fig.suptitle("white furnace: ∫ f cos θi dωi (1 = no energy lost)")
    fig.tight_layout()
    return fig


@renamed_parameter("theta_o_deg", "theta_r_deg", since="0.2")
def variance_table(
    models: Mapping[str, Model],
    theta_r_deg: Sequence[float] = (0.0, 45.0, 80.0),
    n: int = 100_000,
) -> str:
    """Markdown table of the sample-weight variance: the model's strategy vs cosine sampling.

    Each cell is ``variance (cosine variance)``; the mean weight (= albedo) is checked to
    agree between the two strategies within 5 standard errors.
    """
    head = "| model | strategy | " + " | ".join(f"θr = {t:g}°" for t in theta_r_deg) + " |"
    rows = [head, "|" + " --- |" * (2 + len(theta_r_deg))]
    for label, model in models.items():
        strategy = strategy_for(model)
        cells = []
        for t in theta_r_deg:
            m1, v1 = weight_variance(model, math.radians(t), n)
            m2, v2 = weight_variance(model, math.radians(t), n, strategy=COSINE, seed=1)
            err = 5.0 * math.sqrt((v1 + v2) / n) + 1e-9
            flag = "" if abs(m1 - m2) <= err else " (means differ!)"
            cells.append(f"{v1:.3g} ({v2:.3g}){flag}")
        rows.append(f"| {label} | {strategy.name} | " + " | ".join(cells) + " |")
    return "\n".join(rows)
