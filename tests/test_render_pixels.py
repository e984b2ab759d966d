"""roughdiffuse.render.pixels: the per-pixel geometry of a render, for BRDFs known only by
Monte Carlo. Reference: the renderer itself at one sample per pixel (an image formed from
the cosines must be the render)."""

from __future__ import annotations

import math

import numpy as np

import roughdiffuse as rd
from roughdiffuse.render import DistantLight, Sphere, render
from roughdiffuse.render.pixels import pixel_cosines


def test_pixel_cosines_give_the_render() -> None:
    """f μi where lit, from the cosines, is render(..., samples_per_pixel=1)."""
    model = rd.OrenNayar([0.7, 0.5, 0.3], 0.4)
    light = DistantLight(math.radians(40.0), math.radians(20.0))
    img, _ = render(model, Sphere(), light, size=40, samples_per_pixel=1)
    g = pixel_cosines(Sphere(), light, size=40)
    f = np.asarray(model.brdf_cosines(g.mu_i, g.mu_o, g.cos_io))
    mine = np.where(g.lit[..., None], f * np.maximum(g.mu_i, 0.0)[..., None], 0.0)
    np.testing.assert_allclose(mine, img, atol=2e-6)  # the render is float32
    assert g.lit.sum() > 0.5 * g.hit.sum()
