"""Disney's diffuse and its descendants: Burley 2012, Frostbite's renormalisation, Burley 2015.

All three are products of Schlick-like factors in μi and μo with a grazing-retro-reflection
term in cos θd = wi·h (h the half vector), written from the three local cosines with
cos² θd = (1 + wi·wo)/2 (:func:`roughdiffuse.frames.half_vector_cosines`).

* Burley, "Physically-Based Shading at Disney", SIGGRAPH 2012 course notes, Sec. 5.3, Eq. (3)::

      f = ρ/π (1 + (F_D90 − 1)(1 − μi)⁵)(1 + (F_D90 − 1)(1 − μo)⁵),
      F_D90 = 0.5 + 2 r cos² θd.

* Lagarde & de Rousiers, "Moving Frostbite to Physically Based Rendering", SIGGRAPH 2014
  course notes, Listing 1: the same with F_D90 = 0.5 r + 2 r cos² θd and the whole scaled by
  1 − r (1 − 1/1.51), so that the albedo stays at or below 1.

* Burley, "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering",
  SIGGRAPH 2015 course notes, Eq. (4) (its Eq. (5) is the diffusion profile of the subsurface
  part), the diffuse of Mitsuba 3's ``principled``::

      f = ρ/π [(1 − F_L/2)(1 − F_V/2) + R_R (F_L + F_V + F_L F_V (R_R − 1))],
      F = (1 − μ)⁵,  R_R = 2 r cos² θd.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

from .._array import Array
from ..frames import half_vector_cosines
from .base import Model
from .declaration import albedo_param, param

__all__ = ["Burley", "Burley2015", "BurleyRenormalized", "schlick_weight"]

FROSTBITE_FACTOR = 1.0 / 1.51
"""Frostbite's energy factor at roughness 1 (Lagarde & de Rousiers 2014, Listing 1)."""


def schlick_weight(mu: Array) -> Array:
    """(1 − μ)⁵, the weight of Schlick's Fresnel approximation (Schlick 1994, Eq. 24)."""
    m = 1.0 - mu
    m2 = m * m
    return m2 * m2 * m


def _cos2_d(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array) -> Array:
    """cos² θd = (wi·h)²."""
    _, cos_d = half_vector_cosines(xp, mu_i, mu_o, cos_io)
    return cos_d * cos_d


def _schlick_product(mu_i: Array, mu_o: Array, f90: Array) -> Array:
    """(1 + (f90 − 1) F(μi)) (1 + (f90 − 1) F(μo)): Schlick with f0 = 1 at both ends."""
    return (1.0 + (f90 - 1.0) * schlick_weight(mu_i)) * (1.0 + (f90 - 1.0) * schlick_weight(mu_o))


def _roughness(description: str) -> Any:
    """The roughness r in [0, 1], each model saying what it means."""
    return param(description, min=0.0, max=1.0, default=0.5)


class Burley(Model):
    """Burley's (Disney's) 2012 diffuse BRDF.

    Burley, "Physically-Based Shading at Disney", SIGGRAPH 2012 course notes, Eq. (3); as in
    Filament (``shaders/src/surface_brdf.fs``, ``Fd_Burley``, compiled out by default: Filament
    renders Lambert) and MaterialX (``mx_burley_diffuse``); Unity HDRP's default
    ``DisneyDiffuse`` is it at the perceptual roughness, divided by 1.03571. Filament passes
    its α = perceptual roughness² here; roughdiffuse, like the paper and MaterialX, uses
    Disney's roughness r as it is.

    Parameters
    ----------
    albedo : float or array (C,)
        Base colour ρ in [0, 1].
    roughness : float
        Disney's roughness r in [0, 1] (not squared).

    Reciprocal; not energy-conserving (see the white-furnace figure).

    Examples
    --------
    r = 0, lit and seen along the normal: F_D90 = 0.5 does not act, f = ρ/π.

    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> round(float(Burley(1.0, 0.0).brdf(n, n) * np.pi), 12)
    1.0
    """

    albedo: float | Array = albedo_param("base colour ρ")
    roughness: float | Array = _roughness("Disney's roughness r (as it is, not squared)")

    ids: ClassVar[dict[str, dict[str, Any]]] = {"burley": {}}
    labels: ClassVar[dict[str, str]] = {"burley": "Burley 2012 (Disney)"}
    reference: ClassVar[str] = (
        "B. Burley, Physically-Based Shading at Disney, SIGGRAPH 2012 course notes, Eq. 3"
    )
    order: ClassVar[int] = 80
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "roughness": r"r",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\bigl(1 + (F_{D90}-1)(1-\mu_i)^5\bigr)\bigl(1 +
        (F_{D90}-1)(1-\mu_o)^5\bigr), \tag{Eq. 3}
        ```
        ```{math}
        F_{D90} = 0.5 + 2r\cos^2\theta_d
        ```

        Burley (SIGGRAPH 2012 course notes, Sec. 5.3). {math}`\cos\theta_d = \omega_i\cdot h`
        with h the half vector, computed as {math}`\cos^2\theta_d =
        (1+\omega_i\cdot\omega_o)/2`. r is Disney's roughness, not squared. Not
        energy-conserving.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        f90 = 0.5 + 2.0 * roughness * _cos2_d(xp, mu_i, mu_o, cos_io)
        return albedo / math.pi * _schlick_product(mu_i, mu_o, f90)


class BurleyRenormalized(Model):
    """Frostbite's renormalised Disney diffuse.

    Lagarde & de Rousiers, "Moving Frostbite to Physically Based Rendering", SIGGRAPH 2014
    course notes, Listing 1 (``Fr_DisneyDiffuse``); as in Falcor (``BxDF.slang``,
    ``DiffuseReflectionFrostbite``)::

        f = ρ/π (1 − r (1 − 1/1.51)) S(μi) S(μo),  F_D90 = 0.5 r + 2 r cos² θd.

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1].
    roughness : float
        Frostbite's linear roughness r in [0, 1].

    Reciprocal. At r = 0, F_D90 = 0 and f = ρ/π (1 − F(μi))(1 − F(μo)), F = (1 − μ)⁵: the
    product of Schlick transmissions, not Lambert.

    Examples
    --------
    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> round(float(BurleyRenormalized(1.0, 1.0).brdf(n, n) * np.pi), 12)  # 1/1.51
    0.662251655629
    """

    albedo: float | Array = albedo_param("base colour ρ")
    roughness: float | Array = _roughness("Frostbite's linear roughness r")

    ids: ClassVar[dict[str, dict[str, Any]]] = {"frostbite": {}}
    labels: ClassVar[dict[str, str]] = {"frostbite": "Frostbite (renormalised Burley)"}
    reference: ClassVar[str] = (
        "S. Lagarde, C. de Rousiers, Moving Frostbite to Physically Based Rendering,"
        " SIGGRAPH 2014 course notes, Listing 1"
    )
    order: ClassVar[int] = 90
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "roughness": r"r",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\Bigl(1 - r\bigl(1 - \tfrac{1}{1.51}\bigr)\Bigr)\bigl(1 +
        (F_{D90}-1)(1-\mu_i)^5\bigr)\bigl(1 + (F_{D90}-1)(1-\mu_o)^5\bigr),
        ```
        ```{math}
        F_{D90} = 0.5\,r + 2r\cos^2\theta_d
        ```

        Lagarde and de Rousiers (SIGGRAPH 2014 course notes, Listing 1); {math}`\cos^2\theta_d
        = (1+\omega_i\cdot\omega_o)/2`. At r = 0 it is the product of two Schlick
        transmissions, not Lambert.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        f90 = roughness * (0.5 + 2.0 * _cos2_d(xp, mu_i, mu_o, cos_io))
        factor = 1.0 - roughness * (1.0 - FROSTBITE_FACTOR)
        return albedo / math.pi * factor * _schlick_product(mu_i, mu_o, f90)


class Burley2015(Model):
    """Burley's 2015 diffuse: a Lambertian part and a separate retro-reflection lobe.

    Burley, "Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering",
    SIGGRAPH 2015 course notes, Eq. (4); the diffuse of Mitsuba 3's ``principled``
    (``src/bsdfs/principled.cpp``, without sheen and flatness).

    Parameters
    ----------
    albedo : float or array (C,)
        ρ in [0, 1].
    roughness : float
        Disney's roughness r in [0, 1].

    Notes
    -----
    Reciprocal. Expanding shows it is Burley 2012 rewritten, not a new model:
    (1 + (F_D90 − 1) F_L)(1 + (F_D90 − 1) F_V) with F_D90 = 1/2 + R_R is
    1 + (R_R − 1/2)(F_L + F_V) + (R_R − 1/2)² F_L F_V, which is the expression above; the
    2015 notes split it so that the Lambertian part can be replaced by subsurface scattering.
    The values equal :class:`Burley`'s to rounding (tested); the id is kept for users who
    match Mitsuba 3's ``principled``.

    Examples
    --------
    Along the normal F_L = F_V = 0 and only the Lambertian part is left:

    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> round(float(Burley2015(1.0, 0.7).brdf(n, n) * np.pi), 12)
    1.0
    """

    albedo: float | Array = albedo_param("base colour ρ")
    roughness: float | Array = _roughness("Disney's roughness r")

    ids: ClassVar[dict[str, dict[str, Any]]] = {"burley-2015": {}}
    labels: ClassVar[dict[str, str]] = {"burley-2015": "Burley 2015 (diffuse + retro-reflection)"}
    reference: ClassVar[str] = (
        "B. Burley, Extending the Disney BRDF to a BSDF with Integrated Subsurface Scattering, "
        "SIGGRAPH 2015 course notes, Eq. 4"
    )
    order: ClassVar[int] = 100
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "roughness": r"r",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r = \frac{\rho}{\pi}\Bigl[\bigl(1-\tfrac{F_L}{2}\bigr)\bigl(1-\tfrac{F_V}{2}\bigr)
        + R_R\bigl(F_L + F_V + F_L F_V (R_R-1)\bigr)\Bigr], \tag{Eq. 4}
        ```
        ```{math}
        F_L = (1-\mu_i)^5,\ F_V = (1-\mu_o)^5,\ R_R = 2r\cos^2\theta_d
        ```

        Burley (SIGGRAPH 2015 course notes), the diffuse of Mitsuba 3's
        ``principled`` without sheen and flatness; {math}`\cos^2\theta_d =
        (1+\omega_i\cdot\omega_o)/2`. Expanded, it is Burley 2012 with {math}`F_{D90} =
        \tfrac12 + R_R`.
        """

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, roughness: Array
    ) -> Array:
        fl, fv = schlick_weight(mu_i), schlick_weight(mu_o)
        rr = 2.0 * roughness * _cos2_d(xp, mu_i, mu_o, cos_io)
        diffuse = (1.0 - 0.5 * fl) * (1.0 - 0.5 * fv)
        retro = rr * (fl + fv + fl * fv * (rr - 1.0))
        return albedo / math.pi * (diffuse + retro)
