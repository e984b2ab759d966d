"""The microfacet distribution: D, the V-groove masking, facet-normal sampling, the σ floor.

A leaf module (it imports no model), as pbrt-v4 keeps ``TrowbridgeReitzDistribution`` in
``util/scattering.h``: :mod:`.torrance_sparrow` evaluates with it and :mod:`.sampling` samples
with it. Two distributions of the facet normal h, each with its own width parameter:

``"gaussian"``
    Gaussian in the slope angle θh with standard deviation σ (radians), as in the lecture and
    Torrance and Sparrow (1967): D ∝ exp(−θh²/2σ²), normalised by quadrature over [0, π/2].
``"beckmann"``
    Gaussian in the slope tan θh (Beckmann and Spizzichino 1963), with the RMS slope α
    (dimensionless; pbrt-v4's and Mitsuba 3's ``alpha``)::

        D = exp(−tan²θh/α²) / (π α² cos⁴θh).

    Each slope component then has standard deviation α/√2.

Both are normalised so that ∫ D(h) (n·h) dωh = 1.
"""

from __future__ import annotations

import math
from typing import Any

from .._array import Array, asarray, maximum, minimum, safe_div, safe_sqrt
from ._quadrature import gauss_legendre_01

__all__ = [
    "ALPHA_FLOOR",
    "COS_FLOOR",
    "DISTRIBUTIONS",
    "SIGMA_FLOOR",
    "fresnel_dielectric",
    "gaussian_norm",
    "normal_pdf",
    "normal_sample",
    "slope_distribution",
    "v_groove_masking",
]

DISTRIBUTIONS: tuple[str, ...] = ("gaussian", "beckmann")
"""The facet distributions, by name."""

COS_FLOOR = 1e-6
"""Floor of the cosines divided by in the BRDF (n·wi, n·wo, wo·h) and of cos θh."""

SIGMA_FLOOR = 1e-4
"""Smallest σ the Gaussian distribution resolves: a smaller positive σ is evaluated as 1e-4 rad
(peak D = 1.6e7 /sr), so that D stays finite in float32 as σ -> 0 (σ = 0 itself gives 0)."""

ALPHA_FLOOR = math.sqrt(2.0) * SIGMA_FLOOR
"""The same floor for Beckmann's α (α = √2 σ at small slopes)."""

_GL_T, _GL_W = gauss_legendre_01(96)
_GL_X32, _GL_W32 = gauss_legendre_01(32)
_NEWTON_STEPS = 5


def _floor(distribution: str) -> float:
    return SIGMA_FLOOR if distribution == "gaussian" else ALPHA_FLOOR


def fresnel_dielectric(xp: Any, cos_t: Array, eta: Array) -> Array:
    """Unpolarised Fresnel reflectance for cos θ = ``cos_t`` and relative index η.

    F = ½ ((g − c)/(g + c))² [1 + ((c (g + c) − 1)/(c (g − c) + 1))²], g² = η² − 1 + c²
    (Cook and Torrance 1982, Eq. in Appendix); F = 1 where g² ≤ 0 (total internal reflection).
    """
    c = cos_t
    g2 = eta * eta - 1.0 + c * c
    g = safe_sqrt(xp, g2)
    a = safe_div(xp, g - c, g + c, 1.0)
    b = safe_div(xp, c * (g + c) - 1.0, c * (g - c) + 1.0, 1.0)
    return xp.where(g2 > 0, 0.5 * a * a * (1.0 + b * b), 1.0 + 0.0 * c)


def gaussian_norm(xp: Any, sigma: Array, dtype: Any) -> Array:
    """1 / (2π ∫_0^{π/2} exp(−θ²/2σ²) cos θ sin θ dθ), times σ² (finite as σ → 0).

    With θ = σ t the integral is σ² J(σ), J = ∫_0^T exp(−t²/2) sin(2σt)/(2σ) dt,
    T = min(π/(2σ), 12); J → 1 as σ → 0. 96-point Gauss–Legendre (error below 1e-12).
    """
    t_nodes = asarray(xp, _GL_T, dtype)
    w = asarray(xp, _GL_W, dtype)
    pos = sigma > 0
    s = xp.where(pos, sigma, 1.0)
    big_t = minimum(xp, math.pi / (2.0 * s), 12.0)
    t = big_t * t_nodes
    integrand = xp.exp(-0.5 * t * t) * xp.where(pos, xp.sin(2.0 * s * t) / (2.0 * s), t)
    j = big_t * xp.sum(integrand * w, axis=-1)
    return 1.0 / (2.0 * math.pi * j)


def slope_distribution(
    xp: Any, cos_h: Array, width: Array, distribution: str = "gaussian"
) -> Array:
    """D(h) for n·h = ``cos_h``, normalised so that ∫ D (n·h) dωh = 1; 0 for a zero width.

    ``width`` is the distribution's own parameter: σ (radians) for ``"gaussian"``, α for
    ``"beckmann"`` (see the module docstring).
    """
    dtype = cos_h.dtype
    pos = width > 0
    s = xp.where(pos, maximum(xp, width, _floor(distribution)), 1.0)
    sin_h = safe_sqrt(xp, 1.0 - cos_h * cos_h)
    if distribution == "gaussian":
        theta = xp.atan2(sin_h, cos_h)
        norm = gaussian_norm(xp, s[..., None] if s.ndim else s, dtype)
        d = xp.exp(-theta * theta / (2.0 * s * s)) * norm / (s * s)
    else:
        a2 = s * s
        c = maximum(xp, cos_h, COS_FLOOR)
        tan2 = sin_h * sin_h / (c * c)
        d = xp.exp(-tan2 / a2) / (math.pi * a2 * c**4)
        d = xp.where(cos_h > COS_FLOOR, d, 0.0 * d)
    return xp.where(pos, d, 0.0 * d)


def v_groove_masking(xp: Any, mu_i: Array, mu_o: Array, cos_h: Array, cos_d: Array) -> Array:
    """G/(μi μo) of Torrance and Sparrow's V-grooves (JOSA 57, 1967), floored cosines.

    G = min(1, 2 (n·h)(n·wo)/(wo·h), 2 (n·h)(n·wi)/(wo·h)), so
    G/(μi μo) = min(1/(μi μo), 2 n·h/(wo·h μi), 2 n·h/(wo·h μo)).
    """
    mi = maximum(xp, mu_i, COS_FLOOR)
    mo = maximum(xp, mu_o, COS_FLOOR)
    cd = maximum(xp, cos_d, COS_FLOOR)
    return minimum(
        xp, 1.0 / (mi * mo), minimum(xp, 2.0 * cos_h / (cd * mi), 2.0 * cos_h / (cd * mo))
    )


# ---------------------------------------------------------------------------- sampling
def _where(xp: Any, cond: Array, a: Array | float, b: Array | float) -> Array:
    return xp.where(cond, a, b)


def _gaussian_angle(xp: Any, u1: Array, s: Array) -> Array:
    """t = θh/σ with density ∝ exp(−t²/2) sin(2σt)/(2σ) on [0, T], T = min(π/(2σ), 12).

    That is D(h) n·h sin θh dθh for the Gaussian-in-angle D (the truncation at 12σ is the
    distribution's own, see :func:`gaussian_norm`). No closed-form inverse exists: start
    from the inverse of the small-angle density t exp(−t²/2) and take Newton steps on
    √F(t) = √(u Z) (on √(Z − F) = √((1 − u) Z) for u > ½), F the CDF by 32-point
    Gauss–Legendre and Z = F(T); the square roots make both ends, where the density
    vanishes, converge quadratically: 5 steps reach |F(t) − u Z| < 1e-9 Z for every σ.
    """
    dtype = getattr(u1, "dtype", None)
    x = asarray(xp, _GL_X32, dtype)
    w = asarray(xp, _GL_W32, dtype)
    big_t = minimum(xp, math.pi / (2.0 * s), 12.0)

    def density(t: Array) -> Array:
        return xp.exp(-0.5 * t * t) * xp.sin(2.0 * s * t) / (2.0 * s)

    def cdf(t: Array) -> Array:
        return t * xp.sum(density(t[..., None] * x) * w, axis=-1)

    z = cdf(big_t)
    t = safe_sqrt(xp, -2.0 * xp.log(1.0 - u1 * (1.0 - xp.exp(-0.5 * big_t * big_t))))
    low = u1 < 0.5
    for _ in range(_NEWTON_STEPS):
        g = density(t)
        f = cdf(t)
        a = safe_sqrt(xp, f)
        b = safe_sqrt(xp, z - f)
        step_low = safe_div(xp, 2.0 * a * (a - safe_sqrt(xp, u1 * z)), g)
        step_high = safe_div(xp, 2.0 * b * (safe_sqrt(xp, (1.0 - u1) * z) - b), g)
        t = _clip_to(xp, t - _where(xp, low, step_low, step_high), big_t)
    return t


def _clip_to(xp: Any, t: Array, hi: Array) -> Array:
    """t clipped to [0, hi] (``hi`` may be an array)."""
    t = _where(xp, t < 0, 0.0 * t, t)
    return _where(xp, t > hi, hi + 0.0 * t, t)


def normal_sample(xp: Any, u1: Array, width: Array, distribution: str) -> tuple[Array, Array]:
    """(cos θh, sin θh) of a facet normal drawn with density D(h) n·h from uniform ``u1``.

    Beckmann: tan²θh = −α² ln(1 − u1), exactly (Walter et al. 2007, Eq. 28). Gaussian in
    the slope angle: the inverse CDF by Newton's method (:func:`_gaussian_angle`).
    """
    pos = width > 0
    s = _where(xp, pos, maximum(xp, width, _floor(distribution)), 1.0 + 0.0 * width)
    if distribution == "beckmann":
        tan2 = -(s * s) * xp.log(1.0 - u1)
        cos_h = 1.0 / xp.sqrt(1.0 + tan2)
    else:
        cos_h = xp.cos(s * _gaussian_angle(xp, u1, s))
    cos_h = _where(xp, pos, cos_h, 1.0 + 0.0 * cos_h)
    return cos_h, safe_sqrt(xp, 1.0 - cos_h * cos_h)


def normal_pdf(xp: Any, cos_h: Array, width: Array, distribution: str) -> Array:
    """D(h) n·h, the density per solid angle of :func:`normal_sample`'s h (0 for width 0)."""
    p_h = slope_distribution(xp, cos_h, width, distribution) * cos_h
    return _where(xp, (width > 0) & (cos_h > 0), p_h, 0.0 * p_h)
