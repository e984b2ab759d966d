"""Planetary photometry's reflectance conventions and the BRDF: the one conversion.

Planetary photometry (Hapke, *Theory of Reflectance and Emittance Spectroscopy*, 2nd ed.,
2012, Sec. 10.2; USGS ISIS ``PhotoModel``; VICAR ``PHO``) describes a surface by a function of
the incidence, emission and phase angles (i, e, g), in one of these units:

* the bidirectional reflectance r(i, e, g) = (reflected radiance)/(collimated irradiance on a
  plane facing the source), in 1/sr (Hapke 2012, Eq. 10.1a);
* the radiance factor RADF = I/F = π r, the brightness relative to a white Lambertian
  surface lit and seen normally (Hapke 2012, Eq. 10.5); ISIS's photometric functions return it;
* the BRDF f_r = r/μ0 (μ0 = cos i; Hapke 2012, Eq. 10.6), roughdiffuse's unit.

So f_r = RADF/(π μ0). Every phase-angle model in roughdiffuse (Hapke, Minnaert, Lunar-Lambert,
Lommel–Seeliger) is written as a radiance factor and converted here, in
:func:`brdf_from_radiance_factor`, and nowhere else. Their radiance factors all carry the
factor μ0 (the irradiance on the tilted surface); the models cancel it in closed form and pass
RADF/μ0, so that grazing incidence (μ0 = 0) is no 0/0.

:func:`radiance_factor` goes the other way, for comparing a model with photometric software
(I/F at given angles).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._array import Array
from ..frames import angles_to_cosines, photometric_to_local

__all__ = ["HORIZON_FLOOR", "brdf_from_radiance_factor", "radiance_factor"]

HORIZON_FLOOR = 1e-6
"""The least value of a cosine, or sum of cosines, that a photometric formula divides by or
raises to a negative power (Lommel–Seeliger's and Hapke's μ0 + μ, Minnaert's μ^(k−1)): on the
horizon (θ = 90°) such a formula diverges and is evaluated at this floor instead, finite."""


def brdf_from_radiance_factor(radf_over_mu0: Array) -> Array:
    """f_r = RADF/(π μ0), given RADF/μ0 (the μ0 of the radiance factor cancelled).

    Parameters
    ----------
    radf_over_mu0 : array
        The radiance factor I/F divided by μ0 = cos i.

    Examples
    --------
    Lambert's law, RADF = ρ μ0, is f_r = ρ/π:

    >>> round(float(brdf_from_radiance_factor(0.5)), 6)
    0.159155
    """
    return radf_over_mu0 / math.pi


def radiance_factor(model: Any, incidence: Array, emission: Array, phase: Array) -> np.ndarray:
    """The radiance factor I/F = π μ0 f_r of ``model`` at photometric angles (radians).

    Parameters
    ----------
    model : Model
        Any roughdiffuse model.
    incidence, emission, phase : array_like
        i, e in [0, π/2] and the phase angle g in [|i − e|, i + e] (radians). At i = π/2
        the surface is unlit and I/F is 0 (ISIS's photometric functions return 0 there too,
        where cos(π/2) = 6e-17 would otherwise leave a 0/0 limit).

    Examples
    --------
    A white Lambertian surface lit and seen normally has I/F = 1:

    >>> import roughdiffuse as rd
    >>> round(float(radiance_factor(rd.Lambert(1.0), 0.0, 0.0, 0.0)), 12)
    1.0
    """
    i, e, dphi = photometric_to_local(incidence, emission, phase)
    mu_i, mu_o, cos_io = angles_to_cosines(np, i, e, dphi)
    f = np.asarray(model.brdf_cosines(mu_i, mu_o, cos_io))
    mu = np.where(i < math.pi / 2, np.clip(mu_i, 0.0, 1.0), 0.0)  # unlit at i = 90° (as ISIS)
    return math.pi * f * (mu[..., None] if f.ndim > mu.ndim else mu)
