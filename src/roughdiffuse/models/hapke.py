"""Hapke's bidirectional reflectance with opposition surge and macroscopic roughness.

B. Hapke, *Theory of Reflectance and Emittance Spectroscopy*, 2nd ed., Cambridge 2012:
the isotropic-multiple-scattering approximation (Eq. 9.40 with the shadow-hiding opposition
effect, Eq. 9.22 and 9.23) and the roughness correction of Hapke, "Bidirectional reflectance
spectroscopy 3: correction for macroscopic roughness", Icarus 59 (1984) 41, Eq. (46)–(51)
(Hapke 2012, Eq. 12.50–12.55). As a radiance factor (I/F = π r)::

    I/F = (w/4) μ0e/(μ0e + μe) [(1 + B(g)) p(g) − 1 + H(μ0e) H(μe)] S(i, e, g),
    B(g) = B0/(1 + tan(g/2)/h),
    p(g) = (1 − ξ²)/(1 + 2ξ cos g + ξ²)^(3/2)      (Henyey–Greenstein, ξ < 0 backscatters),
    H(x) = (1 + 2x)/(1 + 2γx),  γ = √(1 − w)       (Hapke 2012, Eq. 8.55),

μ0e, μe the effective cosines and S the shadowing function of the 1984 paper for mean slope
angle θ̄; θ̄ = 0 is the smooth model (μ0e = μ0, μe = μ, S = 1). The BRDF is f = I/F/(π μ0)
(:mod:`.photometry`), μ0 cancelled in closed form.

This follows USGS ISIS's ``HapkeHen`` (``isis/src/base/objs/Hapke/Hapke.cpp``), whose unit test
values (``Hapke.truth``) the tests reproduce. ISIS's two-lobe phase function
(1 − c) HG(ξ) + c HG(−ξ) is not offered: its test case c = 1 is the single lobe with −ξ. Like
ISIS, the 1981 H-function approximation is used; the more accurate 2002 one (Hapke 2012,
Eq. 8.56) differs from it by under 1 % and would not reproduce ISIS's values.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, clip, maximum, safe_div, safe_sqrt
from .base import Model, register_pytree
from .declaration import Param
from .photometry import brdf_from_radiance_factor

__all__ = ["Hapke", "chandrasekhar_h"]

THETA_BAR_MAX = math.pi / 3
"""Largest mean slope angle accepted (60°): Hapke's 1984 derivation assumes moderate slopes."""

_TAN_FLOOR = 1e-6  # tan θ̄ in the rough branch (θ̄ = 0 takes the smooth branch)
_TINY = 1e-12


def chandrasekhar_h(x: Array, w: Array) -> Array:
    """Hapke's approximation H(x) = (1 + 2x)/(1 + 2x√(1 − w)) (Hapke 2012, Eq. 8.55)."""
    return (1.0 + 2.0 * x) / (1.0 + 2.0 * x * (1.0 - w) ** 0.5)


def _e1(xp: Any, cot_t: Array, cot_x: Array) -> Array:
    """E1(x) = exp(−(2/π) cot θ̄ cot x) (Hapke 1984, Eq. 46 ff.)."""
    return xp.exp(-2.0 / math.pi * cot_t * cot_x)


def _e2(xp: Any, cot_t: Array, cot_x: Array) -> Array:
    """E2(x) = exp(−(1/π) cot² θ̄ cot² x)."""
    return xp.exp(-1.0 / math.pi * cot_t * cot_t * cot_x * cot_x)


@register_pytree
@dataclass(frozen=True)
class Hapke(Model):
    """Hapke's model (2012 book; roughness after Hapke 1984), as ISIS's ``HapkeHen``.

    Parameters
    ----------
    albedo : float or array (C,)
        Single-scattering albedo w in [0, 1].
    b0 : float
        Amplitude B0 of the shadow-hiding opposition surge, in [0, 1].
    h : float
        Angular width h of the surge, in [0, 1] (0: no surge).
    g : float
        Henyey–Greenstein asymmetry ξ in [−0.99, 0.99]; negative backscatters (Hapke's sign).
    theta_bar : float
        Mean slope angle θ̄ of the macroscopic roughness, radians in [0, π/3].

    Reciprocal: swapping wi and wo swaps the two cases of Hapke's S and (μ0e, μe).

    Examples
    --------
    ISIS's first test (``Hapke.truth``: w = 0.5, nothing else): I/F at i = e = g = 0 is
    (w/8) H(1)² = 0.0965097.

    >>> from roughdiffuse.models.photometry import radiance_factor
    >>> round(float(radiance_factor(Hapke(0.5, 0.0, 0.0, 0.0, 0.0), 0.0, 0.0, 0.0)), 7)
    0.0965097
    """

    albedo: float | Array = 0.5
    b0: float | Array = 0.0
    h: float | Array = 0.1
    g: float | Array = 0.0
    theta_bar: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        Param(
            "albedo",
            "single-scattering albedo w",
            min=0.0,
            max=1.0,
            default=0.5,
            channels=True,
            example=0.3,
        ),
        Param("b0", "opposition-surge amplitude B0", min=0.0, max=1.0, default=0.0, example=0.8),
        Param("h", "opposition-surge width h", min=0.0, max=1.0, default=0.1, example=0.06),
        Param(
            "g",
            "Henyey–Greenstein asymmetry ξ (< 0 backscatters)",
            min=-0.99,
            max=0.99,
            default=0.0,
            example=-0.3,
        ),
        Param(
            "theta_bar",
            "mean slope angle θ̄ of the macroscopic roughness",
            unit="radians",
            min=0.0,
            max=THETA_BAR_MAX,
            default=0.0,
            example=0.35,
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"hapke": {}}
    labels: ClassVar[dict[str, str]] = {"hapke": "Hapke (planetary)"}
    reference: ClassVar[str] = (
        "B. Hapke, Theory of Reflectance and Emittance Spectroscopy,"
        " 2nd ed. (2012); roughness: Hapke, Icarus 59 (1984) 41"
    )
    glsl: ClassVar[dict[str, int]] = {"hapke": 15}
    order: ClassVar[int] = 140
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "hapke": (
            {"b0": 0.8, "h": 0.1, "g": -0.3, "theta_bar": 0.35},
            {"b0": 0.0, "h": 0.0, "g": 0.2, "theta_bar": 0.0},
        )
    }
    glsl_test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "hapke": (
            {"albedo": [0.9, 0.5, 0.05], "b0": 0.8, "h": 0.06, "g": -0.3, "theta_bar": 0.35},
            {"albedo": [1.0, 0.3, 0.02], "b0": 0.0, "h": 0.0, "g": 0.4, "theta_bar": 0.0},
            {"albedo": [0.9, 0.5, 0.05], "b0": 1.0, "h": 1.0, "g": 0.0, "theta_bar": math.pi / 3},
        )
    }
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"w",
        "b0": r"B_0",
        "h": r"h",
        "g": r"\xi",
        "theta_bar": r"\bar\theta",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{I/F}{\pi\mu_i}, \tag{Eq. 9.40, 12.55}
        ```
        ```{math}
        \frac{I}{F} =
        \frac{w}{4}\,\frac{\mu_{0e}}{\mu_{0e}+\mu_e}\Bigl[\bigl(1+B(g)\bigr)p(g) - 1 +
        H(\mu_{0e})H(\mu_e)\Bigr]\,S(i,e,g;\bar\theta)
        ```
        ```{math}
        B(g) = \frac{B_0}{1+\tan(g/2)/h},
        ```
        ```{math}
        p(g) = \frac{1-\xi^2}{(1+2\xi\cos g+\xi^2)^{3/2}},
        ```
        ```{math}
        H(x) = \frac{1+2x}{1+2\gamma x},
        ```
        ```{math}
        \gamma = \sqrt{1-w}
        ```

        Hapke (2012; roughness after Hapke 1984, Eq. 46–51), as USGS ISIS's ``HapkeHen``: g is
        the phase angle (between ωi and ωo), ξ the Henyey–Greenstein asymmetry (ξ < 0
        backscatters), {math}`\mu_{0e}, \mu_e` the effective cosines and S the shadowing
        function of the macroscopic roughness θ̄ (θ̄ = 0: {math}`\mu_{0e}=\mu_i`,
        {math}`\mu_e=\mu_o`, S = 1); the 1981 H-function approximation (Eq. 8.55), as ISIS. μᵢ
        cancels in closed form; tan θ̄ is floored at 10⁻⁶.
        """

    def _kernel(
        self,
        xp: Any,
        mu_i: Array,
        mu_o: Array,
        cos_io: Array,
        albedo: Array,
        b0: Array,
        h: Array,
        g: Array,
        theta_bar: Array,
    ) -> Array:
        w, cos_g = albedo, cos_io
        # opposition surge B(g) = B0 h/(h + tan(g/2)), 0 for h = 0 (as ISIS)
        tan_half = safe_sqrt(xp, (1.0 - cos_g) / maximum(xp, 1.0 + cos_g, _TINY))
        surge = b0 * h / maximum(xp, h + tan_half, _TINY)
        p = (1.0 - g * g) / (1.0 + g * g + 2.0 * g * cos_g) ** 1.5
        lobe = (1.0 + surge) * p - 1.0

        def bracket(mu0e: Array, mue: Array) -> Array:
            return lobe + chandrasekhar_h(mu0e, w) * chandrasekhar_h(mue, w)

        # smooth surface: I/F/μ0 = (w/4) [..]/(μ0 + μ)
        smooth = w / 4.0 * bracket(mu_i, mu_o) / maximum(xp, mu_i + mu_o, _TINY)

        # rough surface (Hapke 1984; the expressions of ISIS's Hapke.cpp)
        tan_t = maximum(xp, xp.sin(theta_bar) / xp.cos(theta_bar), _TAN_FLOOR)  # θ̄ <= π/3
        cot_t = 1.0 / tan_t
        chi = 1.0 / (1.0 + math.pi * tan_t * tan_t) ** 0.5
        sin_i = safe_sqrt(xp, 1.0 - mu_i * mu_i)
        sin_e = safe_sqrt(xp, 1.0 - mu_o * mu_o)
        cot_i = mu_i / maximum(xp, sin_i, 1e-10)
        cot_e = mu_o / maximum(xp, sin_e, 1e-10)
        e1i, e2i = _e1(xp, cot_t, cot_i), _e2(xp, cot_t, cot_i)
        e1e, e2e = _e1(xp, cot_t, cot_e), _e2(xp, cot_t, cot_e)
        mu0e_0 = chi * (mu_i + sin_i * tan_t * e2i / (2.0 - e1i))
        mue_0 = chi * (mu_o + sin_e * tan_t * e2e / (2.0 - e1e))
        sin_ie = sin_i * sin_e
        cos_phi = clip(xp, safe_div(xp, cos_g - mu_i * mu_o, sin_ie, 1.0), -1.0, 1.0)
        phi_pi = xp.acos(cos_phi) / math.pi
        f_phi = xp.exp(-2.0 * safe_sqrt(xp, (1.0 - cos_phi) / maximum(xp, 1.0 + cos_phi, _TINY)))
        sin2_half = 0.5 * (1.0 - cos_phi)
        i_le_e = mu_i >= mu_o
        # i <= e
        den_a = maximum(xp, 2.0 - e1e - phi_pi * e1i, _TINY)  # 0 only both grazing, φ = π
        mu0e_a = chi * (mu_i + sin_i * tan_t * (cos_phi * e2e + sin2_half * e2i) / den_a)
        mue_a = chi * (mu_o + sin_e * tan_t * (e2e - sin2_half * e2i) / den_a)
        # i > e
        den_b = maximum(xp, 2.0 - e1i - phi_pi * e1e, _TINY)
        mu0e_b = chi * (mu_i + sin_i * tan_t * (e2i - sin2_half * e2e) / den_b)
        mue_b = chi * (mu_o + sin_e * tan_t * (cos_phi * e2i + sin2_half * e2e) / den_b)
        mu0e = xp.where(i_le_e, mu0e_a, mu0e_b)
        mue = xp.where(i_le_e, mue_a, mue_b)
        q = xp.where(i_le_e, chi * mu_i / mu0e_0, chi * mu_o / mue_0)
        # S/μ0 = μe/(μe(0) μ0e(0)) χ/(1 − f + f q)
        s_over_mu0 = mue * chi / maximum(xp, mue_0 * mu0e_0 * (1.0 - f_phi + f_phi * q), _TINY)
        rough = w / 4.0 * mu0e / maximum(xp, mu0e + mue, _TINY) * bracket(mu0e, mue) * s_over_mu0
        return brdf_from_radiance_factor(xp.where(theta_bar > 0, rough, smooth))
