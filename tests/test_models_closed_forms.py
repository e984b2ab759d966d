"""Models against closed forms, limits and hand computations (issue: models)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from conftest import all_models, random_hemisphere


@pytest.mark.parametrize("variant", ["qualitative", "full"])
@pytest.mark.parametrize("albedo", [0.3, 1.0, [0.9, 0.5, 0.1]])
def test_sigma_zero_is_lambert(rng, variant, albedo):
    wi, wo = random_hemisphere(rng, 2000), random_hemisphere(rng, 2000)
    on = rd.OrenNayar(albedo, 0.0, variant).brdf(wi, wo)
    lam = rd.Lambert(albedo).brdf(wi, wo)
    np.testing.assert_allclose(on, lam, rtol=0, atol=1e-7)
    np.testing.assert_allclose(lam, np.broadcast_to(np.asarray(albedo) / np.pi, lam.shape))


@pytest.mark.parametrize("model", all_models() + all_models(rgb=True), ids=repr)
def test_reciprocity(rng, model):
    wi, wo = random_hemisphere(rng, 3000), random_hemisphere(rng, 3000)
    np.testing.assert_allclose(model.brdf(wi, wo), model.brdf(wo, wi), rtol=1e-10, atol=1e-12)


def test_qualitative_vector_form_equals_lecture_angle_form(rng):
    """The lecture's expression with trigonometry, in float64, against the vector form."""
    n = 5000
    ti, tr = rng.uniform(0, np.pi / 2, n), rng.uniform(0, np.pi / 2, n)
    pi_, pr = rng.uniform(-np.pi, np.pi, n), rng.uniform(-np.pi, np.pi, n)
    for sigma in (0.1, 0.35, 1.2):
        rho = 0.8
        a = 1.0 - 0.5 * sigma**2 / (sigma**2 + 0.33)
        b = 0.45 * sigma**2 / (sigma**2 + 0.09)
        alpha, beta = np.maximum(ti, tr), np.minimum(ti, tr)
        expected = (
            rho / np.pi * (a + b * np.maximum(0, np.cos(pr - pi_)) * np.sin(alpha) * np.tan(beta))
        )
        wi = rd.spherical_to_vector(ti, pi_)
        wo = rd.spherical_to_vector(tr, pr)
        got = rd.OrenNayar(rho, sigma).brdf(wi, wo)
        np.testing.assert_allclose(got, expected, rtol=1e-12, atol=1e-13)
        got_angles = rd.oren_nayar(ti, tr, pr - pi_, sigma, rho)
        np.testing.assert_allclose(got_angles, expected, rtol=1e-12, atol=1e-13)


def test_full_model_by_hand():
    """Oren & Nayar 1994 Eq. 27-31 worked by hand at θi = 30°, θr = 60°, σ = 0.3, ρ = 0.5.

    σ² = 0.09: C1 = 1 - 0.5*0.09/0.42 = 0.8928571; T = 0.09/(0.09+0.09) = 0.5;
    α = 60°, β = 30°, tan β = 1/√3, sin α = √3/2, 2β/π = 1/3.
    L2 factor: 0.17 * 0.09/0.22 = 0.0695455.
    """
    rho, c1, t = 0.5, 1 - 0.5 * 0.09 / 0.42, 0.5
    l2 = 0.17 * 0.09 / 0.22
    # Δφ = 0, c = 1: C2 = 0.45 T sin α; the C3 term vanishes (1 - |c| = 0)
    c2 = 0.45 * t * math.sqrt(3) / 2
    f0 = rho / math.pi * (c1 + c2 / math.sqrt(3)) + rho**2 / math.pi * l2 * (1 - 1 / 9)
    # Δφ = π, c = -1: C2 = 0.45 T (sin α - (2β/π)^3)
    c2n = 0.45 * t * (math.sqrt(3) / 2 - 1 / 27)
    fpi = rho / math.pi * (c1 - c2n / math.sqrt(3)) + rho**2 / math.pi * l2 * (1 + 1 / 9)
    # Δφ = π/2, c = 0: only C1 and C3 = 0.125 T (4αβ/π²)² = 0.0625 (2/9)², tan 45° = 1
    c3 = 0.125 * t * (4 * (math.pi / 3) * (math.pi / 6) / math.pi**2) ** 2
    fhalf = rho / math.pi * (c1 + c3) + rho**2 / math.pi * l2
    got = rd.oren_nayar(
        np.radians(30.0), np.radians(60.0), np.array([0.0, np.pi, np.pi / 2]), 0.3, rho, "full"
    )
    np.testing.assert_allclose(got, [f0, fpi, fhalf], rtol=1e-12)
    assert c1 == pytest.approx(0.8928571, abs=1e-7)  # the published coefficients, evaluated
    assert c3 == pytest.approx(0.0030864, abs=1e-7)


def test_full_model_interreflection_is_quadratic_in_albedo(rng):
    """f(ρ) = a ρ + b ρ²: no constant or cubic term, and b is the paper's L2 coefficient."""
    wi, wo = random_hemisphere(rng, 500), random_hemisphere(rng, 500)
    sigma = 0.6
    g = {r: rd.OrenNayar(r, sigma, "full").brdf(wi, wo) for r in (0.25, 0.5, 1.0)}
    b = 2 * (g[1.0] - 2 * g[0.5])  # g(1) - 2 g(1/2) = b/2
    a = g[1.0] - b
    np.testing.assert_allclose(g[0.25], a / 4 + b / 16, rtol=1e-12, atol=1e-14)
    ti, tr = np.arccos(wi[:, 2]), np.arccos(wo[:, 2])
    c = (np.sum(wi * wo, -1) - wi[:, 2] * wo[:, 2]) / (np.sin(ti) * np.sin(tr))
    beta = np.minimum(ti, tr)
    b_paper = 0.17 / np.pi * sigma**2 / (sigma**2 + 0.13) * (1 - c * (2 * beta / np.pi) ** 2)
    np.testing.assert_allclose(b, b_paper, rtol=1e-9, atol=1e-12)
    assert np.all(np.abs(b) > 1e-3)  # a real ρ² term, not a linear model


def test_full_model_continuous_across_c2_branch():
    """C2 switches branch at cos Δφ = 0, where it is multiplied by c = 0: f is continuous."""
    eps = 1e-7
    for ti, tr in [(0.3, 1.1), (1.2, 0.5), (0.9, 0.9)]:
        lo, hi = rd.oren_nayar(
            ti, tr, np.array([np.pi / 2 - eps, np.pi / 2 + eps]), 0.5, 0.9, "full"
        )
        assert abs(lo - hi) < 1e-6


def test_oren_nayar_head_on_is_rho_a_over_pi():
    n = np.array([0.0, 0.0, 1.0])
    for sigma in (0.0, 0.2, 0.5, 1.0):
        a = 1 - 0.5 * sigma**2 / (sigma**2 + 0.33)
        assert float(rd.OrenNayar(0.6, sigma).brdf(n, n)) == pytest.approx(
            0.6 * a / np.pi, rel=1e-12
        )


def test_fujii_is_eon_single_scatter_and_paper_coefficients(rng):
    """Fujii's A = 1/(π + (π/2 - 2/3) r), B = r A, f = ρ (A + B s/t)."""
    wi, wo = random_hemisphere(rng, 2000), random_hemisphere(rng, 2000)
    r, rho = 0.7, 0.6
    A = 1 / (np.pi + (np.pi / 2 - 2 / 3) * r)
    s = np.sum(wi * wo, -1) - wi[:, 2] * wo[:, 2]
    t = np.where(s > 0, np.maximum(wi[:, 2], wo[:, 2]), 1.0)
    np.testing.assert_allclose(rd.Fujii(rho, r).brdf(wi, wo), rho * (A + r * A * s / t), rtol=1e-12)


def test_torrance_sparrow_by_formula(rng):
    """F G D / (4 cos θi cos θr) written out with vectors, Beckmann D."""
    wi, wo = random_hemisphere(rng, 2000), random_hemisphere(rng, 2000)
    wi[:, 2] += 0.05
    wo[:, 2] += 0.05
    wi /= np.linalg.norm(wi, axis=-1, keepdims=True)
    wo /= np.linalg.norm(wo, axis=-1, keepdims=True)
    eta, sigma = 1.5, 0.25
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    nh, vh = h[:, 2], np.sum(wo * h, -1)
    m = np.sqrt(2) * sigma
    tan2 = (1 - nh**2) / nh**2
    D = np.exp(-tan2 / m**2) / (np.pi * m**2 * nh**4)
    G = np.minimum(1, np.minimum(2 * nh * wo[:, 2] / vh, 2 * nh * wi[:, 2] / vh))
    c = vh
    g = np.sqrt(eta**2 - 1 + c**2)
    F = 0.5 * ((g - c) / (g + c)) ** 2 * (1 + ((c * (g + c) - 1) / (c * (g - c) + 1)) ** 2)
    expected = F * G * D / (4 * wi[:, 2] * wo[:, 2])
    got = rd.TorranceSparrow(eta, sigma, "beckmann").brdf(wi, wo)
    np.testing.assert_allclose(got, expected, rtol=1e-9)


@pytest.mark.parametrize("distribution", ["gaussian", "beckmann"])
@pytest.mark.parametrize("sigma", [0.02, 0.1, 0.3, 0.7, 1.2])
def test_slope_distribution_normalised(distribution, sigma):
    """∫ D(h) (n·h) dωh = 1 to 1e-6, by adaptive quadrature (scipy) over θh."""
    from scipy.integrate import quad

    from roughdiffuse.models import slope_distribution

    xp = np

    def integrand(theta):
        d = slope_distribution(xp, np.asarray(np.cos(theta)), np.asarray(sigma), distribution)
        return 2 * np.pi * float(d) * np.cos(theta) * np.sin(theta)

    total, _ = quad(integrand, 0, np.pi / 2, points=[sigma, 3 * sigma], limit=400, epsabs=1e-12)
    assert total == pytest.approx(1.0, abs=1e-6)


def test_fresnel_limits():
    from roughdiffuse.models import fresnel_dielectric

    eta = 1.5
    assert float(fresnel_dielectric(np, np.asarray(1.0), eta)) == pytest.approx(
        ((eta - 1) / (eta + 1)) ** 2
    )
    assert float(fresnel_dielectric(np, np.asarray(0.0), eta)) == pytest.approx(1.0)
    assert (
        float(fresnel_dielectric(np, np.asarray(0.5), 1 / eta)) == 1.0
    )  # total internal reflection


def test_lunar_models_by_formula(rng):
    wi, wo = random_hemisphere(rng, 1000), random_hemisphere(rng, 1000)
    mi, mo = wi[:, 2], wo[:, 2]
    np.testing.assert_allclose(
        rd.LommelSeeliger(0.4).brdf(wi, wo), 0.4 / (4 * np.pi * (mi + mo)), rtol=1e-12
    )
    lam = 0.3 / np.pi * ((1 - 0.7) + 2 * 0.7 / (mi + mo))
    np.testing.assert_allclose(rd.LunarLambert(0.3, 0.7).brdf(wi, wo), lam, rtol=1e-12)
    np.testing.assert_allclose(
        rd.LunarLambert(0.3, 0.0).brdf(wi, wo), rd.Lambert(0.3).brdf(wi, wo), rtol=1e-12
    )


def test_mix_is_weighted_sum(rng):
    wi, wo = random_hemisphere(rng, 500), random_hemisphere(rng, 500)
    on, ts = rd.OrenNayar([0.8, 0.6, 0.4], 0.3), rd.TorranceSparrow(1.5, 0.2)
    got = rd.Mix([(0.9, on), (0.1, ts)]).brdf(wi, wo)
    expected = 0.9 * on.brdf(wi, wo) + 0.1 * ts.brdf(wi, wo)[:, None]
    np.testing.assert_allclose(got, expected, rtol=1e-12)


def test_radiance_is_brdf_times_irradiance_times_cosine(rng):
    """World-space radiance in a random rotated frame equals the local-frame BRDF · E0 · cos θi."""
    from scipy.spatial.transform import Rotation

    wi, wo = random_hemisphere(rng, 800), random_hemisphere(rng, 800)
    rot = Rotation.random(random_state=7).as_matrix()
    n, l, v = rot @ np.array([0, 0, 1.0]), wi @ rot.T, wo @ rot.T
    for model in all_models() + all_models(rgb=True):
        f = model.brdf(wi, wo)
        cos = wi[:, 2][:, None] if f.ndim == 2 else wi[:, 2]
        np.testing.assert_allclose(
            model.radiance(n, 3 * l, v, 2.5), 2.5 * f * cos, rtol=1e-9, atol=1e-12
        )


def test_rgb_irradiance_adds_channel_axis(rng):
    wi, wo = random_hemisphere(rng, 10), random_hemisphere(rng, 10)
    n = np.array([0, 0, 1.0])
    L = rd.OrenNayar(0.5, 0.3).radiance(n, wi, wo, np.array([1.0, 2.0, 3.0]))
    assert L.shape == (10, 3)
    np.testing.assert_allclose(L[:, 2], 3 * L[:, 0])


def test_below_horizon_is_zero(rng):
    wi, wo = random_hemisphere(rng, 200), random_hemisphere(rng, 200)
    below = wi * np.array([1, 1, -1.0])
    for model in all_models():
        assert np.all(model.brdf(below, wo) == 0)
        assert np.all(model.brdf(wi, below * np.array([1, 1, 1.0])) >= 0)
        assert np.all(model.brdf(wo, below) == 0)


def test_nonunit_directions_are_normalised(rng):
    wi, wo = random_hemisphere(rng, 100), random_hemisphere(rng, 100)
    for model in all_models():
        np.testing.assert_allclose(model.brdf(7 * wi, 0.01 * wo), model.brdf(wi, wo), rtol=1e-12)


def test_roughness_conversions():
    from roughdiffuse import roughness

    assert roughness.degrees_to_sigma(45.0) == pytest.approx(np.pi / 4)
    assert roughness.sigma_to_degrees(np.pi) == pytest.approx(180.0)
    assert roughness.mitsuba_alpha_to_sigma(np.sqrt(2) * 0.3) == pytest.approx(0.3)
    assert roughness.sigma_to_mitsuba_alpha(0.3) == pytest.approx(0.3 * np.sqrt(2))
    with pytest.raises(ValueError, match="src"):
        roughness.convert(1.0, "gradians", "radians")


def test_full_model_clamped_at_zero_at_grazing_backscatter():
    """Eq. 27-31 give L1 + L2 < 0 at θi = θr = 89°, Δφ = π, σ = 1.2 (by hand: C2 < 0 wins)."""
    ti = tr = np.radians(89.0)
    sigma, rho = 1.2, 0.5
    s2 = sigma**2
    c1, t = 1 - 0.5 * s2 / (s2 + 0.33), s2 / (s2 + 0.09)
    b = 2 * ti / np.pi
    c2 = 0.45 * t * (np.sin(ti) - b**3)
    c3 = 0.125 * t * (4 * ti * ti / np.pi**2) ** 2
    l1 = rho / np.pi * (c1 - c2 * np.tan(ti))  # c = -1: the C3 term has weight 1 - |c| = 0
    l2 = 0.17 * rho**2 / np.pi * s2 / (s2 + 0.13) * (1 + b**2)
    assert l1 + l2 < 0 and c3 > 0
    assert float(rd.oren_nayar(ti, tr, np.pi, sigma, rho, "full")) == 0.0
