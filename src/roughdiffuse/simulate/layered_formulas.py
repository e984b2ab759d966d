"""The element-wise formulas of the layered walk's interface, written once for two back-ends.

As :mod:`.smith_formulas` does for the Smith walk: :func:`build` takes primitives
(``jit``, ``where``, ``maximum``, ``minimum``, ``sqrt``) and returns the formulas made of them,
so that the NumPy walk (:mod:`.layered`, on arrays) and the compiled walk
(:mod:`.layered_walk_numba`, on scalars inside a Numba loop) apply the same source:

* ``fresnel``: the unpolarised Fresnel reflectance of a dielectric of relative index η at
  cos θ, from the s and p amplitudes (Born and Wolf, *Principles of Optics*, Sec. 1.5.2): with
  cos θt = √(1 − (1 − c²)/η²), r_s = (c − η cos θt)/(c + η cos θt),
  r_p = (η c − cos θt)/(η c + cos θt), F = (r_s² + r_p²)/2; F = 1 under total internal
  reflection. Written from the amplitudes, not shared with the models' form (Cook and
  Torrance's), so that the truth and the closed forms check each other.
* ``refract_in``: the direction into the layer of light arriving from ω (above) through a
  facet of normal m, t = −ω/η + (c/η − cos θt) m with c = ω·m (Walter, Marschner, Li and
  Torrance 2007, "Microfacet models for refraction through rough surfaces", EGSR, eq. 40),
  and the transmission 1 − F(c, η); 0 where no light is refracted.

The functions use only arithmetic and those primitives; both sides of a choice are computed
and ``where`` picks one (callers on NumPy silence floating-point warnings).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

__all__ = ["build"]


def build(p: Any) -> SimpleNamespace:
    """The interface's formulas made of the primitives ``p`` (``jit``, ``where``,
    ``maximum``, ``minimum``, ``sqrt``)."""
    jit, where, maximum, minimum, sqrt = p.jit, p.where, p.maximum, p.minimum, p.sqrt

    @jit
    def fresnel(cos_t, eta):
        """F(cos θ, η), cos θ clipped to [0, 1]; 1 under total internal reflection."""
        c = minimum(maximum(cos_t, 0.0), 1.0)
        k = 1.0 - (1.0 - c * c) / (eta * eta)
        ct = sqrt(maximum(k, 0.0))
        # r_s² + r_p² over the common denominator: one division
        ns, ds = c - eta * ct, c + eta * ct
        np_, dp = eta * c - ct, eta * c + ct
        f = 0.5 * (ns * ns * dp * dp + np_ * np_ * ds * ds) / (ds * ds * dp * dp)
        return where(k > 0.0, f, 1.0)

    @jit
    def refract_in(wx, wy, wz, mx, my, mz, eta):
        """(t_x, t_y, t_z, 1 − F) for light from ω through the facet m (t not normalised
        where nothing is refracted; the transmission is 0 there)."""
        c = minimum(maximum(wx * mx + wy * my + wz * mz, 0.0), 1.0)
        k = 1.0 - (1.0 - c * c) / (eta * eta)
        s = c / eta - sqrt(maximum(k, 0.0))
        trans = where(k > 0.0, 1.0 - fresnel(c, eta), 0.0)
        return -wx / eta + s * mx, -wy / eta + s * my, -wz / eta + s * mz, trans

    return SimpleNamespace(fresnel=fresnel, refract_in=refract_in)
