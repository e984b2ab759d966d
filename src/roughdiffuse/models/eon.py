"""EON: the energy-preserving Oren–Nayar model.

J. Portsmouth, P. Kutz, S. Hill, "EON: A practical energy-preserving rough diffuse BRDF",
JCGT 2025 (arXiv 2410.18026); adopted by OpenPBR 1.1, MaterialX and Blender Cycles.

Single scattering is Fujii's model (f_ss = ρ/π A_F (1 + r s/t)); the energy it loses is given
back by a multiple-scattering lobe (paper Eq. 11–13)::

    ρ_ms = ρ² Ē_F / (1 − ρ (1 − Ē_F)),
    f_ms = ρ_ms/π · (1 − E_F(μo)) (1 − E_F(μi)) / (1 − Ē_F),

so that with ρ = 1 the directional albedo is 1 at every angle (the white furnace test).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array, safe_div
from .base import Model, register_pytree
from .declaration import Param
from .fujii import fon_albedo, fon_average_albedo, fon_lobe
from .sampling import CLTC, Strategy

__all__ = ["EON", "eon_albedo", "multiple_scattering"]


def _rho_ms(albedo: Array, e_avg: Array) -> Array:
    """Multiple-scattering albedo ρ² Ē_F / (1 − ρ (1 − Ē_F)) (paper Eq. 12)."""
    return albedo * albedo * e_avg / (1.0 - albedo * (1.0 - e_avg))


def multiple_scattering(xp: Any, mu_i: Array, mu_o: Array, albedo: Array, r: Array) -> Array:
    """EON's multiple-scattering lobe f_ms = ρ_ms/π (1 − E_F(μo))(1 − E_F(μi))/(1 − Ē_F)
    (paper Eq. 11–13); 0 at r = 0, where no energy is lost to give back."""
    e_avg = fon_average_albedo(r)
    lobe = (1.0 - fon_albedo(xp, mu_o, r)) * (1.0 - fon_albedo(xp, mu_i, r))
    return _rho_ms(albedo, e_avg) / math.pi * safe_div(xp, lobe, 1.0 - e_avg + 0.0 * lobe)


@register_pytree
@dataclass(frozen=True)
class EON(Model):
    """Energy-preserving Oren–Nayar BRDF, f = f_ss + f_ms.

    Parameters
    ----------
    albedo : float or array (C,)
        Single-scattering albedo ρ in [0, 1].
    roughness : float
        r in [0, 1] (Fujii's parameter, not an angle).

    Examples
    --------
    White furnace: ρ = 1 reflects everything at every angle.

    >>> import numpy as np
    >>> wo = np.array([0.6, 0.0, 0.8])
    >>> round(float(EON(1.0, 0.7).directional_albedo(wo)), 12)
    1.0
    """

    albedo: float | Array = 1.0
    roughness: float | Array = 0.0

    params: ClassVar[tuple[Param, ...]] = (
        Param(
            "albedo",
            "single-scattering albedo ρ",
            min=0.0,
            max=1.0,
            default=1.0,
            channels=True,
            example=0.8,
        ),
        Param(
            "roughness",
            "Fujii's roughness r (not an angle)",
            min=0.0,
            max=1.0,
            default=0.0,
            example=0.5,
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"eon": {}}
    labels: ClassVar[dict[str, str]] = {"eon": "EON"}
    sampling: ClassVar[Strategy] = CLTC
    reference: ClassVar[str] = (
        "J. Portsmouth, P. Kutz, S. Hill, EON: A practical energy-preserving rough diffuse BRDF, "
        "JCGT 2025"
    )
    order: ClassVar[int] = 30
    test_points: ClassVar[dict[str, tuple[dict[str, Any], ...]]] = {
        "eon": ({"roughness": 0.0}, {"roughness": 1.0})
    }
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "roughness": r"r",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = f_{ss} + f_{ms}, \tag{Eq. 11–13}
        ```
        ```{math}
        f_{ss} = \frac{\rho}{\pi}A_F\Bigl(1 + r\,\frac{s}{t}\Bigr),
        ```
        ```{math}
        f_{ms} =
        \frac{\rho_{ms}}{\pi}\,\frac{\bigl(1-E_F(\mu_o)\bigr)\bigl(1-E_F(\mu_i)\bigr)}{1-\bar
        E_F}
        ```
        ```{math}
        \rho_{ms} = \frac{\rho^2\,\bar E_F}{1-\rho\,(1-\bar E_F)},
        ```
        ```{math}
        A_F = \frac{1}{1+K_1 r},
        ```
        ```{math}
        K_1 = \frac12 - \frac{2}{3\pi}
        ```
        ```{math}
        E_F(\mu) = A_F + \frac{r A_F}{\pi}\,G(\mu), \tag{Eq. 8}
        ```
        ```{math}
        G(\mu) = S\,(\arccos\mu - S\mu) + \frac23\Bigl[\frac{S}{\mu}(1-S^3) - S\Bigr],
        ```
        ```{math}
        S = \sqrt{1-\mu^2}
        ```
        ```{math}
        \bar E_F = A_F\,(1 + K_2 r),
        ```
        ```{math}
        K_2 = \frac23 - \frac{28}{15\pi}
        ```

        Portsmouth, Kutz and Hill (JCGT 2025): s and t as in {doc}`fujii`. With ρ = 1 the
        directional albedo is 1 at every angle. {math}`(S/\mu)(1-S^3)` is evaluated as
        {math}`S\mu(1+S+S^2)/(1+S)`, finite at μ = 0; at r = 0 the 0/0 of f_ms is 0.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        f_ss = albedo / math.pi * fon_lobe(xp, mu_i, mu_o, cos_io, roughness)
        return f_ss + multiple_scattering(xp, mu_i, mu_o, albedo, roughness)

    def directional_albedo(self, wo: Array) -> Array:
        """Closed form ρ E_F(μo) + ρ_ms (1 − E_F(μo)) (paper Eq. 14)."""

        return self._closed_form_albedo(wo, eon_albedo)


def eon_albedo(
    xp: Any, mu: Array, albedo: Array, roughness: Array, ms_weight: Array | float = 1.0
) -> Array:
    """ρ E_F(μ) + w ρ_ms (1 − E_F(μ)): EON's directional albedo (paper Eq. 14) with the
    multiple-scattering part weighted by ``w`` (1 for EON)."""
    e = fon_albedo(xp, mu, roughness)
    return albedo * e + ms_weight * _rho_ms(albedo, fon_average_albedo(roughness)) * (1.0 - e)
