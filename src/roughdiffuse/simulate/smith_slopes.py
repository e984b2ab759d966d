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

import numpy as np

from .._validate import ParameterError
from . import smith_formulas

__all__ = [
    "DISTRIBUTIONS",
    "check_distribution",
    "sample_visible_normals",
    "slope_cdf_inverse",
    "smith_lambda",
]

DISTRIBUTIONS: tuple[str, ...] = ("beckmann", "ggx")
_F = smith_formulas.numpy_formulas()


def check_distribution(distribution: object) -> str:
    """Validate the slope distribution's name ("beckmann" or "ggx")."""
    if distribution not in DISTRIBUTIONS:
        raise ParameterError(f"distribution must be one of {DISTRIBUTIONS} (got {distribution!r})")
    return str(distribution)


def smith_lambda(distribution: str, z: np.ndarray, alpha: float) -> np.ndarray:
    """Smith's Λ(ω) for unit directions with z-component ``z`` (isotropic roughness α).

    Above the horizon Λ ≥ 0 (Heitz 2014 eq. 72 for GGX, eq. 86 for Beckmann); below it
    Λ(ω) = −1 − Λ(−ω) ≤ −1 (Heitz et al. 2016, Sec. 3). At the horizon ±∞. The formula is
    :mod:`.smith_formulas`' (shared with the compiled walk).

    Examples
    --------
    >>> import numpy as np
    >>> float(smith_lambda("ggx", np.array(1.0), 0.5))
    0.0
    >>> float(smith_lambda("beckmann", np.array(-1.0), 0.5))
    -1.0
    """
    z = np.asarray(z, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        return np.asarray(_F.smith_lambda(distribution == "ggx", z, alpha), dtype=np.float64)


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


def _visible_slope_beckmann(mu: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """x̃ ~ (μ − x̃)⁺ exp(−x̃²), μ = cot θ (stretched α = 1 Beckmann, Heitz & d'Eon 2014).

    Exact, by composition and rejection from proposals sampled in closed form
    (:mod:`.smith_formulas`, ``slope_proposal_pos`` and ``slope_proposal_neg``):

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
        with np.errstate(divide="ignore", invalid="ignore"):
            out[pos] = _F.slope_proposal_pos(m[pos], u[0][pos], u[1][pos], u[2][pos])
            neg = ~pos
            out[neg] = _F.slope_proposal_neg(m[neg], u[0][neg], u[1][neg], u[2][neg])
        done = np.isfinite(out)
        x[todo[done]] = out[done]
        todo = todo[~done]
    return x


def _visible_beckmann(
    w: np.ndarray, alpha: float, u2: np.ndarray, u3: np.ndarray, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Beckmann visible normals for directions ``w`` (N, 3) on the whole sphere."""
    with np.errstate(divide="ignore", invalid="ignore"):
        mu, cphi, sphi = _F.beckmann_frame(w[:, 0], w[:, 1], w[:, 2], alpha)
    # ỹ ~ N(0, 1/2) by Box–Muller; x̃ likewise where μ = +∞ (the normal is along z)
    tx, ty = _F.gaussian_pair(u2, u3)
    finite = np.isfinite(mu)
    if np.any(finite):
        tx = tx.copy()
        tx[finite] = _visible_slope_beckmann(mu[finite], rng)
    return _F.beckmann_normal(alpha, cphi, sphi, tx, ty)


def sample_visible_normals(
    distribution: str, w: np.ndarray, alpha: float, rng: np.random.Generator
) -> np.ndarray:
    """Normals ωm ~ D_ω(ωm) for unit directions ``w`` (N, 3) above or below the horizon.

    Returns an (N, 3) array of unit normals with z ≥ 0 and ⟨w, ωm⟩ ≥ 0.
    """
    n = w.shape[0]
    u = rng.random((2, n))
    if distribution == "ggx":
        m = _F.visible_ggx(w[:, 0], w[:, 1], w[:, 2], alpha, u[0], u[1])
    else:
        m = _visible_beckmann(w, alpha, u[0], u[1], rng)
    return np.stack(m, axis=1)
