"""Lambertian photometric stereo: the linear least-squares baseline.

Woodham, "Photometric method for determining surface orientation from multiple images",
Optical Engineering 19(1), 1980. For a Lambertian pixel of albedo ρ and normal n, the image
under a distant light l_k of irradiance E_k is I_k = (ρ/π) E_k max(n·l_k, 0) (the lecture's
L = ρ/π E0 n·s). Where the light is in front (n·l_k > 0), I_k / E_k = l_k · b is linear in
b = (ρ/π) n, so b is the least-squares solution over the observations kept, ρ = π |b| and
n = b / |b|. Shadowed and saturated observations are left out (see :func:`observation_weights`).
"""

from __future__ import annotations

import numpy as np

from .._validate import ParameterError
from .inputs import StereoInput

__all__ = [
    "LambertianResult",
    "albedo_and_residual",
    "lambertian",
    "lambertian_normals",
    "observation_weights",
]

CHUNK = 8192
"""Pixels per block of :func:`albedo_and_residual`: its (K, block, C) temporaries stay in
the cache (96 lights: 6 MB) instead of taking a gigabyte at a megapixel."""


def observation_weights(data: StereoInput, shadow: float = 0.02) -> np.ndarray:
    """0/1 weights (K, P) of the observations kept, for the P object pixels.

    An observation is left out when it is invalid (saturated, not finite) or dark: below
    ``shadow`` times the pixel's brightest observation, after dividing by each light's
    irradiance. Dark values are attached or cast shadows, where I = 0 carries no linear
    information on n, and where a cast shadow is not modelled at all.
    """
    if not 0.0 <= shadow < 1.0:
        raise ParameterError(f"shadow must be in [0, 1) (got {shadow:g})")
    grey = data.grey  # (K, P)
    top = grey.max(axis=0, keepdims=True)
    keep = data.observed & (grey > shadow * top) & (grey > 0)
    return keep.astype(np.float64)


class LambertianResult:
    """Per-pixel results of Lambertian photometric stereo.

    Attributes
    ----------
    normals : array (P, 3)
        Unit normals of the P object pixels (NaN where fewer than 3 observations were kept).
    albedo : array (P, C)
        ρ per channel.
    residual : array (P,)
        RMS of the residuals over the kept observations, relative to the pixel's mean value.
    weights : array (K, P)
        Observations used.
    """

    def __init__(
        self, normals: np.ndarray, albedo: np.ndarray, residual: np.ndarray, weights: np.ndarray
    ) -> None:
        self.normals = normals
        self.albedo = albedo
        self.residual = residual
        self.weights = weights


def lambertian(
    data: StereoInput, *, shadow: float = 0.02, weights: np.ndarray | None = None
) -> LambertianResult:
    """Lambertian photometric stereo on every object pixel.

    Parameters
    ----------
    data : StereoInput
        Images, lights and mask.
    shadow : float
        Relative threshold below which an observation counts as shadowed.
    weights : array (K, P), optional
        0/1 weights of the observations to use, when already at hand (e.g.
        :func:`observation_weights` of ``shadow``, computed once for several solvers);
        ``shadow`` is then not used.

    Returns
    -------
    LambertianResult

    Examples
    --------
    Three lights, one pixel facing the camera with ρ = 0.5:

    >>> import numpy as np
    >>> from roughdiffuse.stereo import StereoInput
    >>> L = np.array([[0, 0, 1.0], [0.6, 0, 0.8], [0, 0.6, 0.8]])
    >>> imgs = (0.5 / np.pi * L[:, 2]).reshape(3, 1, 1)
    >>> r = lambertian(StereoInput.from_arrays(imgs, L))
    >>> bool(np.allclose(r.normals[0], [0, 0, 1])), round(float(r.albedo[0, 0]), 6)
    (True, 0.5)
    """
    if weights is None:
        w = observation_weights(data, shadow)  # (K, P)
    else:
        w = np.asarray(weights, dtype=np.float64)
        if w.shape != data.grey.shape:
            raise ParameterError(f"weights must have shape {data.grey.shape} (lights, object "
                                 f"pixels; got {w.shape})")
    return albedo_and_residual(data, lambertian_normals(data.grey, data.directions, w), w)


def lambertian_normals(grey: np.ndarray, directions: np.ndarray, weights: np.ndarray
                       ) -> np.ndarray:
    """The Lambertian normals (P, 3) of the values ``grey`` (K, P; I_k / E_k, e.g.
    :attr:`StereoInput.grey`, or any common multiple of it) under the lights ``directions``
    (K, 3), over the observations of weight 1 (``weights`` (K, P)): b = (ρ/π) n by the least
    squares of I_k / E_k = l_k · b (Woodham 1980), n = b / |b|; NaN where fewer than three
    observations are kept or they do not determine b."""
    w, l = weights, directions
    # weighted normal equations per pixel: (Σ w l lᵀ) b = Σ w l I (matrix products over k)
    a = (w.T @ (l[:, :, None] * l[:, None, :]).reshape(-1, 9)).reshape(-1, 3, 3)
    rhs = (w * grey).T @ l
    enough = w.sum(axis=0) >= 3
    det = np.linalg.det(a)
    ok = enough & (np.abs(det) > 1e-12)
    b = np.full((grey.shape[1], 3), np.nan)
    b[ok] = np.linalg.solve(a[ok], rhs[ok][..., None])[..., 0]
    length = np.linalg.norm(b, axis=-1)
    ok &= length > 0
    return np.where(ok[:, None], b / np.where(ok, length, 1.0)[:, None], np.nan)


def albedo_and_residual(
    data: StereoInput, normals: np.ndarray, weights: np.ndarray
) -> LambertianResult:
    """The Lambertian result of given normals: per-channel albedo and relative residual.

    The albedo of channel c is the least-squares solution of I_c / E_c = (ρ_c/π) max(n·l, 0)
    over the observations of weight 1 (Woodham 1980); the residual is the RMS misfit over
    them, relative to the pixel's mean kept value. Pixels with a NaN normal stay NaN.

    Parameters
    ----------
    data : StereoInput
        Images, lights and mask.
    normals : array (P, 3)
        Unit normals of the object pixels (NaN: none).
    weights : array (K, P)
        0/1 weights of the observations kept.
    """
    w = weights
    obs, e = data.observations, data.intensities[:, None, :]
    l = data.directions  # (K, 3)
    ok = np.all(np.isfinite(normals), axis=-1)
    p_count, c = obs.shape[1], obs.shape[2]
    albedo = np.full((p_count, c), np.nan)
    resid, scale = np.zeros(p_count), np.ones(p_count)
    for lo in range(0, p_count, CHUNK):  # a block of pixels at a time: temporaries in cache
        part = slice(lo, lo + CHUNK)
        vals = obs[:, part] / e  # (K, B, C)
        wp = w[:, part]
        shading = np.maximum(l @ np.nan_to_num(normals[part]).T, 0.0) / np.pi  # (K, B)
        ws = wp * shading
        num = np.einsum("kp,kpc->pc", ws, vals)
        den = np.einsum("kp,kp->p", ws, shading)
        albedo[part] = np.where(ok[part, None] & (den[:, None] > 0),
                                num / np.where(den > 0, den, 1.0)[:, None], np.nan)
        miss = shading[..., None] * np.nan_to_num(albedo[part])[None]
        miss -= vals
        miss *= miss
        kept = wp.sum(axis=0)
        resid[part] = np.sqrt(np.einsum("kp,kpc->p", wp, miss) / np.maximum(kept * c, 1))
        scale[part] = np.maximum(
            np.einsum("kp,kp->p", wp, data.grey[:, part]) / np.maximum(kept, 1), 1e-30)
    return LambertianResult(normals, albedo, np.where(ok, resid / scale, np.nan), w)
