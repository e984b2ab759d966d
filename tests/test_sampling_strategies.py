"""The samplers of roughdiffuse.models.sampling: EON's clipped LTC and Torrance–Sparrow's.

References: closed forms (EON/Fujii directional albedo, paper Eq. 8/14; the LTC reduces to
the cosine lobe at r = 0), midpoint quadrature in (cos θ, φ) written here, and the mean of
the sample weights, which any unbiased strategy must bring to the directional albedo.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.models.sampling import COSINE, strategy_for, weight_variance

K1 = 0.5 - 2.0 / (3.0 * math.pi)


def _wo(theta: float) -> np.ndarray:
    return np.array([math.sin(theta), 0.0, math.cos(theta)])


def _hemisphere_grid(n: int = 300) -> tuple[np.ndarray, float]:
    mu = (np.arange(n) + 0.5) / n
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m**2)
    return np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1), (1 / n) * (np.pi / n)


def test_strategies_are_assigned():
    assert strategy_for(rd.EON(0.5, 0.5)).name == "cltc"
    assert strategy_for(rd.Fujii(0.5, 0.5)).name == "cltc"
    assert strategy_for(rd.TorranceSparrow(1.5, 0.3)).name == "microfacet-gaussian"
    assert strategy_for(rd.TorranceSparrow(1.5, 0.3, "beckmann")).name == "microfacet-beckmann"
    assert strategy_for(rd.OrenNayar(0.5, 0.3)).name == "cosine"


def test_eon_at_r0_is_cosine_sampling():
    """r = 0: M = identity and P_u = 0, so the CLTC pdf is cos θi / π exactly."""
    wi, _ = _hemisphere_grid(20)
    for theta in (0.0, 0.6, 1.4):
        np.testing.assert_allclose(
            rd.EON(0.5, 0.0).pdf(wi, _wo(theta)), wi[..., 2] / np.pi, rtol=1e-12, atol=1e-15
        )


@pytest.mark.parametrize("r", [0.2, 0.5, 1.0])
@pytest.mark.parametrize("theta", [0.0, 0.8, 1.48])
def test_cltc_pdf_integrates_to_one(r, theta):
    wi, dw = _hemisphere_grid()
    assert float(np.sum(rd.EON(1.0, r).pdf(wi, _wo(theta))) * dw) == pytest.approx(1.0, abs=2e-3)


@pytest.mark.parametrize(
    "model",
    [rd.EON(0.8, 1.0), rd.EON(1.0, 0.4), rd.Fujii(0.8, 1.0), rd.Fujii(0.6, 0.3)],
    ids=repr,
)
@pytest.mark.parametrize("theta", [0.3, 1.2, 1.5])
def test_mean_weight_is_the_closed_form_albedo(model, theta):
    mean, var = weight_variance(model, theta, n=200_000, seed=3)
    # closed form, written here: FON E_F(μ) (EON paper Eq. 8); EON adds ρ_ms (1 − E_F)
    mu = math.cos(theta)
    s = math.sqrt(1 - mu * mu)
    r, rho = model.roughness, model.albedo
    g = s * (math.acos(mu) - s * mu) + (2 / 3) * ((s / mu) * (1 - s**3) - s)
    e = (1 + r * g / math.pi) / (1 + K1 * r)
    if isinstance(model, rd.EON):
        e_avg = (1 + (2 / 3 - 28 / (15 * math.pi)) * r) / (1 + K1 * r)
        expected = rho * e + rho**2 * e_avg / (1 - rho * (1 - e_avg)) * (1 - e)
    else:
        expected = rho * e
    assert mean == pytest.approx(expected, abs=5 * math.sqrt(var / 200_000) + 1e-6)


@pytest.mark.parametrize("r", [0.5, 1.0])
def test_cltc_beats_cosine_sampling_at_grazing_views(r):
    """The point of the paper's sampler: a lower weight variance where the lobe is skewed."""
    for theta in (math.radians(60), math.radians(80)):
        _, v_cltc = weight_variance(rd.EON(1.0, r), theta, n=100_000)
        _, v_cos = weight_variance(rd.EON(1.0, r), theta, n=100_000, strategy=COSINE)
        assert v_cltc < 0.5 * v_cos


@pytest.mark.parametrize("distribution", ["gaussian", "beckmann"])
@pytest.mark.parametrize("sigma", [0.1, 0.3, 0.6])
@pytest.mark.parametrize("theta", [0.0, 0.9, 1.4])
def test_torrance_sparrow_mean_weight_is_the_albedo(distribution, sigma, theta):
    """Mean weight against the model's albedo integrated over half vectors (its own rule)."""
    model = rd.TorranceSparrow(1.5, sigma, distribution)
    mean, var = weight_variance(model, theta, n=200_000, seed=5)
    expected = float(model.directional_albedo(_wo(theta)))
    assert mean == pytest.approx(expected, abs=5 * math.sqrt(var / 200_000) + 2e-4 * expected)


@pytest.mark.parametrize("distribution", ["gaussian", "beckmann"])
@pytest.mark.parametrize("theta", [0.0, 0.9, 1.4])
def test_torrance_sparrow_pdf_mass_is_the_valid_fraction(distribution, theta):
    """Invalid reflections (below the horizon) are lost: ∫ pdf = fraction of valid samples."""
    model = rd.TorranceSparrow(1.5, 0.3, distribution)
    rng = np.random.default_rng(8)
    s = model.sample(rng.random((400_000, 2)), _wo(theta))
    valid = float(np.mean(np.asarray(s.pdf) > 0))
    wi, dw = _hemisphere_grid(600)
    mass = float(np.sum(model.pdf(wi, _wo(theta))) * dw)
    assert mass == pytest.approx(valid, abs=4e-3)
    assert mass <= 1.0 + 2e-3


def test_sampling_in_jax_matches_numpy():
    import jax.numpy as jnp

    rng = np.random.default_rng(2)
    u = rng.random((64, 2))
    for model in (rd.EON(0.7, 0.6), rd.TorranceSparrow(1.5, 0.3, "beckmann")):
        a = model.sample(u, _wo(0.7))
        b = model.sample(jnp.asarray(u), jnp.asarray(_wo(0.7)))
        np.testing.assert_allclose(np.asarray(b.wi), a.wi, rtol=1e-5, atol=1e-6)
        np.testing.assert_allclose(np.asarray(b.weight), a.weight, rtol=1e-4, atol=1e-6)


def test_pdf_zero_below_the_horizon():
    wi, _ = _hemisphere_grid(10)
    below = wi * np.array([1, 1, -1.0])
    for model in (rd.EON(0.7, 1.0), rd.TorranceSparrow(1.5, 0.3)):
        assert np.all(model.pdf(below, _wo(0.5)) == 0)
        assert np.all(model.pdf(wi, -_wo(0.5)) == 0)
