"""The layered walk's multiple-scattering rough interface (Heitz, Hanika, d'Eon and
Dachsbacher 2016) against conservation, reciprocity and its limits.

* The white furnace: a white Lambertian base under a rough coat, no absorption, reflects
  all the light (directional albedo 1). The albedo is estimated with next events through an
  exit direction sampled from the viewer's side, so it holds only if the walk's
  transmission is reciprocal with the 1/η² of the radiance crossing the interface.
* The interface alone: the reflection the walk's next events estimate (Heitz et al.'s
  stochastic evaluation) integrates over the hemisphere to the fraction of walks that come
  back up (two estimators of R); the diffuse transmittance from below times η² equals the
  one from above (reciprocity of a dielectric interface); R + T = 1 from either side.
* Where multiple scattering is negligible (α = 0.05) the interface agrees with the single
  scattering one; η = 1 is the base alone; α → 0 is the smooth walk (Mitsuba's plastic).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from mitsuba_setup import random_geometries
from roughdiffuse.quadrature import gauss_legendre
from roughdiffuse.simulate import layered

pytest.importorskip("numba")

Z_MAX = 4.5
"""|z| bound per value: with up to 30 values, a 4.5σ excursion of a correct walk has odds
below 1e-3."""


@pytest.mark.parametrize(
    ("distribution", "eta", "alpha"),
    [("ggx", 1.5, 0.6), ("beckmann", 2.5, 1.0)],
)
def test_white_furnace_rough_coat(distribution: str, eta: float, alpha: float) -> None:
    theta = np.array([0.0, 1.0, 1.45])
    a, se = layered.directional_albedo(theta, rd.Lambert(1.0), eta=eta, roughness=alpha,
                                       distribution=distribution, samples=30_000,
                                       return_stderr=True)
    assert np.all(se < 0.006), se
    assert np.all(np.abs(a - 1.0) < Z_MAX * se), (a, se)


def test_single_interface_loses_what_the_multiple_one_keeps() -> None:
    """The single-scattering interface drops light (the defect the multiple one removes):
    its furnace is far below 1 at α = 1."""
    a = layered.directional_albedo(0.5, rd.Lambert(1.0), eta=1.5, roughness=1.0,
                                   samples=5_000, interface="single")
    assert a < 0.5


def test_interface_reflection_next_events_integrate_to_the_walks_that_return() -> None:
    """∫ f_r cos θo dωo of the interface's next-event reflection (a black base) equals the
    fraction of walks leaving upwards, counted: two estimators of the same R."""
    alpha, eta, theta_i = 0.6, 1.5, 0.9
    mu, wmu = gauss_legendre(12)
    phi, wphi = gauss_legendre(12)  # on [0, 1]: φ = π x, both halves of the azimuth
    mm, pp = np.meshgrid(mu, phi, indexing="ij")
    ww = np.outer(wmu, wphi) * 2.0 * math.pi  # dω = dμ dφ, φ in [0, π] counted twice
    f, se = layered.brdf(theta_i, np.arccos(mm).ravel(), (math.pi * pp).ravel(),
                         rd.Lambert(0.0), eta=eta, roughness=alpha, samples=2_000,
                         return_stderr=True)
    r_nee = float(np.sum(f * mm.ravel() * ww.ravel()))
    r_nee_se = float(np.sqrt(np.sum((se * mm.ravel() * ww.ravel()) ** 2)))
    r, r_se = layered.interface_reflectance(theta_i, eta, alpha, samples=200_000,
                                       return_stderr=True)
    assert abs(r_nee - r) < Z_MAX * math.hypot(r_nee_se, r_se) + 2e-3 * r, (r_nee, r)


def test_interface_transmittance_reciprocal_from_above_and_below() -> None:
    """η² T̄_below = T̄_above for the cosine-weighted transmittances (T = 1 − R: each walk
    leaves on one side), the reciprocity of a dielectric interface; R + T = 1 on each side
    is that no walk is lost."""
    eta, alpha = 1.5, 0.5
    mu, w = gauss_legendre(12)
    t = np.arccos(mu)
    kw = dict(samples=30_000, return_stderr=True, distribution="beckmann")
    ra, sa = layered.interface_reflectance(t, eta, alpha, side="above", **kw)
    rb, sb = layered.interface_reflectance(t, eta, alpha, side="below", **kw)
    ta = float(np.sum((1 - ra) * 2 * mu * w))
    tb = float(np.sum((1 - rb) * 2 * mu * w)) * eta**2
    se = math.hypot(float(np.sqrt(np.sum((sa * 2 * mu * w) ** 2))),
                    eta**2 * float(np.sqrt(np.sum((sb * 2 * mu * w) ** 2))))
    assert abs(ta - tb) < Z_MAX * se, (ta, tb, se)
    # from below, beyond the critical angle of the mean surface most light is reflected
    assert rb[0] > 0.5 and ra[0] < 0.5


def test_small_roughness_agrees_with_the_single_interface() -> None:
    """α = 0.05: a second facet event is rare, the two interfaces agree within errors (the
    interface's own albedo, and a grey base under it)."""
    theta = np.array([0.0, 0.8])
    kw = dict(eta=1.5, roughness=0.05, samples=40_000, return_stderr=True)
    m, sm = layered.directional_albedo(theta, rd.Lambert(0.5), **kw)
    s, ss = layered.directional_albedo(theta, rd.Lambert(0.5), interface="single", **kw)
    assert np.all(np.abs(m - s) < Z_MAX * np.hypot(sm, ss)), (m, s, sm, ss)


def test_eta_one_rough_coat_is_the_base_alone() -> None:
    """η = 1: every facet transmits, undeviated; the walk is the base, path by path."""
    base = rd.OrenNayar(0.8, 0.4, "full")
    ti, tr, dp = random_geometries(6, seed=4)
    f = layered.brdf(ti, tr, dp, base, eta=1.0, roughness=0.7, samples=50)
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], -1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], -1)
    np.testing.assert_allclose(f, base.brdf(wi, wo), rtol=1e-9)


def test_vanishing_roughness_is_the_smooth_walk() -> None:
    """α = 1e-4 away from the mirror direction: the smooth coat's value (which equals
    Mitsuba's plastic, tests/test_simulate_layered.py)."""
    ti, tr, dp = random_geometries(6, seed=8)
    kw = dict(eta=1.5, samples=8_000, return_stderr=True)
    f, sf = layered.brdf(ti, tr, dp, rd.Lambert(0.7), roughness=1e-4, **kw)
    g, sg = layered.brdf(ti, tr, dp, rd.Lambert(0.7), roughness=0.0, seed=5, **kw)
    z = (f - g) / np.hypot(sf, sg)
    assert np.max(np.abs(z)) < Z_MAX, z


def test_reciprocity_multiple_interface() -> None:
    base = rd.Lambert(0.8)
    ti, tr, dp = random_geometries(6, seed=6)
    kw = dict(eta=2.0, roughness=0.8, distribution="beckmann", samples=6_000,
              return_stderr=True)
    f1, s1 = layered.brdf(ti, tr, dp, base, seed=1, **kw)
    f2, s2 = layered.brdf(tr, ti, dp, base, seed=2, **kw)
    z = (f1 - f2) / np.hypot(s1, s2)
    assert np.max(np.abs(z)) < Z_MAX, z
