"""The Smith Lambertian microsurface (roughdiffuse.simulate.smith): limits, energy, reciprocity.

Every Monte Carlo comparison uses a fixed seed and the tolerance |x − ref| < 4.5 s.e. (a
4.5σ event has probability 7e-6 per comparison for a Gaussian estimate).
"""

from __future__ import annotations

import functools
import importlib.util
import math

import numpy as np
import pytest

from roughdiffuse.simulate import smith
from roughdiffuse.simulate.smith_slopes import sample_visible_normals, smith_lambda

Z = 4.5
DISTS = ("beckmann", "ggx")
ENGINES = (
    "numpy",
    pytest.param(
        "compiled",
        marks=pytest.mark.skipif(
            importlib.util.find_spec("numba") is None, reason="the compiled walk needs Numba"
        ),
    ),
)


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("dist", DISTS)
@pytest.mark.parametrize("alpha", [0.3, 1.0])
def test_white_furnace(dist, alpha, engine):
    """ρ = 1, all bounces: every path leaves eventually, so the directional albedo is 1."""
    theta = np.radians([0.0, 60.0, 85.0])
    a, se = smith.directional_albedo(theta, alpha, 1.0, "all", dist, samples=20_000, seed=5,
                                     engine=engine)
    assert np.all(se > 0) and np.all(se < 0.01)
    assert np.all(np.abs(a - 1.0) < Z * se), (a, se)


@pytest.mark.parametrize("dist", DISTS)
def test_albedo_below_one_loses_energy(dist):
    """ρ = 0.5: every order is scaled by ρ^k ≤ ρ, so the albedo is at most ρ (and above ρ²)."""
    a, se = smith.directional_albedo(0.5, 0.8, 0.5, "all", dist, samples=20_000, seed=2)
    assert 0.25 + Z * se < a < 0.5 - Z * se


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("dist", DISTS)
def test_reciprocity(dist, engine):
    ti, tr, dp = np.radians([20.0, 70.0, 45.0]), np.radians([65.0, 10.0, 80.0]), 0.7
    kw = dict(alpha=0.7, albedo=0.9, distribution=dist, samples=20_000, return_stderr=True,
              engine=engine)
    f, se = smith.brdf(ti, tr, dp, seed=1, **kw)
    g, sg = smith.brdf(tr, ti, dp, seed=2, **kw)
    assert np.all(np.abs(f - g) < Z * np.hypot(se, sg)), (f, g, se, sg)


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("dist", DISTS)
def test_smooth_limit_is_lambert(dist, engine):
    """α → 0: the flat Lambertian plane, ρ/π, for one bounce and for all of them."""
    ti, tr, dp = np.radians([0.0, 40.0, 80.0]), np.radians([30.0, 75.0, 60.0]), 2.0
    rho = 0.5
    one = smith.single_scattering(ti, tr, dp, 1e-4, rho, dist)
    assert np.allclose(one * math.pi / rho, 1.0, atol=1e-4)
    f, se = smith.brdf(ti, tr, dp, 1e-3, rho, "all", dist, samples=5_000, return_stderr=True,
                       engine=engine)
    # the O(α²) change of a smooth surface is below 1e-3 here
    assert np.all(np.abs(f * math.pi / rho - 1.0) < Z * se * math.pi / rho + 1e-3)
    assert float(smith.brdf(0.3, 0.2, 0.1, 0.0, rho, "all", dist)) == rho / math.pi


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("dist", DISTS)
def test_walk_single_scattering_equals_quadrature(dist, engine):
    rng = np.random.default_rng(4)
    ti, tr = rng.uniform(0.0, 1.5, 6), rng.uniform(0.0, 1.5, 6)
    dp = rng.uniform(0.0, 2 * math.pi, 6)
    for alpha in (0.25, 0.9):
        q = smith.single_scattering(ti, tr, dp, alpha, 1.0, dist)
        r = smith.random_walk(ti, tr, dp, alpha, 1.0, 1, dist, samples=30_000, seed=9,
                              engine=engine)
        assert np.all(np.abs(r.values[0] - q) < Z * r.stderr[0]), (alpha, q, r.values[0])


@pytest.mark.parametrize("dist", DISTS)
def test_quadrature_converged(dist):
    ti, tr, dp = np.radians([0.0, 30.0, 70.0, 85.0]), np.radians([50.0, 30.0, 70.0, 89.0]), 2.5
    for alpha in (0.05, 0.5, 1.5):
        f = smith.single_scattering(ti, tr, dp, alpha, 1.0, dist)
        g = smith.single_scattering(ti, tr, dp, alpha, 1.0, dist, n_theta=64, n_phi=32)
        assert np.all(np.abs(f - g) <= 1e-5 * g)


def _d(dist, tan2, alpha):
    """D(ωm) in slope form: Beckmann, Walter et al. 2007 eq. 25; GGX, eq. 33."""
    cos4 = 1.0 / (1.0 + tan2) ** 2
    if dist == "beckmann":
        return np.exp(-tan2 / alpha**2) / (math.pi * alpha**2 * cos4)
    return alpha**2 / (math.pi * cos4 * (alpha**2 + tan2) ** 2)


def _hemisphere(dist, alpha, *ws, n=2000):
    """∫ Π⟨ω, ωm⟩⁺ D(ωm) dωm over the hemisphere by the midpoint rule on a (θm, φm) grid.

    A different algorithm from the solver's (no splitting at kinks, no change of measure):
    its error, O(h²) at the kinks of the positive parts, is below 1e-5 relative for n ≥ 1000.
    """
    th = (np.arange(n) + 0.5) * (math.pi / 2 / n)
    ph = (np.arange(2 * n) + 0.5) * (math.pi / n)
    st, ct = np.sin(th)[:, None], np.cos(th)[:, None]
    m = (st * np.cos(ph), st * np.sin(ph), np.broadcast_to(ct, (n, 2 * n)))
    val = _d(dist, np.tan(th) ** 2, alpha)[:, None] * st
    for w in ws:
        val = val * np.maximum(w[0] * m[0] + w[1] * m[1] + w[2] * m[2], 0.0)
    return float(val.sum()) * (math.pi / 2 / n) * (math.pi / n)


@pytest.mark.parametrize("dist", DISTS)
def test_quadrature_against_a_midpoint_rule_on_the_hemisphere(dist):
    ti, tr, dp, alpha = 0.6, 1.1, 2.2, 0.5
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.array([math.sin(tr) * math.cos(dp), math.sin(tr) * math.sin(dp), math.cos(tr)])
    val = _hemisphere(dist, alpha, wi, wo)
    lam = smith_lambda(dist, np.array([math.cos(ti), math.cos(tr)]), alpha)
    ref = val / (math.pi * math.cos(ti) * math.cos(tr) * (1 + lam.sum()))
    assert float(smith.single_scattering(ti, tr, dp, alpha, 1.0, dist)) == pytest.approx(
        ref, rel=2e-5
    )


def test_lambda_closed_forms():
    """Λ at 45° for α = 1: GGX (√2 − 1)/2 (Heitz 2014 eq. 72); Beckmann eq. 86 by hand."""
    z = np.array(math.cos(math.pi / 4))
    assert float(smith_lambda("ggx", z, 1.0)) == pytest.approx((math.sqrt(2) - 1) / 2, 1e-14)
    ref = (math.erf(1.0) - 1) / 2 + math.exp(-1.0) / (2 * math.sqrt(math.pi))
    assert float(smith_lambda("beckmann", z, 1.0)) == pytest.approx(ref, 1e-13)
    assert float(smith_lambda("beckmann", -z, 1.0)) == pytest.approx(-1 - ref, 1e-13)


@pytest.mark.parametrize("dist", DISTS)
def test_g1_formula_is_one_over_one_plus_lambda(dist):
    """``smith_g1`` (GGX as 2z/(z + √(α²(1 − z²) + z²))) against 1/(1 + Λ) from
    ``smith_lambda`` (Heitz 2014 eqs. 72, 86), from grazing to the normal; and G1 = 1 in
    float64 where Beckmann's a = cot θ/α ≥ 6 (the compiled layered walk skips erfc there)."""
    from roughdiffuse.simulate.smith_formulas import numpy_formulas

    f = numpy_formulas()
    ggx = dist == "ggx"
    z = np.concatenate([np.logspace(-8, -1, 50), np.linspace(0.1, 1.0, 200)])
    for alpha in (0.05, 0.3, 1.0, 2.5):
        ref = 1.0 / (1.0 + smith_lambda(dist, z, alpha))
        got = np.array([f.smith_g1(ggx, v, alpha) for v in z])
        np.testing.assert_allclose(got, ref, rtol=2e-15, atol=0)
        if not ggx:
            z6 = 6.0 * alpha / math.sqrt(1.0 + 36.0 * alpha * alpha)  # a = 6
            edge = np.linspace(z6, 1.0, 1000)
            assert np.all(1.0 / (1.0 + smith_lambda(dist, edge, alpha)) == 1.0)


@functools.cache
def _compiled_sampler():
    """A Numba loop drawing n visible normals of ω from the compiled walks' sampler (its own
    random numbers: normal pairs, disc points, a Gaussian-proposal rejection for Beckmann's
    slope)."""
    import numba

    from roughdiffuse.engine.numba_random import path_key
    from roughdiffuse.simulate.smith_walk_numba import visible_normal

    @numba.njit
    def draw(ggx, wx, wy, wz, alpha, n):
        out = np.empty((n, 3))
        for i in range(n):
            mx, my, mz, _ = visible_normal(ggx, wx, wy, wz, alpha, path_key(7, i), 0)
            out[i, 0], out[i, 1], out[i, 2] = mx, my, mz
        return out

    return draw


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("dist", DISTS)
def test_visible_normals_and_lambda_below_the_horizon(dist, engine):
    """Visible normals of ω above and below the horizon against a midpoint rule.

    ∫ ⟨ω, ωm⟩⁺ D dωm = (1 + Λ(ω)) cos θ for every ω (Heitz 2014 eq. 17 with Λ(−ω) = −1 − Λ(ω)),
    and the sampled normals' mean of ⟨ω', ωm⟩⁺ is ∫ ⟨ω, ωm⟩⁺ ⟨ω', ωm⟩⁺ D / ∫ ⟨ω, ωm⟩⁺ D,
    for the NumPy walk's sampler and for the compiled walks' (different random numbers and,
    for Beckmann, a different rejection).
    """
    alpha, rng = 0.6, np.random.default_rng(3)
    w2 = np.array([math.sin(0.8) * math.cos(2.0), math.sin(0.8) * math.sin(2.0), math.cos(0.8)])
    for theta in (0.3, 1.2, 1.9, 2.6):
        w = np.array([math.sin(theta), 0.0, math.cos(theta)])
        norm = _hemisphere(dist, alpha, w, n=1000)
        lam = float(smith_lambda(dist, np.array(math.cos(theta)), alpha))
        assert norm == pytest.approx((1.0 + lam) * math.cos(theta), rel=2e-5)
        num = _hemisphere(dist, alpha, w, w2, n=1000)
        if engine == "numpy":
            m = sample_visible_normals(dist, np.tile(w, (100_000, 1)), alpha, rng)
        else:
            m = _compiled_sampler()(dist == "ggx", *w, alpha, 100_000)
        assert np.all(m[:, 2] >= 0) and np.all(m @ w >= -1e-12)
        x = np.maximum(m @ w2, 0.0)
        se = np.std(x, ddof=1) / math.sqrt(x.size)
        assert abs(np.mean(x) - num / norm) < Z * se, (theta, np.mean(x), num / norm)


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("dist", DISTS)
def test_orders_non_negative_and_additive(dist, engine):
    ti, tr, dp = np.radians([30.0, 75.0]), np.radians([60.0, 80.0]), np.radians([0.0, 180.0])
    r = smith.random_walk(ti, tr, dp, 0.8, (1.0, 0.5), 3, dist, samples=10_000, seed=3,
                          max_order=3, engine=engine)
    assert np.all(r.orders >= 0) and np.all(r.orders[1] > 0)
    for a, rho in enumerate(r.albedos):
        s = sum(rho**k * r.orders[k - 1] for k in (1, 2, 3))
        assert np.allclose(r.values[a], s, rtol=1e-12)
    more = smith.random_walk(ti, tr, dp, 0.8, 1.0, "all", dist, samples=10_000, seed=3,
                             engine=engine)
    assert np.all(more.values[0] >= r.values[0])  # the same paths, more orders scored


@pytest.mark.parametrize("engine", ENGINES)
def test_seeded_and_reproducible(engine):
    kw = dict(alpha=0.5, albedo=0.7, samples=2_000, engine=engine)
    a = smith.brdf([0.2, 0.9], 0.4, 1.0, seed=11, **kw)
    b = smith.brdf([0.2, 0.9], 0.4, 1.0, seed=11, **kw)
    c = smith.brdf([0.2, 0.9], 0.4, 1.0, seed=12, **kw)
    assert np.array_equal(a, b) and not np.array_equal(a, c)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(alpha=-0.1), "alpha"),
        (dict(alpha=2.5), "alpha"),
        (dict(alpha=0.5, albedo=1.2), "albedo"),
        (dict(alpha=0.5, distribution="phong"), "distribution"),
        (dict(alpha=0.5, samples=1), "samples"),
        (dict(alpha=0.5, bounces=0), "bounces"),
        (dict(alpha=0.5, method="exact"), "method"),
        (dict(alpha=0.5, bounces=2, method="quadrature"), "quadrature"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        smith.brdf(0.3, 0.4, 0.0, **kwargs)


def test_bad_angles():
    with pytest.raises(ValueError, match="theta_r"):
        smith.brdf(0.3, 1.7, 0.0, alpha=0.5)
    with pytest.raises(ValueError, match="delta_phi"):
        smith.brdf(0.3, 0.4, math.nan, alpha=0.5)


def test_workers_do_not_change_the_numbers(monkeypatch):
    """NumPy walk: each batch of paths has its own spawned generator: 1 or 2 threads, same
    values (the compiled walk: tests/test_smith_walk_compiled.py)."""
    monkeypatch.setattr(smith, "_BATCH", 2048)  # several batches from few paths
    kw = dict(alpha=0.6, albedo=0.8, bounces="all", distribution="ggx", samples=3_000, seed=3,
              engine="numpy")
    a = smith.random_walk([0.2, 1.0], 0.5, 1.0, workers=1, **kw)
    b = smith.random_walk([0.2, 1.0], 0.5, 1.0, workers=2, **kw)
    assert np.array_equal(a.values, b.values) and np.array_equal(a.stderr, b.stderr)
    assert a.segments == b.segments > 6_000
