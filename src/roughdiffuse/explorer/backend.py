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
    """A function (model, query) -> PNG bytes of the vase, or None without the renderer."""
    try:
        from ..render import DistantLight, SurfaceOfRevolution, render
        from ..render.imagefile import linear_to_srgb
    except ImportError:
        return None

    def vase(model: Any, q: dict[str, str]) -> bytes:
        import io

        import numpy as np
        from PIL import Image

        theta = _float(q, "light_theta", 0.0)
        phi = _float(q, "light_phi", 0.0)
        if not 0.0 <= theta <= 180.0:
            raise ValueError(f"light_theta must be in [0, 180] degrees (got {theta:g})")
        exposure = _float(q, "exposure", 0.0)
        if not -10.0 <= exposure <= 10.0:
            raise ValueError(f"exposure must be in [-10, 10] stops (got {exposure:g})")
        size = int(_float(q, "size", 200))
        if not 16 <= size <= 512:
            raise ValueError(f"size must be in [16, 512] pixels (got {size})")
        # E0 = π and 2^exposure, as on the page's sphere (a white Lambert surface facing the
        # light has radiance 1)
        light = DistantLight(math.radians(theta), math.radians(phi), math.pi)
        image, _ = render(model, SurfaceOfRevolution(), light, size=size, samples_per_pixel=4)
        rgb = np.asarray(image, dtype=np.float64) * 2.0**exposure
        if rgb.ndim == 2:
            rgb = np.repeat(rgb[..., None], 3, axis=-1)
        data = np.round(linear_to_srgb(rgb) * 255.0).astype(np.uint8)
        buf = io.BytesIO()
        Image.fromarray(data, "RGB").save(buf, format="PNG")
        return buf.getvalue()

    return vase


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
    """PNG bytes of the vase (Oren and Nayar's Fig. 7 clay vase, :func:`~roughdiffuse.render.
    clay_vase_profile`), rendered by the Python renderer with the model the query describes,
    lit from ``light_theta``, ``light_phi`` (degrees), ``exposure`` in stops."""
    model = model_from_params(params_from_query(q))
    render = _render_vase()
    if render is None:
        raise Unavailable("the Python renderer (roughdiffuse.render) is not available")
    return render(model, q)


def ground_truth(q: dict[str, str]) -> dict[str, Any]:
    """V-cavity radiance in the plane of incidence for the query's σ, θi and albedo."""
    table = _ground_truth_table()
    if table is None:
        raise Unavailable("no V-cavity ground-truth table (roughdiffuse.simulate) is available")
    raise Unavailable("ground-truth lookup is not implemented")
