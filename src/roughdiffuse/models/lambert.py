"""Lambert's law: the perfectly diffuse (smooth matte) surface.

f = ρ/π (Lambert 1760; the lecture's recap, L = ρ/π E0 n·s).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array
from .base import Model, register_pytree
from .declaration import Param


@register_pytree
@dataclass(frozen=True)
class Lambert(Model):
    """Lambertian BRDF, f = ρ/π.

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1], per channel for RGB.

    Examples
    --------
    >>> import numpy as np
    >>> float(Lambert(0.5).brdf(np.array([0, 0, 1.0]), np.array([0, 0, 1.0])))  # 0.5/π
    0.15915494309189535
    """

    albedo: float | Array = 1.0

    params: ClassVar[tuple[Param, ...]] = (
        Param("albedo", "albedo ρ", min=0.0, max=1.0, default=1.0, channels=True, example=0.8),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"lambert": {}}
    labels: ClassVar[dict[str, str]] = {"lambert": "Lambert"}
    reference: ClassVar[str] = "J. H. Lambert, Photometria (1760)"
    order: ClassVar[int] = 0
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}
        ```

        Lambert (1760): the same radiance in every direction. The directional albedo is ρ at
        every angle.
        """

    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array) -> Array:
        return albedo / math.pi + 0.0 * mu_i

    def directional_albedo(self, wo: Array) -> Array:
        """Closed form: ρ for wo above the horizon, 0 below."""
        return self._closed_form_albedo(wo, lambda xp, mu, albedo: albedo + 0.0 * mu)
