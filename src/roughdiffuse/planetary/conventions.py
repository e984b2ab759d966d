"""Planetary photometry's units and angles, and their conversion to roughdiffuse's.

Units (Hapke, *Theory of Reflectance and Emittance Spectroscopy*, 2nd ed., 2012, Ch. 10),
for a surface lit from incidence angle i (μ0 = cos i) and seen at emission angle e:

========  ====================================================  =====================
``brdf``  the BRDF f (1/sr), roughdiffuse's unit                 f
``r``     bidirectional reflectance r = radiance / (collimated   r = f μ0 (Eq. 10.6)
          irradiance on a plane facing the source) (1/sr)
``iof``   radiance factor I/F (RADF): brightness relative to a   I/F = π r = π f μ0
          white Lambertian surface lit and seen normally          (Eq. 10.5)
``reff``  reflectance factor REFF: relative to a white           REFF = π f = I/F / μ0
          Lambertian surface in the same geometry                 (Eq. 10.9)
========  ====================================================  =====================

Angles: planetary software describes a geometry by (i, e, g), g the phase angle between the
directions to the sun and to the observer; roughdiffuse by (θi, θr, Δφ) in the surface's
frame, with cos g = wi·wo = cos θi cos θr + sin θi sin θr cos Δφ (spherical law of cosines;
Δφ = 0 puts sun and observer on the same side: g = |i − e|). θi = i, θr = e, and

    cos Δφ = (cos g − cos i cos e)/(sin i sin e),

undefined where sin i sin e = 0 (sun or observer at the zenith: then g = e or g = i and Δφ
does not matter; it is set to 0). A (i, e, g) with g outside [|i − e|, i + e] is no geometry;
:func:`photometric_to_local` refuses it beyond a tolerance of rounding (1e-9 rad) and clips
within it. Python takes radians; the command line takes degrees.

This module is a leaf (NumPy only).
"""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np

__all__ = [
    "UNITS",
    "check_angle",
    "convert",
    "local_to_photometric",
    "photometric_to_local",
]

Unit = Literal["brdf", "r", "iof", "reff"]
UNITS: tuple[str, ...] = ("brdf", "r", "iof", "reff")
"""The reflectance units :func:`convert` knows (see the module's table)."""

_GEOMETRY_TOL = 1e-9  # radians: g this far outside [|i − e|, i + e] is rounding


def check_angle(name: str, value: Any, hi: float = math.pi) -> np.ndarray:
    """``value`` as a float64 array in [0, ``hi``] radians, else ``ValueError`` naming it.

    >>> check_angle("phase", 4.0)
    Traceback (most recent call last):
    ...
    ValueError: phase must be in [0, π] radians = [0°, 180°] (got 4 rad = 229.183°)
    """
    a = np.asarray(value, dtype=np.float64)
    bad = ~np.isfinite(a) | (a < 0.0) | (a > hi)
    if np.any(bad):
        shown = float(a[bad].flat[0]) if a.ndim else float(a)
        top = "π/2" if hi == math.pi / 2 else "π" if hi == math.pi else f"{hi:g}"
        raise ValueError(
            f"{name} must be in [0, {top}] radians = [0°, {math.degrees(hi):g}°] "
            f"(got {shown:g} rad = {math.degrees(shown):g}°)"
        )
    return a


def _factor(unit: str, mu0: np.ndarray) -> np.ndarray | float:
    """value = f × factor for each unit."""
    if unit == "brdf":
        return 1.0
    if unit == "r":
        return mu0
    if unit == "iof":
        return math.pi * mu0
    if unit == "reff":
        return math.pi
    raise ValueError(f"unit must be one of {', '.join(UNITS)} (got {unit!r})")


def convert(value: Any, unit_from: Unit, unit_to: Unit, incidence: Any = 0.0) -> np.ndarray:
    """Convert reflectance values between ``brdf``, ``r``, ``iof`` and ``reff``.

    Parameters
    ----------
    value : array_like
        The values, in ``unit_from``.
    unit_from, unit_to : {"brdf", "r", "iof", "reff"}
        See the module's table.
    incidence : array_like
        The incidence angle i (radians, [0, π/2]) of each value; needed between units that
        differ by μ0. Converting *to* ``brdf`` or ``reff`` from ``r`` or ``iof`` at i = 90°
        (no light) gives NaN.

    Examples
    --------
    A white Lambertian surface (f = 1/π) lit at i = 60°: I/F = cos 60° = 0.5, REFF = 1.

    >>> round(float(convert(1 / math.pi, "brdf", "iof", math.radians(60.0))), 12)
    0.5
    >>> round(float(convert(0.5, "iof", "reff", math.radians(60.0))), 12)
    1.0
    """
    mu0 = np.cos(check_angle("incidence", incidence, math.pi / 2))
    f_from, f_to = _factor(unit_from, mu0), _factor(unit_to, mu0)
    v = np.asarray(value, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        f = v / f_from
        f = np.where(np.broadcast_to(np.asarray(f_from), np.shape(f)) > 1e-15, f, np.nan)
    return f * f_to


def photometric_to_local(
    incidence: Any, emission: Any, phase: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(θi, θr, Δφ) from the photometric angles (i, e, g), radians.

    Parameters
    ----------
    incidence, emission : array_like
        i and e in [0, π/2] (0 at the zenith).
    phase : array_like
        g in [0, π], within [|i − e|, i + e] (up to 1e-9 rad of rounding).

    Examples
    --------
    >>> ti, tr, dphi = photometric_to_local(*np.radians([30.0, 40.0, 70.0]))
    >>> round(float(np.degrees(dphi)), 6)  # sun and observer on opposite sides
    180.0
    """
    i = check_angle("incidence", incidence, math.pi / 2)
    e = check_angle("emission", emission, math.pi / 2)
    g = check_angle("phase", phase)
    i, e, g = np.broadcast_arrays(i, e, g)
    bad = (g < np.abs(i - e) - _GEOMETRY_TOL) | (g > i + e + _GEOMETRY_TOL)
    if np.any(bad):
        k = np.flatnonzero(bad.ravel())[0]
        gi, ii, ei = (math.degrees(float(a.ravel()[k])) for a in (g, i, e))
        raise ValueError(
            f"phase must be in [|incidence − emission|, incidence + emission] "
            f"(got phase {gi:g}° with incidence {ii:g}°, emission {ei:g}°)"
        )
    s = np.sin(i) * np.sin(e)
    num = np.cos(g) - np.cos(i) * np.cos(e)
    cos_dphi = np.divide(num, s, out=np.ones_like(s), where=s > 1e-15)
    return i.copy(), e.copy(), np.arccos(np.clip(cos_dphi, -1.0, 1.0))


def local_to_photometric(
    theta_i: Any, theta_r: Any, delta_phi: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(i, e, g) from (θi, θr, Δφ), radians: cos g = cos θi cos θr + sin θi sin θr cos Δφ.

    >>> i, e, g = local_to_photometric(*np.radians([30.0, 40.0, 0.0]))
    >>> round(float(np.degrees(g)), 6)  # same side: g = |i − e|
    10.0
    """
    ti = check_angle("theta_i", theta_i, math.pi / 2)
    tr = check_angle("theta_r", theta_r, math.pi / 2)
    dp = np.asarray(delta_phi, dtype=np.float64)
    if not np.all(np.isfinite(dp)):
        raise ValueError("delta_phi must be finite")
    ti, tr, dp = np.broadcast_arrays(ti, tr, dp)
    cos_g = np.cos(ti) * np.cos(tr) + np.sin(ti) * np.sin(tr) * np.cos(dp)
    return ti.copy(), tr.copy(), np.arccos(np.clip(cos_g, -1.0, 1.0))
