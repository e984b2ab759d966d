"""Chan's diffuse of Call of Duty: WWII: Lambertian microfacets with multiple scattering.

D. Chan, "Material Advances in Call of Duty: WWII", SIGGRAPH 2018 course "Advances in
Real-Time Rendering", Sec. 5 (course notes); read from the notes and from Unreal Engine's
``Engine/Shaders/Private/BRDF.ush`` (``Diffuse_Chan``), which ships it::

    f = ρ/π (F_d + F_b),
    F_d = lerp(wi·h + (1 − wi·h)⁵, (1 − 0.75 (1 − μi)⁵)(1 − 0.75 (1 − μo)⁵), sat(2.2 g − 0.5)),
    F_b = ((34.5 g − 59) g + 24.5) (wi·h) 2^(−max(73.2 g − 21.2, 8.9) √(n·h)),

with the gloss g = sat(log₂(2/α² − 1)/18), the inverse of Chan's parameterisation
α = √(2/(1 + 2^(18 g))) of GGX (notes Eq. 1). α is the GGX roughness; α ≤ 0.0028 is g = 1.
Unreal's extra ``RetroReflectivityWeight`` (a fade for area lights) is 1 here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, clip, maximum, safe_sqrt
from ..frames import half_vector_cosines
from .base import Model, register_pytree
from .burley import schlick_weight
from .declaration import Param

__all__ = ["Chan", "chan_gloss"]

_LN2 = math.log(2.0)
_ALPHA2_FLOOR = 1e-12  # α² below this is g = 1 anyway (g saturates at α² = 2/(2¹⁸ + 1))


def chan_gloss(xp: Any, alpha: Array) -> Array:
    """Chan's gloss g = sat(log₂(2/α² − 1)/18) in [0, 1] from GGX α in [0, 1]."""
    a2 = maximum(xp, alpha * alpha, _ALPHA2_FLOOR)
    return clip(xp, xp.log(2.0 / a2 - 1.0) / (18.0 * _LN2), 0.0, 1.0)


@register_pytree
@dataclass(frozen=True)
class Chan(Model):
    """Chan's diffuse BRDF (SIGGRAPH 2018).

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1].
    alpha : float
        GGX roughness α in [0, 1].

    Reciprocal (every term is symmetric in wi and wo).

    Examples
    --------
    α = 1 is g = 0: F_d = wi·h + (1 − wi·h)⁵ and F_b = 24.5 (wi·h) 2^(−8.9 √(n·h)). Lit and
    seen along the normal, π f/ρ = 1 + 24.5 · 2^−8.9:

    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> round(float(Chan(1.0, 1.0).brdf(n, n) * np.pi), 12) == round(1 + 24.5 * 2**-8.9, 12)
    True
    """

    albedo: float | Array = 1.0
    alpha: float | Array = 0.3

    params: ClassVar[tuple[Param, ...]] = (
        Param(
            "albedo",
            "albedo ρ",
            min=0.0,
            max=1.0,
            default=1.0,
            channels=True,
            example=0.8,
        ),
        Param("alpha", "GGX roughness α", min=0.0, max=1.0, default=0.3),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"chan": {}}
    labels: ClassVar[dict[str, str]] = {"chan": "Chan (Call of Duty: WWII)"}
    reference: ClassVar[str] = (
        "D. Chan, Material Advances in Call of Duty: WWII, SIGGRAPH 2018 course notes, Sec. 5"
    )
    order: ClassVar[int] = 120
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {"chan": ({"alpha": 0.4},)}
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "alpha": r"\alpha",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\,(F_d + F_b)
        ```
        ```{math}
        F_d &= \operatorname{lerp}\Bigl(\omega_i\cdot h + (1-\omega_i\cdot h)^5,\ \\
        &\qquad \bigl(1-0.75(1-\mu_i)^5\bigr)\bigl(1-0.75(1-\mu_o)^5\bigr),\
        \operatorname{sat}(2.2g-0.5)\Bigr)
        ```
        ```{math}
        F_b = \bigl((34.5g-59)g+24.5\bigr)\,(\omega_i\cdot h)\;2^{-\max(73.2g-21.2,\
        8.9)\sqrt{n\cdot h}},
        ```
        ```{math}
        g = \operatorname{sat}\Bigl(\frac{\log_2(2/\alpha^2-1)}{18}\Bigr)
        ```

        Chan (SIGGRAPH 2018, "Material Advances in Call of Duty: WWII", Sec. 5), as Unreal
        Engine's ``Diffuse_Chan``; g is the gloss, the inverse of Chan's {math}`\alpha =
        \sqrt{2/(1+2^{18g})}` (notes Eq. 1); sat clamps to [0, 1]. α² is floored at 10⁻¹² (g =
        1 there).
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, alpha: Array
    ) -> Array:
        g = chan_gloss(xp, alpha)
        cos_h, cos_d = half_vector_cosines(xp, mu_i, mu_o, cos_io)
        cos_h = clip(xp, cos_h, 0.0, 1.0)
        rough = cos_d + schlick_weight(cos_d)
        smooth = (1.0 - 0.75 * schlick_weight(mu_i)) * (1.0 - 0.75 * schlick_weight(mu_o))
        fd = rough + clip(xp, 2.2 * g - 0.5, 0.0, 1.0) * (smooth - rough)
        rate = maximum(xp, 73.2 * g - 21.2, 8.9)
        fb = ((34.5 * g - 59.0) * g + 24.5) * cos_d * xp.exp(-_LN2 * rate * safe_sqrt(xp, cos_h))
        return albedo / math.pi * (fd + fb)
