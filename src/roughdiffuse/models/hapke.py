"""Hapke's bidirectional reflectance: ISIS's HapkeHen and HapkeLeg, and the 2012 form.

B. Hapke, *Theory of Reflectance and Emittance Spectroscopy*, 2nd ed., Cambridge 2012, with
the roughness correction of Hapke, "Bidirectional reflectance spectroscopy 3: correction for
macroscopic roughness", Icarus 59 (1984) 41, Eq. (46)–(51) (Hapke 2012, Eq. 12.50–12.55).
Every variant is, as a radiance factor (I/F = π r)::

    I/F = K (w/4) μ0e/(μ0e + μe) [B_SH(g) p(g) − 1 + H(μ0e/K) H(μe/K)] B_CB(g) S(i, e, g),

μ0e, μe the effective cosines and S the shadowing function of the 1984 paper for mean slope
angle θ̄ (θ̄ = 0: μ0e = μ0, μe = μ, S = 1). The variants differ in the factors:

* :class:`Hapke` (ISIS ``HapkeHen``, ``isis/src/base/objs/Hapke/Hapke.cpp``,
  ``Hapke::PhotoModelAlgorithm``): K = 1, B_CB = 1, B_SH = 1 + B0/(1 + tan(g/2)/h), the 1981
  H-function H(x) = (1 + 2x)/(1 + 2γx), γ = √(1 − w) (Hapke 2012, Eq. 8.55), and ISIS's
  two-term Henyey–Greenstein function
  p(g) = (1 − c) HG(ξ; g) + c HG(−ξ; g), HG(ξ; g) = (1 − ξ²)/(1 + 2ξ cos g + ξ²)^(3/2)
  (ξ = ISIS ``Hg1``, c = ``Hg2``; c = 0 is the one-term function, ξ < 0 backscatters).
* :class:`HapkeLegendre` (ISIS ``HapkeLeg``, same function): the same with
  p(g) = 1 + b cos g + c (3 cos² g − 1)/2 (b = ``Bh``, c = ``Ch``).
* :class:`Hapke2012` (Hapke 2012, Eq. 12.55 with Eq. 9.22–9.23 and 9.43): porosity factor K,
  the 2002 H-function (Hapke, Icarus 157 (2002) 523, Eq. 13; Hapke 2012, Eq. 8.56)
  H(x) = 1/(1 − w x [r0 + (1 − 2 r0 x)/2 · ln((1 + x)/x)]), r0 = (1 − γ)/(1 + γ), and the
  coherent-backscatter surge B_CB = 1 + B_C0 B_C(g) with
  B_C(g) = [1 + (1 − e^(−y))/y] / [2 (1 + y)²], y = tan(g/2)/h_C (Hapke 2002, Eq. 31).

The BRDF is f = I/F/(π μ0) (:mod:`roughdiffuse.models.photometry`), μ0 cancelled in closed
form. Each formula lives once here: the phase functions, the H-functions, the surges and the
roughness are functions every variant calls.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, ClassVar

from .._array import Array, clip, maximum, safe_div, safe_sqrt
from .._validate import ParameterError
from ..deprecation import renamed_parameter
from .base import Model
from .constraints import LEGENDRE_PHASE_NON_NEGATIVE, Constraint
from .declaration import albedo_param, param
from .photometry import HORIZON_FLOOR, brdf_from_radiance_factor

__all__ = [
    "Hapke",
    "Hapke2012",
    "HapkeLegendre",
    "chandrasekhar_h",
    "chandrasekhar_h_2002",
    "porosity_factor",
]

THETA_BAR_MAX = math.pi / 3
"""Largest mean slope angle accepted (60°): Hapke's 1984 derivation assumes moderate slopes."""

B0_SOFT_MAX = 3.0
"""Upper end of the box a fit searches for a surge amplitude, and of the explorer's slider.
Published fits exceed 1 where the shadow-hiding surge absorbs coherent backscatter."""

AMPLITUDE_MAX = 1e3
"""Largest accepted surge amplitude (B0, B_S0, B_C0) and porosity factor K. ISIS accepts any
B0 >= 0 (``Hapke::SetPhotoB0``); published fits stay below 3 and K below 3, and a finite
ceiling keeps the BRDF finite (B0 = 1e308 overflows to ∞): 1e3 is far beyond both."""

_TAN_FLOOR = 1e-6  # tan θ̄ in the rough branch (θ̄ = 0 takes the smooth branch)
_TINY = 1e-12
_X_FLOOR = 1e-12  # the 2002 H-function's x ln(1/x) -> 0 as x -> 0


# ---------------------------------------------------------------- H-functions
def chandrasekhar_h(x: Array, w: Array) -> Array:
    """Hapke's 1981 approximation H(x) = (1 + 2x)/(1 + 2x√(1 − w)) (Hapke 2012, Eq. 8.55)."""
    return (1.0 + 2.0 * x) / (1.0 + 2.0 * x * (1.0 - w) ** 0.5)


def chandrasekhar_h_2002(xp: Any, x: Array, w: Array) -> Array:
    """Hapke's 2002 approximation of Chandrasekhar's H (Hapke 2002, Eq. 13; 2012, Eq. 8.56).

    H(x) = 1/(1 − w x [r0 + (1 − 2 r0 x)/2 ln((1 + x)/x)]), r0 = (1 − γ)/(1 + γ),
    γ = √(1 − w): within 1 % of the exact function for every w (Hapke 2012, Sec. 8.7).
    """
    gamma = (1.0 - w) ** 0.5
    r0 = (1.0 - gamma) / (1.0 + gamma)
    xs = maximum(xp, x, _X_FLOOR)
    log_term = xp.log1p(xs) - xp.log(xs)  # ln((1 + x)/x)
    return 1.0 / (1.0 - w * xs * (r0 + 0.5 * (1.0 - 2.0 * r0 * xs) * log_term))


def porosity_factor(filling_factor: float) -> float:
    """Hapke's porosity factor K = −ln(1 − 1.209 φ^(2/3))/(1.209 φ^(2/3)) (Hapke 2008,
    Icarus 195, 918, Eq. 23; Hapke 2012, Eq. 7.45b) for filling factor φ in [0, 0.752).

    >>> porosity_factor(0.0)
    1.0
    >>> round(porosity_factor(0.41), 4)
    1.6491
    """
    if not 0.0 <= filling_factor < 0.752:
        raise ParameterError(f"filling_factor must be in [0, 0.752) (got {filling_factor:g})")
    y = 1.209 * filling_factor ** (2.0 / 3.0)
    return 1.0 if y == 0.0 else -math.log1p(-y) / y


# ---------------------------------------------------------------- phase functions, surges
def henyey_greenstein(xi: Array, cos_g: Array) -> Array:
    """HG(ξ; g) = (1 − ξ²)/(1 + 2ξ cos g + ξ²)^(3/2) in the phase angle g (ξ < 0 backscatters)."""
    return (1.0 - xi * xi) / (1.0 + xi * xi + 2.0 * xi * cos_g) ** 1.5


def two_term_hg(xi: Array, c: Array, cos_g: Array) -> Array:
    """ISIS's two-term function (1 − c) HG(ξ; g) + c HG(−ξ; g) (``Hapke.cpp``: pg1 + pg2)."""
    return (1.0 - c) * henyey_greenstein(xi, cos_g) + c * henyey_greenstein(-xi, cos_g)


def legendre_phase(b: Array, c: Array, cos_g: Array) -> Array:
    """ISIS's Legendre phase function 1 + b P1(cos g) + c P2(cos g) (``Hapke.cpp``)."""
    return 1.0 + b * cos_g + c * (1.5 * cos_g * cos_g - 0.5)


def _tan_half(xp: Any, cos_g: Array) -> Array:
    """tan(g/2) = √((1 − cos g)/(1 + cos g))."""
    return safe_sqrt(xp, (1.0 - cos_g) / maximum(xp, 1.0 + cos_g, _TINY))


def shadow_hiding(xp: Any, b0: Array, h: Array, cos_g: Array) -> Array:
    """B_SH − 1 = B0/(1 + tan(g/2)/h) = B0 h/(h + tan(g/2)); 0 for h = 0, as ISIS."""
    return b0 * h / maximum(xp, h + _tan_half(xp, cos_g), _TINY)


def coherent_backscatter(xp: Any, bc0: Array, hc: Array, cos_g: Array) -> Array:
    """B_CB − 1 = B_C0 [1 + (1 − e^(−y))/y]/[2 (1 + y)²], y = tan(g/2)/h_C (Hapke 2002,
    Eq. 31); B_C0 at g = 0, and 0 for h_C = 0."""
    y = _tan_half(xp, cos_g) / maximum(xp, hc, _TINY)
    small = y < 1e-4  # (1 − e^(−y))/y by its series there (error < y³/24), no cancellation
    ys = xp.where(small, 1.0, y)
    ratio = xp.where(small, 1.0 - y / 2.0 + y * y / 6.0, (1.0 - xp.exp(-ys)) / ys)
    bc = (1.0 + ratio) / (2.0 * (1.0 + y) ** 2)
    return xp.where(hc > 0, bc0 * bc, 0.0 * bc)


# ---------------------------------------------------------------- macroscopic roughness
def _e1(xp: Any, cot_t: Array, cot_x: Array) -> Array:
    """E1(x) = exp(−(2/π) cot θ̄ cot x) (Hapke 1984, Eq. 46 ff.)."""
    return xp.exp(-2.0 / math.pi * cot_t * cot_x)


def _e2(xp: Any, cot_t: Array, cot_x: Array) -> Array:
    """E2(x) = exp(−(1/π) cot² θ̄ cot² x)."""
    return xp.exp(-1.0 / math.pi * cot_t * cot_t * cot_x * cot_x)


def _rough(
    xp: Any, mu_i: Array, mu_o: Array, cos_g: Array, theta_bar: Array
) -> tuple[Array, Array, Array]:
    """(μ0e, μe, S/μ0) of Hapke 1984 (Eq. 46–51; the expressions of ISIS's ``Hapke.cpp``)."""
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
    cos_phi = clip(xp, safe_div(xp, cos_g - mu_i * mu_o, sin_i * sin_e, 1.0), -1.0, 1.0)
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
    return mu0e, mue, s_over_mu0


def hapke_sum(
    xp: Any,
    mu_i: Array,
    mu_o: Array,
    cos_g: Array,
    theta_bar: Array,
    bracket: Callable[[Array, Array], Array],
) -> Array:
    """μ0e/(μ0e + μe) · bracket(μ0e, μe) · S/μ0, the common frame of every Hapke variant.

    θ̄ = 0 is the smooth surface, bracket(μ0, μ)/(μ0 + μ). The caller multiplies by w/4 (and
    K, B_CB) to get I/F/μ0.
    """
    smooth = bracket(mu_i, mu_o) / maximum(xp, mu_i + mu_o, HORIZON_FLOOR)
    mu0e, mue, s_over_mu0 = _rough(xp, mu_i, mu_o, cos_g, theta_bar)
    rough = mu0e / maximum(xp, mu0e + mue, HORIZON_FLOOR) * bracket(mu0e, mue) * s_over_mu0
    return xp.where(theta_bar > 0, rough, smooth)


def _isis_hapke(
    xp: Any,
    mu_i: Array,
    mu_o: Array,
    cos_g: Array,
    w: Array,
    surge: Array,
    p: Array,
    theta_bar: Array,
) -> Array:
    """The BRDF of ISIS's ``Hapke::PhotoModelAlgorithm`` for a phase-function value p."""
    lobe = (1.0 + surge) * p - 1.0

    def bracket(mu0e: Array, mue: Array) -> Array:
        return lobe + chandrasekhar_h(mu0e, w) * chandrasekhar_h(mue, w)

    return brdf_from_radiance_factor(w / 4.0 * hapke_sum(xp, mu_i, mu_o, cos_g, theta_bar, bracket))


# ---------------------------------------------------------------- declarations
# functions, not constants: each model's field is a declaration of its own
def _surge_amplitude(what: str, example: float) -> Any:
    return param(
        f"{what} amplitude",
        min=0.0,
        max=AMPLITUDE_MAX,
        default=0.0,
        example=example,
        fit_range=(0.0, B0_SOFT_MAX),
    )


def _surge_width(what: str) -> Any:
    return param(f"{what} width", min=0.0, max=1.0, default=0.1, example=0.06)


def _theta_bar() -> Any:
    return param(
        "mean slope angle θ̄ of the macroscopic roughness",
        unit="radians",
        min=0.0,
        max=THETA_BAR_MAX,
        default=0.0,
        example=0.35,
    )


def _xi() -> Any:
    return param(
        "Henyey–Greenstein asymmetry ξ (< 0 backscatters; ISIS Hg1)",
        min=-0.99,
        max=0.99,
        default=0.0,
        example=-0.3,
    )


def _hg2() -> Any:
    return param(
        "weight c of the mirrored lobe HG(−ξ) (ISIS Hg2; 0: one-term HG)",
        min=0.0,
        max=1.0,
        default=0.0,
    )


_REFERENCE = (
    "B. Hapke, Theory of Reflectance and Emittance Spectroscopy,"
    " 2nd ed. (2012); roughness: Hapke, Icarus 59 (1984) 41; as USGS ISIS3 Hapke.cpp"
)


@renamed_parameter("g", "xi", since="0.2")
class Hapke(Model):
    """Hapke's model with a one- or two-term Henyey–Greenstein function, as ISIS's ``HapkeHen``.

    Parameters
    ----------
    albedo : float or array (C,)
        Single-scattering albedo w in [0, 1] (ISIS ``Wh``).
    b0 : float
        Amplitude B0 in [0, 1000] of the shadow-hiding opposition surge (``B0``; ISIS accepts
        any B0 >= 0, see ``AMPLITUDE_MAX``).
    h : float
        Angular width h of the surge, in [0, 1] (``Hh``; 0: no surge).
    xi : float
        Henyey–Greenstein asymmetry ξ in [−0.99, 0.99] (``Hg1``); negative backscatters. The
        former keyword ``g`` (the phase angle's letter in the formulas) still works, with a
        ``DeprecationWarning``.
    theta_bar : float
        Mean slope angle θ̄ of the macroscopic roughness, radians in [0, π/3] (``Theta``, which
        ISIS takes in degrees).
    hg2 : float
        Weight c in [0, 1] of the mirrored lobe (``Hg2``): p = (1 − c) HG(ξ) + c HG(−ξ);
        0 (the default) is the one-term function.

    Reciprocal: swapping wi and wo swaps the two cases of Hapke's S and (μ0e, μe).

    Examples
    --------
    ISIS's first test (``Hapke.truth``: w = 0.5, nothing else): I/F at i = e = g = 0 is
    (w/8) H(1)² = 0.0965097.

    >>> from roughdiffuse.models.photometry import radiance_factor
    >>> round(float(radiance_factor(Hapke(0.5, 0.0, 0.0, 0.0, 0.0), 0.0, 0.0, 0.0)), 7)
    0.0965097
    >>> Hapke(0.3, b0=2.0).b0  # B0 > 1, as published fits have it
    2.0
    """

    albedo: float | Array = albedo_param("single-scattering albedo w", default=0.5, example=0.3)
    b0: float | Array = _surge_amplitude("shadow-hiding opposition-surge", 0.8)
    h: float | Array = _surge_width("shadow-hiding opposition-surge")
    xi: float | Array = _xi()
    theta_bar: float | Array = _theta_bar()
    hg2: float | Array = _hg2()
    ids: ClassVar[dict[str, dict[str, Any]]] = {"hapke": {}}
    labels: ClassVar[dict[str, str]] = {"hapke": "Hapke (planetary)"}
    reference: ClassVar[str] = _REFERENCE
    order: ClassVar[int] = 140
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"w",
        "b0": r"B_0",
        "h": r"h",
        "xi": r"\xi",
        "theta_bar": r"\bar\theta",
        "hg2": r"c",
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
        p(g) = (1-c)\,P(\xi) + c\,P(-\xi),\quad
        P(\xi) = \frac{1-\xi^2}{(1+2\xi\cos g+\xi^2)^{3/2}},
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
        cancels in closed form; tan θ̄ and μ0e + μe (both directions on the horizon) are
        floored at 10⁻⁶.
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
        xi: Array,
        theta_bar: Array,
        hg2: Array,
    ) -> Array:
        surge = shadow_hiding(xp, b0, h, cos_io)
        p = two_term_hg(xi, hg2, cos_io)
        return _isis_hapke(xp, mu_i, mu_o, cos_io, albedo, surge, p, theta_bar)


class HapkeLegendre(Model):
    """Hapke's model with ISIS's Legendre phase function, as ISIS's ``HapkeLeg``.

    p(g) = 1 + b cos g + c (3 cos² g − 1)/2. For some (b, c) p is negative at some g (e.g.
    b = 1, c = −1 at g = 180°); ISIS accepts them, and so does this model: the I/F can then
    be negative there.

    Parameters
    ----------
    albedo, b0, h, theta_bar : float
        As :class:`Hapke` (ISIS ``Wh``, ``B0``, ``Hh``, ``Theta``).
    bh : float
        First Legendre coefficient b in [−1, 1] (ISIS ``Bh``).
    ch : float
        Second Legendre coefficient c in [−1, 1] (ISIS ``Ch``).

    Examples
    --------
    ISIS's ``HapkeLeg`` test (``Hapke.truth``): w = 0.52, B0 = 1, h = 1, θ̄ = 30°, b = c = 0.

    >>> import math
    >>> from roughdiffuse.models.photometry import radiance_factor
    >>> m = HapkeLegendre(0.52, 1.0, 1.0, 0.0, 0.0, math.radians(30.0))
    >>> round(float(radiance_factor(m, 0.0, 0.0, 0.0)), 5)
    0.16145
    """

    albedo: float | Array = albedo_param("single-scattering albedo w", default=0.5, example=0.3)
    b0: float | Array = _surge_amplitude("shadow-hiding opposition-surge", 0.8)
    h: float | Array = _surge_width("shadow-hiding opposition-surge")
    bh: float | Array = param(
        "Legendre coefficient b of cos g (ISIS Bh)",
        min=-1.0,
        max=1.0,
        default=0.0,
        example=-0.4,
    )
    ch: float | Array = param(
        "Legendre coefficient c of P2(cos g) (ISIS Ch)",
        min=-1.0,
        max=1.0,
        default=0.0,
        example=0.3,
    )
    theta_bar: float | Array = _theta_bar()
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"w",
        "b0": r"B_0",
        "h": r"h",
        "bh": r"b",
        "ch": r"c",
        "theta_bar": r"\bar\theta",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        \frac{I}{F} =
        \frac{w}{4}\,\frac{\mu_{0e}}{\mu_{0e}+\mu_e}\Bigl[\bigl(1+B(g)\bigr)p(g) - 1 +
        H(\mu_{0e})H(\mu_e)\Bigr]\,S(i,e,g;\bar\theta)
        ```
        ```{math}
        p(g) = 1 + b\cos g + c\,\frac{3\cos^2 g - 1}{2},\quad B(g) = \frac{B_0}{1+\tan(g/2)/h}
        ```

        As :class:`Hapke` (ISIS ``HapkeHen``, Hapke 2012 Eq. 12.55 with the 1984 roughness
        S) with ISIS ``HapkeLeg``'s Legendre phase function; f = (I/F)/(π μi).
        """
    constraints: ClassVar[tuple[Constraint, ...]] = (LEGENDRE_PHASE_NON_NEGATIVE,)
    ids: ClassVar[dict[str, dict[str, Any]]] = {"hapke-legendre": {}}
    labels: ClassVar[dict[str, str]] = {"hapke-legendre": "Hapke, Legendre phase (planetary)"}
    reference: ClassVar[str] = _REFERENCE
    order: ClassVar[int] = 141

    def _kernel(
        self,
        xp: Any,
        mu_i: Array,
        mu_o: Array,
        cos_io: Array,
        albedo: Array,
        b0: Array,
        h: Array,
        bh: Array,
        ch: Array,
        theta_bar: Array,
    ) -> Array:
        surge = shadow_hiding(xp, b0, h, cos_io)
        p = legendre_phase(bh, ch, cos_io)
        return _isis_hapke(xp, mu_i, mu_o, cos_io, albedo, surge, p, theta_bar)


@renamed_parameter("g", "xi", since="0.2")
class Hapke2012(Model):
    """Hapke's 2012 model: porosity, shadow-hiding and coherent-backscatter surges.

    I/F = K (w/4) μ0e/(μ0e + μe) [B_SH p − 1 + H(μ0e/K) H(μe/K)] B_CB S (Hapke 2012,
    Eq. 12.55 with isotropic multiple scattering), H the 2002 approximation. With K = 1 and
    B_C0 = 0 it differs from :class:`Hapke` only by the H-function (under 1 %).

    Parameters
    ----------
    albedo : float or array (C,)
        Single-scattering albedo w in [0, 1].
    bs0, h_s : float
        Shadow-hiding surge amplitude B_S0 >= 0 and width h_S in [0, 1].
    bc0, h_c : float
        Coherent-backscatter surge amplitude B_C0 >= 0 and width h_C in [0, 1].
    porosity : float
        Porosity factor K >= 1 (1: very porous; :func:`porosity_factor` from the filling
        factor).
    xi, hg2 : float
        Two-term Henyey–Greenstein function, as :class:`Hapke` (``g``, the former name of
        ``xi``, still works with a ``DeprecationWarning``).
    theta_bar : float
        Mean slope angle θ̄, radians in [0, π/3] (Hapke 1984).

    Notes
    -----
    Checked against ``refmod`` (arunoruto/reflectance-models, ``src/refmod/hapke/_core.py``:
    ``h_function``, ``shadow_hiding``, ``coherent_backscatter``, ``roughness_correction``),
    transcribed in the tests, and the H-function against Chandrasekhar's exact one.

    Examples
    --------
    At g = 0 both surges are at their peak: I/F = K (w/8) [(1 + B_S0) p − 1 + H(1/K)²](1 + B_C0).

    >>> from roughdiffuse.models.photometry import radiance_factor
    >>> m = Hapke2012(0.4, bs0=1.0, h_s=0.05, bc0=0.5, h_c=0.02)
    >>> round(float(radiance_factor(m, 0.0, 0.0, 0.0)), 6)
    0.179845
    """

    albedo: float | Array = albedo_param("single-scattering albedo w", default=0.5, example=0.3)
    bs0: float | Array = _surge_amplitude("shadow-hiding surge", 0.8)
    h_s: float | Array = _surge_width("shadow-hiding surge")
    bc0: float | Array = param(
        "coherent-backscatter surge amplitude B_C0",
        min=0.0,
        max=AMPLITUDE_MAX,
        default=0.0,
        example=0.4,
        fit_range=(0.0, 1.0),
    )
    h_c: float | Array = param(
        "coherent-backscatter surge width h_C",
        min=0.0,
        max=1.0,
        default=0.1,
        example=0.02,
    )
    porosity: float | Array = param(
        "porosity factor K (1: very porous)",
        min=1.0,
        max=AMPLITUDE_MAX,
        default=1.0,
        example=1.3,
        fit_range=(1.0, 3.0),
    )
    xi: float | Array = _xi()
    hg2: float | Array = _hg2()
    theta_bar: float | Array = _theta_bar()
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"w",
        "bs0": r"B_{S0}",
        "h_s": r"h_S",
        "bc0": r"B_{C0}",
        "h_c": r"h_C",
        "porosity": r"K",
        "xi": r"\xi",
        "hg2": r"c",
        "theta_bar": r"\bar\theta",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        \frac{I}{F} = K\frac{w}{4}\,\frac{\mu_{0e}\,B_{CB}\,S}{\mu_{0e}+\mu_e}\Bigl[B_{SH}\,p(g)
        - 1 + H\bigl(\tfrac{\mu_{0e}}{K}\bigr)H\bigl(\tfrac{\mu_e}{K}\bigr)\Bigr]
        ```
        ```{math}
        B_{SH} = 1 + \frac{B_{S0}}{1+\tan(g/2)/h_S},\quad
        B_{CB} = 1 + B_{C0}\,\frac{1 + (1-e^{-y})/y}{2(1+y)^2}
        ```
        ```{math}
        y = \frac{\tan(g/2)}{h_C},\quad S = S(i,e,g;\bar\theta)
        ```
        ```{math}
        H(x) = \Bigl[1 - w x\Bigl(r_0 + \frac{1-2r_0x}{2}\ln\frac{1+x}{x}\Bigr)\Bigr]^{-1}
        ```
        ```{math}
        r_0 = \frac{1-\sqrt{1-w}}{1+\sqrt{1-w}}
        ```
        ```{math}
        p(g) = (1-c)\,P(\xi) + c\,P(-\xi),\quad
        P(\xi) = \frac{1-\xi^2}{(1+2\xi\cos g+\xi^2)^{3/2}}
        ```

        Hapke 2012 (Eq. 12.55, the 2002 H-function Eq. 8.56, the coherent-backscatter term of
        Hapke 2002 Eq. 31) with the 1984 roughness S; f = (I/F)/(π μi).
        """
    ids: ClassVar[dict[str, dict[str, Any]]] = {"hapke-2012": {}}
    labels: ClassVar[dict[str, str]] = {"hapke-2012": "Hapke 2012 (planetary)"}
    reference: ClassVar[str] = (
        "B. Hapke, Theory of Reflectance and Emittance Spectroscopy, 2nd ed. (2012), Eq. 12.55;"
        " H and coherent backscatter: Hapke, Icarus 157 (2002) 523; checked against refmod"
        " (arunoruto/reflectance-models)"
    )
    order: ClassVar[int] = 142

    def _kernel(
        self,
        xp: Any,
        mu_i: Array,
        mu_o: Array,
        cos_io: Array,
        albedo: Array,
        bs0: Array,
        h_s: Array,
        bc0: Array,
        h_c: Array,
        porosity: Array,
        xi: Array,
        hg2: Array,
        theta_bar: Array,
    ) -> Array:
        w, k = albedo, porosity
        lobe = (1.0 + shadow_hiding(xp, bs0, h_s, cos_io)) * two_term_hg(xi, hg2, cos_io) - 1.0

        def bracket(mu0e: Array, mue: Array) -> Array:
            return lobe + chandrasekhar_h_2002(xp, mu0e / k, w) * chandrasekhar_h_2002(
                xp, mue / k, w
            )

        b_cb = 1.0 + coherent_backscatter(xp, bc0, h_c, cos_io)
        total = hapke_sum(xp, mu_i, mu_o, cos_io, theta_bar, bracket)
        return brdf_from_radiance_factor(k * w / 4.0 * total * b_cb)
