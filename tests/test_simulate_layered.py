"""The layered walk (roughdiffuse.simulate.layered) against independent anchors.

* Mitsuba 3's own ``plastic`` plugin (run through ``mi.load_dict``/``eval``): a smooth coat
  over a Lambertian base, its internal reflections summed in closed form. With
  ``nonlinear=true`` it is ρ (1 − F_i)(1 − F_o) / (π η² (1 − ρ F_dr)), the exact sum (its
  F_dr is a fit, accurate to about 0.1 %, well inside the walk's errors here); with
  ``nonlinear=false`` it divides by (1 − F_dr) instead (colours kept), which equals it at
  ρ = 1 only, so that mode is compared at ρ = 1.
* Mitsuba 3's ``roughdielectric`` reflection for a black base (the interface alone).
* The white furnace, the η → 1 limit, one bounce with absorption in closed form, reciprocity.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from mitsuba_setup import mitsuba_brdf, mitsuba_variant, random_geometries
from roughdiffuse.models.microfacet import fresnel_dielectric
from roughdiffuse.simulate import layered

Z_MAX = 4.5
"""|z| bound per value: with 60 values, a 4.5σ excursion of a correct walk has odds < 1e-3."""


@pytest.mark.parametrize("eta", [1.2, 1.5, 2.0])
def test_walk_matches_mitsuba_plastic(eta: float) -> None:
    mi = mitsuba_variant("scalar_rgb")
    ti, tr, dp = random_geometries()
    z_all = []
    for rho, nonlinear in ((0.6, True), (1.0, False)):
        bsdf = mi.load_dict({
            "type": "plastic", "int_ior": eta, "ext_ior": 1.0, "nonlinear": nonlinear,
            "diffuse_reflectance": {"type": "rgb", "value": [rho] * 3},
        })
        ref = mitsuba_brdf(mi, bsdf, ti, tr, dp)
        f, se = layered.brdf(ti, tr, dp, rd.Lambert(rho), eta=eta, samples=3_000, seed=3,
                             return_stderr=True)
        z_all.append((f - ref) / se)
    z = np.concatenate(z_all)
    assert np.max(np.abs(z)) < Z_MAX, z
    assert abs(np.mean(z * z) - 1.0) < 0.6, np.mean(z * z)  # chi²/dof of 40 values


def test_black_base_is_mitsuba_roughdielectric_reflection() -> None:
    mi = mitsuba_variant("scalar_rgb")
    ti, tr, dp = random_geometries(8, seed=2)
    bsdf = mi.load_dict({"type": "roughdielectric", "distribution": "ggx", "alpha": 0.3,
                         "int_ior": 1.5, "ext_ior": 1.0})
    ref = mitsuba_brdf(mi, bsdf, ti, tr, dp)
    f = layered.brdf(ti, tr, dp, rd.Lambert(0.0), eta=1.5, roughness=0.3, samples=100,
                     interface="single")
    np.testing.assert_allclose(f, ref, rtol=2e-4, atol=1e-6)  # Mitsuba computes in float32


@pytest.mark.parametrize("eta", [1.1, 1.5, 2.5])
def test_white_furnace_smooth_coat(eta: float) -> None:
    theta = np.array([0.0, 0.8, 1.4])
    a, se = layered.directional_albedo(theta, rd.Lambert(1.0), eta=eta, samples=8_000,
                                       return_stderr=True)
    assert np.all(np.abs(a - 1.0) < Z_MAX * se + 1e-9), (a, se)


def test_eta_one_is_the_base_alone() -> None:
    base = rd.OrenNayar(0.8, 0.4, "full")
    ti, tr, dp = random_geometries(10, seed=4)
    f = layered.brdf(ti, tr, dp, base, eta=1.0, samples=50)
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], -1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], -1)
    np.testing.assert_allclose(f, base.brdf(wi, wo), rtol=1e-9)


def test_one_bounce_with_absorption_closed_form() -> None:
    """bounces=1 over Lambert: ρ/(π η²) (1 − F_i)(1 − F_o) e^{−τ/μi'} e^{−τ/μo'} per channel."""
    eta, rho, tau = 1.5, 0.7, np.array([0.0, 0.2, 1.0])
    ti, tr, dp = random_geometries(6, seed=5)
    f = layered.brdf(ti, tr, dp, rd.Lambert(rho), eta=eta, absorption=tau, bounces=1,
                     samples=20)
    mi_, mo_ = (np.sqrt(1 - np.sin(t) ** 2 / eta**2) for t in (ti, tr))
    t_io = (1 - fresnel_dielectric(np, np.cos(ti), eta)) * (1 - fresnel_dielectric(
        np, np.cos(tr), eta))
    ref = (rho / (math.pi * eta**2) * t_io)[:, None] * np.exp(
        -tau[None, :] * (1 / mi_ + 1 / mo_)[:, None])
    np.testing.assert_allclose(f, ref, rtol=1e-9)


def test_reciprocity_rough_coat() -> None:
    base = rd.OrenNayar(0.9, 0.5, "full")
    ti, tr, dp = random_geometries(10, seed=6)
    kw = dict(eta=1.5, roughness=0.4, samples=4_000, return_stderr=True)
    f1, s1 = layered.brdf(ti, tr, dp, base, seed=1, **kw)
    f2, s2 = layered.brdf(tr, ti, dp, base, seed=2, **kw)
    z = (f1 - f2) / np.hypot(s1, s2)
    assert np.max(np.abs(z)) < Z_MAX, z


def test_seeded() -> None:
    a = layered.brdf(0.3, 0.5, 1.0, rd.Lambert(0.5), roughness=0.2, samples=500, seed=7)
    b = layered.brdf(0.3, 0.5, 1.0, rd.Lambert(0.5), roughness=0.2, samples=500, seed=7)
    assert a == b


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"eta": 0.0}, "eta"),
        ({"eta": -1.5}, "eta"),
        ({"absorption": -0.1}, "absorption"),
        ({"roughness": -0.1}, "roughness"),
        ({"distribution": "phong"}, "distribution"),
        ({"interface": "double"}, "interface"),
        ({"base": rd.SmithDiffuse(0.5, 0.8)}, "base"),
        ({"base": "lambert"}, "base"),
    ],
)
def test_bad_input_named(kwargs: dict, name: str) -> None:
    args = {"base": rd.Lambert(0.5), **kwargs}
    with pytest.raises(ValueError, match=name):
        layered.brdf(0.3, 0.3, 0.0, samples=10, **args)
