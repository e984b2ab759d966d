"""The production renderers' diffuse models against their public reference code.

Each reference below is the formula of the named file and function, transcribed from its
source into scalar Python on the vectors L, V, N (not on roughdiffuse's three cosines), so it
is an independent implementation. Geometry stays away from the sources' clamps (their
M_FLOAT_EPS, kMinCosTheta), where they agree with the papers.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from conftest import midpoint_albedo, random_hemisphere

N = np.array([0.0, 0.0, 1.0])


def _dirs(rng, n=400):
    wi, wo = random_hemisphere(rng, n), random_hemisphere(rng, n)
    keep = (wi[:, 2] > 1e-3) & (wo[:, 2] > 1e-3)
    return wi[keep], wo[keep]


def _normalize(v):
    return v / np.linalg.norm(v)


def _pow5(x):
    return x**5


def _reference(fn, wi, wo, *args):
    return np.array([fn(li, vi, *args) for li, vi in zip(wi, wo, strict=True)])


# --- Filament, shaders/src/brdf.fs: F_Schlick(f0, f90, VoH) and Fd_Burley -------------------
def filament_fd_burley(l, v, albedo, roughness):
    h = _normalize(l + v)
    no_v, no_l, lo_h = v @ N, l @ N, l @ h

    def f_schlick(f0, f90, voh):
        return f0 + (f90 - f0) * _pow5(1.0 - voh)

    f90 = 0.5 + 2.0 * roughness * lo_h * lo_h
    light_scatter = f_schlick(1.0, f90, no_l)
    view_scatter = f_schlick(1.0, f90, no_v)
    return albedo * light_scatter * view_scatter * (1.0 / math.pi)


# --- MaterialX, libraries/pbrlib/genglsl/lib/mx_microfacet_diffuse.glsl: mx_burley_diffuse ----
# (bsdf.response = color * NdotL * M_PI_INV * mx_burley_diffuse(...): the BRDF is color/π ·)
def materialx_burley(l, v, albedo, roughness, eps=1e-8):
    h = _normalize(l + v)
    l_dot_h = min(max(l @ h, eps), 1.0)
    n_dot_v = min(max(N @ v, eps), 1.0)
    n_dot_l = min(max(N @ l, eps), 1.0)
    f90 = 0.5 + (2.0 * roughness * l_dot_h**2)

    def mx_fresnel_schlick(cos_theta, f0, f90):
        return f0 + (f90 - f0) * _pow5(1.0 - cos_theta)

    ref_l = mx_fresnel_schlick(n_dot_l, 1.0, f90)
    ref_v = mx_fresnel_schlick(n_dot_v, 1.0, f90)
    return albedo / math.pi * ref_l * ref_v


# --- Falcor, Source/Falcor/Rendering/Materials/BxDF.slang: DiffuseReflectionFrostbite -------
# eval = evalWeight(wi, wo) * M_1_PI * wo.z,
# evalWeight = albedo * wiScatter * woScatter * energyFactor
def falcor_frostbite(l, v, albedo, roughness):
    h = _normalize(l + v)
    wi_dot_h = l @ h
    energy_bias = 0.0 + (0.5 - 0.0) * roughness
    energy_factor = 1.0 + (1.0 / 1.51 - 1.0) * roughness
    fd90 = energy_bias + 2.0 * wi_dot_h * wi_dot_h * roughness
    fd0 = 1.0

    def eval_fresnel_schlick(f0, f90, cos_theta):
        return f0 + (f90 - f0) * (1.0 - cos_theta) ** 5

    wi_scatter = eval_fresnel_schlick(fd0, fd90, l[2])
    wo_scatter = eval_fresnel_schlick(fd0, fd90, v[2])
    return albedo * wi_scatter * wo_scatter * energy_factor / math.pi


# --- Mitsuba 3, src/bsdfs/principled.cpp: Principled::eval, diffuse without flatness/sheen ---
def mitsuba3_principled_diffuse(wi, wo, base_color, roughness):
    def schlick_weight(cos_i):
        m = min(max(1.0 - cos_i, 0.0), 1.0)
        return m**5

    wh = _normalize(wi + wo)
    fo, fi = schlick_weight(abs(wo[2])), schlick_weight(abs(wi[2]))
    f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo)
    cos_theta_d = wh @ wo
    rr = 2.0 * roughness * cos_theta_d**2
    f_retro = rr * (fo + fi + fo * fi * (rr - 1.0))
    return base_color / math.pi * (f_diff + f_retro)  # value / |cos θo|, brdf = 1


# --- Unity Graphics, Packages/com.unity.render-pipelines.core/ShaderLibrary/BSDF.hlsl -------
# DiffuseGGX = INV_PI * DiffuseGGXNoPI(albedo, NdotV, NdotL, NdotH, LdotV, roughness); the
# caller multiplies by the diffuse colour.
def unity_diffuse_ggx(l, v, albedo, roughness):
    h = _normalize(l + v)
    n_dot_v, n_dot_l, n_dot_h, l_dot_v = N @ v, N @ l, N @ h, l @ v

    def f_transm_schlick(f0, u):
        x = 1.0 - u
        return (1.0 - f0) * (1.0 - x**5)

    facing = 0.5 + 0.5 * l_dot_v
    rough = facing * (0.9 - 0.4 * facing) * (0.5 / n_dot_h + 1)
    transmit_l = f_transm_schlick(0, n_dot_l)
    transmit_v = f_transm_schlick(0, n_dot_v)
    smooth = transmit_l * transmit_v * 1.05
    single = smooth + (rough - smooth) * roughness
    multiple = roughness * (0.1159 * math.pi)
    return albedo * (1.0 / math.pi) * (single + albedo * multiple)


# --- Unreal Engine, Engine/Shaders/Private/BRDF.ush: Diffuse_Chan (Chan 2018) --------------
def unreal_diffuse_chan(l, v, diffuse_color, alpha, retro_weight=1.0):
    a2 = alpha * alpha
    h = _normalize(l + v)

    def saturate(x):
        return min(max(x, 0.0), 1.0)

    no_v, no_l, vo_h, no_h = saturate(N @ v), saturate(N @ l), saturate(v @ h), saturate(N @ h)
    g = saturate((1.0 / 18.0) * math.log2(2 / a2 - 1))
    f0 = vo_h + _pow5(1 - vo_h)
    fd_v = 1 - 0.75 * _pow5(1 - no_v)
    fd_l = 1 - 0.75 * _pow5(1 - no_l)
    t = saturate(2.2 * g - 0.5)
    fd = f0 + (fd_v * fd_l - f0) * t
    fb = ((34.5 * g - 59) * g + 24.5) * vo_h * 2.0 ** (-max(73.2 * g - 21.2, 8.9) * math.sqrt(no_h))
    fb *= retro_weight
    return diffuse_color * ((1 / math.pi) * (fd + fb))


@pytest.mark.parametrize("roughness", [0.0, 0.3, 1.0])
@pytest.mark.parametrize("albedo", [0.25, 1.0])
def test_burley_against_filament_and_materialx(rng, roughness, albedo):
    wi, wo = _dirs(rng)
    got = rd.Burley(albedo, roughness).brdf(wi, wo)
    np.testing.assert_allclose(
        got, _reference(filament_fd_burley, wi, wo, albedo, roughness), rtol=1e-12
    )
    np.testing.assert_allclose(
        got, _reference(materialx_burley, wi, wo, albedo, roughness), rtol=1e-12
    )


@pytest.mark.parametrize("roughness", [0.0, 0.4, 1.0])
def test_frostbite_against_falcor(rng, roughness):
    wi, wo = _dirs(rng)
    got = rd.BurleyRenormalized(0.8, roughness).brdf(wi, wo)
    np.testing.assert_allclose(
        got, _reference(falcor_frostbite, wi, wo, 0.8, roughness), rtol=1e-12
    )


@pytest.mark.parametrize("roughness", [0.0, 0.5, 1.0])
def test_burley2015_against_mitsuba3_principled_and_equal_to_burley(rng, roughness):
    wi, wo = _dirs(rng)
    got = rd.Burley2015(0.6, roughness).brdf(wi, wo)
    ref = _reference(mitsuba3_principled_diffuse, wi, wo, 0.6, roughness)
    np.testing.assert_allclose(got, ref, rtol=1e-12)
    # the 2015 split is an algebraic rewrite of the 2012 model
    np.testing.assert_allclose(got, rd.Burley(0.6, roughness).brdf(wi, wo), rtol=1e-13)


@pytest.mark.parametrize("alpha", [0.0, 0.25, 1.0])
@pytest.mark.parametrize("albedo", [0.3, 1.0])
def test_hammon_against_unity(rng, alpha, albedo):
    wi, wo = _dirs(rng)
    got = rd.Hammon(albedo, alpha).brdf(wi, wo)
    np.testing.assert_allclose(
        got, _reference(unity_diffuse_ggx, wi, wo, albedo, alpha), rtol=1e-12
    )


@pytest.mark.parametrize("alpha", [0.01, 0.1, 0.3, 0.6, 1.0])
def test_chan_against_unreal(rng, alpha):
    wi, wo = _dirs(rng)
    got = rd.Chan(0.7, alpha).brdf(wi, wo)
    np.testing.assert_allclose(got, _reference(unreal_diffuse_chan, wi, wo, 0.7, alpha), rtol=1e-12)


def test_chan_gloss_saturates_where_the_parameterisation_ends():
    """α = √(2/(1 + 2^(18 g))) (Chan 2018, Eq. 1): g = 1 at α = √(2/(2^18 + 1)), 0 at α = 1."""
    from roughdiffuse.models.chan import chan_gloss

    for g in (0.0, 0.25, 0.5, 0.999):
        alpha = math.sqrt(2.0 / (1.0 + 2.0 ** (18.0 * g)))
        assert float(chan_gloss(np, np.float64(alpha))) == pytest.approx(g, abs=1e-12)
    assert float(chan_gloss(np, np.float64(0.0))) == 1.0


def test_burley_roughness_zero_albedo_closed_form():
    """r = 0: f = ρ/π (1 − F(μi)/2)(1 − F(μo)/2), so the albedo is
    (1 − F(μo)/2)(1 − 2∫(1 − μ)⁵ μ dμ /2) = (1 − F(μo)/2)·(1 − 1/42) (B(2, 6) = 1/42);
    MaterialX's fit ``mx_burley_diffuse_dir_albedo`` has exactly 0.97619 − 0.488095 F."""
    for mu in (1.0, 0.6, 0.2, 0.0):
        wo = np.array([math.sqrt(1 - mu * mu), 0.0, mu])
        expected = (1.0 - 0.5 * (1.0 - mu) ** 5) * (1.0 - 1.0 / 42.0)
        assert float(rd.Burley(1.0, 0.0).directional_albedo(wo)) == pytest.approx(
            expected, abs=2e-6
        )


def test_burley_normal_incidence_value():
    """μi = 1: f = ρ/π (1 + (F_D90 − 1)(1 − μo)⁵) with cos² θd = (1 + μo)/2."""
    for r in (0.0, 0.5, 1.0):
        for mu in (1.0, 0.5, 0.0):
            wo = np.array([math.sqrt(1 - mu * mu), 0.0, mu])
            f90 = 0.5 + r * (1.0 + mu)
            expected = 0.9 / math.pi * (1.0 + (f90 - 1.0) * (1.0 - mu) ** 5)
            assert float(rd.Burley(0.9, r).brdf(N, wo)) == pytest.approx(expected, rel=1e-13)


def test_hammon_smooth_limit_normalised():
    """α = 0: 1.05 (1 − F(μi))(1 − F(μo))/π; its albedo at normal view is
    1.05 (1 − 2 B(2, 6)) = 1.05 · 20/21 = 1 (Hammon's 1.05 "normalises F_t")."""
    assert float(rd.Hammon(1.0, 0.0).directional_albedo(N)) == pytest.approx(1.0, abs=2e-6)


@pytest.mark.parametrize(
    "model",
    [rd.Burley(1.0, 0.7), rd.BurleyRenormalized(1.0, 0.7), rd.Hammon(1.0, 0.6), rd.Chan(1.0, 0.4)],
    ids=repr,
)
def test_directional_albedo_against_midpoint_rule(model):
    for mu in (0.9, 0.3):
        assert float(model.directional_albedo(np.array([math.sqrt(1 - mu * mu), 0, mu]))) == (
            pytest.approx(float(midpoint_albedo(model, mu)), abs=2e-5)
        )


@pytest.mark.parametrize(
    "model",
    [
        rd.Burley(1.0, 1.0),
        rd.BurleyRenormalized(1.0, 1.0),
        rd.Burley2015(1.0, 1.0),
        rd.Hammon(1.0, 1.0),
        rd.Chan(1.0, 0.0),
        rd.Chan(1.0, 1.0),
        rd.LambertSphere(1.0, "full"),
        rd.LambertSphere(1.0, "fast"),
        rd.Minnaert(1.0, 0.0),
        rd.Hapke(1.0, 1.0, 0.0, -0.99, 1.0),
        rd.Hapke(1.0, 1.0, 1.0, 0.99, 0.0),
    ],
    ids=repr,
)
def test_finite_at_grazing_and_degenerate_pairs(model):
    """Both on the horizon, opposite or equal; one on the horizon; normal with normal."""
    s = math.sqrt(0.5)
    dirs = [
        np.array([1.0, 0.0, 0.0]),
        np.array([-1.0, 0.0, 0.0]),
        np.array([0.0, 1.0, 0.0]),
        np.array([s, 0.0, s]),
        np.array([0.0, 0.0, 1.0]),
        np.array([1.0, 0.0, 1e-9]),
    ]
    wi = np.array([a for a in dirs for _ in dirs])
    wo = np.array([b for _ in dirs for b in dirs])
    f = np.asarray(model.brdf(wi, wo))
    assert np.all(np.isfinite(f)) and np.all(f >= 0)
