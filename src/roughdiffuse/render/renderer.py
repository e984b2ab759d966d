"""The image loop: rays from an orthographic camera, shapes, distant lights, a model.

For every pixel sample: find the surface point the camera ray hits and its normal n; for every
light l with irradiance E0, the radiance is L = f_r(l, v) E0 max(n·l, 0) V, where f_r is the
model's own :meth:`~roughdiffuse.models.base.Model.brdf_cosines` on (n·l, n·v, l·v) and V is 0
where the light's ray meets the surface again (a cast shadow) and 1 elsewhere. The lecture's
L = ρ/π I n·s is this with f_r = ρ/π. The attached shadow (n·l ≤ 0) comes from the cosine and
from the model, which is 0 below the horizon.

The whole loop is one ``jax.jit``-compiled function of the model (a JAX pytree), compiled
once per shape, image size, sample count and light count. A large image (many pixels times
many samples) is rendered in bands of rows, :data:`BAND_RAYS` rays each, by the same compiled
function, with a progress bar (:mod:`roughdiffuse.progress`) counting the bands.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from functools import partial
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from .._validate import ParameterError
from ..models.base import Model
from .camera import DistantLight, OrthographicCamera
from .shapes import Shape

__all__ = ["pixel_coordinates", "render"]

MAX_SIZE = 8192
"""Largest image side accepted."""

CHUNK = 1 << 14
"""Rays shaded together (one ``jax.lax.map`` step): large enough to amortise the loop,
small enough for the working set of a surface of revolution to stay in cache."""

BAND_RAYS = 1 << 21
"""Rays in one band of image rows (a band is at least one row): an image with more is
rendered band by band, each band a step of the progress bar, and holds only one band's
samples in memory at a time."""


def _check_size(size: int | Sequence[int]) -> tuple[int, int]:
    dims = (size, size) if isinstance(size, int | np.integer) else tuple(size)
    if len(dims) != 2 or not all(
        isinstance(s, int | np.integer) and 1 <= s <= MAX_SIZE for s in dims
    ):
        raise ParameterError(
            f"size must be an integer or (height, width) in [1, {MAX_SIZE}] (got {size!r})"
        )
    return int(dims[0]), int(dims[1])


def _check_spp(spp: int) -> int:
    k = math.isqrt(spp) if isinstance(spp, int) and spp > 0 else 0
    if not (isinstance(spp, int) and 1 <= spp <= 256 and k * k == spp):
        raise ParameterError(
            f"samples_per_pixel must be a square number in [1, 256]: 1, 4, 9, 16, ... (got {spp!r})"
        )
    return k


def _with_shape_albedo(model: Model, shape: Shape) -> Model:
    albedo = getattr(shape, "albedo", None)
    if albedo is None:
        return model
    names = {f.name for f in dataclasses.fields(model)} if dataclasses.is_dataclass(model) else ()
    if "albedo" in names:
        return dataclasses.replace(model, albedo=albedo)
    return model


@partial(jax.jit, static_argnames=("shape", "height", "rows", "width", "k", "shadows"))
def _render(
    model: Model,
    light_dirs: Any,
    light_e0: Any,
    basis: Any,
    centre: Any,
    pixel: Any,
    row0: Any,
    *,
    shape: Shape,
    height: int,
    rows: int,
    width: int,
    k: int,
    shadows: bool,
) -> tuple[Any, Any]:
    """Image rows ``row0`` to ``row0 + rows - 1`` of an image ``height`` rows high."""
    right, up, view = basis[0], basis[1], basis[2]
    # stratified k x k samples per pixel; image row 0 is the top
    sub = (jnp.arange(k, dtype=jnp.float32) + 0.5) / k
    cols = jnp.arange(width, dtype=jnp.float32)[None, :, None, None] + sub[None, None, None, :]
    first = jnp.asarray(row0, jnp.float32)
    band = first + jnp.arange(rows, dtype=jnp.float32)
    ys = band[:, None, None, None] + sub[None, None, :, None]
    a = (cols - 0.5 * width) * pixel  # along "right"
    b = (0.5 * height - ys) * pixel  # along "up"
    a, b = (x.reshape(-1) for x in jnp.broadcast_arrays(a, b))  # (H W k k,)
    d = (-view[0], -view[1], -view[2])

    def shade(ab: tuple[Any, Any]) -> tuple[Any, Any]:
        a, b = ab
        o = tuple(centre[c] + a * right[c] + b * up[c] for c in range(3))
        t, hit, n = shape.intersect(o, d)
        t = jnp.where(hit, t, 0.0)
        p = tuple(o[c] + t * d[c] for c in range(3))
        mu_o = n[0] * view[0] + n[1] * view[1] + n[2] * view[2]
        total = None
        for j in range(light_dirs.shape[0]):
            lt = light_dirs[j]
            mu_i = n[0] * lt[0] + n[1] * lt[1] + n[2] * lt[2]
            cos_io = jnp.full_like(mu_i, lt[0] * view[0] + lt[1] * view[1] + lt[2] * view[2])
            f = model.brdf_cosines(mu_i, mu_o, cos_io)
            weight = jnp.where(hit, jnp.maximum(mu_i, 0.0), 0.0)
            if shadows and not shape.convex:
                lit = ~shape.occluded(p, (lt[0], lt[1], lt[2]), 1e-4 * shape.scale)
                weight = jnp.where(lit, weight, 0.0)
            e0 = light_e0[j]
            if f.ndim > weight.ndim:
                weight = weight[..., None]
            elif e0.ndim:
                f, weight = f[..., None], weight[..., None]
            term = f * e0 * weight
            total = term if total is None else total + term
        return total, hit

    # chunks of rays, so that the per-piece loops of a surface of revolution run in cache
    n_rays = a.shape[0]
    chunk = min(CHUNK, n_rays)
    pad = (-n_rays) % chunk
    if pad:
        a, b = jnp.pad(a, (0, pad)), jnp.pad(b, (0, pad))
    total, hit = jax.lax.map(shade, (a.reshape(-1, chunk), b.reshape(-1, chunk)))
    total = total.reshape(-1, *total.shape[2:])[:n_rays]
    hit = hit.reshape(-1)[:n_rays]
    image = jnp.mean(total.reshape(rows, width, k * k, *total.shape[1:]), axis=2)
    mask = jnp.mean(hit.reshape(rows, width, k * k).astype(jnp.float32), axis=2)
    return image.astype(jnp.float32), mask


def pixel_coordinates(
    shape: Shape,
    camera: OrthographicCamera | None = None,
    size: int | tuple[int, int] = 256,
) -> tuple[np.ndarray, np.ndarray]:
    """World coordinates of the pixel centres along the image's right and up axes.

    Returns
    -------
    x : array (W,)
        Coordinate along the camera's "right" axis of each column's centre.
    y : array (H,)
        Coordinate along the camera's "up" axis of each row's centre (row 0 at the top).
    """
    height, width = _check_size(size)
    camera = OrthographicCamera() if camera is None else camera
    centre, pixel = camera.frame(shape, height, width)
    right, up, _ = camera.basis()
    x = float(centre @ right) + (np.arange(width) + 0.5 - 0.5 * width) * pixel
    y = float(centre @ up) + (0.5 * height - np.arange(height) - 0.5) * pixel
    return x, y


def render(
    model: Model,
    shape: Shape,
    light: DistantLight | Sequence[DistantLight] | None = None,
    camera: OrthographicCamera | None = None,
    size: int | tuple[int, int] = 256,
    *,
    samples_per_pixel: int = 4,
    shadows: bool = True,
    progress: bool | None = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Render ``shape`` made of ``model`` under distant light(s), seen by an orthographic camera.

    Parameters
    ----------
    model : Model
        Any reflectance model (its :meth:`brdf_cosines` is evaluated, under ``jax.jit``).
    shape : Shape
        :class:`Sphere`, :class:`Cylinder`, :class:`SurfaceOfRevolution`, :class:`Plane` or
        :class:`Moon` (whose albedo replaces the model's ``albedo``).
    light : DistantLight or sequence of them
        Default: one light of irradiance 1 behind the viewer (θ = 0). Several lights add.
    camera : OrthographicCamera
        Default: looking along −z (θ = 0); the shape fills the frame.
    size : int or (height, width)
        Image size in pixels.
    samples_per_pixel : int
        A square number (1, 4, 9, ...): k × k stratified samples per pixel, averaged.
    shadows : bool
        Cast shadows on non-convex shapes (attached shadows are always there).
    progress : bool or None
        A progress bar on standard error counting the bands of rows of an image of more than
        :data:`BAND_RAYS` rays (pixels × samples); None: only when standard error is a
        terminal (:func:`roughdiffuse.progress.progress_enabled`). Default False.

    Returns
    -------
    image : float32 array (H, W) or (H, W, C)
        Linear radiance (W m⁻² sr⁻¹ per unit E0), averaged over the pixel's samples with 0
        for samples that miss the shape (so silhouette pixels are partly covered).
    mask : float32 array (H, W)
        Coverage: the fraction of the pixel's samples that hit the shape (1 inside, 0 outside).

    Examples
    --------
    >>> from roughdiffuse import Lambert
    >>> from roughdiffuse.render import Sphere
    >>> img, mask = render(Lambert(1.0), Sphere(), size=33, samples_per_pixel=1)
    >>> round(float(img[16, 16]) * 3.141592653589793, 5)  # ρ/π E0 n·l at the centre
    1.0
    """
    if not isinstance(model, Model):
        raise ParameterError(f"model must be a roughdiffuse Model (got {type(model).__name__})")
    if not isinstance(shape, Shape):
        raise ParameterError(
            f"shape must be a roughdiffuse.render Shape (got {type(shape).__name__})"
        )
    height, width = _check_size(size)
    k = _check_spp(samples_per_pixel)
    lights = [DistantLight()] if light is None else light
    if isinstance(lights, DistantLight):
        lights = [lights]
    lights = list(lights)
    if not lights or not all(isinstance(x, DistantLight) for x in lights):
        raise ParameterError("light must be a DistantLight or a non-empty sequence of them")
    camera = OrthographicCamera() if camera is None else camera
    if not isinstance(camera, OrthographicCamera):
        raise ParameterError(f"camera must be an OrthographicCamera (got {type(camera).__name__})")
    model = _with_shape_albedo(model, shape)
    e0 = [np.asarray(x.irradiance, dtype=np.float32) for x in lights]
    channels = {int(x.size) for x in e0 if x.ndim} | ({model.channels} if model.channels else set())
    if len(channels) > 1:
        raise ParameterError(
            f"model and lights disagree on the number of colour channels {channels}"
        )
    if channels and any(x.ndim == 0 for x in e0):
        c = channels.pop()
        e0 = [np.broadcast_to(x, (c,)) if x.ndim == 0 else x for x in e0]
    centre, pixel = camera.frame(shape, height, width)
    band = partial(
        _render,
        model,
        jnp.asarray(np.stack([x.direction for x in lights]), jnp.float32),
        jnp.asarray(np.stack(e0)),
        jnp.asarray(np.stack(camera.basis()), jnp.float32),
        jnp.asarray(centre, jnp.float32),
        jnp.float32(pixel),
        shape=shape,
        height=height,
        width=width,
        k=k,
        shadows=bool(shadows),
    )
    return _in_bands(band, height, width * k * k, progress)


def _in_bands(
    band: Any, height: int, rays_per_row: int, progress: bool | None
) -> tuple[np.ndarray, np.ndarray]:
    """The image and mask, rendered by ``band(row0, rows=...)`` in bands of at most
    :data:`BAND_RAYS` rays (at least one row), all bands as high (one compilation; the last
    one's rows past the image are dropped); a progress bar counts the bands."""
    from ..progress import progress as bar_of

    rows = max(1, min(height, BAND_RAYS // rays_per_row))
    starts = range(0, height, rows)
    images, masks = [], []
    enabled = False if len(starts) == 1 or progress is False else progress
    with bar_of(len(starts), "render", unit="band", enabled=enabled) as bar:
        for row0 in starts:
            image, mask = band(jnp.int32(row0), rows=rows)
            images.append(np.asarray(image))  # waits for the band: the bar counts work done
            masks.append(np.asarray(mask))
            bar.update(1)
    return np.concatenate(images)[:height], np.concatenate(masks)[:height]
