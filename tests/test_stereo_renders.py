"""The photometric-stereo renders of ``scripts/stereo_renders.py``: a coated sphere rendered by
Mitsuba 3 in its ``coat03`` material holds, in each pixel, the coated model's value averaged
over the pixel's footprint.

The reference is made here without Mitsuba: the orthographic camera's framing
(:data:`roughdiffuse.stereo.mitsuba_render.MARGIN`) places each pixel on the unit sphere, a
fine grid of points over the pixel gives the exact normals, and the model's NumPy value
E f(l, v) max(n·l, 0) is averaged over them (0 off the sphere). Mitsuba averages ``spp``
random points of the pixel instead: the two agree within that sampling noise, the standard
deviation of the values over the pixel divided by √spp.
"""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd

pytest.importorskip("mitsuba", reason="Mitsuba 3 is an optional extra (pip install mitsuba)")
from mitsuba_setup import mitsuba_variant  # noqa: E402

SIZE, SPP, GRID = 12, 64, 24


def _reference(model, light: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray]:
    """The mean and the standard deviation over each pixel of E f max(n·l, 0) (E = 1) on the
    unit sphere seen along −z, image row 0 at the top, by a GRID × GRID grid per pixel."""
    from roughdiffuse.stereo.mitsuba_render import MARGIN

    half = 1.0 + 2.0 * MARGIN
    u = (np.arange(size * GRID) + 0.5) / (size * GRID) * 2 * half - half
    x, y = np.meshgrid(u, -u)
    on = x * x + y * y < 1.0
    z = np.sqrt(np.clip(1.0 - x * x - y * y, 0.0, None))
    mu_i = x * light[0] + y * light[1] + z * light[2]
    lit = on & (mu_i > 0)
    f = np.zeros_like(x)
    f[lit] = np.asarray(model.brdf_cosines(mu_i[lit], z[lit], np.full(lit.sum(), light[2])))
    value = (f * np.where(lit, mu_i, 0.0)).reshape(size, GRID, size, GRID)
    return value.mean(axis=(1, 3)), value.std(axis=(1, 3))


@pytest.mark.slow
def test_coated_render_holds_the_coated_model():
    from roughdiffuse.stereo.mitsuba_render import MATERIALS, render_mitsuba

    mitsuba_variant("llvm_ad_rgb")
    spec = dict(MATERIALS["coat03"])
    truth = rd.Coated(rd.OrenNayar(0.6, 0.4, "full"), 1.5, 0.3)  # the script's coat03
    assert spec["type"] == "roughdiffuse_coated" and spec["sigma"] == 0.4
    lights = np.array([[0.0, 0.0, 1.0], [0.5, 0.3, 0.81], [-0.6, 0.2, 0.77]])
    lights /= np.linalg.norm(lights, axis=1, keepdims=True)
    data, _ = render_mitsuba(spec, lights, shape="sphere", size=SIZE, spp=SPP, seed=4)
    inside = data.mask
    assert inside.sum() > 50
    for k, light in enumerate(lights):
        mean, spread = _reference(truth, light, SIZE)
        got = data.images[k, ..., 0]
        noise = spread / np.sqrt(SPP)
        # within 4 noise standard deviations, and float32's rounding where the pixel is even
        err = np.abs(got - mean)[inside]
        assert np.all(err <= 4.0 * noise[inside] + 1e-5 * mean[inside] + 1e-6), (
            k, float(np.max(err / (noise[inside] + 1e-9))))
