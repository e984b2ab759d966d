"""Hammon's diffuse for GGX–Smith microsurfaces of Lambertian facets.

E. Hammon Jr., "PBR Diffuse Lighting for GGX+Smith Microsurfaces", GDC 2017, slide 113: a fit
to simulations of Lambertian facets on a GGX height field with Smith shadowing, single and
multiple scattering::

    f = ρ/π [(1 − α) f_smooth + α f_rough] + ρ² f_multi,
    f_smooth = 1.05 (1 − (1 − μi)⁵)(1 − (1 − μo)⁵),
    f_rough  = F (0.9 − 0.4 F)(0.5 + n·h)/n·h,   F = (1 + wi·wo)/2 = (wi·h)²,
    f_multi  = 0.1159 α,

α the GGX roughness (Trowbridge–Reitz α = perceptual roughness²). The single-scattering part
is ρ/π times a lerp; the multiple-scattering part 0.1159 α ρ² carries no 1/π: Unity's
``DiffuseGGXNoPI`` (Graphics, ``ShaderLibrary/BSDF.hlsl``), which returns π f/ρ, writes it as
``roughness * (0.1159 * PI)``, and with that reading the white furnace stays near 1 (see
:class:`Hammon`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, maximum
from ..frames import half_vector_cosines
from .base import Model, register_pytree
from .burley import schlick_weight
from .declaration import Param

__all__ = ["Hammon"]

_NH_FLOOR = 1e-6
"""n·h is 0 only when wi = −wo on the horizon; f_rough's 1/n·h is floored there."""


@register_pytree
@dataclass(frozen=True)
class Hammon(Model):
    """Hammon's GGX diffuse (GDC 2017).

    Parameters
    ----------
    albedo : float or array (C,)
        Facet albedo ρ in [0, 1].
    alpha : float
        GGX roughness α in [0, 1] (α = perceptual roughness²); 0 is the smooth limit.

    Reciprocal. At α = 0 it is 1.05 ρ/π times the two Schlick transmissions (Hammon's
    smooth-surface model); it is not Lambert.

    Examples
    --------
    α = 0, lit and seen along the normal: f = 1.05 ρ/π.

    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> round(float(Hammon(1.0, 0.0).brdf(n, n) * np.pi), 12)
    1.05
    """

    albedo: float | Array = 1.0
    alpha: float | Array = 0.3

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
        Param("alpha", "GGX roughness α (perceptual roughness²)", min=0.0, max=1.0, default=0.3),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"hammon": {}}
    labels: ClassVar[dict[str, str]] = {"hammon": "Hammon (GGX diffuse)"}
    reference: ClassVar[str] = (
        "E. Hammon Jr., PBR Diffuse Lighting for GGX+Smith Microsurfaces, GDC 2017"
    )
    order: ClassVar[int] = 110
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {"hammon": ({"alpha": 0.5},)}
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "alpha": r"\alpha",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\bigl[(1-\alpha)f_{\mathrm{smooth}} + \alpha
        f_{\mathrm{rough}}\bigr] + \rho^2 f_{\mathrm{multi}}
        ```
        ```{math}
        f_{\mathrm{smooth}} = 1.05\bigl(1-(1-\mu_i)^5\bigr)\bigl(1-(1-\mu_o)^5\bigr),
        ```
        ```{math}
        f_{\mathrm{rough}} = F\,(0.9-0.4F)\,\frac{0.5 + n\cdot h}{n\cdot h},
        ```
        ```{math}
        F = \frac{1+\omega_i\cdot\omega_o}{2},
        ```
        ```{math}
        f_{\mathrm{multi}} = 0.1159\,\alpha
        ```

        Hammon (GDC 2017, slide 113), a fit to Lambertian facets on a GGX–Smith microsurface;
        α is the GGX roughness (perceptual roughness²). f_multi carries no 1/π, as in Unity's
        ``DiffuseGGXNoPI``. n·h is floored at 10⁻⁶. At α = 0 it is 1.05 ρ/π times two Schlick
        transmissions, not Lambert.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, alpha: Array
    ) -> Array:
        cos_h, cos_d = half_vector_cosines(xp, mu_i, mu_o, cos_io)
        facing = cos_d * cos_d
        rough = facing * (0.9 - 0.4 * facing) * (1.0 + 0.5 / maximum(xp, cos_h, _NH_FLOOR))
        smooth = 1.05 * (1.0 - schlick_weight(mu_i)) * (1.0 - schlick_weight(mu_o))
        single = smooth + alpha * (rough - smooth)
        return albedo / math.pi * single + albedo * albedo * (0.1159 * alpha)
