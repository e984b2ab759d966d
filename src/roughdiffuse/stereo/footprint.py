"""How far the surface turns across a pixel, and the pixels that turn least.

A camera's pixel integrates the surface over its footprint: its value is the mean of the
reflectance over the normals it spans, not the reflectance at their mean. Where the normals
spread by a fair part of a lobe's width (a narrow coat's highlight; the full Oren–Nayar
model near grazing), the difference biases the values fitted for the whole object: the
footprint broadens a highlight (α up, σ with it) and flattens the shading near the limb. The
stereo fits draw those values from the pixels whose normals turn least
(:func:`smoothest`), measured by :func:`normal_spread`.
"""

from __future__ import annotations

import math

import numpy as np

from .depth import neighbour_pairs

__all__ = ["normal_spread", "smoothest"]


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
