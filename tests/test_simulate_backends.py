"""The V-cavity solver on JAX and PyTorch arrays: one array-API code, three namespaces.

The NumPy path is checked against independent references in test_simulate_cavity.py and
test_simulate_surface.py (Monte Carlo, closed forms, Mitsuba). Here the compiled JAX path
(chunks under ``jax.jit``, the θa nodes under ``lax.scan``, every φ kink column kept) and the
eager PyTorch path must give the NumPy path's values, and the JAX path must meet the same
limits on its own.
"""

from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from roughdiffuse.simulate import Settings, brdf, cavity_radiance

RNG = np.random.default_rng(2026)
N = 40
TI = RNG.uniform(0.0, 1.5, N)
TR = RNG.uniform(0.0, 1.5, N)
DP = RNG.uniform(-math.pi, math.pi, N)
TI[:3], TR[:3] = math.pi / 2, [0.0, math.pi / 2, 1.2]  # grazing and normal geometries
COARSE = Settings(elements=4, n_theta=6, n_phi=6, n_theta_inter=6)


def _j(a):
    """A float64 JAX array (whatever the session's ``jax_enable_x64``)."""
    with jax.enable_x64(True):
        return jnp.asarray(a, dtype=jnp.float64)


def _rel(a, b) -> float:
    a, b = np.asarray(a), np.asarray(b)
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300)))


@pytest.mark.parametrize(
    ("sigma", "bounces", "measure"),
    [(0.2, 1, "solid-angle"), (0.7, 2, "angle"), (0.3, 3, "solid-angle"), (1.2, "all", "angle")],
)
def test_jax_brdf_equals_numpy(sigma, bounces, measure):
    s = Settings(measure=measure, elements=4, n_theta=6, n_phi=6, n_theta_inter=6)
    ref, dref = brdf(TI, TR, DP, sigma, 0.8, bounces, s, return_difference=True)
    got, dgot = brdf(
        _j(TI), _j(TR), _j(DP), sigma, 0.8, bounces, s,
        chunk=16, return_difference=True,
    )  # fmt: skip
    assert isinstance(got, jax.Array) and got.dtype == jnp.float64
    assert np.all(np.isfinite(np.asarray(got)))
    assert _rel(got, ref) < 1e-9
    assert np.max(np.abs(np.asarray(dgot) - dref)) < 1e-9 * np.max(np.abs(ref))


def test_jax_brdf_limits():
    # σ → 0 is Lambert, one bounce is linear in ρ, and more bounces add light
    ti, tr, dp = (_j(a) for a in (TI, TR, DP))
    lam = np.asarray(brdf(ti, tr, dp, 1e-4, 0.6, 1, COARSE))
    # (away from grazing: at θi = θr = π/2, f ~ 1 / cos θ for every σ > 0; the limits in σ
    # and in θ do not commute there)
    inner = np.maximum(TI, TR) < 1.5
    assert _rel(lam[inner], np.full(N, 0.6 / math.pi)[inner]) < 1e-6
    one = np.asarray(brdf(ti, tr, dp, 0.4, 0.5, 1, COARSE))
    half = np.asarray(brdf(ti, tr, dp, 0.4, 0.25, 1, COARSE))
    assert _rel(half, one / 2) < 1e-9
    two = np.asarray(brdf(ti, tr, dp, 0.4, 0.5, 2, COARSE))
    assert np.all(two >= one) and np.any(two > one * 1.001)


def test_jax_brdf_shape_and_chunks():
    # broadcasting, a scalar, and a length that is not a multiple of the chunk
    ti = _j(TI[:7])[:, None]
    got = brdf(ti, _j(TR[:3])[None, :], 0.5, 0.3, 1.0, 1, COARSE, chunk=4)
    assert got.shape == (7, 3)
    ref = brdf(TI[:7, None], TR[None, :3], 0.5, 0.3, 1.0, 1, COARSE)
    assert _rel(got, ref) < 1e-9
    assert brdf(_j(0.3), 0.2, 0.0, 0.3, 1.0, 1, COARSE).shape == ()


def test_jax_float32_input():
    # float32 angles (JAX's default) up to π/2 in float32 are accepted, computed in float64
    ti = jnp.asarray(TI, dtype=jnp.float32)
    got = brdf(ti, jnp.asarray(TR, dtype=jnp.float32), jnp.asarray(DP, dtype=jnp.float32), 0.3)
    assert got.dtype == jnp.float64
    ti64 = np.minimum(np.asarray(ti, np.float64), math.pi / 2)  # the solver clamps anyway
    ref = brdf(ti64, TR.astype(np.float32), DP.astype(np.float32), 0.3)
    assert _rel(got, ref) < 1e-9


def test_brdf_inside_the_callers_jit():
    f = jax.jit(lambda t: brdf(t, 0.5, 1.0, 0.3, 0.9, 1, COARSE))
    got = f(_j(TI[:5]))
    assert _rel(got, brdf(TI[:5], 0.5, 1.0, 0.3, 0.9, 1, COARSE)) < 1e-9


def test_jax_brdf_bad_input_is_named():
    with pytest.raises(ValueError, match="theta_i"):
        brdf(_j([2.0]), 0.5, 0.0, 0.3)
    with pytest.raises(ValueError, match="delta_phi"):
        brdf(_j([0.2]), 0.5, _j([jnp.nan]), 0.3)
    with pytest.raises(ValueError, match="chunk"):
        brdf(_j([0.2]), 0.5, 0.0, 0.3, chunk=0)


def _dirs(n: int, rng) -> np.ndarray:
    th, ph = rng.uniform(0.0, 1.5, n), rng.uniform(0.0, 2 * math.pi, n)
    return np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)


def test_jax_cavity_radiance_equals_numpy():
    rng = np.random.default_rng(5)
    ta = rng.choice([0.2, 0.9, 1.45], 30)  # cavities of three slopes, grouped by slope
    pa, wi, wo = rng.uniform(0, 2 * math.pi, 30), _dirs(30, rng), _dirs(30, rng)
    for bounces in (1, 3, "all"):
        ref = cavity_radiance(ta, pa, wi, wo, 0.9, bounces, elements=8)
        got = cavity_radiance(*(_j(a) for a in (ta, pa, wi, wo)), 0.9, bounces, 8)
        assert _rel(got, ref) < 1e-9


def test_jax_cavity_radiance_under_jit():
    wi, wo = _j([0.3, 0.0, 0.954]), _j([0.0, 0.0, 1.0])
    one = jax.jit(lambda t: cavity_radiance(t, 0.3, wi, wo, bounces=1))
    assert _rel(one(_j([0.5, 0.8])), cavity_radiance([0.5, 0.8], 0.3, wi, wo, 1.0, 1)) < 1e-9
    with pytest.raises(ValueError, match="concrete theta_a"):
        jax.jit(lambda t: cavity_radiance(t, 0.3, wi, wo, bounces=2))(_j([0.5]))


def test_torch_brdf_and_cavity_equal_numpy():
    torch = pytest.importorskip("torch")
    s = Settings(elements=4, n_theta=6, n_phi=6, n_theta_inter=6)
    got = brdf(*(torch.from_numpy(a) for a in (TI, TR, DP)), 0.5, 0.8, "all", s)
    assert isinstance(got, torch.Tensor) and got.dtype == torch.float64
    assert _rel(got.numpy(), brdf(TI, TR, DP, 0.5, 0.8, "all", s)) < 1e-9
    rng = np.random.default_rng(6)
    ta, pa, wi, wo = rng.uniform(0, 1.4, 12), rng.uniform(0, 6, 12), _dirs(12, rng), _dirs(12, rng)
    ref = cavity_radiance(ta, pa, wi, wo, 0.7, "all", 8)
    got = cavity_radiance(*(torch.from_numpy(a) for a in (ta, pa, wi, wo)), 0.7, "all", 8)
    assert _rel(got.numpy(), ref) < 1e-9
