"""Shared helpers of the test suite: random directions and an independent quadrature."""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import registry


def random_hemisphere(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniform random unit vectors with z >= 0, shape (n, 3)."""
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2])
    return v


def midpoint_albedo(model: rd.Model, mu_o: float, n_mu: int = 600, n_phi: int = 600) -> np.ndarray:
    """∫ f cos θi dωi by the midpoint rule in (μi, φi): independent of the package's rules.

    Midpoint error is O(h²) even across the kinks of the Oren–Nayar family (about 1e-6 at
    this resolution).
    """
    mu = (np.arange(n_mu) + 0.5) / n_mu
    phi = (np.arange(n_phi) + 0.5) / n_phi * 2 * np.pi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m**2)
    wi = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1)
    wo = np.array([np.sqrt(1 - mu_o**2), 0.0, mu_o])
    f = np.asarray(model.brdf(wi, wo))
    weight = m * (1.0 / n_mu) * (2 * np.pi / n_phi)
    if f.ndim == 3:
        weight = weight[..., None]
    return (f * weight).sum(axis=(0, 1))


def all_models(rgb: bool = False) -> list[rd.Model]:
    """One instance per test point of every closed-form model of the package, for
    interface-wide tests: each registry id's declared ``example`` point and its class's
    ``test_points`` (:meth:`roughdiffuse.registry.Entry.test_points`), with every colour
    parameter set to 0.7 (or three channels with ``rgb``)."""
    a = [0.9, 0.5, 0.2] if rgb else 0.7
    out = []
    for entry in registry.entries():
        if entry.source != "roughdiffuse" or not entry.cls.closed_form:
            continue
        channels = {p.name for p in entry.parameters if p.channels}
        for point in entry.test_points():
            out.append(entry.create(**{**point, **dict.fromkeys(channels, a)}))
    return out


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(1994)
