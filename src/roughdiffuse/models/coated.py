"""A dielectric coat over a rough-diffuse base, in closed form: glazes, paint, plastic.

Where :class:`~roughdiffuse.models.mix.Mix` adds a diffuse and a specular lobe with a tuned
weight, ``Coated`` puts the base under a dielectric interface of relative index η, as
OpenPBR's coat, Autodesk Standard Surface and Mitsuba 3's ``plastic``/``roughplastic`` do:

    f = f_coat(ωi, ωo)
        + (1 − F(μi, η)) (1 − F(μo, η)) / η² · [ f_b(ωi', ωo') e^{−τ/μi' − τ/μo'}
          + a(μi') e^{−τ/μi'} K / (1 − ā K) · a(μo') e^{−τ/μo'} / π ].

* ωi', ωo': ωi and ωo refracted into the layer (Snell: sin θ' = sin θ / η, the azimuths
  kept, so cos γ' = μi' μo' + (cos γ − μi μo) / η²); the base is evaluated there, with the
  Fresnel transmittances in and out and the 1/η² of the radiance crossing the interface.
* The second term sums the internal reflections (Kelemen and Szirmay-Kalos 2001; Weidlich
  and Wilkie 2007, "Arbitrarily layered micro-facet surfaces", GRAPHITE, Sec. 4): light
  the base reflects (its directional albedo a(μi') at the refracted angle) is reflected back
  down by the interface with the internal diffuse reflectance
  K = ∫ F(μ, 1/η) e^{−2τ/μ} 2μ dμ (F = 1 beyond the critical angle), returns to the base,
  which reflects ā (its albedo averaged over the returning light), and so on; what finally
  leaves towards ωo' does so in proportion to a(μo') (reciprocity). For a Lambertian base
  this is exactly Mitsuba 3's ``plastic`` with ``nonlinear=true``,
  ρ (1 − F_i)(1 − F_o) / (π η² (1 − ρ K)); for other bases it assumes that light returning
  after an internal reflection is diffuse.
* f_coat: nothing for a smooth coat (its mirror reflection, F(μi, η), is a Dirac delta that
  no BRDF value holds); for a rough one (α > 0) the microfacet reflection of Walter,
  Marschner, Li and Torrance 2007, eq. 20, F(ωi·h) D(h) G2 / (4 μi μo), GGX or Beckmann,
  with the height-correlated masking and shadowing G2 = 1/(1 + Λi + Λo) of the Smith
  microsurface (Heitz 2014, eq. 99; Beckmann's Λ by Walter's rational fit, eq. 27): the
  single scattering of the exact interface.
* The rough coat's transmittances and internal reflectance are its own energy: a Smith
  microsurface loses no light (Heitz, Hanika, d'Eon and Dachsbacher 2016), so what it does
  not reflect enters, T(μ) = 1 − E(μ) in both directions, E its directional reflectance
  (:func:`interface_albedo`), and the reciprocity of a dielectric interface,
  η² T̄_below = T̄_above, gives its internal diffuse reflectance without absorption exactly,
  K = 1 − (1 − Ē)/η² (:func:`_internal_sums`). E is the single-scattering reflectance
  E_ss (the lobe's albedo by a node rule) times 1 + c(μ), c = ΔE/E_ss the walk's
  directional reflectance by two or more facet events relative to it (:func:`ms_ratio`,
  fitted to ``data/coat_interface.npz``). That light (a few per cent of the coat's
  reflection, most of it near grazing) is added to f_coat resolved in direction,
  f_ms = Σ_s f_ss(s α) p_s(η, α, μi, μo) (:func:`ms_lobe`): single-scattering lobes of
  roughness 0.7 α, α and 2 α (Beckmann's second reflections gather closer to the mirror
  direction than its first, GGX's spread wider) with symmetric polynomial weights fitted to
  the walk's interface alone (``data/coat_lobe.npz``, :func:`lobe_fit`), its albedo held
  in the fit to E(μ) minus the single-scattering lobe's, so the white furnace stays 1
  (within 1 % for η in [1.1, 2.5], α in [0.01, 1], θ to 89°). How far
  this is from the truth is measured against the layered walk with the exact interface
  (:mod:`roughdiffuse.simulate.layered`) on the accuracy page.
* τ: the optical depth of the layer (thickness × absorption coefficient), Beer–Lambert along
  each crossing; one number, or one per colour channel (then K and ā K are per channel too).

The base's directional albedo a(μ) is a fixed 32-point rule over the hemisphere (4 nodes in
μ², 2 × 4 in azimuth split at π/2) of the base's own formula, so every namespace (NumPy,
JAX, PyTorch, the compiled fast path, Dr.Jit in Mitsuba) evaluates the same expression; K and
ā use 8 Gauss–Legendre nodes on each side of the critical angle (in √(μ − μc) above it, where
the Fresnel factor has a square-root edge): 1e-7 of K for η in [1.1, 3] without absorption,
1e-4 with it (e^{−2τ/μ} turns on at μ ≈ 2τ; 6.5e-5 at worst, near τ = 0.01). Each rule is one
trailing node axis of the arrays, added up by ``xp.sum``: the compiled fast path turns it
into a loop (:mod:`roughdiffuse.engine.trace`), so the traced code does not grow with the
number of nodes.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from pathlib import Path
from typing import Any, ClassVar

import numpy as np

from .._array import Array, asarray, clip, maximum, safe_div, safe_sqrt
from .._validate import ParameterError
from ..quadrature import gauss_legendre
from . import microfacet
from .base import Model
from .declaration import Param, declared_params, param
from .eon import EON
from .lambert import Lambert
from .microfacet import fresnel_dielectric, slope_distribution
from .oren_nayar import OrenNayar
from .sampling import Strategy

__all__ = ["Coated", "COAT_BASES", "COAT_DISTRIBUTIONS", "COAT_ETA_RANGE"]

COAT_DISTRIBUTIONS: tuple[str, ...] = ("ggx", "beckmann")

COAT_BASES: tuple[str, ...] = ("lambert", "oren-nayar", "oren-nayar-full", "fujii", "eon")
"""The registry ids the registry's ``coated`` accepts as its ``base`` (the explorer's base
menu; each has a GLSL copy). In Python, :class:`Coated` takes any closed-form model."""

ALPHA_FLOOR = 1e-6
"""The smallest rough α evaluated (a smaller one is evaluated here): the lobe of α = 1e-6 is
a mirror's to float precision, and powers of a subnormal α overflow."""

COAT_ETA_RANGE: tuple[float, float] = (1.0, 5.0)
"""The coat's relative index η accepted: a coat in air or in a less dense medium (η ≥ 1;
η = 1 is no interface), up to 5, beyond the most refractive transparent materials (rutile
2.9 in the visible, silicon and germanium about 3.5 and 4 in the infrared). Below 1 the
rough coat's internal reflectance, 1 − (1 − Ē)/η² from above, is not what the formula
assumes (the total internal reflection is on the way in), and at η ≈ 1e-154 η² underflows."""

_ON_BASES = ("oren-nayar", "oren-nayar-full")
_FON_BASES = ("fujii", "eon")


def _base_param(cls: type[Model], name: str, coat_name: str, bases: tuple[str, ...],
                description: str, **changes: Any) -> Param:
    """The declaration of the base's parameter ``name`` (its range, unit and fit box) as the
    coat's parameter ``coat_name``, existing only for these base ids."""
    declared = next(p for p in cls.params if p.name == name)
    return dataclasses.replace(declared, name=coat_name, description=description,
                               when={"base": bases}, **changes)


_BASE_PARAMS: dict[str, str] = {"sigma": "sigma", "base_roughness": "roughness"}
"""The coat's name of each base parameter -> the base model's own name for it (the coat has
a ``roughness`` of its own, α, so Fujii's and EON's r is ``base_roughness``)."""

_S_NODES, _S_WEIGHTS = gauss_legendre(4)
_PHI_NODES, _PHI_WEIGHTS = gauss_legendre(4)
_MU_NODES, _MU_WEIGHTS = gauss_legendre(8)
_INV_PI = 1.0 / math.pi


def _smith_lambda(xp: Any, mu: Array, alpha: Array, distribution: str) -> Array:
    """Smith's Λ for a direction of cosine μ > 0 (GGX exact; Beckmann by Walter's fit)."""
    mu = maximum(xp, mu, 1e-7)
    tan2 = (1.0 - mu * mu) / (mu * mu)
    if distribution == "ggx":
        return 0.5 * (xp.sqrt(1.0 + alpha * alpha * tan2) - 1.0)
    a = safe_div(xp, 1.0, alpha * safe_sqrt(xp, tan2), 1e7)
    fit = (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)
    return xp.where(a < 1.6, fit, 0.0 * a)


def _ndf(xp: Any, cos_h: Array, alpha: Array, distribution: str) -> Array:
    """D(h) with ∫ D (n·h) dωh = 1 (GGX: Walter eq. 33; Beckmann: :mod:`.microfacet`)."""
    if distribution == "beckmann":
        return slope_distribution(xp, cos_h, alpha, "beckmann")
    a2 = maximum(xp, alpha * alpha, 1e-14)
    c = clip(xp, cos_h, 0.0, 1.0)
    # cos²θh (α² − 1) + 1 as sin²θh + cos²θh α²: never 0 for α > 0 (in float32, α² − 1 rounds
    # to −1 at the floor and the first form is 0 at the peak)
    den = (1.0 - c) * (1.0 + c) + c * c * a2
    return xp.where(cos_h > 0, a2 / (math.pi * den * den), 0.0 * cos_h)


def coat_reflection(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, eta: Array,
                    alpha: Array, distribution: str) -> Array:
    """The rough coat's own reflection F D G2 / (4 μi μo) (Walter et al. 2007, eq. 20, with
    the height-correlated G2 = 1/(1 + Λi + Λo), Heitz 2014, eq. 99); 0 for α = 0."""
    len_h = safe_sqrt(xp, 2.0 * (1.0 + cos_io))
    cos_h = safe_div(xp, mu_i + mu_o, len_h)
    cos_d = 0.5 * len_h
    # height-correlated masking and shadowing, G2 = 1/(1 + Λi + Λo): the single scattering of
    # the Smith microsurface (Heitz 2014, eq. 99; the first order of the walk's interface)
    g = 1.0 / (1.0 + _smith_lambda(xp, mu_i, alpha, distribution)
               + _smith_lambda(xp, mu_o, alpha, distribution))
    d = _ndf(xp, cos_h, alpha, distribution)
    # μ floored as in Λ, so that G1(μ)/μ keeps its finite limit 2/α at a grazing direction
    den = 4.0 * maximum(xp, mu_i, 1e-7) * maximum(xp, mu_o, 1e-7)
    val = fresnel_dielectric(xp, cos_d, eta) * d * g / den
    return xp.where(alpha > 0, val, xp.zeros_like(val))  # (not 0 × val: inf at the peak)


def _rule(*factors: tuple[np.ndarray, np.ndarray]) -> tuple[list[np.ndarray], np.ndarray]:
    """The product of 1-D rules (nodes, weights) flattened onto one node axis: the nodes of
    each factor repeated to the product's length, and the product of the weights."""
    grids = np.meshgrid(*(n for n, _ in factors), indexing="ij")
    weights = np.prod(np.meshgrid(*(w for _, w in factors), indexing="ij"), axis=0)
    return [g.reshape(-1) for g in grids], weights.reshape(-1)


# the azimuth on [0, π]: 4 Gauss–Legendre nodes on each side of π/2, weights summing to π
_HALF_PHI = (
    np.concatenate([0.5 * math.pi * _PHI_NODES, 0.5 * math.pi * (1.0 + _PHI_NODES)]),
    np.concatenate([_PHI_WEIGHTS, _PHI_WEIGHTS]) * 0.5 * math.pi,
)
_U_NODES, _U_WEIGHTS = gauss_legendre(6)
(_IF_U, _IF_PHI), _IF_W = _rule((_U_NODES, _U_WEIGHTS), _HALF_PHI)
_IF_COS_PHI = np.cos(_IF_PHI)
_IF_W = _IF_W / math.pi  # the azimuth's mean over [0, π]
# tan²θh / α² at which the fraction u of the projected facet area D cos θh dωh lies below θh
# (GGX: u / (1 − u); Beckmann: −ln(1 − u))
_IF_TAN2 = {"ggx": _IF_U / (1.0 - _IF_U), "beckmann": -np.log1p(-_IF_U)}
(_BA_S, _BA_PHI), _BA_W = _rule((_S_NODES, _S_WEIGHTS), _HALF_PHI)
_BA_MU = np.sqrt(_BA_S)
_BA_SIN_COS = np.sqrt(1.0 - _BA_S) * np.cos(_BA_PHI)
# 8 nodes in [0, μc] (x = t) and 8 in [μc, 1] (x = t², the square-root edge above μc)
_KS_UPPER = np.repeat([0.0, 1.0], _MU_NODES.size)
_KS_X = np.concatenate([_MU_NODES, _MU_NODES**2])
_KS_JAC = np.concatenate([_MU_WEIGHTS, 2.0 * _MU_NODES * _MU_WEIGHTS])


def _node_axis(xp: Any, x: Any) -> Any:
    """``x`` with a trailing axis of length 1, to broadcast against a rule's nodes (a Python
    number as it is)."""
    return x[..., None] if hasattr(x, "shape") else x


def interface_albedo(xp: Any, mu: Array, eta: Array, alpha: Array, distribution: str,
                     transmitted: bool = False, boosted: bool = False) -> Array:
    """The interface's directional reflectance E(μ) (or, with ``transmitted``, its
    transmittance T(μ)) for light from a direction of cosine μ on the side where the relative
    index is η (η < 1: from inside the coat, total internal reflection included).

    Single-scattering microfacet interface (Walter et al. 2007, eq. 20 and 21): with facets
    m drawn from the visible normals of ω, E = E_m[F(ω·m, η) G2/G1(ω)] (the height-correlated
    masking of :func:`coat_reflection`, G2/G1(ω) = (1 + Λ(ω))/(1 + Λ(ω) + Λ(ω_r))) and
    T = E_m[(1 − F(ω·m, η)) G1(ω_t)] (separable), ω_r, ω_t the reflected and refracted
    directions (a reflection below the horizon counts as lost). With ``boosted``, E of the
    coat's reflection with its multiple scattering, E_ss (1 + c(μ)) (:func:`ms_ratio`, fitted
    to the walk's interface). ``Coated`` takes E only (its transmittance is 1 − E). The visible
    normals are reached from D cos θh dωh, 6 nodes in its fraction u (``_IF_TAN2``) and
    2 × 4 in azimuth, weight G1(μ) (ω·m) / (μ cos θh), the 48 nodes on one trailing axis
    that ``xp.sum`` adds up. α = 0 gives F(μ, η) and 1 − F(μ, η) exactly (the smooth
    interface). μ is floored at 1e-7, as in Λ: θ = 90° gives the value just above the
    horizon, its limit (the weight's ω·m / μ is 1 there for a smooth interface, not 0)."""
    mu = maximum(xp, mu, 1e-7)
    lam_i = _smith_lambda(xp, mu, alpha, distribution)
    g_o = 1.0 / (1.0 + lam_i)
    if boosted:
        g_o = g_o * (1.0 + ms_ratio(xp, mu, eta, alpha, distribution))
    mu, eta, alpha = _node_axis(xp, mu), _node_axis(xp, eta), _node_axis(xp, alpha)
    lam_i = _node_axis(xp, lam_i)
    dtype = getattr(mu, "dtype", None)
    sin = safe_sqrt(xp, 1.0 - mu * mu)
    tan2 = alpha * alpha * asarray(xp, _IF_TAN2[distribution], dtype)
    cos_h = 1.0 / xp.sqrt(1.0 + tan2)
    sin_h = safe_sqrt(xp, 1.0 - cos_h * cos_h)
    dot = mu * cos_h + sin * sin_h * asarray(xp, _IF_COS_PHI, dtype)
    c = clip(xp, dot, 0.0, 1.0)
    f = fresnel_dielectric(xp, c, eta)
    if transmitted:
        k = 1.0 - (1.0 - c * c) / (eta * eta)
        t_z = -mu / eta + (c / eta - safe_sqrt(xp, k)) * cos_h
        g = 1.0 / (1.0 + _smith_lambda(xp, -t_z, alpha, distribution))
        val = (1.0 - f) * g
        ok = (k > 0) & (t_z < 0) & (dot > 0)
    else:
        mu_r = 2.0 * dot * cos_h - mu
        # G2 / G1(ω) = (1 + Λ(ω)) / (1 + Λ(ω) + Λ(ω_r)), height-correlated as
        # coat_reflection
        val = f * (1.0 + lam_i) / (1.0 + lam_i + _smith_lambda(xp, mu_r, alpha, distribution))
        ok = (mu_r > 0) & (dot > 0)
    val = val * dot / (mu * cos_h)
    term = xp.where(ok, val, xp.zeros_like(val)) * asarray(xp, _IF_W, dtype)
    return xp.sum(term, axis=-1) * g_o


def _refracted(xp: Any, mu: Array, eta: Array) -> Array:
    """cos θ' of the direction refracted into the layer (sin θ' = sin θ / η), written
    √(μ² + η² − 1)/η: at η = 1 it is μ exactly in any precision (the form
    √(1 − (1 − μ²)/η²) loses a grazing μ < 1e-4 to float32's cancellation)."""
    return safe_sqrt(xp, mu * mu + (eta * eta - 1.0)) / eta


def _with_node_axis(base: Model) -> Model:
    """A grey base whose parameter arrays (ndim ≥ 1) get a trailing axis of length 1, to
    broadcast against a rule's node axis as μ does (:func:`_node_axis`); a base with colour
    channels, or with scalar parameters, as it is."""
    if base.channels:
        return base
    extended = {
        f: v[..., None]
        for f in base.array_fields
        if getattr(v := getattr(base, f), "ndim", 0) > 0
    }
    return dataclasses.replace(base, **extended) if extended else base


def base_albedo(xp: Any, base: Model, mu: Array, dtype: Any) -> Array:
    """The base's directional albedo at cosine μ, ∫ f cos dω by a 32-point rule: μ'² by
    4 Gauss–Legendre nodes, the azimuth by 4 on each side of π/2 (the Oren–Nayar kink),
    with the symmetry φ → −φ; the nodes on one trailing axis that ``xp.sum`` adds up (before
    the base's channel axis, if it has one). Exact for Lambert. A grey base's parameter
    arrays (one value per pixel, say) broadcast against μ's leading axes."""
    base = _with_node_axis(base)
    mu = _node_axis(xp, mu)
    sin = safe_sqrt(xp, 1.0 - mu * mu)
    m2 = asarray(xp, _BA_MU, dtype)
    c = mu * m2 + sin * asarray(xp, _BA_SIN_COS, dtype)
    f = base.evaluate(xp, mu + 0.0 * m2, m2 + 0.0 * mu, c, dtype)
    w = asarray(xp, _BA_W, dtype)
    if base.channels:
        return xp.sum(f * w[..., None], axis=-2)
    return xp.sum(f * w, axis=-1)


_EB_NODES, _EB_WEIGHTS = gauss_legendre(8)
_DATA = Path(__file__).resolve().parent.parent / "data"
_TABLE = _DATA / "coat_interface.npz"
_LOBE_TABLE = _DATA / "coat_lobe.npz"
_FIT_POWERS = tuple((i, j, k) for i in range(1, 4) for j in range(1, 4) for k in range(4))
"""Monomials x^i α^j (1 − μ)^k of the fitted multiple-scattering reflection (x = 1 − 1/η:
0 at η = 1, where nothing is reflected; α^j: 0 for a smooth coat)."""


def _monomials(xp: Any, eta: Array, alpha: Array) -> tuple[list[Any], list[Any]]:
    """[1, x, x², x³] and [1, a, a², a³], x = 1 − 1/η clamped to [0, 2/3] (η in [1, 3]), a = α
    clamped to [0, 1]: the variables of the fitted polynomials (:func:`ms_fit`,
    :func:`lobe_fit`), held at the ends of the fitted range beyond it."""
    x = clip(xp, 1.0 - 1.0 / eta, 0.0, 2.0 / 3.0)
    a = clip(xp, alpha, 0.0, 1.0)
    return [1.0, x, x * x, x * x * x], [1.0, a, a * a, a * a * a]


@functools.lru_cache(maxsize=2)
def ms_fit(distribution: str) -> tuple[float, ...]:
    """The coefficients of :func:`ms_ratio` (of the monomials :data:`_FIT_POWERS`), as
    stored in ``data/coat_interface.npz`` (``coef``, one row per distribution) by
    ``scripts/coat_interface_tables.py``: least squares (weight √μ E_ss, the reflectance
    each relative error multiplies, seen at cosine μ) of c = ΔE/E_ss, ΔE the walk's
    reflectance from above (the multiple-scattering microsurface) minus the
    single-scattering E_ss (:func:`interface_albedo`), over that file's table (η in
    [1.05, 3], α in [0.025, 1], 12 μ). Nothing is fitted here."""
    with np.load(_TABLE) as t:
        coef = np.asarray(t["coef"], np.float64)[COAT_DISTRIBUTIONS.index(distribution)]
    return tuple(float(c) for c in coef)


def ms_ratio(xp: Any, mu: Array, eta: Array, alpha: Array, distribution: str) -> Array:
    """c(μ) = ΔE/E_ss ≥ 0: the rough coat's directional reflectance by more than one facet
    event relative to its single scattering (light from above at cosine μ), a polynomial
    fitted to the walk (:func:`ms_fit`; arithmetic only; η clamped to [1, 3], α to [0, 1];
    c = 0 at η = 1 and α = 0). The coat reflects E = E_ss (1 + c) and transmits 1 − E."""
    coef = ms_fit(distribution)
    xs, as_ = _monomials(xp, eta, alpha)
    u = 1.0 - clip(xp, mu, 0.0, 1.0)
    us = [1.0, u, u * u, u * u * u]
    total = 0.0 * u
    for c, (i, j, k) in zip(coef, _FIT_POWERS, strict=True):
        total = total + c * (xs[i] * as_[j] * us[k])
    return maximum(xp, total, 0.0)


LOBE_WIDTHS: tuple[float, ...] = (0.7, 1.0, 2.0)
"""The multiple-scattering lobe is a sum of single-scattering lobes of roughness s α for
these s (:func:`ms_lobe`): Beckmann's second reflections gather closer to the mirror
direction than its first (s < 1), GGX's spread wider (s > 1)."""


def _lobe_terms(xp: Any, mu_i: Array, mu_o: Array) -> list[Any]:
    """The symmetric polynomials of degree up to 4 in v = 1 − μ (0 along the normal, 1 at
    grazing), 1, vi + vo, vi² + vo², vi vo, vi³ + vo³, vi vo (vi + vo), vi⁴ + vo⁴,
    vi vo (vi² + vo²), vi² vo²: the angular weights of each lobe of :func:`ms_lobe`
    (symmetric, so that it stays reciprocal); μ clamped to [0, 1]."""
    vi = 1.0 - clip(xp, mu_i, 0.0, 1.0)
    vo = 1.0 - clip(xp, mu_o, 0.0, 1.0)
    s1, p = vi + vo, vi * vo
    s2 = vi * vi + vo * vo
    return [1.0 + 0.0 * p, s1, s2, p, vi * vi * vi + vo * vo * vo, p * s1,
            vi * vi * vi * vi + vo * vo * vo * vo, p * s2, p * p]


@functools.lru_cache(maxsize=2)
def lobe_fit(distribution: str) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The α nodes and the coefficients of :func:`ms_lobe`, as stored in
    ``data/coat_lobe.npz`` (``alphas``; ``coef``, one row per distribution) by
    ``scripts/coat_lobe_tables.py``: weighted least squares of the walk's f_ms at the table's
    geometries (η in [1.2, 3], α in [0.05, 1], 270 geometries) together with the lobe's
    own albedo against what the coat reflects beyond its single-scattering lobe, E(μ)
    (:func:`interface_albedo`, boosted) minus that lobe's albedo, from θ = 0 to 89° and for
    α from 0.01 to 1: the white furnace stays 1 where the table's azimuths cannot resolve
    the narrow lobes (small α, grazing). Nothing is fitted here."""
    with np.load(_LOBE_TABLE) as t:
        nodes = tuple(float(a) for a in t["alphas"])
        coef = np.asarray(t["coef"], np.float64)[COAT_DISTRIBUTIONS.index(distribution)]
    return nodes, tuple(float(c) for c in coef)


def _lobe_basis(xp: Any, eta: Array, alpha: Array, nodes: tuple[float, ...],
                dtype: Any) -> Any:
    """x^i times the hat of α's node h (x = 1 − 1/η as :func:`_monomials` clamps it; the hat
    of node h rises from the node before it, 0 for the first, so the weights vanish with α,
    and falls to the one after: piecewise-linear interpolation in α), for i = 1..3 and each
    node, on one trailing axis of 3 × len(nodes) in :func:`lobe_fit`'s order
    (i major): the polynomials p_st of :func:`ms_lobe` are each one ``xp.sum`` of it times
    their coefficients (30 products on an axis, where 30 separate terms made JAX's forward
    derivative of ``Coated`` too large for XLA to compile)."""
    n = len(nodes)
    left = (0.0, *nodes[:-1]) * 3
    node = tuple(nodes) * 3
    right = (*nodes[1:], 2.0) * 3  # the last node: (2 − a)/(2 − 1) ≥ 1, no falling side
    x = _node_axis(xp, clip(xp, 1.0 - 1.0 / eta, 0.0, 2.0 / 3.0))
    a = _node_axis(xp, clip(xp, alpha, 0.0, 1.0))
    c = {name: asarray(xp, v, dtype) for name, v in (
        ("left", left), ("node", node), ("right", right),
        ("m1", (1.0,) * n + (0.0,) * 2 * n), ("m2", (0.0,) * n + (1.0,) * n + (0.0,) * n),
        ("m3", (0.0,) * 2 * n + (1.0,) * n))}
    up = clip(xp, (a - c["left"]) / (c["node"] - c["left"]), 0.0, 1.0)
    hat = up + clip(xp, (c["right"] - a) / (c["right"] - c["node"]), 0.0, 1.0) - 1.0
    x2 = x * x
    return (x * c["m1"] + x2 * c["m2"] + x2 * x * c["m3"]) * hat


def ms_lobe(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, eta: Array, alpha: Array,
            distribution: str) -> Array:
    """f_ms: the rough coat's reflection by two or more facet events (the multiple-scattering
    dielectric microsurface of Heitz, Hanika, d'Eon and Dachsbacher 2016), as
    Σ_s f_ss(s α) Σ_t p_st(x, α) w_t(μi, μo): single-scattering lobes
    (:func:`coat_reflection`) of the widths :data:`LOBE_WIDTHS` times the symmetric angular
    weights w_t (:func:`_lobe_terms`), p_st cubic in x = 1 − 1/η (no constant term) and
    piecewise linear in α between the table's nodes (:func:`_lobe_basis`; 0 at α = 0),
    fitted to the walk (:func:`lobe_fit`; arithmetic only). Reciprocal; 0 at η = 1 and
    α = 0."""
    nodes, coef = lobe_fit(distribution)
    basis = _lobe_basis(xp, eta, alpha, nodes, getattr(mu_i, "dtype", None))
    width = 3 * len(nodes)
    terms = _lobe_terms(xp, mu_i, mu_o)
    total = 0.0 * terms[0]
    k = 0
    for s in LOBE_WIDTHS:
        weight = 0.0 * terms[0]
        for t in terms:
            p = xp.sum(basis * asarray(xp, coef[k : k + width], basis.dtype), axis=-1)
            k += width
            weight = weight + p * t
        total = total + weight * coat_reflection(xp, mu_i, mu_o, cos_io, eta, alpha * s,
                                                 distribution)
    return total


def coat_lobe(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, eta: Array, alpha: Array,
              distribution: str) -> Array:
    """The rough coat's whole reflection, f_ss + f_ms (:func:`coat_reflection`,
    :func:`ms_lobe`), floored at 0; 0 for α = 0."""
    f = coat_reflection(xp, mu_i, mu_o, cos_io, eta, alpha, distribution) + ms_lobe(
        xp, mu_i, mu_o, cos_io, eta, alpha, distribution)
    return maximum(xp, f, 0.0)


def _mean_reflectance(xp: Any, eta: Array, alpha: Array, distribution: str,
                      dtype: Any) -> Array:
    """Ē = ∫ E(μ) 2μ dμ, E the coat's reflectance from above (:func:`interface_albedo`),
    8 Gauss–Legendre nodes in μ on one trailing axis."""
    mu_e = asarray(xp, _EB_NODES, dtype)
    eta_n, alpha_n = _node_axis(xp, eta), _node_axis(xp, alpha)
    mu_n = mu_e + 0.0 * eta_n
    e = interface_albedo(xp, mu_n, eta_n, alpha_n, distribution, boosted=True)
    return xp.sum(e * 2.0 * mu_e * asarray(xp, _EB_WEIGHTS, dtype), axis=-1)


def _internal_sums(xp: Any, base: Model, eta: Array, tau: Array, alpha: Array,
                   distribution: str, dtype: Any, channels: bool = False):
    """K = ∫ R(μ) e^{−2τ/μ} 2μ dμ and ā K = ∫ a(μ) R(μ) e^{−2τ/μ} 2μ dμ, R the coat's
    reflectance from inside (:func:`interface_albedo` with 1/η; F(μ, 1/η) when smooth).
    A rough interface loses no light (the multiple-scattering microsurface of Heitz,
    Hanika, d'Eon and Dachsbacher 2016): T = 1 − R on both sides, and the reciprocity of a
    dielectric interface, η² T̄_below = T̄_above, gives its K at τ = 0 exactly,
    1 − (1 − Ē)/η² (:func:`_mean_reflectance`); the single-scattering R misses part of it,
    which is added as a diffuse (constant) reflectance. The rules are
    split at the critical cosine μc = √(1 − 1/η²) (R = 1 below it when smooth; μc = 0 for
    η ≤ 1): 8 nodes on each side, on one trailing axis (in √(μ − μc) above μc, where
    F(μ, 1/η) − 1 has a square-root edge). With ``channels``, both are per channel (a
    trailing axis after the nodes): τ, the base's albedo, or both carry one."""
    mu_c = _node_axis(xp, safe_sqrt(xp, 1.0 - 1.0 / (eta * eta)))
    upper = asarray(xp, _KS_UPPER, dtype)
    lo = mu_c * upper
    width = mu_c + (1.0 - 2.0 * mu_c) * upper  # μc below it, 1 − μc above
    mu = lo + width * asarray(xp, _KS_X, dtype)
    r = interface_albedo(xp, mu, 1.0 / _node_axis(xp, eta), _node_axis(xp, alpha), distribution)
    cosine = width * asarray(xp, _KS_JAC, dtype) * 2.0 * mu  # its sum is ∫ 2μ dμ = 1
    # what the single-scattering R misses of the rough interface's own K = 1 − (1 − Ē)/η²,
    # spread evenly over the cosine-weighted hemisphere; 0 for a smooth coat (K_ss exact)
    missing = 1.0 - (1.0 - _mean_reflectance(xp, eta, alpha, distribution, dtype)) / (
        eta * eta) - xp.sum(cosine * r, axis=-1)
    missing = xp.where(alpha > 0, missing, 0.0 * missing)
    term = cosine * (r + _node_axis(xp, missing))
    a = base_albedo(xp, _with_node_axis(base), mu, dtype)
    if channels:
        term, mu = term[..., None], mu[..., None]
        a = a if base.channels else a[..., None]
        term = term * xp.exp(-2.0 * tau / maximum(xp, mu, 1e-12))
        return xp.sum(term, axis=-2), xp.sum(term * a, axis=-2)
    term = term * xp.exp(-2.0 * _node_axis(xp, tau) / maximum(xp, mu, 1e-12))
    return xp.sum(term, axis=-1), xp.sum(term * a, axis=-1)


def _coat_sample(xp: Any, u1, u2, wox, woy, woz, p: dict, distribution: str):
    """Half vector h ∝ D(h) n·h (GGX: tan²θh = α² u/(1 − u); Beckmann: −α² ln(1 − u)),
    wi the reflection of wo about it."""
    a2 = p["roughness"] * p["roughness"]
    if distribution == "ggx":
        tan2 = a2 * safe_div(xp, u1, 1.0 - u1)
    else:
        tan2 = -a2 * xp.log(maximum(xp, 1.0 - u1, 1e-300))
    cos_h = 1.0 / xp.sqrt(1.0 + tan2)
    sin_h = safe_sqrt(xp, 1.0 - cos_h * cos_h)
    phi = (2.0 * math.pi) * u2
    hx, hy, hz = sin_h * xp.cos(phi), sin_h * xp.sin(phi), cos_h
    dot = wox * hx + woy * hy + woz * hz
    return 2.0 * dot * hx - wox, 2.0 * dot * hy - woy, 2.0 * dot * hz - woz


def _coat_pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, p: dict, distribution: str) -> Array:
    hx, hy, hz = wix + wox, wiy + woy, wiz + woz
    inv = safe_div(xp, 1.0, safe_sqrt(xp, hx * hx + hy * hy + hz * hz))
    cos_h = hz * inv
    dot = (wox * hx + woy * hy + woz * hz) * inv
    alpha = maximum(xp, p["roughness"], 1e-7)
    val = safe_div(xp, _ndf(xp, cos_h, alpha, distribution) * cos_h, 4.0 * dot)
    return xp.where((wiz > 0) & (dot > 0) & (cos_h > 0), val, 0.0 * val)


def coat_strategy(distribution: str) -> Strategy:
    """Sampling of a coat: its microfacet reflection with probability q = F(μo, η) when the
    coat is rough (0 when smooth), else the cosine lobe for the base; the density is the
    mixture's, q p_coat + (1 − q) cos θi / π."""

    def selection(xp: Any, woz: Array, p: dict) -> Array:
        q = fresnel_dielectric(xp, clip(xp, woz, 0.0, 1.0), p["eta"])
        return xp.where(p["roughness"] > 0, q, 0.0 * q)

    def pdf(xp: Any, wix, wiy, wiz, wox, woy, woz, p: dict) -> Array:
        q = selection(xp, woz, p)
        cos = xp.where(wiz > 0, wiz * _INV_PI, 0.0 * wiz)
        spec = _coat_pdf(xp, wix, wiy, wiz, wox, woy, woz, p, distribution)
        return q * spec + (1.0 - q) * cos

    def sample(xp: Any, u1, u2, wox, woy, woz, p: dict):
        q = selection(xp, woz, p)
        use_coat = u1 < q
        uc = xp.where(use_coat, safe_div(xp, u1, q), 0.5 + 0.0 * u1)
        ub = xp.where(use_coat, 0.5 + 0.0 * u1, safe_div(xp, u1 - q, 1.0 - q))
        sx, sy, sz = _coat_sample(xp, uc, u2, wox, woy, woz, p, distribution)
        r = safe_sqrt(xp, ub)
        phi = (2.0 * math.pi) * u2
        x = xp.where(use_coat, sx, r * xp.cos(phi))
        y = xp.where(use_coat, sy, r * xp.sin(phi))
        z = xp.where(use_coat, sz, safe_sqrt(xp, 1.0 - ub))
        return x, y, z, pdf(xp, x, y, z, wox, woy, woz, p)

    return Strategy(f"coat-{distribution}", sample, pdf)


COAT_GGX = coat_strategy("ggx")
COAT_BECKMANN = coat_strategy("beckmann")


class Coated(Model):
    """A dielectric coat of index η (smooth, or rough with α) over a base model.

    Parameters
    ----------
    base : Model or str
        The base: a model instance, or a registry id with ``base_params`` (e.g.
        ``base="oren-nayar-full", base_params={"albedo": 0.8, "sigma": 0.3}``). It must be
        a closed form or a table (not a simulation such as ``SmithDiffuse``), and not a coat.
    eta : float
        Relative refractive index η of the coat in [1, 5] (:data:`COAT_ETA_RANGE`; 1.5 for
        glazes and plastics).
    roughness : float
        The coat's roughness α in [0, 1] (0: smooth, a mirror reflection that the BRDF value
        does not hold).
    distribution : {"ggx", "beckmann"}
        The rough coat's facet distribution.
    absorption : float or array (C,)
        Optical depth τ ≥ 0 of the layer at normal incidence (thickness × absorption
        coefficient), one number or one per colour channel (as many as the base has, if it
        has channels): a tinted coat over a grey base gives a coloured BRDF.
    base_params : dict, optional
        Parameters of the base when it is given by id.

    Examples
    --------
    Over a white Lambertian base the smooth coat at normal incidence and view gives
    (1 − F0)² / (π η² (1 − K)), K = 0.5963 for η = 1.5:

    >>> import numpy as np
    >>> from roughdiffuse import Lambert
    >>> w = np.array([0.0, 0.0, 1.0])
    >>> f = float(Coated(Lambert(1.0), eta=1.5).brdf(w, w))
    >>> round(f * np.pi, 3)  # 0.9216 / (2.25 × 0.4037) = 1.0146
    1.015
    """

    base: Any = None
    eta: float | Array = param("relative refractive index η of the coat",
                               min=COAT_ETA_RANGE[0], max=COAT_ETA_RANGE[1], default=1.5,
                               fit_range=(1.05, 3.0))
    roughness: float | Array = param("α, roughness of the coat (0: smooth)", min=0.0, max=1.0,
                                     default=0.0, fit_range=(0.0, 1.0))
    distribution: str = param("facet distribution of the rough coat",
                              choices=COAT_DISTRIBUTIONS, default="ggx")
    absorption: float | Array = param("τ, optical depth of the coat (thickness × absorption)",
                                      min=0.0, max=50.0, default=0.0, channels=True)
    base_params: Any = None

    is_coat: ClassVar[bool] = True
    array_fields: ClassVar[tuple[str, ...]] = ("base", "eta", "roughness", "absorption")
    channel_fields: ClassVar[tuple[str, ...]] = ("absorption",)
    # The registry's "coated": a coat over the base of registry id `base` (one of COAT_BASES)
    # with albedo ρ and the base's own parameter: σ (Oren–Nayar), r (Fujii, EON, as
    # base_roughness: the coat's roughness is α), none (Lambert). See from_params. The
    # coat's own parameters follow, declared on its fields.
    factory_params: ClassVar[tuple[Param, ...]] = (
        Param("base", "base under the coat (registry id)", choices=COAT_BASES,
              default="oren-nayar-full"),
        Param("albedo", "albedo ρ of the base", min=0.0, max=1.0,
              default=0.8, channels=True, example=0.8),
        _base_param(OrenNayar, "sigma", "sigma", _ON_BASES,
                    "σ of the Oren–Nayar base, slope-angle standard deviation (0: Lambert)",
                    default=0.3),
        _base_param(EON, "roughness", "base_roughness", _FON_BASES,
                    "r of the Fujii or EON base, Fujii's roughness (not an angle)",
                    default=0.5),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"coated": {}}
    labels: ClassVar[dict[str, str]] = {"coated": "Coated: dielectric coat over a diffuse base"}
    reference: ClassVar[str] = (
        "A. Weidlich, A. Wilkie, Arbitrarily layered micro-facet surfaces, GRAPHITE (2007); "
        "Mitsuba 3 plastic"
    )
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "sigma": r"\sigma",
        "base_roughness": r"r",
        "eta": r"\eta",
        "roughness": r"\alpha",
        "absorption": r"\tau",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = f_{\text{coat}}(\eta,\alpha) + \frac{T_\alpha(\mu_i)\,T_\alpha(\mu_o)}{\eta^2}
        \Big[f_b(\omega_i',\omega_o')\,e^{-\tau/\mu_i'-\tau/\mu_o'}
        + \frac{a(\mu_i')\,a(\mu_o')\,e^{-\tau/\mu_i'-\tau/\mu_o'}\,K}{\pi\,(1-\bar a K)}\Big]
        ```

        A dielectric coat of index {math}`\eta` and roughness {math}`\alpha` over the base
        {math}`f_b` of registry id ``base``: {doc}`lambert` ({math}`\rho`),
        {doc}`oren-nayar` or {doc}`oren-nayar-full` ({math}`\rho`, {math}`\sigma`),
        {doc}`fujii` or {doc}`eon` ({math}`\rho` and {math}`r`, ``base_roughness``),
        evaluated at the refracted directions; {math}`T_\alpha = 1 - E_\alpha(\mu)` the
        coat's transmittance, its own energy (what it does not reflect enters),
        {math}`a` the base's directional albedo, {math}`K = 1 - (1 - \bar E_\alpha)/\eta^2`
        the coat's internal diffuse reflectance (exact for a lossless interface, without
        absorption), {math}`\tau` the layer's optical depth; {math}`f_{\text{coat}}` has
        the height-correlated masking of the Smith microsurface and its multiple scattering,
        a sum of lobes of roughness 0.7 α, α and 2 α fitted to the exact interface (within
        1 % of the white furnace). The truth is
        {mod}`roughdiffuse.simulate.layered`, whose rough interface is the exact
        multiple-scattering microsurface of Heitz, Hanika, d'Eon and Dachsbacher (2016).
        """
    traceable: ClassVar[bool] = True
    """Traced by jax.jit and compiled by the fast path: the node rules are arrays with a
    trailing node axis that ``xp.sum`` adds up (a loop in the compiled kernel), not unrolled
    Python loops."""
    order: ClassVar[int] = 175

    @classmethod
    def from_params(
        cls,
        albedo: float | Array = 0.8,
        sigma: float | Array | None = None,
        eta: float | Array = 1.5,
        roughness: float | Array = 0.0,
        distribution: str = "ggx",
        absorption: float | Array = 0.0,
        base: str = "oren-nayar-full",
        base_roughness: float | Array | None = None,
    ) -> Coated:
        """The registry's ``coated``: a coat over the base of id ``base`` (one of
        :data:`COAT_BASES`) with albedo ``albedo`` and its own parameter: ``sigma`` for
        Oren–Nayar (default 0.3), ``base_roughness`` (r, default 0.5) for Fujii and EON,
        none for Lambert. A base parameter the base does not take must be left ``None``.

        >>> Coated.from_params(albedo=0.5, sigma=0.0).base
        OrenNayar(albedo=0.5, sigma=0.0, variant='full')
        >>> Coated.from_params(albedo=0.5, base="eon", base_roughness=0.2).base
        EON(albedo=0.5, roughness=0.2)
        """
        declared = {p.name: p for p in cls.params}
        _check_base_id(base)
        given = {"sigma": sigma, "base_roughness": base_roughness}
        base_params: dict[str, Any] = {"albedo": albedo}
        for name, value in given.items():
            p = declared[name]
            if not p.applies({"base": base}):
                if value is not None:
                    raise ParameterError(
                        f"{name} applies only with {p.when_text()} (got {name}={value!r} "
                        f"with base={base!r})"
                    )
                continue
            base_params[_BASE_PARAMS[name]] = p.check(p.default if value is None else value)
        model = _model_by_id(base, base_params)
        return cls(model, eta, roughness, distribution, absorption)

    def __post_init__(self) -> None:
        from ..simulate.layered import check_base

        base = self.base
        if isinstance(base, str):
            base = _model_by_id(base, dict(self.base_params or {}))
        elif self.base_params is not None:
            raise ParameterError("base_params applies only with a base given by id (a string)")
        elif base is None:
            raise ParameterError("base must be a model or a registry id (got None)")
        object.__setattr__(self, "base", check_base(base))
        object.__setattr__(self, "base_params", None)
        super().__post_init__()
        tau_channels = Model.channels.fget(self)  # type: ignore[attr-defined]
        if tau_channels and base.channels and tau_channels != base.channels:
            raise ParameterError(
                f"absorption has {tau_channels} channels, the base {base.channels}: give one "
                "number or one per channel of the base"
            )

    def _validate(self) -> None:
        """The coat's own parameters (η, α, distribution, τ: those declared on its fields)
        checked by name; the field ``base`` holds the base model
        (:func:`~roughdiffuse.simulate.layered.check_base`), where the declared ``base`` is the
        registry's choice of id (:meth:`from_params`)."""
        for p in declared_params(dataclasses.fields(self)):
            object.__setattr__(self, p.name, p.check(getattr(self, p.name)))

    # ------------------------------------------------------------------ parameters
    def parameter_values(self) -> list[Any]:
        return [*self.base.parameter_values(), self.eta, self.roughness, self.absorption]

    def parameter_arrays(self, xp: Any, dtype: Any = None) -> dict[str, Any]:
        return {
            "eta": asarray(xp, self.eta, dtype),
            "roughness": asarray(xp, self.roughness, dtype),
            "absorption": asarray(xp, self.absorption, dtype),
            "base": self.base.parameter_arrays(xp, dtype),
        }

    @property
    def channels(self) -> int:
        """The base's channels, or the absorption's (one per channel) over a grey base."""
        return self.base.channels or Model.channels.fget(self)  # type: ignore[attr-defined]

    def channel(self, c: int) -> Coated:
        """This coat (its absorption of channel ``c``) over the base's channel ``c``."""
        tau = self.absorption
        if getattr(tau, "ndim", 0) == 1:
            tau = tau[c]
        base = self.base.channel(c) if self.base.channels else self.base
        return Coated(base, self.eta, self.roughness, self.distribution, tau)

    @property
    def lobes(self) -> frozenset[str]:
        """The base's lobe and the coat's glossy reflection."""
        return frozenset({"diffuse", "glossy"})

    def sampling_strategy(self) -> Strategy:
        """:func:`coat_strategy` of this coat's distribution."""
        return COAT_BECKMANN if self.distribution == "beckmann" else COAT_GGX

    def albedo_estimate(self, xp: Any, mu_o: Array, p: dict[str, Any]) -> Array:
        """The base's estimate (it is what a coat mostly reflects in a :class:`Mix`)."""
        return self.base.albedo_estimate(xp, mu_o, p["base"])

    # ------------------------------------------------------------------ formula
    def evaluate(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, dtype: Any) -> Array:
        p = self.parameter_arrays(xp, dtype)
        eta, alpha, tau = p["eta"], p["roughness"], p["absorption"]
        # a rough α below ALPHA_FLOOR is evaluated at the floor: its lobe is a mirror's to
        # float precision, and powers of a subnormal α overflow (α = 0 stays smooth)
        alpha = xp.where(alpha > 0, maximum(xp, alpha, ALPHA_FLOOR), alpha)
        above = (mu_i >= 0) & (mu_o >= 0)
        mi, mo = clip(xp, mu_i, 0.0, 1.0), clip(xp, mu_o, 0.0, 1.0)
        c = clip(xp, cos_io, -1.0, 1.0)
        ri, ro = _refracted(xp, mi, eta), _refracted(xp, mo, eta)
        inv_eta2 = 1.0 / (eta * eta)
        # ri ro + (c − μi μo)/η², grouped so that η = 1 gives c plus a difference of equal
        # products (float32: the form above loses c − μi μo at grazing to cancellation)
        cos_in = clip(xp, c * inv_eta2 + (ri * ro - mi * mo * inv_eta2), -1.0, 1.0)
        dist = self.distribution
        # the rough interface's own energy: what it does not reflect enters (T = 1 − E, as
        # for a multiple-scattering microsurface, which loses nothing); E = E_ss (1 + c),
        # its reflectance with the multiple scattering (ms_ratio, fitted to the walk)
        trans = (1.0 - interface_albedo(xp, mi, eta, alpha, dist, boosted=True)) * (
            1.0 - interface_albedo(xp, mo, eta, alpha, dist, boosted=True))
        single = self.base.evaluate(xp, ri, ro, cos_in, dtype)
        chan = self.channels > 0
        k, ak = _internal_sums(xp, self.base, eta, tau, alpha, dist, dtype, chan)
        a_i = base_albedo(xp, self.base, ri, dtype)
        a_o = base_albedo(xp, self.base, ro, dtype)
        weight = trans * inv_eta2
        spec = coat_lobe(xp, mi, mo, c, eta, alpha, dist)
        if chan:
            weight, spec, above = weight[..., None], spec[..., None], above[..., None]
            ri, ro = ri[..., None], ro[..., None]
            if not self.base.channels:  # channels from the absorption alone
                single, a_i, a_o = single[..., None], a_i[..., None], a_o[..., None]
        att_i = xp.exp(-tau / maximum(xp, ri, 1e-12))
        att_o = xp.exp(-tau / maximum(xp, ro, 1e-12))
        multi = a_i * a_o * safe_div(xp, k, 1.0 - ak) * _INV_PI
        val = spec + weight * att_i * att_o * (single + multi)
        return xp.where(above, val, xp.zeros_like(val))

    def directional_albedo(self, wo: Array) -> Array:
        """∫ f cos θi dωi: the default quadrature over the hemisphere, with the rough coat's
        own reflection (a narrow lobe the rule may miss) taken out of it and integrated by
        its half-vector rule instead (:meth:`TorranceSparrow.directional_albedo`'s
        substitution). The coat's reflection alone is this coat over a black base. The
        smooth coat's mirror reflection, a delta, is not included, as it is not in the
        BRDF."""
        total = Model.directional_albedo(self, wo)
        if float(np.max(np.asarray(self.roughness))) == 0.0:
            return total
        black = Coated(Lambert(0.0), self.eta, self.roughness, self.distribution)
        correction = _coat_albedo(self, wo) - np.asarray(Model.directional_albedo(black, wo))
        if self.channels:
            correction = correction[..., None]
        return total + correction


def _check_base_id(base: object) -> None:
    """Refuse a ``base`` the registry's ``coated`` does not offer, naming why and the ids it
    takes (:data:`COAT_BASES`)."""
    if isinstance(base, str) and base in COAT_BASES:
        return
    from .. import registry

    choices = ", ".join(map(repr, COAT_BASES))
    known = isinstance(base, str) and base in registry.ids()
    cls = registry.get(base).cls if known else None
    if cls is None:
        why = "is not a model id" if isinstance(base, str) else "must be a registry id"
    elif getattr(cls, "is_coat", False):
        why = "is a coat: a coat on a coat is not supported"
    elif not cls.closed_form:
        why = "is a simulation, which cannot be evaluated at the refracted directions"
    else:
        why = ("is not a base the registry's coated offers (in Python, "
               "Coated(base=..., base_params=...) coats any closed form)")
    raise ParameterError(f"base {base!r} {why}; choose one of {choices}")


def _model_by_id(model_id: str, params: dict[str, Any]) -> Model:
    """The registry's model of id ``model_id`` with ``params``."""
    from .. import registry

    if model_id not in registry.ids():
        known = ", ".join(registry.ids())
        raise ParameterError(f"base: unknown model id {model_id!r}; choose one of: {known}")
    return registry.create(model_id, **params)


def half_vector_rule(mu_o: np.ndarray, alpha: float, distribution: str,
                     n: int = 96) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A rule for ∫ g(ωi) μi dωi of a lobe g around the mirror direction of ωo (cosine
    ``mu_o``, any shape ...), NumPy, over the half vector: Gauss–Legendre in θh to
    atan(10 s α) (Beckmann) or atan(100 s α) (GGX), s the widest of :data:`LOBE_WIDTHS`, and
    in φh over [0, π], doubled (ωo in the xz-plane). Returns μi (clamped to [0, 1]) and
    cos(ωi, ωo) of shape (..., n, n) and the weights, μi and the Jacobian 4 (ωo·h) sin θh
    included (0 where ωi is below the horizon): the sum of g times them is the integral.
    Beckmann's α is taken at least :data:`~roughdiffuse.models.microfacet.ALPHA_FLOOR`
    (1.4e-4), the narrowest D that :func:`_ndf` evaluates."""
    mu_o = np.clip(np.asarray(mu_o, np.float64), 0.0, 1.0)[..., None, None]
    sin_o = np.sqrt(1.0 - mu_o * mu_o)
    if distribution == "beckmann":
        alpha = max(alpha, microfacet.ALPHA_FLOOR)
    reach = (10.0 if distribution == "beckmann" else 100.0) * max(LOBE_WIDTHS)
    theta_max = math.atan(reach * alpha)
    t, w = gauss_legendre(n)
    th = theta_max * t[:, None]
    ph = math.pi * t[None, :]
    cos_oh = sin_o * np.sin(th) * np.cos(ph) + mu_o * np.cos(th)
    mu_i = 2.0 * cos_oh * np.cos(th) - mu_o
    cos_io = 2.0 * cos_oh * cos_oh - 1.0
    jac = 4.0 * np.maximum(cos_oh, 0.0) * np.sin(th)
    weights = (theta_max * w)[:, None] * (2.0 * math.pi * w)[None, :]
    weights = np.maximum(mu_i, 0.0) * jac * weights * (mu_i > 0)
    return np.clip(mu_i, 0.0, 1.0), cos_io, weights


def _coat_albedo(model: Coated, wo: Array, n: int = 96) -> Array:
    """∫ f_coat cos θi dωi by :func:`half_vector_rule`, NumPy; f_coat with its multiple
    scattering (:func:`coat_lobe`)."""
    from ..frames import unit_components

    _, _, z = unit_components(np, np.asarray(wo, dtype=np.float64), "wo")
    alpha = float(model.roughness)
    mu_i, cos_io, weights = half_vector_rule(z, alpha, model.distribution, n)
    mu_o = np.clip(z, 0.0, 1.0)[..., None, None] + 0.0 * mu_i
    f = coat_lobe(np, mu_i, mu_o, cos_io, float(model.eta), alpha, model.distribution)
    return np.where(z >= 0, np.sum(f * weights, axis=(-2, -1)), 0.0)
