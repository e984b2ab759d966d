"""How far the surface turns across a pixel, and the pixels that turn least.

A camera's pixel integrates the surface over its footprint: its value is the mean of the
reflectance over the normals it spans, not the reflectance at their mean. Where the normals
spread by a fair part of a lobe's width (a narrow coat's highlight; the full Oren–Nayar
model near grazing), the difference biases the values fitted for the whole object: the
footprint broadens a highlight (α up, σ with it) and flattens the shading near the limb. The
stereo fits draw those values from the pixels whose normals turn least
(:func:`smoothest`), measured by :func:`normal_spread` (the coated fit: a highlight's
footprint error follows the spread over its width α, at any view) or by :func:`view_spread`
(the rough fit: a matte pixel's follows the spread and the view's angle).
"""

from __future__ import annotations

import math

import numpy as np

from .depth import neighbour_pairs

__all__ = ["VIEW_FLOOR", "normal_spread", "smoothest", "view_spread"]

VIEW_FLOOR = 0.05
"""The least n·v :func:`view_spread` divides by (87° from the view)."""


def normal_spread(mask: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """The largest angle (radians) between each object pixel's normal and those of its four
    neighbours in the mask (P,): how far the surface turns across one pixel. 0 for a pixel
    without a neighbour; NaN normals count as no neighbour.

    Parameters
    ----------
    mask : array (H, W) bool
        The object's pixels.
    normals : array (P, 3)
        Unit normals of the object pixels, in mask order.
    """
    _, _, lo, hi, count = neighbour_pairs(mask)
    n = np.asarray(normals, dtype=np.float64)
    cos = np.clip(np.sum(n[lo] * n[hi], axis=1), -1.0, 1.0)
    angle = np.nan_to_num(np.arccos(cos), nan=0.0)
    out = np.zeros(count)
    np.maximum.at(out, lo, angle)
    np.maximum.at(out, hi, angle)
    return out


def smoothest(spread: np.ndarray, pool: np.ndarray, fraction: float, at_least: int = 0
              ) -> np.ndarray:
    """The pixels of ``pool`` (indices) whose ``spread`` is least: ``fraction`` of them, and
    at least ``at_least`` (all of them when the pool is smaller), with every pixel tied with
    the last one (pixels without neighbours, all of spread 0, are all kept); sorted."""
    keep = max(at_least, math.ceil(fraction * pool.size))
    if keep >= pool.size:
        return np.sort(pool)
    values = spread[pool]
    bound = np.partition(values, keep - 1)[keep - 1]
    return np.sort(pool[values <= bound])


def view_spread(mask: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """:func:`normal_spread` over n·v (v the camera's axis, +z; at least :data:`VIEW_FLOOR`):
    the footprint's error in a matte pixel's value grows with the normals' spread and with
    the shading's curvature in the normal, which rises towards grazing view (the full
    Oren–Nayar model's tan β, β ≤ θr). The matte blob render of
    ``scripts/stereo_renders.py`` at 128² (σ 0.4), σ of the rough fit from the ¾ of the
    pixels that rank lowest: 0.3985 ± 0.0004 by the spread, 0.3997 ± 0.0004 by this; at
    512², where the footprint's error is 16 times smaller, 0.39995 ± 0.00007 from every
    pixel."""
    n = np.asarray(normals, dtype=np.float64)
    return normal_spread(mask, n) / np.maximum(np.nan_to_num(n[:, 2]), VIEW_FLOOR)
