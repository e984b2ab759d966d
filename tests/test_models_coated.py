"""rd.Coated, the closed-form coat: against Mitsuba 3's plugins, exact limits, and fitting.

Independent references: Mitsuba 3's ``plastic`` (``nonlinear=true``: the exact sum of a
smooth coat's internal reflections over Lambert, with Mitsuba's fitted F_dr, accurate to
about 0.2 %) and ``roughdielectric`` (the rough coat's reflection alone, float32, its
separable masking turned into the coat's height-correlated one); the η = 1
limit (no interface: the base alone); the exact smooth-coat Lambert formula with F_dr by
SciPy's adaptive quadrature.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import roughdiffuse as rd
from mitsuba_setup import mitsuba_brdf, mitsuba_variant, random_geometries
from roughdiffuse.fit import Measurements, fit
from roughdiffuse.models.microfacet import fresnel_dielectric


def _dirs(ti, tr, dp):
    return rd.spherical_to_vector(ti, 0.0), rd.spherical_to_vector(tr, dp)


@pytest.mark.parametrize("eta", [1.2, 1.5, 2.0])
def test_smooth_coat_over_lambert_is_mitsuba_plastic(eta: float) -> None:
    mi = mitsuba_variant("scalar_rgb")
    ti, tr, dp = random_geometries(20, 1)
    bsdf = mi.load_dict({"type": "plastic", "int_ior": eta, "ext_ior": 1.0, "nonlinear": True,
                         "diffuse_reflectance": {"type": "rgb", "value": [0.6] * 3}})
    f = rd.Coated(rd.Lambert(0.6), eta).brdf(*_dirs(ti, tr, dp))
    np.testing.assert_allclose(f, mitsuba_brdf(mi, bsdf, ti, tr, dp), rtol=3e-3)


@pytest.mark.parametrize("eta", [1.3, 1.5, 2.5])
def test_smooth_coat_over_lambert_exact_sum(eta: float) -> None:
    rho = 0.9
    fdr = quad(lambda m: 2 * m * fresnel_dielectric(np, np.array(m), 1 / eta), 0, 1,
               points=[math.sqrt(1 - 1 / eta**2)], limit=200, epsabs=1e-12)[0]
    ti, tr, dp = random_geometries(10, 2)
    ref = (1 - fresnel_dielectric(np, np.cos(ti), eta)) * (
        1 - fresnel_dielectric(np, np.cos(tr), eta)) * rho / (math.pi * eta**2 * (1 - rho * fdr))
    np.testing.assert_allclose(rd.Coated(rd.Lambert(rho), eta).brdf(*_dirs(ti, tr, dp)), ref,
                               rtol=1e-6)


def test_eta_one_is_the_base_alone() -> None:
    base = rd.EON(np.array([0.9, 0.5, 0.2]), 0.7)
    ti, tr, dp = random_geometries(10, 3)
    np.testing.assert_allclose(rd.Coated(base, 1.0).brdf(*_dirs(ti, tr, dp)),
                               base.brdf(*_dirs(ti, tr, dp)), rtol=1e-12)


def test_coat_lobe_is_mitsuba_roughdielectric_reflection() -> None:
    mi = mitsuba_variant("scalar_rgb")
    ti, tr, dp = random_geometries(10, 4)
    bsdf = mi.load_dict({"type": "roughdielectric", "distribution": "ggx", "alpha": 0.3,
                         "int_ior": 1.5, "ext_ior": 1.0})
    from roughdiffuse.models.coated import coat_reflection

    mu_i, mu_o = np.cos(ti), np.cos(tr)
    cos_io = mu_i * mu_o + np.sin(ti) * np.sin(tr) * np.cos(dp)
    # the coat's single-scattering lobe (Coated adds its multiple scattering to it:
    # tests/test_coated_rough_energy.py checks that against the layered walk)
    f = coat_reflection(np, mu_i, mu_o, cos_io, 1.5, 0.3, "ggx")
    # Mitsuba masks separably, G1(ωi) G1(ωo); the coat height-correlated, 1/(1 + Λi + Λo)
    # (Heitz 2014, eq. 99), GGX Λ = (√(1 + α² tan²θ) − 1)/2 (Heitz 2014, eq. 72)
    lam = [(np.sqrt(1 + 0.09 * np.tan(t) ** 2) - 1) / 2 for t in (ti, tr)]
    ratio = (1 + lam[0]) * (1 + lam[1]) / (1 + lam[0] + lam[1])
    np.testing.assert_allclose(f, mitsuba_brdf(mi, bsdf, ti, tr, dp) * ratio, rtol=2e-4,
                               atol=1e-6)


def test_base_by_id_and_parameters() -> None:
    a = rd.Coated(base="eon", base_params={"albedo": 0.7, "roughness": 0.4}, eta=1.4)
    b = rd.Coated(rd.EON(0.7, 0.4), 1.4)
    w = _dirs(*random_geometries(5, 5))
    np.testing.assert_array_equal(a.brdf(*w), b.brdf(*w))
    assert rd.registry.create("coated", albedo=0.5, sigma=0.0).base == rd.OrenNayar(
        0.5, 0.0, "full")


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"eta": 0.0}, "eta"),
        ({"eta": -1.0}, "eta"),
        ({"absorption": -0.5}, "absorption"),
        ({"roughness": 1.5}, "roughness"),
        ({"base": rd.SmithDiffuse(0.5, 0.5)}, "base"),
        ({"base": rd.Coated(rd.Lambert(0.5))}, "coat on a coat"),
        ({"base_params": {"albedo": 0.5}}, "base_params"),
        ({"base": "no-such-model"}, "no-such-model"),
    ],
)
def test_bad_input_named(kwargs: dict, name: str) -> None:
    args = {"base": rd.Lambert(0.5), **kwargs}
    with pytest.raises(ValueError, match=name):
        rd.Coated(**args)


@pytest.mark.slow  # JAX compiles the residuals and Jacobian of the coat: too long for the fast set
@pytest.mark.parametrize("fit_eta", [False, True])
def test_fit_recovers_parameters(fit_eta: bool) -> None:
    truth = {"albedo": 0.7, "sigma": 0.35, "eta": 1.6, "roughness": 0.25}
    model = rd.Coated.from_params(**truth)
    ti, tr, dp = random_geometries(300, 6)
    f = np.asarray(model.brdf(*_dirs(ti, tr, dp)))
    rng = np.random.default_rng(7)
    data = Measurements.from_angles(ti, tr, dp, f * (1 + 0.01 * rng.standard_normal(f.shape)))
    names = ["albedo", "sigma", "roughness"] + (["eta"] if fit_eta else [])
    fixed = {} if fit_eta else {"eta": truth["eta"]}
    r = fit(rd.Coated.from_params, data, params=names, fixed=fixed, noise="relative")
    values = dict(zip(r.names, r.values, strict=True))
    errors = dict(zip(r.names, r.errors, strict=True))
    for name in names:
        assert abs(values[name] - truth[name]) <= 4 * errors[name], (name, values, errors)
        assert errors[name] < 0.1 * truth[name]


def test_absorption_per_channel_is_the_exact_sum_per_channel() -> None:
    """A smooth coat over a grey Lambert base with one optical depth per channel: in each
    channel c, (1 − F_i)(1 − F_o) e^{−τ_c/μi' − τ_c/μo'} ρ / (π η² (1 − ρ K_c)),
    K_c = ∫ F(μ, 1/η) e^{−2τ_c/μ} 2μ dμ by SciPy's adaptive quadrature."""
    rho, eta, tau = 0.8, 1.5, np.array([0.05, 0.4, 1.5])
    ti, tr, dp = random_geometries(10, 8)
    mu_i, mu_o = np.cos(ti), np.cos(tr)
    ri, ro = (np.sqrt(1 - (1 - m**2) / eta**2) for m in (mu_i, mu_o))
    ref = []
    for t in tau:
        k = quad(lambda m, t=t: 2 * m * fresnel_dielectric(np, np.array(m), 1 / eta)
                 * math.exp(-2 * t / m), 0, 1, points=[math.sqrt(1 - 1 / eta**2)], limit=200,
                 epsabs=1e-12)[0]
        ref.append((1 - fresnel_dielectric(np, mu_i, eta)) * (1 - fresnel_dielectric(np, mu_o, eta))
                   * np.exp(-t / ri - t / ro) * rho / (math.pi * eta**2 * (1 - rho * k)))
    model = rd.Coated(rd.Lambert(rho), eta, absorption=tau)
    assert model.channels == 3
    # the model's 16-node rule gives K_c to 1e-4 with absorption (coated.py's docstring):
    # f changes by ρK/(1 − ρK) ≈ 1.9 times that, relatively
    np.testing.assert_allclose(model.brdf(*_dirs(ti, tr, dp)), np.stack(ref, -1), rtol=2e-4)


@pytest.mark.parametrize(
    ("absorption", "base"),
    [([0.1, -0.2, 0.3], rd.Lambert(0.5)), ([0.1, 0.2], rd.Lambert(np.array([0.5, 0.4, 0.3])))],
)
def test_bad_absorption_per_channel_named(absorption: list, base: rd.Model) -> None:
    with pytest.raises(ValueError, match="absorption"):
        rd.Coated(base, 1.5, absorption=np.array(absorption))
