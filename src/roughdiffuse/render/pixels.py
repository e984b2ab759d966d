"""The geometry each pixel of a render sees: cosines for BRDFs that are not array-API code.

:func:`~roughdiffuse.render.render` evaluates a model's ``brdf_cosines`` inside ``jax.jit``.
A reflectance known only by Monte Carlo (the layered walk, :mod:`roughdiffuse.simulate`)
cannot run there; :func:`pixel_cosines` gives the same geometry instead -- the ray through
each pixel's centre (one sample per pixel, as ``samples_per_pixel=1``), its hit, the local
cosines and the cast shadows -- so that the caller evaluates any BRDF on it and forms the
image as :func:`~roughdiffuse.render.render` does: L = f E0 max(μi, 0) where lit.
"""

from __future__ import annotations

from functools import partial
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from .camera import DistantLight, OrthographicCamera
from .renderer import pixel_coordinates
from .shapes import Shape

__all__ = ["PixelCosines", "pixel_cosines"]


@partial(jax.jit, static_argnames=("shape", "d", "light"))
def _trace(shape: Shape, o: tuple, d: tuple, light: tuple) -> tuple:
    """Hit, normal and cast shadow of the rays ``o + t d`` (compiled, as the renderer)."""
    t, hit, n = shape.intersect(o, d)
    t = jnp.where(hit, t, 0.0)
    shadow = jnp.zeros_like(hit)
    if not shape.convex:
        p = tuple(o[c] + t * d[c] for c in range(3))
        shadow = shape.occluded(p, light, 1e-4 * shape.scale)
    return hit, n, shadow


class PixelCosines(NamedTuple):
    """Per pixel (H, W): n·l, n·v, l·v, whether the surface is hit, and whether it is lit
    (hit, facing the light and the viewer, not in a cast shadow)."""

    mu_i: np.ndarray
    mu_o: np.ndarray
    cos_io: np.ndarray
    hit: np.ndarray
    lit: np.ndarray


def pixel_cosines(shape: Shape, light: DistantLight, camera: OrthographicCamera | None = None,
                  size: int | tuple[int, int] = 256) -> PixelCosines:
    """The local cosines at each pixel centre of a render of ``shape`` under ``light``.

    Examples
    --------
    >>> from roughdiffuse.render import Sphere, DistantLight
    >>> g = pixel_cosines(Sphere(), DistantLight(0.0), size=33)
    >>> float(g.mu_i[16, 16]), float(g.mu_o[16, 16]), bool(g.lit[16, 16])
    (1.0, 1.0, True)
    """
    camera = OrthographicCamera() if camera is None else camera
    x, y = pixel_coordinates(shape, camera, size)
    right, up, view = camera.basis()
    xx, yy = np.meshgrid(x, y)
    o = tuple(jnp.asarray(xx * right[c] + yy * up[c], jnp.float32) for c in range(3))
    d = tuple(float(-view[c]) for c in range(3))
    lt = light.direction
    hit, n, shadow = _trace(shape, o, d, tuple(float(v) for v in lt))
    hit, shadow = np.asarray(hit, dtype=bool), np.asarray(shadow, dtype=bool)
    n = tuple(np.asarray(x, dtype=np.float64) for x in n)
    mu_i = n[0] * lt[0] + n[1] * lt[1] + n[2] * lt[2]
    mu_o = n[0] * view[0] + n[1] * view[1] + n[2] * view[2]
    cos_io = np.full_like(mu_i, float(lt @ view))
    lit = hit & (mu_i > 0) & (mu_o > 0) & ~shadow
    return PixelCosines(mu_i, mu_o, cos_io, hit, lit)
