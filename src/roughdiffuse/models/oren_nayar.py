"""The Oren–Nayar model of rough diffuse surfaces (V-cavities of Lambertian facets).

M. Oren and S. K. Nayar, "Generalization of Lambert's reflectance model", SIGGRAPH 1994,
pp. 239–246. Roughness σ is the standard deviation of the facet slope angle, in radians.

* ``variant="qualitative"``: the paper's simplified model (its Eq. 30, the lecture's final
  expression)::

      f = ρ/π (A + B max(0, cos(φr − φi)) sin α tan β),
      A = 1 − 0.5 σ²/(σ² + 0.33),   B = 0.45 σ²/(σ² + 0.09),

  with α = max(θi, θr), β = min(θi, θr). In vector form
  max(0, cos Δφ) sin α tan β = max(0, s)/max(μi, μo), s = wi·wo − μi μo.

* ``variant="full"``: the paper's functional approximation of the single-bounce V-cavity
  radiance L1 (Eq. 27–29, coefficients C1, C2, C3) plus the two-bounce interreflection term
  L2 (Eq. 31; also Mitsuba 0.6, ``src/bsdfs/roughdiffuse.cpp``)::

      L1 = ρ/π E0 cos θi [C1 + c C2 tan β + (1 − |c|) C3 tan((α + β)/2)]
      L2 = 0.17 ρ²/π E0 cos θi σ²/(σ² + 0.13) [1 − c (2β/π)²],     c = cos(φr − φi)

  f = (L1 + L2)/(E0 cos θi). L2 is quadratic in ρ, so f is not linear in the albedo.
  Near grazing backscatter with σ above about 1 rad the fitted C2 term makes L1 + L2
  negative; f is clamped at 0 there (the paper's formula is not).

σ = 0 gives Lambert exactly in both variants.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar, Literal

from .._array import Array, clip, maximum, minimum, namespace, result_dtype, safe_div, safe_sqrt
from .._validate import check_range
from ..frames import angles_to_cosines
from .base import Model, register_pytree
from .declaration import Param

__all__ = ["OrenNayar", "oren_nayar", "SIGMA_MAX"]

SIGMA_MAX = math.pi / 2
"""Largest accepted σ (radians): a facet slope angle cannot exceed π/2."""

TAN_FLOOR = 1e-6
"""Floor of cos β in tan β = sin β / cos β and of cos((α + β)/2) in tan((α + β)/2); reached
only when both directions are within 1e-6 of grazing, where the radiance (× cos θi) vanishes
anyway."""

Variant = Literal["qualitative", "full"]


def _qualitative(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, sigma: Array) -> Array:
    """ρ-free factor A + B max(0, s)/max(μi, μo) of the qualitative model (paper Eq. 30)."""
    s2 = sigma * sigma
    a = 1.0 - 0.5 * s2 / (s2 + 0.33)
    b = 0.45 * s2 / (s2 + 0.09)
    s = cos_io - mu_i * mu_o
    t = maximum(xp, maximum(xp, mu_i, mu_o), TAN_FLOOR)
    return a + b * xp.where(s > 0, s, 0.0 * s) / t


def _full(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, sigma: Array, albedo: Array) -> Array:
    """(L1 + L2)/(E0 cos θi) of the full model (paper Eq. 27–31), ρ included."""
    s2 = sigma * sigma
    sin_i = safe_sqrt(xp, 1.0 - mu_i * mu_i)
    sin_o = safe_sqrt(xp, 1.0 - mu_o * mu_o)
    theta_i = xp.atan2(sin_i, mu_i)
    theta_r = xp.atan2(sin_o, mu_o)
    alpha = maximum(xp, theta_i, theta_r)
    beta = minimum(xp, theta_i, theta_r)
    sin_alpha, sin_beta = maximum(xp, sin_i, sin_o), minimum(xp, sin_i, sin_o)
    cos_alpha, cos_beta = minimum(xp, mu_i, mu_o), maximum(xp, mu_i, mu_o)
    tan_beta = sin_beta / maximum(xp, cos_beta, TAN_FLOOR)
    # c = cos(φr − φi); undefined (and irrelevant: β = 0 there) when either θ is 0
    c = clip(xp, safe_div(xp, cos_io - mu_i * mu_o, sin_i * sin_o), -1.0, 1.0)
    t = s2 / (s2 + 0.09)
    c1 = 1.0 - 0.5 * s2 / (s2 + 0.33)
    b2 = (2.0 * beta / math.pi) ** 2
    c2 = 0.45 * t * xp.where(c >= 0, sin_alpha, sin_alpha - b2 * (2.0 * beta / math.pi))
    c3 = 0.125 * t * (4.0 * alpha * beta / math.pi**2) ** 2
    # tan((α + β)/2) = (sin α + sin β)/(cos α + cos β), exact and without a sine or cosine,
    # which XLA recomputes in every loop of a Jacobian (a stereo fit, stereo/rough.py: 1.3x
    # less CPU time). cos α + cos β = 2 cos((α + β)/2) cos((α − β)/2): floored at twice the
    # floor of cos((α + β)/2), the same value where both directions are grazing
    tan_half = (sin_alpha + sin_beta) / maximum(xp, cos_alpha + cos_beta, 2.0 * TAN_FLOOR)
    l1 = albedo / math.pi * (c1 + c * c2 * tan_beta + (1.0 - xp.abs(c)) * c3 * tan_half)
    l2 = 0.17 * albedo * albedo / math.pi * s2 / (s2 + 0.13) * (1.0 - c * b2)
    # the fitted C2 term (c < 0) drives f below 0 at grazing backscatter for σ > ~1
    # (θi = θr = 89°, Δφ = π, σ = 1.2: -0.008): a BRDF cannot be negative, clamp at 0
    return maximum(xp, l1 + l2, 0.0)


@register_pytree
@dataclass(frozen=True)
class OrenNayar(Model):
    """Oren–Nayar BRDF (SIGGRAPH 1994), qualitative or full.

    Parameters
    ----------
    albedo : float or array (C,)
        Facet albedo ρ in [0, 1], per channel for RGB.
    sigma : float
        Roughness σ in [0, π/2] radians: standard deviation of the facet slope angle.
    variant : {"qualitative", "full"}
        The paper's simplified model (Eq. 30) or its full approximation with
        interreflections (Eq. 27–31).

    Examples
    --------
    Light and view on the normal: f = ρA/π.

    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> m = OrenNayar(albedo=1.0, sigma=0.3)
    >>> round(float(m.brdf(n, n)) * np.pi, 6)  # A = 1 - 0.5 * 0.09 / 0.42
    0.892857
    """

    albedo: float | Array = 1.0
    sigma: float | Array = 0.0
    variant: Variant = "qualitative"

    params: ClassVar[tuple[Param, ...]] = (
        Param(
            "albedo",
            "facet albedo ρ",
            min=0.0,
            max=1.0,
            default=1.0,
            channels=True,
            example=0.8,
        ),
        Param(
            "sigma",
            "roughness σ, standard deviation of the facet slope angle",
            unit="radians",
            min=0.0,
            max=SIGMA_MAX,
            default=0.0,
            example=math.radians(20.0),
        ),
        Param(
            "variant",
            "qualitative model (Eq. 30) or full model with interreflection (Eq. 27-31)",
            choices=("qualitative", "full"),
            default="qualitative",
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {
        "oren-nayar": {"variant": "qualitative"},
        "oren-nayar-full": {"variant": "full"},
    }
    labels: ClassVar[dict[str, str]] = {
        "oren-nayar": "Oren–Nayar qualitative",
        "oren-nayar-full": "Oren–Nayar full",
    }
    reference: ClassVar[str] = (
        "M. Oren, S. K. Nayar, Generalization of Lambert's reflectance model, SIGGRAPH 1994"
    )
    order: ClassVar[int] = 10
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "oren-nayar": ({"sigma": 0.0}, {"sigma": 0.4}),
        "oren-nayar-full": ({"sigma": 0.4}, {"sigma": math.pi / 2}),
    }
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "sigma": r"\sigma",
    }
    formula: ClassVar[str | dict[str, str]] = {
        "oren-nayar": r"""
            ```{math}
            f_r = \frac{\rho}{\pi}\Bigl(A +
            B\,\max\bigl(0,\cos(\phi_r-\phi_i)\bigr)\,\sin\alpha\,\tan\beta\Bigr) \tag{Eq. 30}
            ```
            ```{math}
            A = 1 - 0.5\,\frac{\sigma^2}{\sigma^2+0.33},
            ```
            ```{math}
            B = 0.45\,\frac{\sigma^2}{\sigma^2+0.09},
            ```
            ```{math}
            \alpha = \max(\theta_i,\theta_r),
            ```
            ```{math}
            \beta = \min(\theta_i,\theta_r)
            ```

            The qualitative model of Oren and Nayar (1994), their Eq. 30: the main effect of the
            V-cavity surface, without the interreflection term. Evaluated in vector form:
            {math}`\max(0,\cos(\phi_r-\phi_i))\sin\alpha\tan\beta = \max(0, s)/\max(\mu_i,\mu_o)`
            with {math}`s = \omega_i\cdot\omega_o - \mu_i\mu_o`; the denominator is floored at
            10⁻⁶ (both directions grazing). σ = 0 gives Lambert exactly.
            """,
        "oren-nayar-full": r"""
            ```{math}
            f_r = \max\Bigl(0,\ \frac{L_1 + L_2}{E_0\cos\theta_i}\Bigr)
            ```

            the one-bounce term (the paper's Eq. 27, with its coefficients C1, C2, C3),

            ```{math}
            L_1 = \frac{\rho}{\pi}E_0\cos\theta_i\Bigl[C_1 + c\,C_2\tan\beta +
            \bigl(1-|c|\bigr)\,C_3\tan\frac{\alpha+\beta}{2}\Bigr] \tag{Eq. 27}
            ```
            ```{math}
            C_1 = 1 - 0.5\,\frac{\sigma^2}{\sigma^2+0.33}
            ```
            ```{math}
            C_2 = \begin{cases} 0.45\,\dfrac{\sigma^2}{\sigma^2+0.09}\,\sin\alpha & c \ge
            0,\\[6pt] 0.45\,\dfrac{\sigma^2}{\sigma^2+0.09}\Bigl(\sin\alpha -
            \bigl(\tfrac{2\beta}{\pi}\bigr)^3\Bigr) & c < 0,\end{cases}
            ```
            ```{math}
            C_3 = 0.125\,\frac{\sigma^2}{\sigma^2+0.09}\Bigl(\frac{4\alpha\beta}{\pi^2}\Bigr)^2
            ```

            and the two-bounce interreflection term (Eq. 31)

            ```{math}
            L_2 = 0.17\,\frac{\rho^2}{\pi}E_0\cos\theta_i\,\frac{\sigma^2}{\sigma^2+0.13}\Bigl[1 -
            c\Bigl(\frac{2\beta}{\pi}\Bigr)^2\Bigr] \tag{Eq. 31}
            ```

            with {math}`c = \cos(\phi_r-\phi_i)`, {math}`\alpha = \max(\theta_i,\theta_r)`,
            {math}`\beta = \min(\theta_i,\theta_r)` (as in Mitsuba 0.6's ``roughdiffuse`` plugin).

            Conventions of this implementation: c is computed as
            {math}`(\omega_i\cdot\omega_o-\mu_i\mu_o)/(\sin\theta_i\sin\theta_r)`, clamped to [−1,
            1] (and irrelevant where either angle is 0, since β = 0 there);
            {math}`\tan\frac{\alpha+\beta}{2}` is computed exactly as
            {math}`(\sin\alpha+\sin\beta)/(\cos\alpha+\cos\beta)`, the denominator floored at
            2·10⁻⁶, and cos β in tan β at 10⁻⁶ (both directions grazing). The result is clamped at
            0: near grazing backscatter with σ above about 1 rad the fitted C2 term makes L1 + L2
            negative (the paper's formula is not clamped). L2 is quadratic in ρ, so f is not
            linear in the albedo. σ = 0 gives Lambert exactly.
            """,
    }

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, sigma: Array
    ) -> Array:
        if self.variant == "full":
            return _full(xp, mu_i, mu_o, cos_io, sigma, albedo)
        return albedo / math.pi * _qualitative(xp, mu_i, mu_o, cos_io, sigma)


def oren_nayar(
    theta_i: Array,
    theta_r: Array,
    delta_phi: Array,
    sigma: float,
    albedo: Any = 1.0,
    variant: Variant = "qualitative",
) -> Array:
    """Oren–Nayar BRDF in the paper's notation: f(θi, θr, φr − φi; σ, ρ).

    Parameters
    ----------
    theta_i, theta_r : array
        Incidence and viewing angles from the normal, radians, in [0, π/2].
    delta_phi : array
        Azimuth difference φr − φi, radians.
    sigma : float
        Roughness σ in radians.
    albedo : float or array (C,)
        Facet albedo ρ.
    variant : {"qualitative", "full"}

    Returns
    -------
    array
        f_r in 1/sr (multiply by E0 cos θi for the paper's radiance L).

    Examples
    --------
    >>> round(float(oren_nayar(0.0, 0.0, 0.0, sigma=0.0, albedo=1.0)) * 3.141592653589793, 12)
    1.0
    """
    model = OrenNayar(albedo=albedo, sigma=sigma, variant=variant)
    xp = namespace(theta_i, theta_r, delta_phi, sigma, albedo)
    dtype = result_dtype(xp, theta_i, theta_r, delta_phi)
    for name, th in (("theta_i", theta_i), ("theta_r", theta_r)):
        check_range(name, th, 0.0, math.pi / 2, unit="radians", scalar=False)
    mu_i, mu_o, cos_io = angles_to_cosines(xp, theta_i, theta_r, delta_phi, dtype)
    return model.brdf_cosines(mu_i, mu_o, cos_io)
