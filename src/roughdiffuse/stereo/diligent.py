"""Synthetic data in the layout of the DiLiGenT benchmark: its light pattern and its folders.

DiLiGenT (Shi, Wu, Tan, Yeung, Ikeuchi, Matsushita, "A Benchmark Dataset and Evaluation
Method for Non-Lambertian and Uncalibrated Photometric Stereo", CVPR 2016) lights each object
by 96 LEDs on a frame in front of it, about 12 × 8 of them, within roughly 40° of the view
axis. :func:`diligent_lights` approximates that pattern (the real directions are calibrated
per object and ship with the data; these are not them). :func:`write_diligent` writes images
in its folder layout, which :func:`roughdiffuse.stereo.read_diligent` reads:
``filenames.txt``, one 16-bit PNG per light, ``light_directions.txt``,
``light_intensities.txt``, ``mask.png`` and ``Normal_gt.mat`` (the true normals, (H, W, 3),
camera frame as :mod:`.inputs`).
"""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np

from .._validate import ParameterError
from .inputs import StereoInput

__all__ = ["diligent_lights", "write_diligent"]


def diligent_lights(columns: int = 12, rows: int = 8) -> np.ndarray:
    """Unit directions (columns × rows, 3) of LEDs on a plane grid one unit in front of the
    object: x from −0.55 to 0.55, y from −0.45 to 0.50 (the frame sits a little high), the
    DiLiGenT pattern approximated (largest angle from the view axis about 37°). Row-major
    from the top row, left to right."""
    if columns < 2 or rows < 2:
        raise ParameterError(f"columns and rows must be at least 2 (got {columns}, {rows})")
    x = np.linspace(-0.55, 0.55, columns)
    y = np.linspace(0.50, -0.45, rows)
    gx, gy = np.meshgrid(x, y)
    d = np.stack([gx.ravel(), gy.ravel(), np.ones(gx.size)], axis=1)
    return d / np.linalg.norm(d, axis=1, keepdims=True)


def write_diligent(
    folder: str | os.PathLike[str],
    data: StereoInput,
    normals: np.ndarray,
    *,
    bits: int = 12,
    noise: float = 0.01,
    full_scale: float | None = None,
    seed: int = 0,
) -> Path:
    """Write ``data`` as a DiLiGenT object folder, with noise and quantisation of a camera.

    Each value gets Gaussian noise of standard deviation ``noise`` times the value (a camera's
    signal-dependent noise), is scaled so that ``full_scale`` (default: the 99.5th percentile
    of the object's values over all images) reads 90 % of the range, rounded to ``bits`` bits
    and clipped there (brighter values saturate: the reader marks them invalid), and stored
    in 16-bit PNGs (the ``bits``-bit code shifted up, as a 12-bit camera's 16-bit files).
    ``light_intensities.txt`` holds that scale (the images' irradiance 1 in PNG units), so the
    values read back are the radiance of the images, noise and rounding aside.

    Parameters
    ----------
    folder : path
        The object folder to create (e.g. ``pmsData/spherePNG``): absent or empty.
    data : StereoInput
        Grey images (C = 1) with lights, irradiance 1 each, and the mask.
    normals : array (H, W, 3)
        True normals.

    Returns
    -------
    Path of the folder.
    """
    from PIL import Image
    from scipy.io import savemat

    from ..io import atomic_folder

    if data.channels != 1:
        raise ParameterError(f"write_diligent writes grey images (got {data.channels} channels)")
    if not 8 <= bits <= 16:
        raise ParameterError(f"bits must be in [8, 16] (got {bits})")
    if normals.shape != data.mask.shape + (3,):
        raise ParameterError(f"normals must have shape {data.mask.shape + (3,)}")
    rng = np.random.default_rng(seed)
    imgs = data.images[..., 0]
    noisy = np.maximum(imgs * (1.0 + rng.normal(0.0, noise, imgs.shape)), 0.0)
    top = full_scale if full_scale is not None else float(np.percentile(imgs[:, data.mask], 99.5))
    levels = (1 << bits) - 1
    code = np.clip(np.rint(noisy / top * 0.9 * levels), 0, levels).astype(np.uint32)
    code16 = (code << (16 - bits)).astype(np.uint16)
    out = Path(folder)
    names = [f"{k + 1:03d}.png" for k in range(data.count)]
    with atomic_folder(out) as tmp:
        tmp = Path(tmp)
        for name, img in zip(names, code16, strict=True):
            Image.fromarray(img).save(tmp / name)
        (tmp / "filenames.txt").write_text("\n".join(names) + "\n", encoding="utf-8")
        np.savetxt(tmp / "light_directions.txt", data.directions, fmt="%.6f")
        # each light's irradiance in the PNGs' units (value / 65535): radiance 1 under
        # irradiance 1 reads 0.9 · levels / top codes, shifted up to 16 bits; a model that is
        # not linear in its albedo (a coat: its highlight against the base) needs this scale
        unit = 0.9 * levels / top * (1 << (16 - bits)) / 65535.0
        np.savetxt(tmp / "light_intensities.txt", np.full((data.count, 3), unit), fmt="%.8g")
        Image.fromarray((data.mask * 255).astype(np.uint8)).save(tmp / "mask.png")
        buf = io.BytesIO()
        savemat(buf, {"Normal_gt": np.where(data.mask[..., None], normals, 0.0)})
        (tmp / "Normal_gt.mat").write_bytes(buf.getvalue())
    return out
