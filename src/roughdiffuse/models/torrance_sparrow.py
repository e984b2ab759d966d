"""Torrance–Sparrow: specular reflection from a surface of mirror V-groove facets.

K. E. Torrance and E. M. Sparrow, "Theory for off-specular reflection from roughened
surfaces", JOSA 57(9), 1967 (the lecture's recap)::

    f = F(θ'i) G D(θh) / (4 cos θi cos θr),

h the half vector, θ'i the angle between wi and h (wi·h = √((1 + wi·wo)/2)).

* G, the V-groove shadowing and masking of the 1967 paper:
  G = min(1, 2 (n·h)(n·wo)/(wo·h), 2 (n·h)(n·wi)/(wo·h)).
* D, the facet distribution, normalised so that ∫ D(h) (n·h) dωh = 1, each with its own
  width parameter (see :mod:`.microfacet`):
  ``"gaussian"`` (id ``torrance-sparrow``): Gaussian in the slope angle θh with standard
  deviation σ (radians), as in the lecture (ρ_α(α) ∝ exp(−α²/2σ²));
  ``"beckmann"`` (id ``torrance-sparrow-beckmann``): Gaussian in the slope tan θh,
  D = exp(−tan²θh/α²)/(π α² cos⁴θh), α the RMS slope (Beckmann and Spizzichino 1963;
  pbrt-v4's and Mitsuba 3's ``alpha``).
* F, the unpolarised Fresnel reflectance of a dielectric of relative index η (total
  internal reflection, F = 1, for η < 1).

Zero width is a perfect mirror, a Dirac delta the BRDF cannot hold as a value: f is 0 there.

Earlier versions took σ for Beckmann too, as the standard deviation of each slope component
(α = √2 σ). ``TorranceSparrow(eta, sigma, "beckmann")`` without ``alpha`` still means that
(α = √2 σ is set and σ left unset), so old code gives the same values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

from .._array import Array, asarray, clip, maximum, minimum, result_dtype, safe_div, safe_sqrt
from .._validate import ParameterError
from ..frames import unit_components
from ..quadrature import gauss_legendre
from .base import Model, register_pytree
from .declaration import Param
from .microfacet import (
    SIGMA_FLOOR,
    fresnel_dielectric,
    slope_distribution,
    v_groove_masking,
)
from .oren_nayar import SIGMA_MAX
from .sampling import MICROFACET_BECKMANN, MICROFACET_GAUSSIAN, Strategy

__all__ = ["TorranceSparrow", "fresnel_dielectric", "slope_distribution", "SIGMA_FLOOR"]

Distribution = Literal["gaussian", "beckmann"]

ETA_MAX = 1e3
"""Largest accepted η: real dielectrics lie in about [1, 4]; beyond 1e3 η² would leave the
float range of the formula's intermediate terms long before anything physical."""

_SQRT2 = math.sqrt(2.0)


@register_pytree
@dataclass(frozen=True)
class TorranceSparrow(Model):
    """Torrance–Sparrow specular BRDF, F G D / (4 cos θi cos θr).

    Parameters
    ----------
    eta : float
        Relative refractive index η in (0, 1000] of the facets (1.5 for glass-like coatings).
    sigma : float or None
        Gaussian distribution: σ in [0, π/2] radians, the standard deviation of the facet
        slope angle. ``None`` (unset) for Beckmann.
    distribution : {"gaussian", "beckmann"}
        Facet distribution D.
    alpha : float or None
        Beckmann distribution: the RMS slope α in [0, π/√2] (default √2 · 0.2). ``None``
        (unset) for the Gaussian. Given as ``sigma`` instead (the meaning before), α = √2 σ.

    Examples
    --------
    Normal incidence and view on a Beckmann surface: F = ((η − 1)/(η + 1))², G = 1,
    D(n) = 1/(π α²), so f = F/(4 π α²).

    >>> import numpy as np
    >>> w = np.array([0.0, 0.0, 1.0])
    >>> m = TorranceSparrow(eta=1.5, alpha=0.5, distribution="beckmann")
    >>> round(float(m.brdf(w, w)), 12) == round(0.04 / (4 * np.pi * 0.25), 12)
    True
    """

    eta: float | Array = 1.5
    sigma: float | Array | None = 0.2
    distribution: Distribution = "gaussian"
    alpha: float | Array | None = None

    params: ClassVar[tuple[Param, ...]] = (
        Param(
            "eta",
            "relative refractive index η of the facets",
            min=0.0,
            max=ETA_MAX,
            min_open=True,
            default=1.5,
            fit_range=(1.0, 3.0),
        ),
        Param(
            "sigma",
            "σ, standard deviation of the facet slope angle (Gaussian distribution)",
            unit="radians",
            min=0.0,
            max=SIGMA_MAX,
            default=0.2,
            when={"distribution": "gaussian"},
            example=math.radians(20.0),
            fit_range=(0.02, SIGMA_MAX),
        ),
        Param(
            "distribution",
            "facet distribution: Gaussian in the slope angle, or Beckmann",
            choices=("gaussian", "beckmann"),
            default="gaussian",
        ),
        Param(
            "alpha",
            "α, RMS facet slope (Beckmann distribution; α = √2 σ at small slopes)",
            min=0.0,
            max=_SQRT2 * SIGMA_MAX,
            default=_SQRT2 * 0.2,
            when={"distribution": "beckmann"},
            fit_range=(_SQRT2 * 0.02, _SQRT2 * SIGMA_MAX),
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {
        "torrance-sparrow": {"distribution": "gaussian"},
        "torrance-sparrow-beckmann": {"distribution": "beckmann"},
    }
    labels: ClassVar[dict[str, str]] = {
        "torrance-sparrow": "Torrance–Sparrow",
        "torrance-sparrow-beckmann": "Torrance–Sparrow (Beckmann)",
    }
    lobe: ClassVar[str] = "glossy"
    sampling: ClassVar[Strategy] = MICROFACET_GAUSSIAN
    reference: ClassVar[str] = (
        "K. E. Torrance, E. M. Sparrow, Theory for off-specular reflection from roughened "
        "surfaces, JOSA 57 (1967)"
    )
    order: ClassVar[int] = 40
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "torrance-sparrow": ({"eta": 1.5, "sigma": 0.3}, {"eta": 0.7, "sigma": 0.2}),
        "torrance-sparrow-beckmann": ({"eta": 1.5, "alpha": _SQRT2 * 0.3},),
    }
    symbols: ClassVar[dict[str, str]] = {
        "eta": r"\eta",
        "sigma": r"\sigma",
        "alpha": r"\alpha",
    }
    formula: ClassVar[str | dict[str, str]] = {
        "torrance-sparrow": r"""
            ```{math}
            f_r = \frac{F_\eta(\theta_i')\,G\,D(\theta_h)}{4\cos\theta_i\cos\theta_r},\qquad
            D(\theta_h) = \frac{e^{-\theta_h^2/2\sigma^2}}{N(\sigma)},\quad \int D\,(n\cdot
            h)\,\mathrm{d}\omega_h = 1
            ```
            ```{math}
            G = \min\Bigl(1,\ \frac{2(n\cdot h)(n\cdot\omega_o)}{\omega_o\cdot h},\ \frac{2(n\cdot
            h)(n\cdot\omega_i)}{\omega_o\cdot h}\Bigr)
            ```

            Torrance and Sparrow (1967): mirror V-groove facets, Gaussian in the slope angle θh of
            the half vector h with standard deviation σ; N(σ) is computed by quadrature over [0,
            π/2]. F is the unpolarised Fresnel reflectance of a dielectric of relative index η at
            {math}`\cos\theta_i' = \omega_i\cdot h` (F = 1 under total internal reflection, η <
            1). σ = 0 is a perfect mirror, a delta the BRDF cannot hold: f is 0 there (σ is
            floored at 10⁻⁴).
            """,
        "torrance-sparrow-beckmann": r"""
            ```{math}
            f_r = \frac{F_\eta(\theta_i')\,G\,D(\theta_h)}{4\cos\theta_i\cos\theta_r},\qquad
            D(\theta_h) = \frac{e^{-\tan^2\theta_h/\alpha^2}}{\pi\alpha^2\cos^4\theta_h}
            ```
            ```{math}
            G = \min\Bigl(1,\ \frac{2(n\cdot h)(n\cdot\omega_o)}{\omega_o\cdot h},\ \frac{2(n\cdot
            h)(n\cdot\omega_i)}{\omega_o\cdot h}\Bigr)
            ```

            Torrance and Sparrow (1967) with Beckmann's distribution (Gaussian in the slope tan
            θh; α the RMS slope, as pbrt-v4's and Mitsuba 3's ``alpha``), normalised so that
            {math}`\int D\,(n\cdot h)\,\mathrm{d}\omega_h = 1`. F is the unpolarised Fresnel
            reflectance of relative index η at {math}`\cos\theta_i' = \omega_i\cdot h`; α = 0 is a
            mirror, f = 0 there.
            """,
    }

    def __post_init__(self) -> None:
        if self.distribution == "beckmann" and self.alpha is None and self.sigma is not None:
            # the meaning before α had its own name: σ per slope component, α = √2 σ
            sigma = Param("sigma", "", unit="radians", min=0.0, max=SIGMA_MAX).check(self.sigma)
            object.__setattr__(self, "alpha", _SQRT2 * sigma)
            object.__setattr__(self, "sigma", None)
        elif self.distribution == "beckmann" and self.alpha is not None:
            sigma_default = isinstance(self.sigma, float | int) and self.sigma == 0.2
            if self.sigma is not None and not sigma_default:
                raise ParameterError("give alpha for the Beckmann distribution, not sigma as well")
            object.__setattr__(self, "sigma", None)
        super().__post_init__()

    def sampling_strategy(self) -> Strategy:
        """Facet-normal sampling of this instance's distribution (:mod:`.sampling`)."""
        return MICROFACET_BECKMANN if self.distribution == "beckmann" else MICROFACET_GAUSSIAN

    @property
    def width(self) -> Any:
        """The distribution's width parameter: σ (Gaussian) or α (Beckmann)."""
        return self.alpha if self.distribution == "beckmann" else self.sigma

    def _kernel(
        self,
        xp: Any,
        mu_i: Array,
        mu_o: Array,
        cos_io: Array,
        eta: Array,
        sigma: Array | None = None,
        alpha: Array | None = None,
    ) -> Array:
        # |wi + wo| = sqrt(2 (1 + cos_io)); n·h and wi·h = wo·h from the cosines alone
        len_h = safe_sqrt(xp, 2.0 * (1.0 + cos_io))
        cos_h = safe_div(xp, mu_i + mu_o, len_h)
        cos_d = 0.5 * len_h  # wi·h = √((1 + cos_io)/2)
        width = alpha if self.distribution == "beckmann" else sigma
        d = slope_distribution(xp, cos_h, width, self.distribution)
        f = fresnel_dielectric(xp, cos_d, eta)
        return f * d * v_groove_masking(xp, mu_i, mu_o, cos_h, cos_d) / 4.0

    def albedo_estimate(self, xp: Any, mu_o: Array, p: dict[str, Any]) -> Array:
        """F(μo, η), the albedo of the smooth surface (σ → 0), for choosing this lobe in a
        :class:`~roughdiffuse.models.mix.Mix` (Mitsuba 3's ``roughplastic`` weights its
        specular lobe by the Fresnel reflectance at the incident angle in the same way)."""
        return fresnel_dielectric(xp, mu_o, p["eta"]) + 0.0 * mu_o

    def directional_albedo(self, wo: Array, n: int = 96) -> Array:
        """∫ f cos θi dωi, integrated over the half vector h where the lobe lives.

        With wi = 2 (wo·h) h − wo and dωi = 4 (wo·h) dωh, Gauss–Legendre in θh over
        [0, θmax] (θmax = min(π/2, 10σ) for the Gaussian, atan(10 α) for Beckmann: D is
        below e^-50 of its peak beyond) and in φh over [0, π], doubled. The horizon cut
        (cos θi > 0) is not resolved by the rule: about 1e-4 near grazing, 1e-6 elsewhere.
        """
        xp = self._xp(wo)
        dtype = result_dtype(xp, wo)
        _, _, z = unit_components(xp, wo, "wo", dtype)
        mu_o = clip(xp, z, 0.0, 1.0)[..., None, None]
        sin_o = safe_sqrt(xp, 1.0 - mu_o * mu_o)
        width = asarray(xp, self.width, dtype)
        if self.distribution == "gaussian":
            theta_max = minimum(xp, 10.0 * width, math.pi / 2)
        else:
            theta_max = xp.atan(10.0 * width)
        t, w = (asarray(xp, a, dtype) for a in gauss_legendre(n))
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
