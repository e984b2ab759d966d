"""Mix sampled as a mixture of its components' strategies (Mitsuba 3's blendbsdf).

References written here: the cosine density cos θi / π, the unpolarised Fresnel reflectance
from Snell's law and the s/p amplitudes (Hecht, Optics, Eq. 4.42–4.43, a different form
from the package's Cook–Torrance one), EON's closed-form directional albedo (EON paper,
arXiv 2410.18026, Eq. 8 and 14), midpoint quadrature of the pdf and a chi-square test of the
sampled directions against it.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

import roughdiffuse as rd
from roughdiffuse.models.sampling import COSINE, strategy_for, weight_variance

K1 = 0.5 - 2.0 / (3.0 * math.pi)


def _wo(theta: float) -> np.ndarray:
    return np.array([math.sin(theta), 0.0, math.cos(theta)])


def _grid(n: int = 400) -> tuple[np.ndarray, float]:
    """Midpoints in (cos θ, φ) over the hemisphere, and the solid angle of one cell."""
    mu = (np.arange(n) + 0.5) / n
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m**2)
    return np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1), (1 / n) * (np.pi / n)


def _fresnel(cos_i: float, eta: float) -> float:
    """Unpolarised Fresnel reflectance from the s and p amplitudes (Snell's law)."""
    sin_t = math.sqrt(max(0.0, 1 - cos_i**2)) / eta
    if sin_t >= 1:
        return 1.0
    cos_t = math.sqrt(1 - sin_t**2)
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (cos_t - eta * cos_i) / (cos_t + eta * cos_i)
    return 0.5 * (rs * rs + rp * rp)


def _eon_albedo(rho: float, r: float, mu: float) -> float:
    """EON's directional albedo in closed form (paper Eq. 8 and 14)."""
    s = math.sqrt(1 - mu * mu)
    g = s * (math.acos(mu) - s * mu) + (2 / 3) * ((s / mu) * (1 - s**3) - s)
    e = (1 + r * g / math.pi) / (1 + K1 * r)
    e_avg = (1 + (2 / 3 - 28 / (15 * math.pi)) * r) / (1 + K1 * r)
    return rho * e + rho**2 * e_avg / (1 - rho * (1 - e_avg)) * (1 - e)


DIFFUSE_MIXES = [
    rd.Mix([(0.5, rd.OrenNayar(0.7, 0.4)), (0.5, rd.EON(0.9, 1.0))]),
    rd.Mix([(1.0, rd.Lambert(0.3)), (2.0, rd.Fujii(0.8, 0.6)), (0.5, rd.EON(0.5, 0.3))]),
    rd.Mix([(0.3, rd.Mix([(1, rd.Lambert(0.9)), (1, rd.EON(0.2, 0.8))])), (0.7, rd.Lambert(1))]),
]
GLOSSY_MIXES = [
    rd.Mix([(0.5, rd.OrenNayar(0.7, 0.3)), (0.5, rd.TorranceSparrow(1.5, 0.2))]),
    rd.Mix(
        [
            (0.8, rd.EON(np.array([0.9, 0.5, 0.2]), 0.7)),
            (0.2, rd.TorranceSparrow(1.5, 0.3, "beckmann")),
            (0.1, rd.TorranceSparrow(1.3, 0.15)),
        ]
    ),
]


def test_the_strategy_is_the_mixture_of_the_components():
    m = rd.Mix([(0.5, rd.OrenNayar(0.7, 0.3)), (0.5, rd.TorranceSparrow(1.5, 0.05))])
    assert strategy_for(m).name == "mixture(cosine, microfacet-gaussian)"


@pytest.mark.parametrize("theta", [0.0, 0.7, 1.3])
def test_pdf_is_the_albedo_weighted_sum_of_the_components_pdfs(theta):
    """q_ON ∝ 0.5·ρ, q_TS ∝ 0.5·F(cos θr, η); pdf = q_ON cos θi/π + q_TS pdf_TS."""
    ts = rd.TorranceSparrow(1.5, 0.2)
    m = rd.Mix([(0.5, rd.OrenNayar(0.7, 0.3)), (0.5, ts)])
    wi, _ = _grid(30)
    wo = _wo(theta)
    a_on, a_ts = 0.5 * 0.7, 0.5 * _fresnel(math.cos(theta), 1.5)
    q_on, q_ts = a_on / (a_on + a_ts), a_ts / (a_on + a_ts)
    expected = q_on * wi[..., 2] / np.pi + q_ts * np.asarray(ts.pdf(wi, wo))
    np.testing.assert_allclose(m.pdf(wi, wo), expected, rtol=1e-10, atol=1e-13)


def test_a_zero_weight_component_is_never_sampled():
    m = rd.Mix([(0.0, rd.TorranceSparrow(1.5, 0.1)), (1.0, rd.Lambert(0.5))])
    wi, _ = _grid(20)
    np.testing.assert_allclose(m.pdf(wi, _wo(0.4)), wi[..., 2] / np.pi, rtol=1e-12)
    s = m.sample(np.random.default_rng(1).random((2000, 2)), _wo(0.4))
    np.testing.assert_allclose(s.weight, 0.5, rtol=1e-12)  # Lambert: f cos / (cos/π) = ρ


@pytest.mark.parametrize("components", [[(0.0, rd.Lambert(0.5))], [(1.0, rd.Lambert(0.0))]])
def test_a_black_or_weightless_mix_samples_finite_zeros(components):
    m = rd.Mix(components + [(components[0][0], rd.TorranceSparrow(1.5, 0.0))])
    s = m.sample(np.random.default_rng(2).random((500, 2)), _wo(0.5))
    assert np.all(np.isfinite(s.wi)) and np.all(np.isfinite(s.pdf))
    assert np.all(np.asarray(s.weight) == 0)


@pytest.mark.parametrize("model", DIFFUSE_MIXES, ids=repr)
@pytest.mark.parametrize("theta", [0.0, 0.8, 1.45])
def test_pdf_of_diffuse_mixes_integrates_to_one(model, theta):
    wi, dw = _grid()
    assert float(np.sum(model.pdf(wi, _wo(theta))) * dw) == pytest.approx(1.0, abs=2e-3)


@pytest.mark.parametrize("model", GLOSSY_MIXES, ids=repr)
@pytest.mark.parametrize("theta", [0.0, 1.3])
def test_pdf_of_glossy_mixes_integrates_to_the_valid_fraction(model, theta):
    """Torrance–Sparrow's reflections below the horizon are rejected (pdf 0, weight 0), so
    the mixture's pdf integrates to the fraction of samples that are kept."""
    wi, dw = _grid(400)
    mass = float(np.sum(model.pdf(wi, _wo(theta))) * dw)
    s = model.sample(np.random.default_rng(8).random((200_000, 2)), _wo(theta))
    assert mass == pytest.approx(float(np.mean(np.asarray(s.pdf) > 0)), abs=4e-3)
    assert mass <= 1.0 + 2e-3


@pytest.mark.parametrize("model", DIFFUSE_MIXES + GLOSSY_MIXES, ids=repr)
@pytest.mark.parametrize("theta", [0.3, 1.2])
def test_sampled_directions_follow_the_pdf(model, theta):
    """Chi-square: 200 000 samples in 16 x 16 bins of (cos θ, φ) against the pdf integrated
    over each bin (8 x 8 midpoints)."""
    n, nb = 200_000, 16
    wo = _wo(theta)
    s = model.sample(np.random.default_rng(11).random((n, 2)), wo)
    np.testing.assert_allclose(s.pdf, model.pdf(s.wi, wo), rtol=1e-9)
    wi = np.asarray(s.wi)[np.asarray(s.pdf) > 0]
    b = np.mod(np.arctan2(wi[:, 1], wi[:, 0]), 2 * np.pi) / (2 * np.pi)
    observed, _, _ = np.histogram2d(wi[:, 2], b, bins=nb, range=[[0, 1], [0, 1]])
    k = 8 * nb
    c = (np.arange(k) + 0.5) / k
    mu, bb = np.meshgrid(c, c, indexing="ij")
    st = np.sqrt(1 - mu**2)
    grid = np.stack([st * np.cos(2 * np.pi * bb), st * np.sin(2 * np.pi * bb), mu], -1)
    dens = np.asarray(model.pdf(grid, wo)) * 2 * np.pi / (k * k)
    expected = n * dens.reshape(nb, 8, nb, 8).sum(axis=(1, 3))
    keep = expected > 5
    chi2 = np.sum((observed[keep] - expected[keep]) ** 2 / expected[keep])
    assert stats.chi2.sf(chi2, keep.sum() - 1) > 1e-4, f"chi2={chi2:.1f}, dof={keep.sum() - 1}"


@pytest.mark.parametrize("theta", [0.3, 1.0, 1.45])
def test_mean_weight_is_the_closed_form_albedo(theta):
    """Σ w_k albedo_k: Lambert's ρ and EON's closed form."""
    m = rd.Mix([(0.6, rd.Lambert(0.8)), (0.4, rd.EON(0.9, 1.0))])
    n = 200_000
    mean, var = weight_variance(m, theta, n=n, seed=3)
    expected = 0.6 * 0.8 + 0.4 * _eon_albedo(0.9, 1.0, math.cos(theta))
    assert mean == pytest.approx(expected, abs=5 * math.sqrt(var / n) + 1e-6)
    assert float(m.directional_albedo(_wo(theta))) == pytest.approx(expected, abs=1e-6)


def test_mixture_sampling_beats_cosine_sampling_on_a_coated_surface():
    """A glossy coat over a rough base, 0.5 Oren–Nayar + 0.5 Torrance–Sparrow (σ = 0.05) at
    θr = 0, where cosine sampling gives a weight variance of about 1e-2 (the README's table)."""
    m = rd.Mix([(0.5, rd.OrenNayar(0.7, 0.3)), (0.5, rd.TorranceSparrow(1.5, 0.05))])
    for theta in (0.0, math.radians(45), math.radians(80)):
        _, v_mix = weight_variance(m, theta, n=50_000)
        _, v_cos = weight_variance(m, theta, n=50_000, strategy=COSINE)
        assert v_mix < 0.05 * v_cos


def test_sampling_in_jax_matches_numpy():
    import jax.numpy as jnp

    u = np.random.default_rng(2).random((64, 2))
    m = rd.Mix([(0.8, rd.EON(0.7, 0.6)), (0.2, rd.TorranceSparrow(1.5, 0.3, "beckmann"))])
    a = m.sample(u, _wo(0.7))
    b = m.sample(jnp.asarray(u), jnp.asarray(_wo(0.7)))
    np.testing.assert_allclose(np.asarray(b.wi), a.wi, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(np.asarray(b.weight), a.weight, rtol=1e-4, atol=1e-6)


def test_channel_of_a_mix_is_the_mix_of_its_components_channels():
    """``channel(c)`` (what a per-channel evaluator calls): channel c of the RGB Mix's BRDF."""
    rgb = np.array([0.9, 0.5, 0.2])
    m = rd.Mix([(0.6, rd.EON(rgb, 0.7)), (0.4, rd.TorranceSparrow(1.5, 0.3))])
    wi, _ = _grid(8)
    wo = _wo(0.6)
    full = np.asarray(m.brdf(wi, wo))
    for c in range(3):
        ref = 0.6 * np.asarray(rd.EON(rgb[c], 0.7).brdf(wi, wo))
        ref = ref + 0.4 * np.asarray(rd.TorranceSparrow(1.5, 0.3).brdf(wi, wo))
        np.testing.assert_allclose(np.asarray(m.channel(c).brdf(wi, wo)), ref, rtol=1e-12)
        np.testing.assert_allclose(full[..., c], ref, rtol=1e-12)
