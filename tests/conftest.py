"""Shared helpers of the test suite: random directions and an independent quadrature."""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd


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
    """One instance of every model (several parameter sets), for interface-wide tests."""
    a = np.array([0.9, 0.5, 0.2]) if rgb else 0.7
    return [
        rd.Lambert(a),
        rd.OrenNayar(a, 0.0),
        rd.OrenNayar(a, 0.4),
        rd.OrenNayar(a, 0.4, "full"),
        rd.OrenNayar(a, np.pi / 2, "full"),
        rd.Fujii(a, 0.6),
        rd.EON(a, 0.0),
        rd.EON(a, 1.0),
        rd.TorranceSparrow(1.5, 0.3),
        rd.TorranceSparrow(1.5, 0.3, "beckmann"),
        rd.TorranceSparrow(0.7, 0.2),
        rd.LommelSeeliger(a),
        rd.LunarLambert(a, 0.6),
        rd.Mix([(0.9, rd.OrenNayar(a, 0.3)), (0.1, rd.TorranceSparrow(1.5, 0.2))]),
        rd.Burley(a, 0.5),
        rd.BurleyRenormalized(a, 0.7),
        rd.Burley2015(a, 0.3),
        rd.Hammon(a, 0.5),
        rd.Chan(a, 0.4),
        rd.LambertSphere(a, "full"),
        rd.LambertSphere(a, "fast"),
        rd.Hapke(a, 0.8, 0.1, -0.3, 0.35),
        rd.Hapke(a, 0.0, 0.0, 0.2, 0.0),
        rd.Minnaert(a, 0.7),
        rd.Coated(rd.OrenNayar(a, 0.3, "full"), 1.5),
        rd.Coated(rd.Lambert(a), 1.5, 0.3, "beckmann", 0.2),
    ]


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(1994)
