"""SmithDiffuse: the Smith Lambertian microsurface as a registry model (a Monte Carlo one)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import fastpath, registry
from roughdiffuse.simulate import smith


def test_registered_with_both_distributions():
    for model_id, dist in (("smith-diffuse-beckmann", "beckmann"), ("smith-diffuse-ggx", "ggx")):
        m = registry.create(model_id, albedo=0.7, alpha=0.4)
        assert isinstance(m, rd.SmithDiffuse) and m.distribution == dist
        assert registry.id_of(m) == model_id
        assert [p.name for p in registry.get(model_id).parameters] == ["albedo", "alpha"]


def test_values_are_the_solvers():
    """The model's brdf from directions = simulate.smith.random_walk at the same angles/seed."""
    ti, tr, dp = 0.5, 1.0, 2.0
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.array([math.sin(tr) * math.cos(dp), math.sin(tr) * math.sin(dp), math.cos(tr)])
    m = rd.SmithDiffuse(albedo=0.6, alpha=0.5, distribution="ggx", samples=3000, seed=4)
    ref = smith.random_walk(ti, tr, dp, 0.5, 0.6, "all", "ggx", samples=3000, seed=4)
    assert float(m.brdf(wi, wo)) == pytest.approx(float(ref.values[0]), rel=1e-9)


def test_rgb_albedo_is_one_walk_per_geometry():
    wi = np.array([[0.0, 0.6, 0.8], [0.0, 0.0, 1.0]])
    wo = np.array([[0.6, 0.0, 0.8], [0.8, 0.0, 0.6]])
    rgb = rd.SmithDiffuse(albedo=[0.2, 0.5, 0.9], alpha=0.6, samples=2000)
    out = rgb.brdf(wi, wo)
    assert out.shape == (2, 3)
    for c, rho in enumerate((0.2, 0.5, 0.9)):
        one = rd.SmithDiffuse(albedo=rho, alpha=0.6, samples=2000).brdf(wi, wo)
        assert np.allclose(out[:, c], one, rtol=1e-12)


def test_below_horizon_is_zero_and_lambert_limit():
    m = rd.SmithDiffuse(albedo=0.5, alpha=0.0)
    assert float(m.brdf(np.array([0, 0, 1.0]), np.array([0, 0.6, 0.8]))) == pytest.approx(
        0.5 / math.pi
    )
    assert float(m.brdf(np.array([0, 0, -1.0]), np.array([0, 0.6, 0.8]))) == 0.0


def test_not_traceable_and_refused_cleanly():
    m = rd.SmithDiffuse(albedo=0.5, alpha=0.3)
    n = np.array([[0.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match="simulation"):
        fastpath.evaluate(m, n, n, n)
    jnp = pytest.importorskip("jax.numpy")
    with pytest.raises(ValueError, match="Monte Carlo"):
        m.brdf(jnp.array([0.0, 0.0, 1.0]), jnp.array([0.0, 0.6, 0.8]))


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(alpha=3.0), "alpha"),
        (dict(albedo=-0.1), "albedo"),
        (dict(distribution="phong"), "distribution"),
        (dict(samples=1), "samples"),
        (dict(seed=-1), "seed"),
    ],
)
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        rd.SmithDiffuse(**kwargs)
