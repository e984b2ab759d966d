"""What the explorer's server computes in Python: the vase image and ground truth.

Both depend on other parts of roughdiffuse (:mod:`roughdiffuse.render`,
:mod:`roughdiffuse.simulate`); when a part is missing, :func:`info` says so and the page hides
what needs it. No table of ground truth ships with the package: the server runs the solver for
the plane of incidence on request (about 2 s, cached).
"""

from __future__ import annotations

import functools
import math
import threading
from typing import Any

import numpy as np

from .. import __version__
from .params import model_from_params

__all__ = ["THETA_R_DEG", "Unavailable", "ground_truth", "info", "params_from_query", "vase_png"]


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
        "alpha": _float(q, "alpha", math.sqrt(2.0) * 0.2),
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


def _solver() -> Any:
    """The V-cavity solver's BRDF function, or None when roughdiffuse.simulate is missing."""
    try:
        from ..simulate.surface import brdf
    except ImportError:
        return None
    return brdf


THETA_R_DEG = tuple(float(t) for t in range(-88, 89, 4))
"""Viewing angles of the ground-truth curve (signed: > 0 on the light's side)."""

_SOLVER_LOCK = threading.Lock()  # one solver run at a time: the machine may have 2 cores


@functools.lru_cache(maxsize=64)
def _plane_of_incidence(sigma: float, theta_i_deg: float, albedo: float) -> tuple[float, ...]:
    brdf = _solver()
    tr = np.radians(np.abs(THETA_R_DEG))
    dphi = np.where(np.asarray(THETA_R_DEG) >= 0, 0.0, math.pi)
    with _SOLVER_LOCK:
        f = brdf(math.radians(theta_i_deg), tr, dphi, sigma=sigma, albedo=albedo, bounces="all")
    return tuple(float(v) for v in np.asarray(f))


def info() -> dict[str, Any]:
    """Capabilities of this server, for the page."""
    return {
        "version": __version__,
        "vase": _render_vase() is not None,
        "groundtruth": _solver() is not None,
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
    """V-cavity radiance in the plane of incidence, from the solver (all bounces).

    Query: ``sigma`` (radians, (0, π/2]), ``theta_i`` (degrees, [0, 90)), ``albedo`` ([0, 1]).
    Computed on demand by :func:`roughdiffuse.simulate.surface.brdf` with its default
    settings (about 2 s for the 45 angles; cached), at θr = −88°, −84°, …, 88°.

    Returns
    -------
    dict
        ``theta_r`` (degrees), ``brdf`` (1/sr), ``radiance`` (f E0 cos θi with E0 = π, as on
        the page), the parameters, and a ``note`` for the page.
    """
    if _solver() is None:
        raise Unavailable("the V-cavity solver (roughdiffuse.simulate) is not available")
    sigma = _float(q, "sigma", 0.3)
    theta_i = _float(q, "theta_i", 0.0)
    albedo = _float(q, "albedo", 0.8)
    if not 0.0 < sigma <= math.pi / 2:
        raise ValueError(f"sigma must be in (0, π/2] radians (got {sigma:g})")
    if not 0.0 <= theta_i < 90.0:
        raise ValueError(f"theta_i must be in [0, 90) degrees (got {theta_i:g})")
    if not 0.0 <= albedo <= 1.0:
        raise ValueError(f"albedo must be in [0, 1] (got {albedo:g})")
    # rounded so that small slider moves hit the cache
    sigma, theta_i, albedo = round(sigma, 4), round(theta_i, 1), round(albedo, 3)
    f = _plane_of_incidence(sigma, theta_i, albedo)
    e_cos = math.pi * math.cos(math.radians(theta_i))
    return {
        "theta_r": list(THETA_R_DEG),
        "brdf": list(f),
        "radiance": [v * e_cos for v in f],
        "sigma": sigma,
        "theta_i": theta_i,
        "albedo": albedo,
        "bounces": "all",
        "note": (
            f"V-cavity ground truth (roughdiffuse.simulate, all bounces, default settings): "
            f"σ = {math.degrees(sigma):.1f}°, θi = {theta_i:.1f}°, ρ = {albedo:.3f} "
            "(model A's green albedo)."
        ),
    }
