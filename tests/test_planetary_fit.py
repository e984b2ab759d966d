"""Disk-resolved photometric fits (roughdiffuse.planetary.disk, ``photometry fit``).

Synthetic data: a spacecraft's flyby of a spherical body imaged at phase angles 5–90°; in
each image the visible, lit disk (i, e <= 80°) is sampled at random surface normals; I/F from
Hapke with known parameters times (1 + 1 % Gaussian noise). The fit must recover every
parameter within 3 of its standard errors (the seeded draw is within 2.1), and name what a
coverage without opposition data (g >= 15°) cannot constrain.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.models.photometry import radiance_factor
from roughdiffuse.planetary.disk import DiskData, fit_disk

TRUE = {"albedo": 0.3, "b0": 1.6, "h": 0.06, "xi": -0.3, "theta_bar": math.radians(20.0)}


def flyby(rng, phases_deg, per_image=80, max_angle=80.0):
    """(i, e, g) of random points on the lit, visible disk at each phase angle."""
    out = []
    v = np.array([0.0, 0.0, 1.0])
    for gdeg in phases_deg:
        g = math.radians(gdeg)
        s = np.array([math.sin(g), 0.0, math.cos(g)])
        n = rng.normal(size=(30 * per_image, 3))
        n /= np.linalg.norm(n, axis=1)[:, None]
        lim = math.cos(math.radians(max_angle))
        keep = (n @ s > lim) & (n @ v > lim)
        n = n[keep][:per_image]
        out.append(np.stack([np.arccos(n @ s), np.arccos(n @ v), np.full(len(n), g)]))
    return np.concatenate(out, axis=1)


def synthetic(rng, phases, noise=0.01):
    i, e, g = flyby(rng, phases)
    iof = radiance_factor(rd.Hapke(**TRUE), i, e, g) * (1.0 + noise * rng.normal(size=i.size))
    return DiskData(iof, i, e, g, source="flyby")


@pytest.mark.slow
def test_flyby_fit_recovers_hapke_parameters():
    rng = np.random.default_rng(3)
    data = synthetic(rng, [5, 8, 12, 20, 30, 45, 60, 75, 90])
    f = fit_disk("hapke", data, fixed={"hg2": 0.0})
    r = f.result
    assert r.names == ("albedo", "b0", "h", "xi", "theta_bar")
    z = {n: (v - TRUE[n]) / s for n, v, s in zip(r.names, r.values, r.errors, strict=True)}
    assert all(abs(x) < 3.0 for x in z.values()), z
    assert all(np.isfinite(r.errors))
    assert 0.009 < r.rms_relative < 0.011  # the 1 % noise, no model error
    assert f.correlation.shape == (5, 5)
    np.testing.assert_allclose(np.diag(f.correlation), 1.0)
    assert "b0" not in f.notes and "h" not in f.notes


@pytest.mark.slow
def test_coverage_without_opposition_names_the_surge():
    rng = np.random.default_rng(4)
    data = synthetic(rng, [15, 20, 30, 45, 60, 75, 90])
    f = fit_disk("hapke", data, fixed={"hg2": 0.0})
    assert "no data below g = 10°" in f.notes["b0"]
    assert "no data below g = 10°" in f.notes["h"]
    assert "unconstrained: b0" in f.table()


def test_lunar_lambert_fit_is_exact_on_noise_free_data():
    """Lunar-Lambert is linear in ρ and L: noise-free data give them back to 1e-8."""
    rng = np.random.default_rng(5)
    i, e, g = flyby(rng, [10, 40, 70], per_image=30)
    iof = radiance_factor(rd.LunarLambert(0.12, 0.7), i, e, g)
    f = fit_disk("lunar-lambert", DiskData(iof, i, e, g), noise="absolute")
    np.testing.assert_allclose(f.result.values, [0.12, 0.7], rtol=1e-6)


def test_refusals():
    i, e, g = np.radians([[30.0, 40.0], [20.0, 10.0], [20.0, 35.0]])
    data = DiskData([0.1, 0.1], i, e, g)
    with pytest.raises(ValueError, match="no radiance factor"):
        fit_disk("torrance-sparrow", data)
    with pytest.raises(ValueError, match="phase must be in"):
        DiskData([0.1], [0.5], [0.1], [1.2])
    with pytest.raises(ValueError, match="need more than"):
        fit_disk("hapke", data)
