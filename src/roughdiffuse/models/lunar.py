"""Lunar photometry: the models that make the full moon look flat.

* Lommel–Seeliger (single scattering in a dim, semi-infinite particulate medium; Hapke,
  *Theory of Reflectance and Emittance Spectroscopy*, 2nd ed., 2012, Eq. 9.13 with an isotropic
  phase function)::

      f = w / (4π (cos θi + cos θr)),     w the single-scattering albedo.

  Its directional albedo is closed: (w/2) (1 − μo ln(1 + 1/μo)).

* Lunar-Lambert (McEwen, "Photometric functions for photoclinometry and other applications",
  Icarus 92, 1991), as planetary-photometry software (ISIS ``LunarLambert``) defines the
  reflectance: r = (1 − L) cos i + 2 L cos i/(cos i + cos e). As a BRDF normalised so that
  L = 0 is Lambert with albedo ρ::

      f = ρ/π [(1 − L) + 2 L/(cos θi + cos θr)].

Both are written as radiance factors I/F and converted to f_r in one place,
:func:`.photometry.brdf_from_radiance_factor`. Both diverge only when both directions are
grazing; the sum of cosines is floored at 1e-6.
"""

from __future__ import annotations

from typing import Any, ClassVar

from .._array import Array, maximum, safe_div
from .base import Model
from .declaration import albedo_param, param
from .photometry import HORIZON_FLOOR, brdf_from_radiance_factor

__all__ = ["LommelSeeliger", "LunarLambert"]


L_MAX = 1e3
"""Largest accepted L. ISIS's ``LunarLambert`` accepts any L (its unit test takes L = 2) and
fits search [0, 1]; a finite ceiling keeps the BRDF finite (L = 1e308 overflows to ∞, an
all-zero corrected image): 1e3 is far beyond any fit."""


class LommelSeeliger(Model):
    """Lommel–Seeliger BRDF, f = w / (4π (μi + μo)).

    Parameters
    ----------
    albedo : float or array (C,)
        Single-scattering albedo w in [0, 1].
    """

    albedo: float | Array = albedo_param("single-scattering albedo w")

    ids: ClassVar[dict[str, dict[str, Any]]] = {"lommel-seeliger": {}}
    labels: ClassVar[dict[str, str]] = {"lommel-seeliger": "Lommel–Seeliger"}
    reference: ClassVar[str] = (
        "B. Hapke, Theory of Reflectance and Emittance Spectroscopy, 2nd ed. (2012), Eq. 9.13"
    )
    order: ClassVar[int] = 60
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"w",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{w}{4\pi\,(\mu_i+\mu_o)}
        ```

        Single scattering in a dim semi-infinite particulate medium with an isotropic phase
        function (Hapke 2012, Eq. 9.13), as the radiance factor {math}`I/F =
        \frac{w}{4}\frac{\mu_i}{\mu_i+\mu_o}` divided by {math}`\pi\mu_i`. {math}`\mu_i+\mu_o`
        is floored at 10⁻⁶ (both directions grazing).
        """

    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array) -> Array:
        # I/F = (w/4) μ0/(μ0 + μ)
        return brdf_from_radiance_factor(albedo / (4.0 * maximum(xp, mu_i + mu_o, HORIZON_FLOOR)))

    def directional_albedo(self, wo: Array) -> Array:
        """Closed form (w/2)(1 − μo ln(1 + 1/μo)), 0 below the horizon."""

        def closed(xp: Any, mu: Array, albedo: Array) -> Array:
            # μ ln(1 + 1/μ) = μ (ln(1 + μ) − ln μ) -> 0 as μ -> 0
            pos = mu > 0
            m = xp.where(pos, mu, 1.0)
            return albedo * xp.where(pos, 0.5 * (1.0 - m * (xp.log1p(m) - xp.log(m))), 0.5)

        return self._closed_form_albedo(wo, closed)


class LunarLambert(Model):
    """McEwen's Lunar-Lambert BRDF, f = ρ/π [(1 − L) + 2L/(μi + μo)].

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1]; L = 0 is Lambert with this albedo.
    limb_darkening : float
        L in [0, 1000], the weight of the Lommel–Seeliger term (0.5–1 for the moon near
        full). ISIS's ``LunarLambert`` accepts any L (its unit test takes L = 2; see
        ``L_MAX``); for every L >= 0 the I/F
        μ0 [(1 − L) + 2L/(μ0 + μ)] is positive, as μ0 + μ <= 2. Fits search [0, 1].
        Default 0.5: half Lambert, half Lommel–Seeliger (L = 1 is the ``lommel-seeliger``
        model up to its normalisation).
    """

    albedo: float | Array = albedo_param("albedo ρ (L = 0: Lambert)")
    limb_darkening: float | Array = param(
        "L, weight of the Lommel–Seeliger term",
        min=0.0,
        max=L_MAX,
        default=0.5,
        fit_range=(0.0, 1.0),
    )

    ids: ClassVar[dict[str, dict[str, Any]]] = {"lunar-lambert": {}}
    labels: ClassVar[dict[str, str]] = {"lunar-lambert": "Lunar-Lambert"}
    reference: ClassVar[str] = (
        "A. S. McEwen, Photometric functions for photoclinometry and other applications, "
        "Icarus 92 (1991)"
    )
    order: ClassVar[int] = 70
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "limb_darkening": r"L",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\Bigl[(1-L) + \frac{2L}{\mu_i+\mu_o}\Bigr]
        ```

        McEwen (1991): the reflectance {math}`r = (1-L)\cos i + 2L\cos i/(\cos i+\cos e)`,
        normalised so that L = 0 is Lambert with albedo ρ. {math}`\mu_i+\mu_o` is floored at
        10⁻⁶.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, limb_darkening: Array
    ) -> Array:
        # I/F = ρ [(1 − L) μ0 + 2 L μ0/(μ0 + μ)]
        ls = safe_div(xp, 2.0, maximum(xp, mu_i + mu_o, HORIZON_FLOOR))
        return brdf_from_radiance_factor(albedo * ((1.0 - limb_darkening) + limb_darkening * ls))
