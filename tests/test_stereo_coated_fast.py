"""The coated fit's table solver (roughdiffuse.stereo.coated_table): the table against the
model's own reference evaluation, and the fast fit against the direct fit of every pixel
on the model and against the truth of a rendered sphere."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import stereo
from roughdiffuse._validate import ParameterError
from roughdiffuse.stereo.coated_table import (
    CHECK_VIEW,
    ERROR_BOUND,
    coated_table,
    evaluate,
)

SIGMA, ALBEDO = 0.4, 0.6


def _builder(alpha: float):
    return lambda rho: rd.Coated(rd.OrenNayar(rho, SIGMA, "full"), 1.5, alpha)


@pytest.mark.parametrize("alpha", [0.1, 0.3])
def test_table_matches_the_models_reference_evaluation(alpha):
    """At random lit normals within 80° of the view and random albedos, the table's value
    differs from f_r(μi, μo, cos_io) max(μi, 0) of ``Coated`` on its NumPy reference path
    (not the compiled path that filled the table) by less than ERROR_BOUND of the light's
    brightest value; the table's own check says as much."""
    lights = stereo.default_lights(5, 40.0)
    build = _builder(alpha)
    table = coated_table(build, alpha, lights, check=500)
    assert table.error <= ERROR_BOUND
    rng = np.random.default_rng(7)
    n = rng.normal(size=(3000, 3))
    n[:, 2] = np.abs(n[:, 2])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    k = rng.integers(0, len(lights), n.shape[0])
    mu_i, mu_o = np.sum(n * lights[k], axis=1), n[:, 2]
    keep = (mu_i > 0) & (mu_o >= CHECK_VIEW)
    n, k, mu_i, mu_o = n[keep], k[keep], mu_i[keep], mu_o[keep]
    # each light's peak: the model at its mirror normal h_k (ρ = 1 is the brightest)
    h = lights + [0.0, 0.0, 1.0]
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    with rd.use_fastpath(False):
        peak_model = build(1.0)
        c_peak = np.sum(h * lights, axis=1)
        peak = peak_model.brdf_cosines(c_peak, h[:, 2], lights[:, 2]) * c_peak
        for rho in (0.0, 0.35, 0.8, 1.0):
            ref = build(rho).brdf_cosines(mu_i, mu_o, lights[k, 2]) * mu_i
            got = evaluate(table, k, n, np.full(k.shape, rho))
            assert np.max(np.abs(got - ref) / peak[k]) <= ERROR_BOUND, rho


def test_table_is_exact_at_the_highlights_centre():
    """At n = h_k (u = 0, t = 0: a node) and ρ = 0 (a node of the albedo's polynomial) the
    table holds the coat's own reflection, F D G2 / (4 μi μo) with μi = μo = cos θd: the
    model over a black base, evaluated directly."""
    lights = stereo.default_lights(4, 30.0)
    table = coated_table(_builder(0.2), 0.2, lights, check=0)
    h = lights + [0.0, 0.0, 1.0]
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    cos_d = np.sum(h * lights, axis=1)
    with rd.use_fastpath(False):
        ref = _builder(0.2)(0.0).brdf_cosines(cos_d, cos_d, lights[:, 2]) * cos_d
    got = evaluate(table, np.arange(4), h, np.zeros(4))
    np.testing.assert_allclose(got, ref, rtol=1e-9)


@pytest.fixture(scope="module")
def small_coated_sphere():
    """A coated full Oren–Nayar sphere (ρ 0.6, σ 0.4, η 1.5, GGX α 0.3), 20² pixels, 12
    lights on a 35° ring, 1 % noise; its true normals."""
    truth = rd.Coated(rd.OrenNayar(ALBEDO, SIGMA, "full"), 1.5, 0.3)
    data, normals = stereo.render_stereo(truth, rd.render.Sphere(), stereo.default_lights(12),
                                         20, noise=0.01, seed=2)
    return data, normals[data.mask]


@pytest.mark.slow
def test_table_solver_agrees_with_the_direct_fit(small_coated_sphere):
    """Same images, same start: the table solver's normals within 0.2° of the direct fit's
    (mean), α and σ within two of the direct fit's standard errors (plus the table's share,
    0.01) and both fits' normals within 1° of the truth."""
    data, truth = small_coated_sphere
    fast = stereo.coated(data, solver="table")
    slow = stereo.coated(data, solver="direct")
    assert fast.coat and slow.coat and fast.solver == "table" and slow.solver == "direct"
    apart = np.nanmean(stereo.angular_error(fast.normals, slow.normals))
    assert apart < 0.2
    assert abs(fast.alpha - slow.alpha) <= 2 * slow.alpha_se + 0.01
    assert abs(fast.sigma - slow.sigma) <= 2 * slow.sigma_se + 0.01
    for res in (fast, slow):
        assert np.nanmean(stereo.angular_error(res.normals, truth)) < 1.0
    assert 0 < fast.table_error <= ERROR_BOUND and math.isnan(slow.table_error)
    # the per-pixel standard errors are those of the same Gauss–Newton model
    ratio = np.nanmedian(fast.normal_se) / np.nanmedian(slow.normal_se)
    assert 0.5 < ratio < 2.0


@pytest.mark.slow
def test_light_scale_is_recovered_and_does_not_bias_sigma_or_alpha():
    """Noise-free images of intensity 1 read with intensities 0.5: the fitted light scale
    is 2, σ and α the truth; the albedo alone could not take the factor (the coat's
    reflection does not scale with it)."""
    truth = rd.Coated(rd.OrenNayar(ALBEDO, SIGMA, "full"), 1.5, 0.3)
    clean, normals = stereo.render_stereo(truth, rd.render.Sphere(), stereo.default_lights(12),
                                          24)
    data = stereo.StereoInput.from_arrays(clean.images, clean.directions, 0.5, mask=clean.mask)
    res = stereo.coated(data, light_scale=True)
    assert res.light_scale == pytest.approx(2.0, rel=2e-3)
    assert res.sigma == pytest.approx(SIGMA, abs=5e-3)
    assert res.alpha == pytest.approx(0.3, abs=2e-3)
    assert np.nanmedian(res.albedo) == pytest.approx(ALBEDO, rel=5e-3)
    assert np.nanmean(stereo.angular_error(res.normals, normals[data.mask])) < 0.05
    fixed = stereo.coated(data, light_scale=False)  # the scale left at 1: biased
    assert abs(fixed.alpha - 0.3) > 10 * abs(res.alpha - 0.3) or abs(fixed.sigma - SIGMA) > 0.02


def test_coated_refuses_an_unknown_solver_and_a_tiny_subsample():
    data = stereo.synthetic_sphere(rd.Lambert(0.5), size=8, lights=6, noise=0.0)
    with pytest.raises(ParameterError, match="solver must be one of 'table', 'direct'"):
        stereo.coated(data, solver="fast")
    with pytest.raises(ParameterError, match=r"subsample must be an integer ≥ 16 \(got 3\)"):
        stereo.coated(data, subsample=3)


def test_pixels_stuck_at_a_narrow_highlight_are_fitted_again_to_the_truth():
    """A narrow coat (α 0.1) under half of DiLiGenT's 96 lights: pixels facing the camera see
    highlights that pull their Lambertian start by degrees to tens of degrees; from there the
    table's Levenberg–Marquardt stops at local minima for some. The retry from the darker
    half of the observations brings every pixel within 0.5° of its true normal. Observations
    from ``Coated`` on its NumPy reference path (not the compiled path of the table)."""
    from roughdiffuse.stereo.coated import _retry
    from roughdiffuse.stereo.coated_table import solve_pixels
    from roughdiffuse.stereo.diligent import diligent_lights
    from roughdiffuse.stereo.inputs import StereoInput

    lights = diligent_lights()[::2]
    build = _builder(0.1)
    rng = np.random.default_rng(3)
    tilt = np.radians(rng.uniform(0.0, 20.0, 60))
    phi = rng.uniform(0.0, 2 * math.pi, 60)
    normals = np.stack([np.sin(tilt) * np.cos(phi), np.sin(tilt) * np.sin(phi), np.cos(tilt)], 1)
    mu_i = normals @ lights.T  # (P, K)
    with rd.use_fastpath(False):
        model = build(ALBEDO)
        lit = np.maximum(mu_i.T, 1e-3)
        f = model.brdf_cosines(lit, np.broadcast_to(normals[:, 2], lit.shape),
                               np.broadcast_to(lights[:, 2:3], lit.shape))
    images = np.where(mu_i.T > 0, np.asarray(f) * lit, 0.0)
    images *= 1.0 + 0.01 * rng.normal(size=images.shape)
    data = StereoInput.from_arrays(images[:, None, :, None], lights)
    obs = data.images[:, data.mask, :]
    weights = (mu_i.T > 0).astype(np.float64)
    start = stereo.lambertian(data, shadow=0.0)
    table = coated_table(build, 0.1, lights, check=0)
    light = data.intensities
    plain = solve_pixels(table, light, obs, weights, start.normals, start.albedo, iterations=30)
    stuck = stereo.angular_error(plain["normals"], normals)
    assert np.max(stuck) > 5.0  # the case the retry is for
    fit = _retry(data, table, light, obs, weights, plain, 30)
    assert np.max(stereo.angular_error(fit["normals"], normals)) < 0.5


def test_a_refit_stopped_at_sigma_zero_starts_again_inside_the_box():
    """Oren–Nayar's slope in σ is 0 at σ = 0 (A and B are functions of σ²): a subsample fit
    that reaches σ = 0 stays there from any normals. ``_polish`` fits again from RESTART of
    σ's box and keeps the lower residual: σ within 3 standard errors of the truth (0.4)
    and 0.01 of it. Observations from ``Coated`` on its NumPy reference path, 1 % noise;
    the pixels' normals the true ones."""
    from roughdiffuse.stereo.coated import _family, _Options, _polish
    from roughdiffuse.stereo.diligent import diligent_lights
    from roughdiffuse.stereo.inputs import StereoInput
    from roughdiffuse.stereo.rough import fit_pixels

    lights = diligent_lights()[::2]
    rng = np.random.default_rng(5)
    count = 120
    tilt = np.radians(rng.uniform(10.0, 55.0, count))
    phi = rng.uniform(0.0, 2 * math.pi, count)
    normals = np.stack([np.sin(tilt) * np.cos(phi), np.sin(tilt) * np.sin(phi), np.cos(tilt)], 1)
    mu_i = normals @ lights.T  # (P, K)
    with rd.use_fastpath(False):
        lit = np.maximum(mu_i.T, 1e-3)
        f = _builder(0.1)(ALBEDO).brdf_cosines(lit, np.broadcast_to(normals[:, 2], lit.shape),
                                               np.broadcast_to(lights[:, 2:3], lit.shape))
    images = np.where(mu_i.T > 0, np.asarray(f) * lit, 0.0)
    images *= 1.0 + 0.01 * rng.normal(size=images.shape)
    data = StereoInput.from_arrays(images[:, None, :, None], lights)
    weights = (mu_i.T > 0).astype(np.float64)
    family = _family("oren-nayar-full", 1.5, "ggx")
    start = stereo.lambertian(data, shadow=0.0)
    stuck = fit_pixels(data, family, start=start, weights=weights, initial=np.array([0.0, 0.1]),
                       subset_start=False, precision="double")
    assert stuck.values[0] <= 1e-9  # the case the restart is for: σ = 0 stays
    table_fit = {"normals": normals, "albedo": np.full((count, 1), ALBEDO),
                 "ok": np.ones(count, bool)}
    opts = _Options(shadow=0.0, rounds=0, depth_method="poisson", iterations=30,
                    precision="double", progress=False)
    _, _, polished = _polish(data, family, stuck, table_fit, weights, count, opts)
    sigma, se = polished.values[0], polished.values_se[0]
    assert abs(sigma - SIGMA) <= min(3 * se, 0.01), (sigma, se)
    assert abs(polished.values[1] - 0.1) <= 0.005
