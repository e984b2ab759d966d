"""What the explorer's server computes in Python: the vase image and ground truth.

Both depend on other parts of roughdiffuse (:mod:`roughdiffuse.render`,
:mod:`roughdiffuse.simulate`); when a part is missing, :func:`info` says so and the page hides
what needs it.
"""

from __future__ import annotations

import math
from typing import Any

from .. import __version__
from .params import model_from_params

__all__ = ["Unavailable", "info", "params_from_query", "vase_png", "ground_truth"]


class Unavailable(Exception):
    """The part of roughdiffuse an endpoint needs is not installed or has no data."""


def _float(q: dict[str, str], key: str, default: float) -> float:
    text = q.get(key)
    if text is None:
        return default
    try:
        v = float(text)
    except ValueError:
        raise ValueError(f"{key} must be a number (got {text!r})") from None
    if not math.isfinite(v):
        raise ValueError(f"{key} must be finite (got {text!r})")
    return v


def params_from_query(q: dict[str, str]) -> dict[str, Any]:
    """Explorer parameters (see :func:`~roughdiffuse.explorer.params.model_from_params`) from
    URL query values; σ in radians."""
    albedo_text = q.get("albedo", "0.8,0.8,0.8")
    try:
        albedo = [float(a) for a in albedo_text.split(",")]
    except ValueError:
        raise ValueError(
            f"albedo must be three comma-separated numbers (got {albedo_text!r})"
        ) from None
    if len(albedo) == 1:
        albedo = albedo * 3
    return {
        "model": q.get("model", "oren-nayar"),
        "albedo": albedo,
        "sigma": _float(q, "sigma", 0.0),
        "roughness": _float(q, "roughness", 0.0),
        "eta": _float(q, "eta", 1.5),
        "weight": _float(q, "weight", 0.0),
        "limb": _float(q, "limb", 0.5),
        "distribution": q.get("distribution", "gaussian"),
    }


def _render_vase() -> Any:
    """The renderer's vase function, or None when the renderer is not available."""
    return None


def _ground_truth_table() -> Any:
    """The V-cavity table shipped with the package, or None."""
    return None


def info() -> dict[str, Any]:
    """Capabilities of this server, for the page."""
    return {
        "version": __version__,
        "vase": _render_vase() is not None,
        "groundtruth": _ground_truth_table() is not None,
    }


def vase_png(q: dict[str, str]) -> bytes:
    """PNG bytes of the vase, rendered with the model the query describes."""
    model = model_from_params(params_from_query(q))
    render = _render_vase()
    if render is None:
        raise Unavailable("the Python renderer (roughdiffuse.render) is not available")
    return bytes(render(model))


def ground_truth(q: dict[str, str]) -> dict[str, Any]:
    """V-cavity radiance in the plane of incidence for the query's σ, θi and albedo."""
    table = _ground_truth_table()
    if table is None:
        raise Unavailable("no V-cavity ground-truth table (roughdiffuse.simulate) is available")
    raise Unavailable("ground-truth lookup is not implemented")
