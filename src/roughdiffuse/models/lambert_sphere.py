"""d'Eon's BRDF of a half-space of spherical Lambertian particles.

E. d'Eon, "An analytic BRDF for materials with spherical Lambertian scatterers", Computer
Graphics Forum 40(4) (EGSR 2021). A semi-infinite medium of large white-ish spheres with
Lambertian surfaces (the dusty, powdery look: regolith, plaster, chalk) scatters with the
Lambert-sphere phase function (Lambert 1760; Blinn 1982)::

    P(u) = 2 (√(1 − u²) − u acos u)/(3π²),   u = −wi·wo  (∫ P dω = 1),

and single scattering is f₁ = c P(u)/(μi + μo), c the single-scattering albedo. The paper
fits the multiply-scattered rest in closed form. Two variants, both after d'Eon's Mitsuba
plugins (``eugenedeon/mitsuba``, ``src/bsdfs/lambert_sphere.cpp`` and
``lambert_sphere_fast.cpp``):

* ``"full"``: f = max(0, f₁ + f₀(μi, μo, c) − f₀,single + f₁ₘ(μi, μo, c) sin θi sin θo cos φ),
  the azimuthal Fourier orders 0 and 1 of the multiple scattering, with the fitted H functions
  of the paper's Eq. (28) and (37) and the rational fits of its Sec. 5;
* ``"fast"``: f = max(0, 0.995917 f₁ + 0.0684744 [(φ + √(μi μo))(c − 0.249978) /
  (4.50996 (acos S/S + 0.113706)) + (1.94208 k_d)^1.85432]), S = sin θi sin θo, a symbolic
  regression of the full model.

The user-facing colour k_d (``albedo``) maps to c by the paper's Eq. (46),
c = (1 − (1 − k_d)^2.73556)/(1 − 0.184096 (1 − k_d)^2.48423).

Differences from the plugins, none of which changes a value away from these sets: the sum
μi + μo is floored at 1e-6 (both directions grazing, where f₁ diverges); in the fast variant
1/(acos S/S + 0.113706) is written S/(acos S + 0.113706 S), its limit 0 at S = 0 (normal
incidence or view), where the plugin computes (π/2)/0 = ∞ and relies on 1/∞ = 0; and φ is
acos of the clamped cosine, where the plugin's ``safeacos`` returns 0 instead of π when
rounding puts cos φ at or below −1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

from .._array import Array, clip, maximum, safe_div, safe_sqrt
from .base import Model, register_pytree
from .declaration import Param

__all__ = ["LambertSphere", "lambert_sphere_phase", "single_scattering_albedo"]

_SUM_FLOOR = 1e-6


def single_scattering_albedo(kd: Array) -> Array:
    """The spheres' single-scattering albedo c from the diffuse colour k_d (paper Eq. 46)."""
    t = 1.0 - kd
    return (1.0 - t**2.73556) / (1.0 - 0.184096 * t**2.48423)


def lambert_sphere_phase(xp: Any, u: Array) -> Array:
    """P(u) = 2 (√(1 − u²) − u acos u)/(3π²), normalised to 1 over the sphere.

    With t = acos u this is 2 (sin t − t cos t)/(3π²), which cancels as t → 0 (u → 1,
    wi = −wo: both directions grazing); there the series t³/3 − t⁵/30 + t⁷/840 − t⁹/45360
    (truncation below 1e-12 for t < 0.3) replaces it. t comes from atan2 of
    √((1 − u)(1 + u)), accurate near u = ±1 where acos is not (float32: the explorer's GLSL).
    """
    u = clip(xp, u, -1.0, 1.0)
    sin_t = safe_sqrt(xp, (1.0 - u) * (1.0 + u))
    t = xp.atan2(sin_t, u)
    t2 = t * t
    series = t * t2 * (1.0 / 3.0 + t2 * (-1.0 / 30.0 + t2 * (1.0 / 840.0 - t2 / 45360.0)))
    return 2.0 * xp.where(t < 0.3, series, sin_t - t * u) / (3.0 * math.pi**2)


def _h0(xp: Any, u: Array, c: Array) -> Array:
    """Zeroth-order H function fit (paper Eq. 37)."""
    s = (1.0 - c) ** 0.5
    a = (8.216443463470172 + 1.501116252342486 * s**6.054351911707695) / (
        4.175932557866179 - 1.2122216865199813 * s
    )
    d = (7.773097842804312 - 0.5658108102188075 * s**0.9615460393324836) / (
        8.659120811349371 - 0.15997430541238322 * s**7
    )
    root = safe_sqrt(xp, 1.0 - 2.0 * ((89.0 * c) / 288.0 + (59.0 * c * c) / 288.0 - c**3 / 72.0))
    ud = _power(xp, u, d)
    return (1.0 + a * ud) / (1.0 + a * root * ud)


def _h1(xp: Any, u: Array, c: Array) -> Array:
    """First-order H function fit (paper Eq. 28)."""
    k = -0.14483935877260054 * c + 0.024285125615255733 * c * c
    e = 0.45944184025347456 + u * (
        -1.0787917226917565 + u * (1.8572804924335546 - 1.1283119660147671 * u)
    )
    return xp.exp(k * _power(xp, u, e))


def _power(xp: Any, u: Array, e: Array) -> Array:
    """u^e for u in [0, 1] and e > 0, with 0^e = 0 (e may be an array)."""
    pos = u > 0
    return xp.where(pos, xp.exp(e * xp.log(xp.where(pos, u, 1.0))), 0.0)


def _f0(xp: Any, ui: Array, uo: Array, c: Array) -> Array:
    """Azimuthal average of the multiple scattering (paper Sec. 5, rational fits in c)."""
    q = 1.0 - c
    r = q**0.5
    q15 = q * r
    a = (69.0 * c) / 128.0
    b = (
        -0.08446297239646791
        + 0.5153566145541554 * r
        - 0.77757371002123 * q
        + 0.34668869623791543 * q15
    ) / (0.9648932738041012 - 0.6655015709030936 * r + 0.1826019462608555 * q)
    cc = (
        682.8479477533338 - 2567.7368047535556 * r + 7487.987105705168 * q - 5602.448801045478 * q15
    ) / (5850.602606063662 - 4008.3309624647227 * r + 1480.250743805733 * q)
    d = (
        0.2855294320307508
        + 160.39651500649123 * r
        - 327.42799697993706 * q
        + 166.88327184107732 * q15
    ) / (674.1908010450103 - 412.9837444306491 * r + 596.4232294419696 * q)
    e = (15.0 * q * c * (3.0 + (4.0 * c) / 3.0)) / 128.0
    f = (
        -1.9208967199948512
        - 242.16001167844007 * r
        - 21.914139454773085 * q
        + 266.06342182761813 * q15
    ) / (1499.904420175135 + 457.4200839912641 * r + 215.77342164754094 * q)
    s = maximum(xp, ui + uo, _SUM_FLOOR)
    p = ui * uo
    poly = a + cc * p + e * p * p + b * (ui + uo) + d * p * (ui + uo) + f * (ui * ui + uo * uo)
    return 0.5 / math.pi * _h0(xp, ui, c) * _h0(xp, uo, c) / s * poly


def _f1m(xp: Any, ui: Array, uo: Array, c: Array) -> Array:
    """First azimuthal order divided by sin θi sin θo."""
    l1 = -0.05890107167021953 * c - 0.004740543453386809 * c * c
    h = _h1(xp, ui, c) * _h1(xp, uo, c)
    p = ui * uo
    inner = (
        (c * (64.0 + 45.0 * p)) / 48.0
        - (15.0 * (1.0 + 0.44 * c) * c * p * h) / 16.0
        - (4.0 * c * (1.0 + l1 * ui) * (1.0 + l1 * uo) * h) / 3.0
    )
    return -2.0 / math.pi * inner / (8.0 * maximum(xp, ui + uo, _SUM_FLOOR))


@register_pytree
@dataclass(frozen=True)
class LambertSphere(Model):
    """d'Eon's Lambert-sphere BRDF (EGSR 2021), full or fast.

    Parameters
    ----------
    albedo : float or array (C,)
        The diffuse colour k_d in [0, 1], mapped to the spheres' single-scattering albedo c by
        the paper's Eq. (46) (k_d = 1 is c = 1, white spheres).
    variant : {"full", "fast"}
        The paper's analytic fit or the symbolic-regression approximation.

    Notes
    -----
    Reciprocal (both variants are symmetric in wi and wo). Backscattering (wi near wo,
    u = −wi·wo near −1) brightens: the dusty look.

    Examples
    --------
    Lit and seen along the normal, u = −wi·wo = −1 (pure backscattering), where the phase
    function peaks at P(−1) = 2/(3π); single scattering is then c P(−1)/2 = c/(3π):

    >>> import numpy as np
    >>> round(float(lambert_sphere_phase(np, np.float64(-1.0))) * 3 * np.pi / 2, 12)
    1.0
    >>> round(float(single_scattering_albedo(1.0)), 12)
    1.0
    """

    albedo: float | Array = 0.8
    variant: Literal["full", "fast"] = "full"

    params: ClassVar[tuple[Param, ...]] = (
        Param(
            "albedo",
            "diffuse colour k_d (mapped to the single-scattering albedo c)",
            min=0.0,
            max=1.0,
            default=0.8,
            channels=True,
            example=0.8,
        ),
        Param(
            "variant",
            "d'Eon's analytic fit or its fast approximation",
            choices=("full", "fast"),
            default="full",
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"lambert-sphere": {}}
    labels: ClassVar[dict[str, str]] = {"lambert-sphere": "d'Eon Lambertian spheres"}
    reference: ClassVar[str] = (
        "E. d'Eon, An analytic BRDF for materials with spherical Lambertian scatterers, EGSR 2021"
    )
    order: ClassVar[int] = 130
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "lambert-sphere": ({"variant": "full"}, {"variant": "fast"})
    }
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"k_d",
    }
    formula: ClassVar[str | dict[str, str]] = {
        "lambert-sphere": r"""
            ```{math}
            f_r &= \max\Bigl(0,\ c\,f_1 + f_0(\mu_i,\mu_o,c) - c\,f_{0,1}(\mu_i,\mu_o) \\ &\qquad +
            f_{1m}(\mu_i,\mu_o,c)\,\sin\theta_i\sin\theta_o\cos\phi\Bigr)
            \quad(\text{variant full})
            ```
            ```{math}
            f_1 = \frac{P(u)}{\mu_i+\mu_o},
            ```
            ```{math}
            P(u) = \frac{2\bigl(\sqrt{1-u^2} - u\arccos u\bigr)}{3\pi^2},
            ```
            ```{math}
            u = -\,\omega_i\cdot\omega_o
            ```
            ```{math}
            c = \frac{1-(1-k_d)^{2.73556}}{1-0.184096\,(1-k_d)^{2.48423}} \tag{Eq. 46}
            ```
            ```{math}
            f_r &= \max\Bigl(0,\ 0.995917\,c\,f_1 \\ &\qquad +
            0.0684744\Bigl[\frac{(\phi+\sqrt{\mu_i\mu_o})(c-0.249978)\,S}{4.50996\,(\arccos S +
            0.113706\,S)} \\ &\qquad + (1.94208\,k_d)^{1.85432}\Bigr]\Bigr)
            \quad(\text{variant fast})
            ```

            d'Eon (EGSR 2021): a half-space of spherical Lambertian particles with the
            Lambert-sphere phase function P; {math}`c\,f_1` is single scattering, f₀ and f₁ₘ the
            azimuthal Fourier orders 0 and 1 of multiple scattering with the fitted H functions of
            the paper's Eq. 28 and 37 and the rational fits of its Sec. 5 (their coefficients in
            ``roughdiffuse/models/lambert_sphere.py``, ``_f0``, ``_f1m``), {math}`f_{0,1} =
            \frac{207 + 256\mu_i\mu_o - 45\mu_o^2 + 45\mu_i^2(3\mu_o^2-1)}{768\pi(\mu_i+\mu_o)}`
            the single-scattering part of f₀; {math}`S = \sin\theta_i\sin\theta_o`. The fast
            variant is the paper's symbolic regression of the full one. {math}`\mu_i+\mu_o` is
            floored at 10⁻⁶, both variants are clamped at 0.
            """,
    }

    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array) -> Array:
        c = single_scattering_albedo(albedo)
        ss = lambert_sphere_phase(xp, -cos_io) / maximum(xp, mu_i + mu_o, _SUM_FLOOR)
        cos_phi_sin = cos_io - mu_i * mu_o  # cos φ sin θi sin θo
        if self.variant == "full":
            f0_single = (
                207.0
                + 256.0 * mu_i * mu_o
                - 45.0 * mu_o * mu_o
                + 45.0 * mu_i * mu_i * (-1.0 + 3.0 * mu_o * mu_o)
            ) / (768.0 * math.pi * maximum(xp, mu_i + mu_o, _SUM_FLOOR))
            f = (
                c * ss
                + _f0(xp, mu_i, mu_o, c)
                - c * f0_single
                + _f1m(xp, mu_i, mu_o, c) * cos_phi_sin
            )
            return maximum(xp, f, 0.0)
        s = safe_sqrt(xp, (1.0 - mu_i * mu_i) * (1.0 - mu_o * mu_o))
        phi = xp.acos(clip(xp, safe_div(xp, cos_phi_sin, s), -1.0, 1.0))
        # acos S as atan2(√(1 − S²), S), 1 − S² = μi² + μo² − μi² μo² (no cancellation at S → 1)
        cos_s = safe_sqrt(xp, mu_i * mu_i + mu_o * mu_o - mu_i * mu_i * mu_o * mu_o)
        ratio = s / (xp.atan2(cos_s, s) + 0.113706 * s)
        kd_term = (1.94208 * albedo) ** 1.85432
        multi = (phi + safe_sqrt(xp, mu_i * mu_o)) * (c - 0.249978) * ratio / 4.50996 + kd_term
        return maximum(xp, 0.995917 * c * ss + 0.0684744 * multi, 0.0)
