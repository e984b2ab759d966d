"""Images as measurements: linear image files, normal maps, the renderer's known shapes.

An image of an object of known geometry under a distant light is a set of radiance samples
L = f_r E0 cos θi, one per pixel, at the pixel's normal n, the light direction l and the view
direction v (the lecture's L = ρ/π E0 n·s for Lambert). This module reads linear images
(``.npy``, OpenEXR, PNG with a stated exposure), normal maps (``.npy``, (H, W, 3)), and
computes the normals of the renderer's shapes (:mod:`roughdiffuse.render`) by the same exact
ray intersection the renderer uses, so that an image it rendered can be fitted.

PNG holds display values; the linear radiance is recovered as
L = decode(v / (2^bits − 1)) / 2^exposure, with decode the sRGB curve (IEC 61966-2-1) or the
identity. Files written by :func:`roughdiffuse.io.images.write_png` state their
encoding and scale in text chunks, which are used when present. Saturated pixels (v at its
maximum, :func:`_full_code`: 65520 for a 12-bit camera's codes shifted up in a 16-bit file)
and partly covered pixels (alpha below its maximum) are masked out.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..io.images import read_png, srgb_to_linear
from ..io.reading import MAX_IMAGE_BYTES, check_regular, image_array, load_npy, short
from .measurements import Measurements

__all__ = ["image_measurements", "read_image", "read_normals", "shape_normals"]


def _full_code(samples: np.ndarray, bits: int) -> int:
    """The code of a saturated sample of a PNG of ``bits`` bits whose samples are ``samples``
    (integers): 2^bits − 1, or with its low s bits cleared when every sample's low s bits
    are 0 (s ≤ bits / 2, the most such).

    A camera of fewer bits than the file (12 in a 16-bit PNG) stores its codes shifted up,
    the left-shift of the PNG specification's sample depth scaling (ISO/IEC 15948 §12.5):
    its full scale is then 4095 · 16 = 65520, not 65535. A file whose samples fill the low
    bits (left-bit replication, or a camera of the file's own depth) keeps 2^bits − 1.
    """
    top = (1 << bits) - 1
    lows = np.bitwise_or.reduce(np.asarray(samples, dtype=np.uint32).ravel() & 0xFF)
    shift = 0
    while shift < bits // 2 and not lows & (1 << shift) and lows:
        shift += 1
    return top & ~((1 << shift) - 1)


def _png_linear(
    path: str, exposure: float | None, encoding: str | None
) -> tuple[np.ndarray, np.ndarray]:
    pix, bits, text = read_png(path)
    name = os.path.basename(path)
    top = (1 << bits) - 1
    c = pix.shape[2]
    alpha = pix[..., -1] if c in (2, 4) else None
    color = pix[..., : 1 if c <= 2 else 3]
    mask = np.all(color < _full_code(color, bits), axis=-1)  # saturated pixels carry no value
    color = color.astype(np.float64)
    if alpha is not None:
        mask &= alpha == top
    v = color / top
    scale = None
    if exposure is not None:
        scale = 2.0**exposure
    elif "roughdiffuse:scale" in text:
        scale = float(text["roughdiffuse:scale"])
    if scale is None or not scale > 0:
        raise ParameterError(
            f"{name}: a PNG holds display values; state its exposure (stops, linear value = "
            "pixel / 2^exposure) for the linear radiance"
        )
    if encoding is None:
        encoding = "srgb" if "sRGB" in text.get("roughdiffuse:encoding", "sRGB") else "linear"
    if encoding == "srgb":
        lin = srgb_to_linear(v)
    elif encoding == "linear":
        lin = v
    else:
        raise ParameterError(f"encoding must be 'srgb' or 'linear' (got {encoding!r})")
    img = lin / scale
    return (img[..., 0] if img.shape[2] == 1 else img), mask


def read_image(
    path: str | os.PathLike[str],
    *,
    exposure: float | None = None,
    encoding: str | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Read a linear radiance image and the mask of its usable pixels.

    Parameters
    ----------
    path : path-like
        ``.npy`` (float, (H, W) or (H, W, 3)), ``.exr`` (OpenEXR), or ``.png`` (8 or 16 bit).
    exposure : float, optional
        PNG only: stops, linear = decoded / 2^exposure (default: the file's
        ``roughdiffuse:scale`` text chunk; an error if it has none).
    encoding : {"srgb", "linear"}, optional
        PNG only: the transfer curve (default: the file's statement, else sRGB).

    Returns
    -------
    image : float64 array (H, W) or (H, W, 3)
    mask : bool array (H, W)
        Pixels that hold a value (finite, not saturated, fully covered).
    """
    path = os.fspath(path)
    name = os.path.basename(path)
    ext = os.path.splitext(path)[1].lower()
    size = check_regular(path, "image file")
    if size > MAX_IMAGE_BYTES:
        raise ParameterError(
            f"image file {short(name)} has {size} bytes; at most {MAX_IMAGE_BYTES}"
        )
    if ext == ".npy":
        img = np.asarray(load_npy(path, "image file"), dtype=np.float64)
    elif ext == ".exr":
        import OpenEXR

        with OpenEXR.File(path) as f:
            ch = f.channels()
            if "RGB" in ch:
                img = np.asarray(ch["RGB"].pixels, dtype=np.float64)
            elif "Y" in ch:
                img = np.asarray(ch["Y"].pixels, dtype=np.float64)
            elif all(k in ch for k in "RGB"):
                img = np.stack([np.asarray(ch[k].pixels, np.float64) for k in "RGB"], axis=-1)
            else:
                raise ParameterError(f"{name}: no RGB or Y channels (has {', '.join(ch)})")
    elif ext == ".png":
        return _png_linear(path, exposure, encoding)
    else:
        raise ParameterError(f"image file must end in .npy, .exr or .png (got {name!r})")
    img = image_array(img, f"image {short(name)}")  # the one shape rule (bands first too)
    finite = np.isfinite(img) if img.ndim == 2 else np.all(np.isfinite(img), axis=-1)
    img = np.where(np.isfinite(img), img, 0.0)
    if np.any(img < 0):
        raise ParameterError(f"{name}: negative radiance in {int(np.sum(img < 0))} entries")
    return img, finite


def read_normals(path: str | os.PathLike[str]) -> np.ndarray:
    """A normal map: ``.npy`` of shape (H, W, 3), unit normals, zero vectors for background."""
    path = os.fspath(path)
    if not path.lower().endswith(".npy"):
        raise ParameterError(f"normal map must be a .npy file of shape (H, W, 3) (got {path!r})")
    n = np.asarray(load_npy(path, "normal map"), dtype=np.float64)
    n = image_array(n, f"normal map {short(os.path.basename(path))}", channels=(3,))
    if n.ndim != 3:
        raise ParameterError(f"normal map must have shape (H, W, 3) (got {n.shape})")
    length = np.linalg.norm(n, axis=-1)
    bad = (length > 0) & (np.abs(length - 1) > 1e-3)
    if np.any(bad) or not np.all(np.isfinite(n)):
        raise ParameterError("normal map must hold unit vectors (or zero vectors for background)")
    return n


def shape_normals(
    shape: Any, size: int | tuple[int, int], light: Any = None, camera: Any = None
) -> tuple[np.ndarray, np.ndarray]:
    """Normals of a renderer shape at the pixel centres, and the pixels lit and seen.

    Rays through the pixel centres, as :func:`roughdiffuse.render.render` casts them with
    ``samples_per_pixel=1``, intersect ``shape`` exactly; with a ``light``
    (:class:`~roughdiffuse.render.DistantLight`), pixels in a cast shadow are masked out.

    Returns
    -------
    normals : array (H, W, 3)
        World-frame unit normals (zero where the ray misses the shape).
    mask : bool array (H, W)
        Pixels on the shape (and not in a cast shadow of ``light``).
    """
    import jax.numpy as jnp

    from ..render import OrthographicCamera, pixel_coordinates

    camera = OrthographicCamera() if camera is None else camera
    x, y = pixel_coordinates(shape, camera, size)
    right, up, view = camera.basis()
    xx, yy = np.meshgrid(x, y)
    o = tuple(jnp.asarray(xx * right[c] + yy * up[c]) for c in range(3))
    d = tuple(float(-view[c]) for c in range(3))
    t, hit, n = shape.intersect(o, d)
    hit = np.asarray(hit)
    normals = np.stack([np.asarray(c, dtype=np.float64) for c in n], axis=-1)
    normals /= np.maximum(np.linalg.norm(normals, axis=-1, keepdims=True), 1e-30)
    normals = np.where(hit[..., None], normals, 0.0)
    mask = hit.copy()
    if light is not None and not shape.convex:
        tt = jnp.where(hit, t, 0.0)
        p = tuple(o[c] + tt * d[c] for c in range(3))
        ld = tuple(float(v) for v in light.direction)
        mask &= ~np.asarray(shape.occluded(p, ld, 1e-4 * shape.scale))
    return normals, mask


def image_measurements(
    image: Any,
    normals: Any,
    light: Any,
    view: Any = (0.0, 0.0, 1.0),
    *,
    irradiance: Any = 1.0,
    mask: Any = None,
    erode: int = 1,
    source: str = "image",
) -> Measurements:
    """Pixels of a linear image as :class:`Measurements` (see
    :meth:`Measurements.from_image`); ``light`` and ``view`` are unit vectors (or a
    :class:`~roughdiffuse.render.DistantLight`, whose irradiance is then used)."""
    if hasattr(light, "direction") and hasattr(light, "irradiance"):
        irradiance = light.irradiance
        light = light.direction
    if not isinstance(view, np.ndarray) and hasattr(view, "basis"):  # OrthographicCamera
        view = view.view
    l = np.asarray(light, dtype=np.float64)
    v = np.asarray(view, dtype=np.float64)
    for nm, a in (("light", l), ("view", v)):
        if a.shape != (3,) or not math.isclose(float(np.linalg.norm(a)), 1.0, rel_tol=1e-6):
            raise ParameterError(f"{nm} must be a unit 3-vector (got {a})")
    return Measurements.from_image(
        image, normals, l, v, irradiance=irradiance, mask=mask, erode=erode, source=source
    )
