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

The angle conversions are defined in :mod:`roughdiffuse.frames` and re-exported here.
"""

from __future__ import annotations

import math
from typing import Any, Literal

import numpy as np

from .._validate import ParameterError

__all__ = [
    "UNITS",
    "check_angle",
    "convert",
    "local_to_photometric",
    "photometric_to_local",
]

# the angle conversions live with the other frames (a leaf the models use)
from ..frames import check_angle, local_to_photometric, photometric_to_local  # noqa: E402

Unit = Literal["brdf", "r", "iof", "reff"]
UNITS: tuple[str, ...] = ("brdf", "r", "iof", "reff")
"""The reflectance units :func:`convert` knows (see the module's table)."""


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
    raise ParameterError(f"unit must be one of {', '.join(UNITS)} (got {unit!r})")


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
