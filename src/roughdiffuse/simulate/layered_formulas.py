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
* ``ndf``: D(m) of GGX (Walter et al. 2007, eq. 33) or Beckmann (eq. 25) from cos θm, with
  ∫ D (n·m) dωm = 1; 0 for cos θm ≤ 0.
* ``phase_out``: the next event of the multiple-scattering dielectric microsurface (Heitz,
  Hanika, d'Eon and Dachsbacher 2016, "Multiple-scattering microfacet BSDFs with the Smith
  model", SIGGRAPH, Sec. 5 and their eq. for the dielectric phase function): the phase
  function p(ωi → ωo) of a facet event on either side of the surface towards a direction ωo
  above it, ωi pointing back along the ray. On the air side it is the visible-normal
  reflection F D / (4 (1 + Λ(ωi)) ωi·n); on the dielectric side the transmission into the
  air, with relative index η' = 1/η, m the facet normal facing the dielectric,
  η'² (1 − F(ωi·m, η')) D(−m) ⟨ωi, m⟩ ⟨−ωo, m⟩⁺ / ((1 + Λ(−ωi)) (−ωi)·n (ωi·m + η' ωo·m)²)
  (Walter et al. 2007, eqs. 16–17, times the visible-normal density).

The functions use only arithmetic and those primitives; both sides of a choice are computed
and ``where`` picks one (callers on NumPy silence floating-point warnings).
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

__all__ = ["MS_MAX_EVENTS", "build"]

MS_MAX_EVENTS = 1_000_000
"""Facet events one walk on the microsurface traces at most, in either engine (a walk still
on the surface then is lost: at η = 2.5, α = 1 a walk has a few events on average; none
reaches this)."""


def build(p: Any, smith_lambda: Any = None) -> SimpleNamespace:
    """The interface's formulas made of the primitives ``p`` (``jit``, ``where``,
    ``maximum``, ``minimum``, ``sqrt``, and ``exp`` for the microsurface's ``ndf`` and
    ``phase_out``, which also take Smith's Λ, ``smith_lambda(ggx, z, α)``, of
    :mod:`.smith_formulas` built on the same primitives)."""
    jit, where, maximum, minimum, sqrt = p.jit, p.where, p.maximum, p.minimum, p.sqrt
    exp = getattr(p, "exp", None)

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

    @jit
    def ndf(ggx, cos_m, alpha):
        """D(m) for cos θm (GGX or Beckmann), 0 for cos θm <= 0."""
        c2 = maximum(cos_m * cos_m, 1e-300)
        a2 = alpha * alpha
        s2 = maximum(1.0 - c2, 0.0)
        den = s2 + c2 * a2  # GGX: cos⁴θ (α² + tan²θ)² = (sin²θ + cos²θ α²)²
        d = where(ggx, a2 / (3.141592653589793 * den * den),
                  exp(-s2 / (c2 * a2)) / (3.141592653589793 * a2 * c2 * c2))
        return where(cos_m > 0.0, d, 0.0)

    @jit
    def phase_out(ggx, outside, ix, iy, iz, ox, oy, oz, eta, alpha):
        """p(ωi → ωo) towards ωo above the surface from a facet event on the air side
        (``outside``) or the dielectric side, ωi = −(the ray's direction); 0 where the facet
        cannot send light there."""
        # air side: reflection about h = (ωi + ωo)/|ωi + ωo|
        hx, hy, hz = ix + ox, iy + oy, iz + oz
        hn = sqrt(maximum(hx * hx + hy * hy + hz * hz, 1e-300))
        hx, hy, hz = hx / hn, hy / hn, hz / hn
        ci = ix * hx + iy * hy + iz * hz
        proj_i = (1.0 + smith_lambda(ggx, iz, alpha)) * iz
        refl = fresnel(ci, eta) * ndf(ggx, hz, alpha) / (4.0 * proj_i)
        refl = where((ci > 0.0) & (proj_i > 0.0), refl, 0.0)
        # dielectric side: transmission out, η' = 1/η; m faces the dielectric (m_z < 0)
        e = 1.0 / eta
        mx, my, mz = -(ix + e * ox), -(iy + e * oy), -(iz + e * oz)
        mn = sqrt(maximum(mx * mx + my * my + mz * mz, 1e-300))
        sgn = where(mz > 0.0, -1.0, 1.0) / mn
        mx, my, mz = mx * sgn, my * sgn, mz * sgn
        cim = ix * mx + iy * my + iz * mz
        com = ox * mx + oy * my + oz * mz
        proj_t = (1.0 + smith_lambda(ggx, -iz, alpha)) * (-iz)
        den = cim + e * com
        trans = (e * e * (1.0 - fresnel(cim, e)) * ndf(ggx, -mz, alpha) * cim
                 * maximum(-com, 0.0) / (proj_t * den * den))
        trans = where((cim > 0.0) & (proj_t > 0.0) & (den * den > 0.0), trans, 0.0)
        return where(outside, refl, trans)

    return SimpleNamespace(fresnel=fresnel, refract_in=refract_in, ndf=ndf,
                           phase_out=phase_out)
