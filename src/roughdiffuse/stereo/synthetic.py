"""Synthetic photometric-stereo data from roughdiffuse's renderer, with known truth.

Used by the tests, the benchmark and the documentation: a shape rendered once per light by
:func:`roughdiffuse.render.render` (exact ray intersection, cast shadows), and the true
normals of its pixels from :func:`roughdiffuse.fit.images.shape_normals`.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..models.base import Model
from .inputs import StereoInput

__all__ = ["angular_error", "default_lights", "render_stereo", "synthetic_sphere"]


def default_lights(count: int = 8, elevation_deg: float = 35.0) -> np.ndarray:
    """``count`` unit directions on a cone around the view axis (+z), ``elevation_deg``
    from it, evenly spread in azimuth: the ring of lights of typical capture domes."""
    if count < 3:
        raise ParameterError(f"count must be at least 3 (got {count})")
    t = math.radians(elevation_deg)
    phi = 2 * np.pi * (np.arange(count) + 0.5) / count
    return np.stack(
        [np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi), np.full(count, np.cos(t))], 1
    )


def render_stereo(
    model: Model,
    shape: Any,
    directions: np.ndarray,
    size: int = 64,
    *,
    noise: float = 0.0,
    seed: int = 0,
    samples_per_pixel: int = 1,
) -> tuple[StereoInput, np.ndarray]:
    """Render ``shape`` under each light in turn; return the input and the true normals.

    ``noise`` is the standard deviation of additive Gaussian noise relative to the brightest
    pixel of all images (1% is ``noise=0.01``).
    """
    from ..fit.images import shape_normals
    from ..render import DistantLight, render

    imgs = []
    for d in directions:
        theta = math.acos(float(np.clip(d[2], -1, 1)))
        phi = math.atan2(float(d[1]), float(d[0]))
        img, _ = render(
            model, shape, DistantLight(theta, phi), size=size, samples_per_pixel=samples_per_pixel
        )
        imgs.append(np.asarray(img, dtype=np.float64))
    images = np.stack(imgs)
    normals, mask = shape_normals(shape, size)
    if noise > 0:
        rng = np.random.default_rng(seed)
        images = np.maximum(images + rng.normal(0.0, noise * images.max(), images.shape), 0.0)
    # pixels whose normal faces the camera within 80° (silhouette pixels are partly covered)
    mask = mask & (normals[..., 2] > math.cos(math.radians(80.0)))
    return StereoInput.from_arrays(images, directions, 1.0, mask=mask), normals


def synthetic_sphere(
    model: Model, size: int = 64, *, lights: int = 8, noise: float = 0.01, seed: int = 0
) -> StereoInput:
    """A sphere of ``model`` under ``lights`` lights on a 35° ring (see :func:`render_stereo`)."""
    from ..render import Sphere

    data, _ = render_stereo(model, Sphere(), default_lights(lights), size, noise=noise, seed=seed)
    return data


def angular_error(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Angle in degrees between unit vectors ``a`` and ``b`` (..., 3)."""
    c = np.clip(np.sum(np.asarray(a) * np.asarray(b), axis=-1), -1.0, 1.0)
    return np.degrees(np.arccos(c))
