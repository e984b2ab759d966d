"""Explicit random Gaussian heightfields of Lambertian triangles, rendered by Mitsuba 3.

The arbiter between the V-cavity and Smith ground truths: real geometry, which neither
assumes. Mitsuba 3 is an optional dependency (``pip install roughdiffuse[mitsuba]``); the
module imports it only inside :func:`render_heightfield` and :func:`heightfield_brdf`.

The surface (:func:`gaussian_heightfield`): heights h(x, y) on a periodic n × n grid of
spacing dx, a stationary Gaussian process with Gaussian correlation
C(r) = σh² exp(−r²/ℓ²) (Beckmann & Spizzichino 1963, ch. 5; spectral synthesis: white noise
filtered by √(FFT of C)). Its slopes are Gaussian with variance 2σh²/ℓ² per axis, so a
Gaussian heightfield *is* a Beckmann surface of α² = 4σh²/ℓ² (E[tan²θm] = α², Walter et al.
2007 eq. 25), with correlated heights where Smith assumes none. The triangle mesh
(:func:`heightfield_mesh`, cell diagonals alternating in a checkerboard so that no diagonal
direction is preferred) has finite-difference slopes; the heights are scaled so that the mean
of tan²θm over the triangles of each realisation is exactly α².

The render (:func:`render_heightfield`): the tile repeated ``tiles`` × ``tiles`` times
(periodic: no edges within reach of the central tile), Lambertian ``diffuse`` triangles with
face normals, a ``directional`` emitter of unit irradiance along −ωi, an ``orthographic``
camera along −ωo whose film covers exactly the projection of the central tile (so the image
mean is the average over one period of the surface, weighted by projected area), and the
``path`` integrator with ``max_depth`` = bounces + 1. The image mean divided by cos θi is the
BRDF; :func:`heightfield_brdf` averages independent realisations and reports the standard
error between them (which includes the finite patch and the pixel noise).
"""

from __future__ import annotations

import math
import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError, check_range
from ..io.mesh import write_ply
from .cavity import Bounces, check_bounces
from .grooves import render_lambertian_mesh

__all__ = [
    "HeightfieldSettings",
    "gaussian_heightfield",
    "heightfield_brdf",
    "heightfield_mesh",
    "render_heightfield",
    "triangle_slopes",
    "write_ply",
]


def gaussian_heightfield(
    n: int, spacing: float, correlation_length: float, rng: np.random.Generator
) -> np.ndarray:
    """A periodic n × n Gaussian random field, unit variance, correlation exp(−r²/ℓ²).

    Spectral synthesis: the field is white noise convolved (circularly, by FFT) with the
    kernel k whose autocorrelation is C, k(r) ∝ exp(−2r²/ℓ²). Lengths in any unit (the
    grid ``spacing`` and ℓ in the same one).
    """
    if n < 8:
        raise ParameterError(f"n must be an integer >= 8 (got {n!r})")
    x = np.fft.fftfreq(n, d=1.0 / n) * spacing  # signed periodic distances
    r2 = x[:, None] ** 2 + x[None, :] ** 2
    kernel = np.exp(-2.0 * r2 / correlation_length**2)
    noise = rng.standard_normal((n, n))
    h = np.real(np.fft.ifft2(np.fft.fft2(noise) * np.fft.fft2(kernel)))
    h -= h.mean()
    return h / h.std()


def _cells(n: int):
    """Vertex indices of the two triangles of every grid cell, diagonals in a checkerboard."""
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    i, j = i.ravel(), j.ravel()
    ip, jp = (i + 1) % n, (j + 1) % n
    v00, v10, v01, v11 = i * n + j, ip * n + j, i * n + jp, ip * n + jp
    even = (i + j) % 2 == 0
    # even cells split along (0,0)-(1,1), odd cells along (1,0)-(0,1); counter-clockwise
    # seen from above (x = i, y = j), so that the normals point up
    t1 = np.where(even[:, None], np.stack([v00, v10, v11], 1), np.stack([v00, v10, v01], 1))
    t2 = np.where(even[:, None], np.stack([v00, v11, v01], 1), np.stack([v10, v11, v01], 1))
    return np.concatenate([t1, t2])


def triangle_slopes(h: np.ndarray, spacing: float) -> np.ndarray:
    """Slopes (∂h/∂x, ∂h/∂y) of the triangles of the periodic mesh of ``h``, shape (T, 2)."""
    n = h.shape[0]
    tri = _cells(n)
    i, j = tri // n, tri % n
    z = h.ravel()[tri]
    # unwrap the periodic indices: positions relative to the first vertex
    dx = (((i - i[:, :1]) + 1) % n - 1) * spacing
    dy = (((j - j[:, :1]) + 1) % n - 1) * spacing
    dz = z - z[:, :1]
    e1 = np.stack([dx[:, 1], dy[:, 1], dz[:, 1]], 1)
    e2 = np.stack([dx[:, 2], dy[:, 2], dz[:, 2]], 1)
    nrm = np.cross(e1, e2)
    return -nrm[:, :2] / nrm[:, 2:3]


def heightfield_mesh(h: np.ndarray, spacing: float, tiles: int = 3):
    """Vertices (V, 3) and triangles (T, 3) of ``tiles`` × ``tiles`` copies of ``h``.

    The central copy spans [−L/2, L/2]², L = n × spacing; the copies share their edge
    vertices (one closed periodic surface, no cracks).
    """
    if tiles < 1 or tiles % 2 == 0:
        raise ParameterError(f"tiles must be an odd integer >= 1 (got {tiles!r})")
    n = h.shape[0]
    m = n * tiles + 1
    length = n * spacing
    # vertex (a, b) of the big grid carries h[a mod n, b mod n]; centre the middle tile
    x = (np.arange(m) - (tiles // 2) * n) * spacing - 0.5 * length
    xx, yy = np.meshgrid(x, x, indexing="ij")
    a = np.arange(m) % n
    zz = h[a[:, None], a[None, :]]
    verts = np.stack([xx.ravel(), yy.ravel(), zz.ravel()], axis=1)
    i, j = np.meshgrid(np.arange(m - 1), np.arange(m - 1), indexing="ij")
    i, j = i.ravel(), j.ravel()
    v00, v10, v01, v11 = i * m + j, (i + 1) * m + j, i * m + j + 1, (i + 1) * m + j + 1
    even = ((i % n) + (j % n)) % 2 == 0  # the same checkerboard as triangle_slopes
    t1 = np.where(even[:, None], np.stack([v00, v10, v11], 1), np.stack([v00, v10, v01], 1))
    t2 = np.where(even[:, None], np.stack([v00, v11, v01], 1), np.stack([v10, v11, v01], 1))
    return verts, np.concatenate([t1, t2])


@dataclass(frozen=True)
class HeightfieldSettings:
    """Discretisation and sampling of :func:`heightfield_brdf` (lengths in units of ℓ).

    Attributes
    ----------
    n : int
        Grid points per side of one tile.
    cells_per_length : float
        Grid cells per correlation length ℓ (the tile is n / cells_per_length ℓ wide).
    tiles : int
        Odd number of copies per side (the central one is imaged; the others give its
        surroundings).
    res, spp : int
        Film resolution (square) and samples per pixel.
    realisations : int
        Independent surfaces averaged; the standard error is between them.
    """

    n: int = 128
    cells_per_length: float = 4.0
    tiles: int = 3
    res: int = 128
    spp: int = 16
    realisations: int = 4

    def __post_init__(self) -> None:
        for name, lo in (("n", 8), ("tiles", 1), ("res", 1), ("spp", 1), ("realisations", 2)):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, int | np.integer) or v < lo:
                raise ParameterError(f"{name} must be an integer >= {lo} (got {v!r})")
        if self.tiles % 2 == 0:
            raise ParameterError(f"tiles must be odd (got {self.tiles})")
        check_range("cells_per_length", self.cells_per_length, 1.0, 64.0)


def _rotation_frame(theta_i, theta_r, delta_phi):
    """ωi, ωo with ωo in the x–z plane (the camera's frame; the surface is isotropic)."""
    wo = np.array([math.sin(theta_r), 0.0, math.cos(theta_r)])
    wi = np.array(
        [
            math.sin(theta_i) * math.cos(-delta_phi),
            math.sin(theta_i) * math.sin(-delta_phi),
            math.cos(theta_i),
        ]
    )
    return wi, wo


def render_heightfield(
    mi: Any,
    ply: str | os.PathLike,
    length: float,
    albedo: float,
    wi: np.ndarray,
    wo: np.ndarray,
    max_depth: int,
    *,
    res: int = 128,
    spp: int = 16,
    seed: int = 0,
) -> np.ndarray:
    """Render the mesh of ``ply`` (Mitsuba module ``mi``, a variant set); first channel.

    ``wo`` must lie in the x–z plane; the film covers the projection of the central tile
    [−L/2, L/2]² (L = ``length``), so the image mean is the surface's mean radiance per unit
    irradiance.
    """
    if abs(float(wo[1])) > 1e-12:
        raise ParameterError("wo must lie in the x-z plane (wo[1] = 0)")
    cos_o = float(wo[2])
    return render_lambertian_mesh(
        mi,
        ply,
        albedo,
        wi,
        wo,
        max_depth,
        extent=(0.5 * length * cos_o, 0.5 * length),
        distance=10.0 * length,
        spp=spp,
        res=res,
        seed=seed,
    )


def _depth(bounces: Bounces) -> int:
    return 64 if bounces == "all" else int(bounces) + 1


def heightfield_brdf(
    theta_i: float,
    theta_r: float,
    delta_phi: float,
    alpha: float,
    albedo: float = 1.0,
    bounces: Bounces | tuple[Bounces, ...] = "all",
    settings: HeightfieldSettings | None = None,
    *,
    seed: int = 0,
    image_dir: str | os.PathLike | None = None,
):
    """BRDF of a Gaussian heightfield of Lambertian triangles, rendered by Mitsuba 3.

    Parameters
    ----------
    theta_i, theta_r : float
        Incidence and viewing angles in [0, 85°] radians (beyond, the patch is too small).
    delta_phi : float
        φr − φi in radians.
    alpha : float
        Beckmann roughness of the surface: mean tan²θm over its triangles, in (0, 1].
    albedo : float
        Albedo of the triangles.
    bounces : int, "all", or a tuple of them
        Path depth(s); a tuple renders each on the same surfaces.
    settings : HeightfieldSettings, optional
    seed : int
        Seeds the surfaces (NumPy) and the renders (Mitsuba).
    image_dir : path, optional
        Also save the first realisation's image of each depth there as PNG (for looking).

    Returns
    -------
    (f, se) for one ``bounces``, or a dict {bounces: (f, se)} for a tuple.
    """
    import mitsuba as mi

    s = settings or HeightfieldSettings()
    for name, val in (("theta_i", theta_i), ("theta_r", theta_r)):
        check_range(name, val, 0.0, math.radians(85.0), unit="radians")
    check_range("alpha", alpha, 0.0, 1.0, lo_open=True)
    check_range("albedo", albedo, 0.0, 1.0)
    many = isinstance(bounces, tuple)
    blist = tuple(check_bounces(b) for b in (bounces if many else (bounces,)))
    wi, wo = _rotation_frame(float(theta_i), float(theta_r), float(delta_phi))
    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    rng = np.random.default_rng(seed)
    ell = 1.0
    dx = ell / s.cells_per_length
    length = s.n * dx
    means: dict[Bounces, list[float]] = {b: [] for b in blist}
    try:
        with tempfile.TemporaryDirectory() as tmp:
            for k in range(s.realisations):
                h = gaussian_heightfield(s.n, dx, ell, rng)
                g = triangle_slopes(h, dx)
                h = h * alpha / math.sqrt(np.mean(np.sum(g * g, axis=1)))
                verts, faces = heightfield_mesh(h, dx, s.tiles)
                ply = write_ply(Path(tmp) / f"hf{k}.ply", verts, faces)
                for b in blist:
                    img = render_heightfield(
                        mi,
                        ply,
                        length,
                        albedo,
                        wi,
                        wo,
                        _depth(b),
                        res=s.res,
                        spp=s.spp,
                        seed=seed * 1000 + k,
                    )
                    means[b].append(float(img.mean()) / math.cos(theta_i))
                    if image_dir is not None and k == 0:
                        _save_png(Path(image_dir) / f"heightfield_{b}.png", img)
    finally:
        if previous is not None:
            mi.set_variant(previous)
    out = {}
    for b in blist:
        v = np.asarray(means[b])
        se = float(v.std(ddof=1) / math.sqrt(v.size)) if v.size > 1 else math.nan
        out[b] = (float(v.mean()), se)
    return out if many else out[blist[0]]


def _save_png(path: Path, img: np.ndarray) -> None:
    """An sRGB PNG of the linear image (:func:`roughdiffuse.io.images.write_png`, atomic)."""
    from ..io.images import write_png

    path.parent.mkdir(parents=True, exist_ok=True)
    write_png(path, img)
