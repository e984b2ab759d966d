"""Backplanes — incidence, emission and phase per pixel — of a sphere or a triaxial ellipsoid.

An orthographic view of a body (radii a, b, c along its x, y, z axes; z the spin axis) from the
direction of the sub-observer point, lit from the direction of the sub-solar point (planeto-
centric latitude and longitude of the points where the observer and the sun are at the
zenith; both far away). The image's up is the projection of the body's north (+z); where
the observer is over a pole, +x is up. Each pixel's line of sight meets the ellipsoid at
P; its normal n ∝ (x/a², y/b², z/c²) (the ellipsoid's gradient), and

    cos i = n·s,  cos e = n·o,  cos g = s·o

with s, o the unit vectors to the sun and the observer. Pixels off the body are NaN.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError

__all__ = ["Backplanes", "ellipsoid_backplanes"]


@dataclass(frozen=True)
class Backplanes:
    """Per-pixel geometry (radians; NaN off the body)."""

    incidence: np.ndarray
    emission: np.ndarray
    phase: np.ndarray
    latitude: np.ndarray
    longitude: np.ndarray

    @property
    def on_body(self) -> np.ndarray:
        return np.isfinite(self.emission)


def _direction(lat_lon_deg: tuple[float, float], name: str) -> np.ndarray:
    lat, lon = lat_lon_deg
    if not (math.isfinite(lat) and -90.0 <= lat <= 90.0 and math.isfinite(lon)):
        raise ParameterError(f"{name} latitude must be in [-90, 90] degrees (got {lat:g})")
    la, lo = math.radians(lat), math.radians(lon)
    return np.array([math.cos(la) * math.cos(lo), math.cos(la) * math.sin(lo), math.sin(la)])


def ellipsoid_backplanes(
    shape: tuple[int, int],
    subsolar: tuple[float, float],
    subobserver: tuple[float, float],
    radii: tuple[float, float, float] = (1.0, 1.0, 1.0),
    margin: float = 0.05,
    window: tuple[slice, slice] | None = None,
) -> Backplanes:
    """Backplanes of an ellipsoid seen orthographically (see the module).

    Parameters
    ----------
    shape : (H, W)
        Image size in pixels.
    subsolar, subobserver : (latitude, longitude)
        Planetocentric, in degrees.
    radii : (a, b, c)
        Semi-axes (any unit; only ratios matter); (1, 1, 1) is a sphere.
    margin : float
        Empty border, as a fraction of the half-width, around the body's largest radius.
    window : (rows, cols) slices, optional
        Only these lines and samples of the image (the same values as the whole image's
        there): a chunk of a large image.

    Examples
    --------
    Full phase (sun behind the observer): i = e everywhere, g = 0.

    >>> bp = ellipsoid_backplanes((5, 5), (0.0, 0.0), (0.0, 0.0))
    >>> bool(np.allclose(bp.incidence[bp.on_body], bp.emission[bp.on_body]))
    True
    """
    h, w = (int(n) for n in shape)
    if h < 1 or w < 1:
        raise ParameterError(f"shape must be positive (got {shape})")
    r = np.asarray(radii, dtype=np.float64)
    if r.shape != (3,) or not np.all(np.isfinite(r) & (r > 0)):
        raise ParameterError(f"radii must be three positive numbers (got {radii})")
    s, o = _direction(subsolar, "sub-solar"), _direction(subobserver, "sub-observer")
    up = np.array([0.0, 0.0, 1.0]) if abs(o[2]) < 1.0 - 1e-12 else np.array([1.0, 0.0, 0.0])
    y_img = up - (up @ o) * o
    y_img /= np.linalg.norm(y_img)
    x_img = np.cross(y_img, o)  # east to the right
    half = float(r.max()) * (1.0 + margin)
    scale = 2.0 * half / min(h, w)
    rsel, csel = window if window is not None else (slice(0, h), slice(0, w))
    cols = (np.arange(w)[csel] - (w - 1) / 2.0) * scale
    rows = ((h - 1) / 2.0 - np.arange(h)[rsel]) * scale
    u, v = np.meshgrid(cols, rows)
    p0 = u[..., None] * x_img + v[..., None] * y_img + 4.0 * half * o
    dp0, do = p0 / r, o / r
    a = float(do @ do)
    b = dp0 @ do
    c = np.einsum("...k,...k", dp0, dp0) - 1.0
    disc = b * b - a * c
    hit = disc > 0
    t = np.where(hit, (b - np.sqrt(np.where(hit, disc, 0.0))) / a, np.nan)
    p = p0 - t[..., None] * o
    n = p / (r * r)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    cos_i, cos_e = n @ s, n @ o
    inc = np.arccos(np.clip(cos_i, -1.0, 1.0))
    ema = np.arccos(np.clip(cos_e, -1.0, 1.0))
    pha = np.where(hit, math.acos(float(np.clip(s @ o, -1.0, 1.0))), np.nan)
    lat = np.arcsin(np.clip(p[..., 2] / np.linalg.norm(p, axis=-1), -1.0, 1.0))
    lon = np.arctan2(p[..., 1], p[..., 0])
    return Backplanes(inc, ema, pha, lat, lon)
