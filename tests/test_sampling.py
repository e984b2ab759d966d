"""Sampling: the pdf is normalised and ``sample`` draws from it (chi-square)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import stats

import roughdiffuse as rd
from conftest import all_models


def _wo(theta):
    return rd.spherical_to_vector(theta, 0.3)


def _by_sampler(models: list) -> list:
    """pytest parameters, one model per sampler: the cosine-weighted sampler's density and
    draws do not depend on the model, so its normalisation and histogram are tested once (the
    first such model; test_models_sharing_a_sampler_draw_the_same checks that every other
    cosine-sampled model draws exactly that). A sampler with parameters (LTC, microfacet,
    mixture, coat) is tested for every model: the first test point of each class and sampler
    in `make test`, the others (other parameters of the same code) in the full set (slow)."""
    out, seen = [], set()
    for m in models:
        name = m.sampling_strategy().name
        if name == "cosine" and name in seen:
            continue
        key = name if name == "cosine" else (type(m).__name__, name)
        marks = (pytest.mark.slow,) if key in seen else ()
        seen.update((name, key))
        out.append(pytest.param(m, id=repr(m), marks=marks))
    return out


SAMPLED = _by_sampler(all_models())
COSINE_SAMPLED = [m for m in all_models() if m.sampling_strategy().name == "cosine"]


@pytest.mark.parametrize("model", COSINE_SAMPLED[1:], ids=repr)
def test_models_sharing_a_sampler_draw_the_same(model):
    """The same directions and densities as the model the pdf and histogram tests ran on, and
    the cosine density cos θi / π (Pharr, Jakob, Humphreys, PBR 4th ed., Sec. A.5.3)."""
    rng = np.random.default_rng(8)
    u = rng.random((500, 2))
    wo = _wo(0.9)
    ref = COSINE_SAMPLED[0].sample(u, wo)
    got = model.sample(u, wo)
    np.testing.assert_array_equal(np.asarray(got.wi), np.asarray(ref.wi))
    np.testing.assert_array_equal(np.asarray(got.pdf), np.asarray(ref.pdf))
    w = rd.spherical_to_vector(rng.uniform(0, 1.6, 200), rng.uniform(0, 6.3, 200))
    expected = np.where(w[:, 2] > 0, w[:, 2] / np.pi, 0.0)
    np.testing.assert_allclose(np.asarray(model.pdf(w, wo)), expected, rtol=1e-12, atol=1e-15)


def _valid_fraction(model, wo, n=200_000):
    """Fraction of samples the sampler can use (Torrance-Sparrow's reflections below the
    horizon are rejected with pdf 0, as in pbrt and Mitsuba; cosine and LTC never reject)."""
    s = model.sample(np.random.default_rng(3).random((n, 2)), wo)
    return float(np.mean(np.asarray(s.pdf) > 0))


@pytest.mark.parametrize("model", SAMPLED)
@pytest.mark.parametrize("theta_r", [0.0, 0.7, 1.45])
def test_pdf_integrates_to_one(model, theta_r):
    """Midpoint quadrature over the hemisphere (in cos θ, φ) of pdf(wi, wo): 1, or the
    fraction of valid samples where the sampler rejects some."""
    n = 400
    mu = (np.arange(n) + 0.5) / n
    phi = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * np.pi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m**2)
    wi = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1)
    wo = _wo(theta_r)
    total = np.sum(model.pdf(wi, wo)) * (1 / n) * (np.pi / n)
    assert total <= 1.0 + 2e-3
    assert total == pytest.approx(_valid_fraction(model, wo), abs=5e-3)


@pytest.mark.parametrize("model", SAMPLED)
@pytest.mark.parametrize("theta_r", [0.2, 1.3])
def test_sample_histogram_matches_pdf(model, theta_r):
    """Chi-square test of 200 000 samples in 16 x 16 bins of (cos θ, φ) against the pdf."""
    rng = np.random.default_rng(11)
    n, nb = 200_000, 16
    wo = _wo(theta_r)
    s = model.sample(rng.random((n, 2)), wo)
    assert np.all(np.isfinite(s.wi)) and np.all(s.pdf >= 0)
    np.testing.assert_allclose(s.pdf, model.pdf(s.wi, wo), rtol=1e-9)
    wi = np.asarray(s.wi)[np.asarray(s.pdf) > 0]  # rejected samples carry no direction
    a = wi[:, 2]
    b = np.mod(np.arctan2(wi[:, 1], wi[:, 0]), 2 * np.pi) / (2 * np.pi)
    observed, _, _ = np.histogram2d(a, b, bins=nb, range=[[0, 1], [0, 1]])
    # expected counts: the pdf integrated over each bin (midpoint, 8 x 8 points per bin),
    # dω = dμ dφ
    k = 8 * nb
    c = (np.arange(k) + 0.5) / k
    mu, B = np.meshgrid(c, c, indexing="ij")
    st = np.sqrt(1 - mu**2)
    wgrid = np.stack([st * np.cos(2 * np.pi * B), st * np.sin(2 * np.pi * B), mu], -1)
    dens = model.pdf(wgrid, wo) * 2 * np.pi / (k * k)
    expected = n * dens.reshape(nb, 8, nb, 8).sum(axis=(1, 3))
    keep = expected > 5
    chi2 = np.sum((observed[keep] - expected[keep]) ** 2 / expected[keep])
    p = stats.chi2.sf(chi2, keep.sum() - 1)
    assert p > 1e-4, f"chi2={chi2:.1f}, dof={keep.sum() - 1}"


@pytest.mark.parametrize("model", all_models() + all_models(rgb=True), ids=repr)
def test_sample_weight_is_f_cos_over_pdf(model):
    rng = np.random.default_rng(5)
    wo = _wo(0.6)
    s = model.sample(rng.random((1000, 2)), wo)
    f = np.asarray(model.brdf(s.wi, wo))
    cos = np.asarray(s.wi)[:, 2]
    pdf = np.asarray(s.pdf)
    expected = np.where(pdf > 0, f * (cos / np.where(pdf > 0, pdf, 1)) if f.ndim == 1 else 0, 0)
    if f.ndim == 2:
        expected = np.where(pdf[:, None] > 0, f * (cos / np.where(pdf > 0, pdf, 1))[:, None], 0)
    np.testing.assert_allclose(s.weight, expected, rtol=1e-9, atol=1e-12)


def test_sample_rejects_bad_u():
    with pytest.raises(ValueError, match="u"):
        rd.Lambert(0.5).sample(np.array([[0.5, 1.5]]), np.array([0, 0, 1.0]))
    with pytest.raises(ValueError, match=r"u must have shape"):
        rd.Lambert(0.5).sample(np.array([0.5, 0.5, 0.5]), np.array([0, 0, 1.0]))
