"""stereo.footprint: how far the surface turns across a pixel, and the pixels whose values the
stereo fits trust for the object's roughness."""

import numpy as np
import pytest

from roughdiffuse._validate import ParameterError
from roughdiffuse.stereo.footprint import VIEW_FLOOR, normal_spread, smoothest, view_spread


def test_normal_spread_of_a_cylinder():
    """One row across a cylinder of radius 3 pixels, its normal tilted by θ_c = asin((c − 3)
    / 3) at column c (and a NaN normal at the end, which counts as no neighbour): each
    pixel's spread is the larger difference of θ to its neighbours' (closed form)."""
    cols = np.arange(7)
    theta = np.arcsin((cols - 3) / 3.0)
    normals = np.stack([np.sin(theta), np.zeros(7), np.cos(theta)], axis=1)
    normals[6] = np.nan
    mask = np.zeros((3, 9), dtype=bool)
    mask[1, 1:8] = True
    got = normal_spread(mask, normals)
    step = np.abs(np.diff(theta[:6]))
    want = np.maximum(np.r_[0.0, step], np.r_[step, 0.0])
    np.testing.assert_allclose(got[:6], want, atol=1e-7)
    assert got[6] == 0.0


def test_view_spread_divides_by_the_cosine_of_the_view():
    """The same cylinder's row: each pixel's spread over cos θ_c, the n·v of its normal
    (closed form), and over VIEW_FLOOR for a normal at 90° from the view."""
    cols = np.arange(7)
    theta = np.arcsin((cols - 3) / 3.0)  # ±90° at the ends
    normals = np.stack([np.sin(theta), np.zeros(7), np.cos(theta)], axis=1)
    mask = np.zeros((3, 9), dtype=bool)
    mask[1, 1:8] = True
    step = np.abs(np.diff(theta))
    spread = np.maximum(np.r_[0.0, step], np.r_[step, 0.0])
    want = spread / np.maximum(np.cos(theta), VIEW_FLOOR)
    np.testing.assert_allclose(view_spread(mask, normals), want, rtol=1e-6)
    assert want[0] == pytest.approx(spread[0] / VIEW_FLOOR)


def test_smoothest_keeps_a_fraction_and_the_ties():
    """Spreads 0.1, 0.5, 0.2, 0.4, 0.3 over the pool [0, 1, 2, 3, 4]: 40 % are pixels 0 and 2;
    at least 3 adds pixel 4; a pool of zeros (no neighbours) is kept whole; a pool smaller
    than ``at_least`` is kept whole."""
    spread = np.array([0.1, 0.5, 0.2, 0.4, 0.3])
    pool = np.arange(5)
    np.testing.assert_array_equal(smoothest(spread, pool, 0.4), [0, 2])
    np.testing.assert_array_equal(smoothest(spread, pool, 0.4, 3), [0, 2, 4])
    np.testing.assert_array_equal(smoothest(np.zeros(5), pool, 0.25), pool)
    np.testing.assert_array_equal(smoothest(spread, pool[[3, 1]], 0.5, 4), [1, 3])


def test_fit_pixels_refuses_trusted_of_another_shape():
    """``trusted`` names the object's pixels: another length is refused, naming it."""
    import roughdiffuse as rd
    from roughdiffuse import stereo
    from roughdiffuse.stereo.rough import Family, fit_pixels

    data = stereo.synthetic_sphere(rd.OrenNayar(0.6, 0.3, "full"), size=12)
    lam = stereo.lambertian(data)
    p = int(data.mask.sum())
    with pytest.raises(ParameterError, match="trusted must have shape"):
        fit_pixels(data, Family(rd.OrenNayar(0.6, 0.3, "full"), ("sigma",), ((0.0, 1.0),)),
                   start=lam, weights=np.ones((data.count, p)), initial=np.array([0.3]),
                   trusted=np.ones(p + 1, dtype=bool))
