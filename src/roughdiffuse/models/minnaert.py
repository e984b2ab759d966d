"""Minnaert's limb-darkening law.

M. Minnaert, "The reciprocity principle in lunar photometry", Astrophysical Journal 93 (1941)
403, Eq. (1); as planetary-photometry software defines it (USGS ISIS ``Minnaert``, VICAR
``PHO_MINNAERT``): the radiance factor I/F = ρ μ0^k μ^(k−1), so (through
:mod:`roughdiffuse.models.photometry`)::

    f = ρ/π (μi μo)^(k−1).

k = 1 is Lambert; k < 1 flattens the disk (k ≈ 0.5–0.7 for the moon near full; 0 makes I/F
independent of the incidence) and diverges at the limb; k > 1 darkens the limb. Its directional
albedo is closed: 2ρ μo^(k−1)/(k + 1).
"""

from __future__ import annotations

from typing import Any, ClassVar

from .._array import Array, maximum
from .base import Model
from .declaration import albedo_param, param
from .photometry import HORIZON_FLOOR, brdf_from_radiance_factor

__all__ = ["Minnaert"]


class Minnaert(Model):
    """Minnaert BRDF, f = ρ/π (μi μo)^(k−1).

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1], the normal albedo (I/F at i = e = 0).
    k : float
        Minnaert exponent in [0, 2]; 1 is Lambert.

    Reciprocal (symmetric in μi and μo).

    Examples
    --------
    ISIS's test (``Minnaert.truth``): k = 0.5 at i = 45°, e = 30° gives I/F = 0.903602.

    >>> import numpy as np
    >>> from roughdiffuse.models.photometry import radiance_factor
    >>> i, e = np.radians(45.0), np.radians(30.0)
    >>> round(float(radiance_factor(Minnaert(1.0, 0.5), i, e, np.radians(60.0))), 6)
    0.903602
    """

    albedo: float | Array = albedo_param("normal albedo ρ (I/F at i = e = 0)")
    k: float | Array = param(
        "Minnaert exponent k (1 = Lambert)",
        min=0.0,
        max=2.0,
        default=1.0,
        example=0.7,
    )

    ids: ClassVar[dict[str, dict[str, Any]]] = {"minnaert": {}}
    labels: ClassVar[dict[str, str]] = {"minnaert": "Minnaert (planetary)"}
    reference: ClassVar[str] = (
        "M. Minnaert, The reciprocity principle in lunar photometry, ApJ 93 (1941) 403"
    )
    order: ClassVar[int] = 150
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "k": r"k",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\,(\mu_i\,\mu_o)^{k-1}
        ```

        Minnaert (1941), Eq. 1, as the radiance factor {math}`I/F = \rho\,\mu_i^k\mu_o^{k-1}`
        divided by {math}`\pi\mu_i`. k = 1 is Lambert; each cosine is floored at 10⁻⁶ (k < 1
        diverges at the limb).
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, k: Array
    ) -> Array:
        mi, mo = maximum(xp, mu_i, HORIZON_FLOOR), maximum(xp, mu_o, HORIZON_FLOOR)
        # I/F / μ0 = ρ μ0^(k−1) μ^(k−1)
        return brdf_from_radiance_factor(albedo * (mi * mo) ** (k - 1.0))

    def directional_albedo(self, wo: Array) -> Array:
        """Closed form 2ρ μo^(k−1)/(k + 1) (μo floored at 1e-6 as in the BRDF)."""

        def closed(xp: Any, mu: Array, albedo: Array, k: Array) -> Array:
            return 2.0 * albedo * maximum(xp, mu, HORIZON_FLOOR) ** (k - 1.0) / (k + 1.0)

        return self._closed_form_albedo(wo, closed)
