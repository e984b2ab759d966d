"""Bad input gets a clear ValueError; valid input never gives NaN or Inf (hypothesis)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import roughdiffuse as rd

N = np.array([0.0, 0.0, 1.0])


@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: rd.OrenNayar(0.5, -0.1), r"sigma must be in \[0, π/2\] radians"),
        (lambda: rd.OrenNayar(0.5, float("nan")), "sigma"),
        (lambda: rd.OrenNayar(0.5, 17.0), "sigma"),  # degrees by mistake
        (lambda: rd.OrenNayar(1.2, 0.3), r"albedo must be in \[0, 1\]"),
        (lambda: rd.OrenNayar([0.5, 1.5, 0.2], 0.3), r"albedo .*per channel.*1\.5"),
        (lambda: rd.OrenNayar(0.5, 0.3, "fancy"), "variant"),
        (lambda: rd.Lambert(-0.1), "albedo"),
        (lambda: rd.Lambert(np.ones((2, 3))), "albedo"),
        (lambda: rd.Fujii(0.5, 1.5), r"roughness must be in \[0, 1\]"),
        (lambda: rd.EON(0.5, -1), "roughness"),
        (lambda: rd.TorranceSparrow(0.0, 0.3), r"eta must be in \(0, 1000\]"),
        (lambda: rd.TorranceSparrow(-1.0, 0.3), "eta"),
        (lambda: rd.TorranceSparrow(1.5, 0.3, "ggx"), "distribution"),
        (lambda: rd.LunarLambert(0.5, -0.1), r"limb_darkening must be in \[0, 1000\]"),
        (lambda: rd.Hapke(0.5, -0.1), r"b0 must be in \[0, 1000\]"),
        (lambda: rd.Mix([]), "components"),
        (lambda: rd.Mix([(-1.0, rd.Lambert(0.5))]), "weight"),
        (lambda: rd.Mix([(1.0, "lambert")]), "components"),
        (lambda: rd.OrenNayar("rough", 0.3), "albedo"),
    ],
)
def test_bad_parameters(build, match):
    with pytest.raises(ValueError, match=match):
        build()


@pytest.mark.parametrize(
    ("wi", "wo", "match"),
    [
        (np.zeros(3), N, "wi must contain non-zero"),
        (N, np.array([np.nan, 0, 1]), "wo must contain non-zero"),
        (N, np.array([np.inf, 0, 1]), "wo"),
        (np.ones((4, 3)), np.ones((5, 3)), "do not broadcast"),
        (np.ones((4, 2)), N, r"wi must have shape \(\.\.\., 3\)"),
    ],
)
def test_bad_directions(wi, wo, match):
    for model in (rd.Lambert(0.5), rd.OrenNayar(0.5, 0.3), rd.EON(0.5, 0.5)):
        with pytest.raises(ValueError, match=match):
            model.brdf(wi, wo)


def test_bad_directions_jax():
    import jax.numpy as jnp

    with pytest.raises(ValueError, match="wi must contain non-zero"):
        rd.OrenNayar(0.5, 0.3).brdf(jnp.zeros(3), jnp.asarray(N))


def test_bad_angles_in_paper_notation():
    with pytest.raises(ValueError, match="theta_i"):
        rd.oren_nayar(-0.1, 0.2, 0.0, 0.3)
    with pytest.raises(ValueError, match="theta_r"):
        rd.oren_nayar(0.1, 2.0, 0.0, 0.3)


unit = st.floats(0.0, 1.0)
angle = st.floats(0.0, math.pi / 2)
azimuth = st.floats(-math.pi, math.pi)
special_theta = st.sampled_from([0.0, math.pi / 2, math.pi / 2 - 1e-9, 1e-9])


def _models(a, s, r, eta, dist):
    return [
        rd.Lambert(a),
        rd.OrenNayar(a, s),
        rd.OrenNayar(a, s, "full"),
        rd.Fujii(a, r),
        rd.EON(a, r),
        rd.TorranceSparrow(eta, s, dist),
        rd.LommelSeeliger(a),
        rd.LunarLambert(a, r),
        rd.Mix([(0.7, rd.OrenNayar(a, s)), (0.3, rd.TorranceSparrow(eta, s, dist))]),
    ]


@settings(max_examples=300, deadline=None)
@given(
    a=unit,
    s=st.one_of(st.sampled_from([0.0, math.pi / 2]), angle),
    r=st.one_of(st.sampled_from([0.0, 1.0]), unit),
    eta=st.floats(0.05, 10.0),
    dist=st.sampled_from(["gaussian", "beckmann"]),
    ti=st.one_of(special_theta, angle),
    to=st.one_of(special_theta, angle),
    pi_=azimuth,
    po=st.one_of(azimuth, st.just(None)),
    dtype=st.sampled_from([np.float32, np.float64]),
)
def test_finite_everywhere(a, s, r, eta, dist, ti, to, pi_, po, dtype):
    """Grazing (θ = 90° exactly), wi = wo, wi = normal, σ = 0 and π/2: always finite, >= 0."""
    wi = rd.spherical_to_vector(ti, pi_).astype(dtype)
    wo = wi if po is None else rd.spherical_to_vector(to, po).astype(dtype)
    for m in _models(a, s, r, eta, dist):
        f = np.asarray(m.brdf(wi, wo))
        assert np.all(np.isfinite(f)) and np.all(f >= 0), (m, wi, wo, f)
        alb = np.asarray(m.directional_albedo(wo))
        assert np.all(np.isfinite(alb)), (m, wo, alb)
        L = np.asarray(m.radiance(N.astype(dtype), wi, wo))
        assert np.all(np.isfinite(L)), (m, wi, wo)


def test_minus_normal_is_below_horizon():
    for m in _models(0.5, 0.3, 0.5, 1.5, "gaussian"):
        assert float(m.brdf(-N, N)) == 0.0
        assert float(m.brdf(N, -N)) == 0.0


def test_nonnegative_on_a_grazing_grid():
    """A grid dense at grazing angles, where random search rarely lands: f >= 0 and finite."""
    th = np.radians([0, 30, 60, 80, 85, 88, 89, 89.9, 90])
    ti, to, dp = np.meshgrid(th, th, np.radians([0, 45, 90, 135, 180]), indexing="ij")
    wi = rd.spherical_to_vector(ti, 0.0)
    wo = rd.spherical_to_vector(to, dp)
    for s in (0.0, 0.5, 1.0, 1.2, np.pi / 2):
        for a in (0.2, 1.0):
            for m in _models(a, s, s / (np.pi / 2), 1.5, "gaussian"):
                f = np.asarray(m.brdf(wi, wo))
                assert np.all(np.isfinite(f)) and np.all(f >= 0), m
