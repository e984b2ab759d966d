"""Gaussian heightfields of Lambertian triangles (roughdiffuse.simulate.heightfield).

The geometry checks need NumPy only; the renders need Mitsuba 3 (an optional extra) and skip
with the reason when it is missing.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughdiffuse.simulate import heightfield as hf
from roughdiffuse.simulate import smith

Z = 4.5


def test_field_has_the_gaussian_correlation():
    """Empirical autocorrelation at lags 0.5ℓ, ℓ, 1.5ℓ against exp(−r²/ℓ²).

    The periodic field of n = 128 cells at ℓ = 8 cells has about (128/8)² = 256 independent
    patches; averaged over 8 realisations the sampling error of the correlation is ≈ 0.02.
    """
    rng = np.random.default_rng(1)
    acc = np.zeros(3)
    for _ in range(8):
        h = hf.gaussian_heightfield(128, 1.0, 8.0, rng)
        assert abs(h.mean()) < 1e-12 and h.std() == pytest.approx(1.0)
        acc += [np.mean(h * np.roll(h, lag, axis=ax)) / 2 for lag in (4, 8, 12) for ax in (0,)]
        acc += [np.mean(h * np.roll(h, lag, axis=1)) / 2 for lag in (4, 8, 12)]
    acc /= 8
    ref = np.exp(-np.array([0.5, 1.0, 1.5]) ** 2)
    assert np.all(np.abs(acc - ref) < 0.06), (acc, ref)


def test_mesh_is_a_closed_upward_surface_matching_the_slopes():
    rng = np.random.default_rng(2)
    n, dx = 16, 0.25
    h = hf.gaussian_heightfield(n, dx, 1.0, rng)
    verts, faces = hf.heightfield_mesh(h, dx, tiles=3)
    e1 = verts[faces[:, 1]] - verts[faces[:, 0]]
    e2 = verts[faces[:, 2]] - verts[faces[:, 0]]
    nrm = np.cross(e1, e2)
    assert np.all(nrm[:, 2] > 0)  # every triangle faces up
    # projected areas tile the 3L × 3L square exactly (no holes, no overlaps)
    assert np.sum(nrm[:, 2]) / 2 == pytest.approx((3 * n * dx) ** 2, rel=1e-12)
    # the central tile's slopes are those of the periodic tile (two separate index codes)
    centre = (np.abs(verts[faces].mean(axis=1)[:, :2]) < n * dx / 2).all(axis=1)
    mesh = np.sort(-nrm[centre, 0] / nrm[centre, 2])
    tile = np.sort(hf.triangle_slopes(h, dx)[:, 0])
    assert mesh.size == tile.size and np.allclose(mesh, tile, atol=1e-12)


def test_ply_written_whole(tmp_path):
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], float)
    path = hf.write_ply(tmp_path / "t.ply", verts, np.array([[0, 1, 2]]))
    data = path.read_bytes()
    assert data.startswith(b"ply\n") and len(data.split(b"end_header\n")[1]) == 36 + 13
    assert [p.name for p in tmp_path.iterdir()] == ["t.ply"]  # no temporary left


@pytest.fixture(scope="module")
def mitsuba():
    return pytest.importorskip("mitsuba", reason="Mitsuba 3 (optional extra 'mitsuba') absent")


SMALL = hf.HeightfieldSettings(n=64, cells_per_length=4.0, tiles=3, res=64, spp=8, realisations=3)


def test_flat_heightfield_is_lambert(mitsuba):
    """α → 0: the render of a flat patch is ρ/π exactly (camera framing, irradiance, units)."""
    f, _ = hf.heightfield_brdf(0.7, 0.4, 2.0, 1e-6, 0.6, 1, SMALL)
    assert f == pytest.approx(0.6 / math.pi, rel=1e-4)


def test_heightfield_close_to_smith(mitsuba):
    """A rendered Beckmann heightfield against the Smith solver, one bounce and all of them.

    Tolerance: 4.5 combined standard errors plus 1.5 % of f. At this geometry (away from the
    retro-reflection and forward-grazing directions where Smith's uncorrelated heights fail)
    the accuracy report measured Smith within 0.3 % of the renders at α = 0.3 and 0.7
    (docs/accuracy.md, "Smith and the heightfields"); the 1.5 % covers the small patch
    (16 ℓ) and coarse film of this quick render.
    """
    ti, tr, dp, alpha, rho = math.radians(40), math.radians(30), math.radians(150), 0.5, 0.8
    got = hf.heightfield_brdf(ti, tr, dp, alpha, rho, (1, "all"), SMALL, seed=4)
    for b, (f, se) in got.items():
        ref, ref_se = smith.brdf(ti, tr, dp, alpha, rho, b, samples=20_000, return_stderr=True)
        assert abs(f - ref) < Z * math.hypot(se, float(ref_se)) + 0.015 * ref, (b, f, se, ref)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [(dict(n=4), "n must"), (dict(tiles=2), "tiles"), (dict(realisations=1), "realisations"),
     (dict(cells_per_length=0.5), "cells_per_length")],
)
def test_bad_settings(kwargs, match):
    with pytest.raises(ValueError, match=match):
        hf.HeightfieldSettings(**kwargs)
