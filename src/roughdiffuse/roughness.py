"""Conversions between roughness conventions.

roughdiffuse's σ is the Oren–Nayar roughness: the standard deviation of the facet slope
angle, in radians (Oren and Nayar 1994). Other software names it differently:

* pbrt-v3 ``OrenNayar`` and the Disney BRDF Explorer take σ in **degrees**;
* Mitsuba 0.6 ``roughdiffuse`` takes a Beckmann-style **α** with σ = α/√2
  (``src/bsdfs/roughdiffuse.cpp``: "sigma = alpha / sqrt(2)");
* Fujii's and EON's ``r`` in [0, 1] is a different parameter, not an angle: there is no
  exact conversion, and the models keep it as their own input.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from ._validate import ParameterError

__all__ = [
    "convert",
    "degrees_to_sigma",
    "sigma_to_degrees",
    "mitsuba_alpha_to_sigma",
    "sigma_to_mitsuba_alpha",
]

Convention = Literal["radians", "degrees", "mitsuba_alpha"]
_TO_RADIANS = {"radians": 1.0, "degrees": math.pi / 180.0, "mitsuba_alpha": 1.0 / math.sqrt(2.0)}


def degrees_to_sigma(degrees: float | np.ndarray) -> float | np.ndarray:
    """σ in radians from σ in degrees (pbrt-v3, Disney BRDF Explorer)."""
    return convert(degrees, "degrees", "radians")


def sigma_to_degrees(sigma: float | np.ndarray) -> float | np.ndarray:
    """σ in degrees from σ in radians."""
    return convert(sigma, "radians", "degrees")


def mitsuba_alpha_to_sigma(alpha: float | np.ndarray) -> float | np.ndarray:
    """σ = α/√2 from Mitsuba 0.6 ``roughdiffuse``'s α."""
    return convert(alpha, "mitsuba_alpha", "radians")


def sigma_to_mitsuba_alpha(sigma: float | np.ndarray) -> float | np.ndarray:
    """Mitsuba 0.6's α = √2 σ."""
    return convert(sigma, "radians", "mitsuba_alpha")


def convert(value: float | np.ndarray, src: Convention, dst: Convention) -> float | np.ndarray:
    """Convert a roughness between conventions.

    Parameters
    ----------
    value : float or array
        Roughness in convention ``src``.
    src, dst : {"radians", "degrees", "mitsuba_alpha"}

    Examples
    --------
    >>> round(convert(45.0, "degrees", "radians"), 12) == round(math.pi / 4, 12)
    True
    """
    for name, c in (("src", src), ("dst", dst)):
        if c not in _TO_RADIANS:
            raise ParameterError(f"{name} must be one of {sorted(_TO_RADIANS)} (got {c!r})")
    return value * (_TO_RADIANS[src] / _TO_RADIANS[dst])
