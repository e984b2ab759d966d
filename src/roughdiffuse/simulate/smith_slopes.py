"""Isotropic Beckmann and GGX slope statistics for the Smith microsurface (NumPy, float64).

Everything the Smith solver (:mod:`roughdiffuse.simulate.smith`) needs of a slope
distribution of roughness α, for directions on the whole sphere:

* :func:`smith_lambda` — Smith's Λ(ω) (Heitz 2014, "Understanding the masking-shadowing
  function in microfacet-based BRDFs", JCGT 3(2), eqs. 72 and 86), with Λ(−ω) = −1 − Λ(ω)
  for directions below the horizon (Heitz, Hanika, d'Eon, Dachsbacher 2016, "Multiple-
  scattering microfacet BSDFs with the Smith model", Sec. 3);
* :func:`slope_cdf_inverse` — tan θm as a function of the projected-area fraction of normals
  below θm (the measure D(ωm) cos θm dωm, Heitz 2014 eq. 4), used by the quadrature;
* :func:`sample_visible_normals` — normals distributed as the visible normals
  D_ωi(ωm) = ⟨ωi, ωm⟩⁺ D(ωm) / ∫⟨ωi, ω⟩⁺ D(ω) dω (Heitz & d'Eon 2014, "Importance sampling
  microfacet-based BSDFs using the distribution of visible normals", eq. 2), for ωi above or
  below the horizon: GGX by spherical caps (Dupuy & Benyoub 2023, "Sampling visible GGX
  normals with spherical caps", Listing 3), Beckmann in the stretched configuration α = 1
  (Heitz & d'Eon 2014, Sec. 4: P22 visible ∝ (cos θ − x̃ sin θ)⁺ exp(−x̃² − ỹ²)) by exact
  composition and rejection sampling of x̃.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import erf, erfcx, erfinv

__all__ = [
    "DISTRIBUTIONS",
    "check_distribution",
    "sample_visible_normals",
    "slope_cdf_inverse",
    "smith_lambda",
]

DISTRIBUTIONS: tuple[str, ...] = ("beckmann", "ggx")
_SQRT_PI = math.sqrt(math.pi)


def check_distribution(distribution: object) -> str:
    """Validate the slope distribution's name ("beckmann" or "ggx")."""
    if distribution not in DISTRIBUTIONS:
        raise ValueError(f"distribution must be one of {DISTRIBUTIONS} (got {distribution!r})")
    return str(distribution)


def _lambda_upper(distribution: str, cot: np.ndarray, alpha: float) -> np.ndarray:
    """Λ for a direction above the horizon given a = |cot θ| / α ≥ 0 (inf where a = 0)."""
    a = cot / alpha
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if distribution == "beckmann":
            # (erf(a) − 1)/2 + exp(−a²)/(2a√π), written with erfcx to avoid the cancellation
            lam = 0.5 * np.exp(-a * a) * (1.0 / (a * _SQRT_PI) - erfcx(a))
        else:
            t2 = 1.0 / (a * a)  # α² tan² θ
            lam = t2 / (2.0 * (1.0 + np.sqrt(1.0 + t2)))
    return np.where(a > 0.0, np.maximum(lam, 0.0), np.inf)


def smith_lambda(distribution: str, z: np.ndarray, alpha: float) -> np.ndarray:
    """Smith's Λ(ω) for unit directions with z-component ``z`` (isotropic roughness α).

    Above the horizon Λ ≥ 0 (Heitz 2014 eq. 72 for GGX, eq. 86 for Beckmann); below it
    Λ(ω) = −1 − Λ(−ω) ≤ −1 (Heitz et al. 2016, Sec. 3). At the horizon ±∞.

    Examples
    --------
    >>> import numpy as np
    >>> float(smith_lambda("ggx", np.array(1.0), 0.5))
    0.0
    >>> float(smith_lambda("beckmann", np.array(-1.0), 0.5))
    -1.0
    """
    z = np.asarray(z, dtype=np.float64)
    az = np.abs(z)
    sin = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        cot = np.where(sin > 0.0, az / np.where(sin > 0.0, sin, 1.0), np.inf)
    up = _lambda_upper(distribution, cot, alpha)
    up = np.where(np.isinf(cot), 0.0, up)
    return np.where(z >= 0.0, up, -1.0 - up)


def slope_cdf_inverse(distribution: str, s: np.ndarray, alpha: float) -> np.ndarray:
    """tan θm at which the projected-area fraction of normals steeper than θm is s².

    The projected-area measure D(ωm) cos θm dωm of an isotropic distribution has, for the
    fraction u below θm, u = 1 − exp(−tan²θm / α²) (Beckmann) and
    u = tan²θm / (α² + tan²θm) (GGX) (Walter et al. 2007, "Microfacet models for refraction
    through rough surfaces", eqs. 28 and 35). With u = 1 − s² the quadrature in s has a
    finite integrand at s → 0 for both tails.
    """
    s = np.asarray(s, dtype=np.float64)
    with np.errstate(divide="ignore"):
        if distribution == "beckmann":
            return alpha * np.sqrt(-2.0 * np.log(s))
        return alpha * np.sqrt(np.maximum(1.0 - s * s, 0.0)) / s


def slope_cdf(distribution: str, tan_theta: np.ndarray, alpha: float) -> np.ndarray:
    """The s of :func:`slope_cdf_inverse` at ``tan_theta`` (inverse of that function)."""
    q = (np.asarray(tan_theta, dtype=np.float64) / alpha) ** 2
    if distribution == "beckmann":
        return np.exp(-0.5 * q)
    return 1.0 / np.sqrt(1.0 + q)


def _visible_ggx(w: np.ndarray, alpha: float, u1: np.ndarray, u2: np.ndarray) -> np.ndarray:
    """GGX visible normals for directions ``w`` (N, 3) on the whole sphere (spherical caps)."""
    ws = np.stack([alpha * w[:, 0], alpha * w[:, 1], w[:, 2]], axis=1)
    ws /= np.linalg.norm(ws, axis=1, keepdims=True)
    phi = 2.0 * math.pi * u1
    z = (1.0 - u2) * (1.0 + ws[:, 2]) - ws[:, 2]
    sin = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
    h = np.stack([sin * np.cos(phi), sin * np.sin(phi), z], axis=1) + ws
    m = np.stack([alpha * h[:, 0], alpha * h[:, 1], np.maximum(h[:, 2], 0.0)], axis=1)
    norm = np.linalg.norm(m, axis=1, keepdims=True)
    return m / np.where(norm > 0.0, norm, 1.0)


def _visible_slope_beckmann(mu: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """x̃ ~ (μ − x̃)⁺ exp(−x̃²), μ = cot θ (stretched α = 1 Beckmann, Heitz & d'Eon 2014).

    Exact, by composition and rejection from proposals sampled in closed form:

    * μ ≥ 0, x̃ < 0: (μ + |x̃|) e^{−x̃²} is a mixture of a half-Gaussian (mass μ√π/2) and
      |x̃| e^{−x̃²} (mass 1/2, |x̃| = √(−ln U));
    * μ ≥ 0, 0 ≤ x̃ < μ: the envelope μ e^{−x̃²} (mass μ (√π/2) erf μ), a Gaussian
      truncated to [0, μ), accepted with probability (μ − x̃)/μ (a rejection draws both
      parts anew: the parts are chosen by their envelope masses);
    * μ < 0 (y = −x̃ > m = −μ, density (y − m) e^{−y²}): for m < 0.8, y from y e^{−y²}
      truncated to y > m (y = √(m² − ln U)), accepted with probability (y − m)/y; for
      m ≥ 0.8, y = m + s with s ~ Gamma(2, 2m), accepted with probability e^{−s²}.

    Every acceptance rate is above 0.3.
    """
    x = np.empty_like(mu)
    todo = np.arange(mu.size)
    while todo.size:
        m = mu[todo]
        u = rng.random((3, todo.size))
        out = np.full(todo.size, np.nan)
        pos = m >= 0.0
        # μ ≥ 0
        mp = m[pos]
        neg_mass = mp * (_SQRT_PI / 2) + 0.5
        pos_mass = mp * (_SQRT_PI / 2) * erf(mp)  # of the envelope μ e^{−x̃²} on [0, μ)
        u0, u1, u2 = u[0][pos], u[1][pos], u[2][pos]
        left = u0 * (neg_mass + pos_mass) < neg_mass
        gauss = u1 * neg_mass < mp * (_SQRT_PI / 2)
        half = np.abs(erfinv(np.clip(2.0 * u2 - 1.0, -1.0 + 1e-16, 1.0 - 1e-16)))
        xl = -np.where(gauss, half, np.sqrt(-np.log1p(-u2)))
        xr = erfinv(u1 * erf(mp))
        with np.errstate(divide="ignore", invalid="ignore"):
            keep_r = u2 * mp < mp - xr
        out_pos = np.where(left, xl, np.where(keep_r, xr, np.nan))
        # μ < 0
        mn = -m[~pos]
        v0, v1, v2 = u[0][~pos], u[1][~pos], u[2][~pos]
        small = mn < 0.8
        y_small = np.sqrt(mn * mn - np.log1p(-v0))
        with np.errstate(divide="ignore", invalid="ignore"):  # Gamma(2, 2m): two exponentials
            s_big = -(np.log1p(-v0) + np.log1p(-v2)) / (2.0 * mn)
        y_big = mn + s_big
        ok_small = v1 * y_small < y_small - mn
        ok_big = v1 < np.exp(-s_big * s_big)
        y = np.where(small, y_small, y_big)
        ok = np.where(small, ok_small, ok_big)
        out_neg = np.where(ok, -y, np.nan)
        out[pos] = out_pos
        out[~pos] = out_neg
        done = np.isfinite(out)
        x[todo[done]] = out[done]
        todo = todo[~done]
    return x


def _visible_beckmann(
    w: np.ndarray, alpha: float, u2: np.ndarray, u3: np.ndarray, rng: np.random.Generator
) -> np.ndarray:
    """Beckmann visible normals for directions ``w`` (N, 3) on the whole sphere."""
    sx, sy = alpha * w[:, 0], alpha * w[:, 1]
    rho = np.hypot(sx, sy)
    cos, sin = w[:, 2], rho
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(sin > 1e-300, cos / np.where(sin > 1e-300, sin, 1.0), np.inf)
        cphi = np.where(rho > 0.0, sx / np.where(rho > 0.0, rho, 1.0), 1.0)
        sphi = np.where(rho > 0.0, sy / np.where(rho > 0.0, rho, 1.0), 0.0)
    # ỹ ~ N(0, 1/2) by Box–Muller; x̃ likewise where μ = +∞ (the normal is along z)
    radius = np.sqrt(-np.log1p(-u2))
    ty = radius * np.sin(2.0 * math.pi * u3)
    tx = radius * np.cos(2.0 * math.pi * u3)
    finite = np.isfinite(mu)
    if np.any(finite):
        tx = tx.copy()
        tx[finite] = _visible_slope_beckmann(mu[finite], rng)
    px = alpha * (cphi * tx - sphi * ty)
    py = alpha * (sphi * tx + cphi * ty)
    m = np.stack([-px, -py, np.ones_like(px)], axis=1)
    return m / np.linalg.norm(m, axis=1, keepdims=True)


def sample_visible_normals(
    distribution: str, w: np.ndarray, alpha: float, rng: np.random.Generator
) -> np.ndarray:
    """Normals ωm ~ D_ω(ωm) for unit directions ``w`` (N, 3) above or below the horizon.

    Returns an (N, 3) array of unit normals with z ≥ 0 and ⟨w, ωm⟩ ≥ 0.
    """
    n = w.shape[0]
    if distribution == "ggx":
        u = rng.random((2, n))
        return _visible_ggx(w, alpha, u[0], u[1])
    u = rng.random((2, n))
    return _visible_beckmann(w, alpha, u[0], u[1], rng)
