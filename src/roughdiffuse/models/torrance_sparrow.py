"""Torrance–Sparrow: specular reflection from a surface of mirror V-groove facets.

K. E. Torrance and E. M. Sparrow, "Theory for off-specular reflection from roughened
surfaces", JOSA 57(9), 1967 (the lecture's recap)::

    f = F(θ'i) G D(θh) / (4 cos θi cos θr),

h the half vector, θ'i the angle between wi and h (wi·h = √((1 + wi·wo)/2)).

* G, the V-groove shadowing and masking of the 1967 paper:
  G = min(1, 2 (n·h)(n·wo)/(wo·h), 2 (n·h)(n·wi)/(wo·h)).
* D, the facet distribution, normalised so that ∫ D(h) (n·h) dωh = 1:
  ``"gaussian"``: Gaussian in the slope angle θh with standard deviation σ, as in the lecture
  (ρ_α(α) ∝ exp(−α²/2σ²)), normalised by quadrature over θh in [0, π/2];
  ``"beckmann"``: Gaussian in the slope tan θh, D = exp(−tan²θh/m²)/(π m² cos⁴θh) with
  m = √2 σ, so that σ is the standard deviation of each slope component (Beckmann and
  Spizzichino 1963; the same σ = m/√2 as Mitsuba 0.6, see :mod:`roughdiffuse.roughness`).
* F, the unpolarised Fresnel reflectance of a dielectric of relative index η (total
  internal reflection, F = 1, for η < 1).

σ = 0 is a perfect mirror, a Dirac delta the BRDF cannot hold as a value: f is 0 there.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

import numpy as np

from .._array import Array, asarray, clip, maximum, minimum, result_dtype, safe_div, safe_sqrt
from .._validate import check_range
from ..frames import half_vector_cosines, unit_components
from ._quadrature import gauss_legendre_01
from .base import Model, register_pytree
from .oren_nayar import SIGMA_MAX

__all__ = ["TorranceSparrow", "fresnel_dielectric", "slope_distribution"]

Distribution = Literal["gaussian", "beckmann"]

_COS_FLOOR = 1e-6
SIGMA_FLOOR = 1e-4
"""Smallest σ the facet distribution resolves: a smaller positive σ is evaluated as 1e-4 rad
(peak D = 1.6e7 /sr), so that D stays finite in float32 as σ -> 0 (σ = 0 itself gives 0)."""
_GL_T, _GL_W = np.polynomial.legendre.leggauss(96)
_GL_T, _GL_W = 0.5 * (_GL_T + 1.0), 0.5 * _GL_W


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


def _gaussian_norm(xp: Any, sigma: Array, dtype: Any) -> Array:
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
    xp: Any, cos_h: Array, sigma: Array, distribution: Distribution = "gaussian"
) -> Array:
    """D(h) for n·h = ``cos_h``, normalised so that ∫ D (n·h) dωh = 1; 0 for σ = 0."""
    dtype = cos_h.dtype
    pos = sigma > 0
    s = xp.where(pos, maximum(xp, sigma, SIGMA_FLOOR), 1.0)
    sin_h = safe_sqrt(xp, 1.0 - cos_h * cos_h)
    if distribution == "gaussian":
        theta = xp.atan2(sin_h, cos_h)
        norm = _gaussian_norm(xp, s[..., None] if s.ndim else s, dtype)
        d = xp.exp(-theta * theta / (2.0 * s * s)) * norm / (s * s)
    else:
        m2 = 2.0 * s * s
        c = maximum(xp, cos_h, _COS_FLOOR)
        tan2 = sin_h * sin_h / (c * c)
        d = xp.exp(-tan2 / m2) / (math.pi * m2 * c**4)
        d = xp.where(cos_h > _COS_FLOOR, d, 0.0 * d)
    return xp.where(pos, d, 0.0 * d)


@register_pytree
@dataclass(frozen=True)
class TorranceSparrow(Model):
    """Torrance–Sparrow specular BRDF, F G D / (4 cos θi cos θr).

    Parameters
    ----------
    eta : float
        Relative refractive index η > 0 of the facets (1.5 for glass-like coatings).
    sigma : float
        Roughness σ in [0, π/2] radians (slope-angle std for ``"gaussian"``, slope std per
        component for ``"beckmann"``).
    distribution : {"gaussian", "beckmann"}
        Facet distribution D.

    Examples
    --------
    >>> import numpy as np
    >>> m = TorranceSparrow(eta=1.5, sigma=0.2)
    >>> w = np.array([0.0, 0.0, 1.0])
    >>> float(m.brdf(w, w)) > 0
    True
    """

    eta: Any = 1.5
    sigma: Any = 0.2
    distribution: Distribution = "gaussian"

    array_fields: ClassVar[tuple[str, ...]] = ("eta", "sigma")
    sampling: ClassVar[str] = "microfacet"

    def __post_init__(self) -> None:
        check_range("eta", self.eta, 0.0, math.inf, lo_open=True)
        check_range("sigma", self.sigma, 0.0, SIGMA_MAX, unit="radians")
        if self.distribution not in ("gaussian", "beckmann"):
            raise ValueError(
                f"distribution must be 'gaussian' or 'beckmann' (got {self.distribution!r})"
            )

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, eta: Array, sigma: Array
    ) -> Array:
        cos_h, cos_d = half_vector_cosines(xp, mu_i, mu_o, cos_io)
        d = slope_distribution(xp, cos_h, sigma, self.distribution)
        f = fresnel_dielectric(xp, cos_d, eta)
        mi = maximum(xp, mu_i, _COS_FLOOR)
        mo = maximum(xp, mu_o, _COS_FLOOR)
        cd = maximum(xp, cos_d, _COS_FLOOR)
        # G / (μi μo) = min(1/(μi μo), 2 n·h/(wo·h μi), 2 n·h/(wo·h μo))
        g_over = minimum(
            xp, 1.0 / (mi * mo), minimum(xp, 2.0 * cos_h / (cd * mi), 2.0 * cos_h / (cd * mo))
        )
        return f * d * g_over / 4.0

    def directional_albedo(self, wo: Array, n: int = 96) -> Array:
        """∫ f cos θi dωi, integrated over the half vector h where the lobe lives.

        With wi = 2 (wo·h) h − wo and dωi = 4 (wo·h) dωh, Gauss–Legendre in θh over
        [0, θmax] (θmax = min(π/2, 10σ) for the Gaussian, atan(10·√2 σ) for Beckmann: D is
        below e^-50 of its peak beyond) and in φh over [0, π], doubled. The horizon cut
        (cos θi > 0) is not resolved by the rule: about 1e-4 near grazing, 1e-6 elsewhere.
        """
        xp = self._xp(wo)
        dtype = result_dtype(xp, wo)
        _, _, z = unit_components(xp, wo, "wo", dtype)
        mu_o = clip(xp, z, 0.0, 1.0)[..., None, None]
        sin_o = safe_sqrt(xp, 1.0 - mu_o * mu_o)
        sigma = asarray(xp, self.sigma, dtype)
        if self.distribution == "gaussian":
            theta_max = minimum(xp, 10.0 * sigma, math.pi / 2)
        else:
            theta_max = xp.atan(10.0 * math.sqrt(2.0) * sigma)
        t, w = (asarray(xp, a, dtype) for a in gauss_legendre_01(n))
        th = theta_max * t[:, None]
        ph = math.pi * t[None, :]
        cos_oh = sin_o * xp.sin(th) * xp.cos(ph) + mu_o * xp.cos(th)
        mu_i = 2.0 * cos_oh * xp.cos(th) - mu_o
        cos_io = 2.0 * cos_oh * cos_oh - 1.0
        f = self.brdf_cosines(mu_i, z[..., None, None] + 0.0 * mu_i, cos_io)
        jac = 4.0 * maximum(xp, cos_oh, 0.0) * xp.sin(th)
        weights = (theta_max * w)[:, None] * (2.0 * math.pi * w)[None, :]
        integrand = f * maximum(xp, mu_i, 0.0) * jac * weights
        return xp.sum(xp.sum(integrand, axis=-1), axis=-1)
