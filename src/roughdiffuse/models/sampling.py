"""Importance sampling of the incident direction: pbrt-v4's ``Sample_f`` and ``PDF``.

Each strategy is a pair of branch-free functions on vector *components* (structure of
arrays), written against an array namespace ``xp`` like the models' kernels, so the same code
runs on NumPy, JAX, PyTorch and, through :mod:`roughdiffuse.integrations.drjit_namespace`,
inside Mitsuba 3:

* ``sample(xp, u1, u2, wox, woy, woz, p) -> (x, y, z, pdf)``: a direction wi (towards the
  light) from two uniform numbers, and its density per solid angle;
* ``pdf(xp, wix, wiy, wiz, wox, woy, woz, p) -> pdf``.

``p`` holds the model's parameters by name (``roughness``, ``sigma``, ``alpha``). A model
class names its strategy as an object in its ``sampling`` class attribute (a model whose
strategy depends on a categorical parameter overrides ``Model.sampling_strategy``).
Strategies:

``cosine``
    pdf = cos θi / π (Malley's method; pbrt-v4 ``SampleCosineHemisphere``). Lambert,
    Oren–Nayar, the lunar models.
``cltc``
    EON's sampler (Portsmouth, Kutz, Hill, JCGT 2025, arXiv 2410.18026, Sec. 5 and its
    Listing 2): a *clipped linearly transformed cosine* fitted to the Fujii lobe, mixed with
    uniform hemisphere sampling with probability P_u(μo, r) as the paper does. Used for EON
    and Fujii (same single-scattering lobe).
``microfacet``
    Torrance–Sparrow: sample a facet normal h from D(h) (n·h), reflect wo about it
    (wi = 2 (wo·h) h − wo, pdf = p_h / (4 wo·h); Walter et al. 2007, Eq. 14 and 17).
    Beckmann: tan²θh = −α² ln(1 − u1), exactly. Gaussian in the slope angle (no closed-form
    inverse): the inverse CDF by Newton's method on a 32-point quadrature of the CDF,
    converged to 1e-9. Both return D(h) n·h as the density of h, with the model's own D;
    the distribution's code lives in :mod:`.microfacet`.

Directions below the horizon have pdf 0; a sample with pdf 0 gets weight 0.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np

from .._array import Array, asarray, concrete, result_dtype, safe_div, safe_sqrt
from .._validate import ParameterError
from ..deprecation import renamed_parameter
from ..frames import unit_components
from .microfacet import normal_pdf, normal_sample

if TYPE_CHECKING:
    from .base import Model

__all__ = [
    "BSDFSample",
    "CLTC",
    "COSINE",
    "MICROFACET_BECKMANN",
    "MICROFACET_GAUSSIAN",
    "Strategy",
    "microfacet",
    "pdf_model",
    "sample_model",
    "strategy_for",
    "weight_variance",
]


class BSDFSample(NamedTuple):
    """A sampled incident direction.

    Attributes
    ----------
    wi : array (..., 3)
        Sampled direction towards the light (local frame).
    pdf : array (...)
        Its probability density per unit solid angle.
    weight : array (...) or (..., C)
        ``brdf(wi, wo) * cos θi / pdf`` (0 where the sample is invalid).
    """

    wi: Array
    pdf: Array
    weight: Array


_INV_PI = 1.0 / math.pi
_INV_2PI = 0.5 / math.pi


class Strategy(NamedTuple):
    """A sampling strategy: name, sampler and density on vector components."""

    name: str
    sample: Callable[..., tuple[Array, Array, Array, Array]]
    pdf: Callable[..., Array]


def _where(xp: Any, cond: Array, a: Array | float, b: Array | float) -> Array:
    return xp.where(cond, a, b)


# ---------------------------------------------------------------------------- cosine
def _cosine_dir(xp: Any, u1: Array, u2: Array) -> tuple[Array, Array, Array]:
    r = safe_sqrt(xp, u1)
    phi = (2.0 * math.pi) * u2
    return r * xp.cos(phi), r * xp.sin(phi), safe_sqrt(xp, 1.0 - u1)


def _cosine_sample(xp: Any, u1: Array, u2: Array, wox: Array, woy: Array, woz: Array, p: dict):
    x, y, z = _cosine_dir(xp, u1, u2)
    return x, y, z, z * _INV_PI


def _cosine_pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, p: dict) -> Array:
    return _where(xp, wiz > 0, wiz * _INV_PI, 0.0 * wiz)


COSINE = Strategy("cosine", _cosine_sample, _cosine_pdf)


# ---------------------------------------------------------------------------- EON (CLTC)
def _ltc_terms(xp: Any, mu: Array, r: Array) -> tuple[Array, Array, Array, Array]:
    """Coefficients a, b, c, d of the LTC matrix M(μo, r) (EON paper, Listing 2, fitted)."""
    a = 1.0 + r * (0.303392 + (-0.518982 + 0.111709 * mu) * mu + (-0.276266 + 0.335918 * mu) * r)
    b = r * (-1.16407 + 1.15859 * mu + (0.150815 - 0.150105 * mu) * r) / (mu * mu * mu - 1.43545)
    c = 1.0 + (0.20013 + (-0.506373 + 0.261777 * mu) * mu) * r
    d = ((0.540852 + (-1.01625 + 0.475392 * mu) * mu) * r) / (-1.0743 + mu * (0.0725628 + mu))
    return a, b, c, d


def _ltc_basis(xp: Any, wox: Array, woy: Array) -> tuple[Array, Array]:
    """Unit X axis (cos φr, sin φr) of the LTC frame; (1, 0) at normal incidence."""
    len2 = wox * wox + woy * woy
    inv = safe_div(xp, 1.0, safe_sqrt(xp, len2))
    has = len2 > 0
    return _where(xp, has, wox * inv, 1.0 + 0.0 * wox), _where(xp, has, woy * inv, 0.0 * woy)


def _clip_factor(xp: Any, d: Array) -> Array:
    """s = (1 + v_z)/2, v_z = 1/√(1 + d²): the clipped fraction of the disk (CLTC)."""
    return 0.5 * (1.0 + 1.0 / xp.sqrt(d * d + 1.0))


def _cltc_sample(xp: Any, u1, u2, wox, woy, woz, r) -> tuple[Array, Array, Array, Array]:
    a, b, c, d = _ltc_terms(xp, woz, r)
    rad = safe_sqrt(xp, u1)
    phi = (2.0 * math.pi) * u2
    x = rad * xp.cos(phi)
    y = rad * xp.sin(phi)
    s = _clip_factor(xp, d)
    x = -((1.0 - s) * safe_sqrt(xp, 1.0 - y * y) + s * x)
    zh = safe_sqrt(xp, 1.0 - (x * x + y * y))
    pdf_h = zh / (math.pi * s)
    lx, ly, lz = a * x + b * zh, c * y, d * x + zh
    length = xp.sqrt(lx * lx + ly * ly + lz * lz)
    det = c * (a - b * d)
    pdf = pdf_h * length * length * length / det
    bx, by = _ltc_basis(xp, wox, woy)
    inv = 1.0 / length
    return (lx * bx - ly * by) * inv, (lx * by + ly * bx) * inv, lz * inv, pdf


def _cltc_pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, r) -> Array:
    bx, by = _ltc_basis(xp, wox, woy)
    wx = wix * bx + wiy * by  # to the LTC frame (transpose of the basis)
    wy = -wix * by + wiy * bx
    wz = wiz
    a, b, c, d = _ltc_terms(xp, woz, r)
    det = c * (a - b * d)
    hx = c * (wx - b * wz)  # adj(M) wi
    hy = (a - b * d) * wy
    hz = -c * (d * wx - a * wz)
    len2 = hx * hx + hy * hy + hz * hz
    s = _clip_factor(xp, d)
    q = det / len2
    return q * q * _where(xp, hz > 0, hz, 0.0 * hz) / (math.pi * s)


def _uniform_probability(xp: Any, mu: Array, r: Array) -> Array:
    """P_u = r^0.1 (0.162925 + μ(−0.372058 + (0.538233 − 0.290822 μ) μ)) (EON Listing 2)."""
    pos = r > 0
    r01 = _where(xp, pos, xp.exp(0.1 * xp.log(_where(xp, pos, r, 1.0 + 0.0 * r))), 0.0 * r)
    return r01 * (0.162925 + mu * (-0.372058 + (0.538233 - 0.290822 * mu) * mu))


def _eon_sample(xp: Any, u1, u2, wox, woy, woz, p: dict):
    r = p["roughness"]
    p_u = _uniform_probability(xp, woz, r)
    use_u = u1 < p_u
    uu = safe_div(xp, u1, p_u)  # uniform branch: u1 / P_u
    uc = safe_div(xp, u1 - p_u, 1.0 - p_u)  # CLTC branch
    uz = uu
    us = safe_sqrt(xp, 1.0 - uz * uz)
    phi = (2.0 * math.pi) * u2
    cx, cy, cz, _ = _cltc_sample(xp, uc, u2, wox, woy, woz, r)
    x = _where(xp, use_u, us * xp.cos(phi), cx)
    y = _where(xp, use_u, us * xp.sin(phi), cy)
    z = _where(xp, use_u, uz, cz)
    return x, y, z, _eon_pdf(xp, x, y, z, wox, woy, woz, p)


def _eon_pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, p: dict) -> Array:
    r = p["roughness"]
    p_u = _uniform_probability(xp, woz, r)
    pdf = p_u * _INV_2PI + (1.0 - p_u) * _cltc_pdf(xp, wix, wiy, wiz, wox, woy, woz, r)
    return _where(xp, wiz > 0, pdf, 0.0 * pdf)


CLTC = Strategy("cltc", _eon_sample, _eon_pdf)


# ---------------------------------------------------------------------------- microfacet
def microfacet(distribution: str) -> Strategy:
    """The Torrance–Sparrow strategy for facet distribution ``"gaussian"`` or ``"beckmann"``.

    h is drawn with density p_h ∝ D(h) n·h and wi = 2 (wo·h) h − wo has density
    p_h / (4 wo·h) (Walter et al. 2007, Eq. 14). A reflection below the horizon (or off a
    facet facing away from wo) is an invalid sample, pdf 0 and weight 0, as in pbrt and
    Mitsuba: this pdf integrates to the fraction of valid samples, which is < 1 at grazing
    views and large σ. (Folding such samples back above the horizon would normalise it, but
    puts an integrable 1/(wo·h) spike at the mirror of −wo, which quadrature-based
    tests, Mitsuba's chi-square test among them, cannot integrate.)

    The width parameter is read from ``p["sigma"]`` (Gaussian) or ``p["alpha"]`` (Beckmann).
    """
    width = "sigma" if distribution == "gaussian" else "alpha"

    def pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, p: dict) -> Array:
        hx, hy, hz = wix + wox, wiy + woy, wiz + woz
        inv = safe_div(xp, 1.0, safe_sqrt(xp, hx * hx + hy * hy + hz * hz))
        cos_h = hz * inv
        dot = (wox * hx + woy * hy + woz * hz) * inv
        val = safe_div(xp, normal_pdf(xp, cos_h, p[width], distribution), 4.0 * dot)
        return _where(xp, (wiz > 0) & (dot > 0) & (cos_h > 0), val, 0.0 * val)

    def sample(xp: Any, u1, u2, wox, woy, woz, p: dict):
        cos_h, sin_h = normal_sample(xp, u1, p[width], distribution)
        phi = (2.0 * math.pi) * u2
        hx, hy, hz = sin_h * xp.cos(phi), sin_h * xp.sin(phi), cos_h
        dot = wox * hx + woy * hy + woz * hz
        x, y, z = 2.0 * dot * hx - wox, 2.0 * dot * hy - woy, 2.0 * dot * hz - woz
        return x, y, z, pdf(xp, x, y, z, wox, woy, woz, p)

    return Strategy(f"microfacet-{distribution}", sample, pdf)


MICROFACET_GAUSSIAN = microfacet("gaussian")
MICROFACET_BECKMANN = microfacet("beckmann")


def strategy_for(model: Model) -> Strategy:
    """The strategy ``model`` declares (``model.sampling_strategy()``; cosine by default)."""
    return model.sampling_strategy()


# ---------------------------------------------------------------------------- model API
def _check_u(xp: Any, u: Array, dtype: Any) -> Array:
    u = asarray(xp, u, dtype)
    if u.ndim < 1 or u.shape[-1] != 2:
        raise ParameterError(f"u must have shape (..., 2) (got shape {tuple(u.shape)})")
    uc = concrete(u)
    if uc is not None and (np.any(~(uc >= 0)) or np.any(uc > 1)):
        raise ParameterError("u must lie in [0, 1]")
    return u


def sample_model(model: Model, u: Array, wo: Array, strategy: Strategy | None = None) -> BSDFSample:
    """``model.sample(u, wo)`` with ``strategy`` (default :func:`strategy_for`).

    Returns wi, its pdf and the weight f cos θi / pdf (0 where pdf = 0 or wo is below
    the horizon).
    """
    strategy = strategy or strategy_for(model)
    xp = model._xp(u, wo)
    dtype = result_dtype(xp, u, wo)
    u = _check_u(xp, u, dtype)
    wo = asarray(xp, wo, dtype)
    wox, woy, woz = unit_components(xp, wo, "wo", dtype)
    p = model.parameter_arrays(xp, dtype)
    x, y, z, pdf = strategy.sample(xp, u[..., 0], u[..., 1], wox, woy, woz, p)
    valid = (pdf > 0) & (z > 0) & (woz > 0)
    pdf = _where(xp, valid, pdf, 0.0 * pdf)
    wi = xp.stack([x, y, z], axis=-1)
    wi_safe = xp.stack([x, y, _where(xp, valid, z, 1.0 + 0.0 * z)], axis=-1)
    f = model.brdf(wi_safe, wo)
    ratio = _where(xp, valid, z / _where(xp, valid, pdf, 1.0 + 0.0 * pdf), 0.0 * pdf)
    if f.ndim > ratio.ndim:
        ratio = ratio[..., None]
    return BSDFSample(wi, pdf, f * ratio)


def pdf_model(model: Model, wi: Array, wo: Array, strategy: Strategy | None = None) -> Array:
    """``model.pdf(wi, wo)``: density per solid angle of :func:`sample_model`'s wi."""
    strategy = strategy or strategy_for(model)
    xp = model._xp(wi, wo)
    dtype = result_dtype(xp, wi, wo)
    wix, wiy, wiz = unit_components(xp, wi, "wi", dtype)
    wox, woy, woz = unit_components(xp, wo, "wo", dtype)
    p = model.parameter_arrays(xp, dtype)
    pdf = strategy.pdf(xp, wix, wiy, wiz, wox, woy, woz, p)
    return _where(xp, (wiz > 0) & (woz > 0), pdf, 0.0 * pdf)


@renamed_parameter("theta_o", "theta_r", since="0.2")
def weight_variance(
    model: Model, theta_r: float, n: int = 200_000, strategy: Strategy | None = None, seed: int = 0
) -> tuple[float, float]:
    """Mean and variance of the sample weight f cos θi / pdf for a view at ``theta_r`` (rad).

    The mean is the directional albedo (for every unbiased strategy); the variance measures
    the strategy (lower is better; 0 for a perfect sampler). Colour models use channel 0.
    """
    rng = np.random.default_rng(seed)
    u = rng.random((n, 2))
    wo = np.array([math.sin(theta_r), 0.0, math.cos(theta_r)])
    w = np.asarray(sample_model(model, u, wo, strategy).weight, dtype=np.float64)
    if w.ndim > 1:
        w = w[..., 0]
    return float(w.mean()), float(w.var())
