"""Explicit V-groove surfaces rendered by Mitsuba 3 (optional dependency ``mitsuba``).

A plane covered with parallel V-grooves of one slope θa (grooves along y, width 1, rims at
z = 0), Lambertian ``diffuse`` facets, a ``directional`` emitter of unit irradiance and an
orthographic camera; the ``path`` integrator's ``max_depth`` sets the bounces (2: direct light
only, 3: two bounces, large: all). The camera's horizontal axis is perpendicular to the
grooves and to the view and spans an exact number of projected groove periods, so the mean of
each image row is the flux-weighted mean radiance of a groove, the quantity
:func:`roughdiffuse.simulate.cavity_radiance` computes (for φa = 0).

Used by ``tests/test_simulate_mitsuba.py`` (the renderer's check of the solver) and by the
report's finite-pixel figure.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any

import numpy as np

from .._mitsuba_scene import orthographic_sensor
from ..io.atomic import atomic_open

__all__ = ["render_grooves", "render_lambertian_mesh", "write_groove_ply"]

HALF_GROOVES = 150


def write_groove_ply(path: str | os.PathLike, theta_a: float, half_grooves: int = HALF_GROOVES):
    """Write an ASCII PLY of 2 × ``half_grooves`` grooves of width 1 along y (800 long)."""
    depth = 0.5 * math.tan(theta_a)
    y0, y1 = -400.0, 400.0
    verts, faces = [], []
    for k in range(-half_grooves, half_grooves):
        x0, xm, x1 = float(k), k + 0.5, k + 1.0
        for (ax, az), (bx, bz) in (((x0, 0.0), (xm, -depth)), ((xm, -depth), (x1, 0.0))):
            n = len(verts)
            verts += [(ax, y0, az), (bx, y0, bz), (bx, y1, bz), (ax, y1, az)]
            # counter-clockwise seen from above the facet: the normal points out of the groove
            faces += [(n, n + 1, n + 2), (n, n + 2, n + 3)]
    path = Path(path)
    with atomic_open(path, "w") as fh:
        fh.write("ply\nformat ascii 1.0\n")
        fh.write(f"element vertex {len(verts)}\n")
        fh.write("property float x\nproperty float y\nproperty float z\n")
        fh.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in verts:
            fh.write(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
        for f in faces:
            fh.write(f"3 {f[0]} {f[1]} {f[2]}\n")
    return path


def render_grooves(
    mi: Any,
    ply: str | os.PathLike,
    albedo: float,
    wi: np.ndarray,
    wo: np.ndarray,
    max_depth: int,
    *,
    spp: int = 32,
    res: int = 48,
    n_periods: float = 12,
    seed: int = 0,
) -> np.ndarray:
    """Render the grooves of ``ply`` (Mitsuba module ``mi`` with a variant set).

    Returns the image's first channel, shape (res, res); each row spans ``n_periods``
    projected groove periods.
    """
    vx, vy, vz = (float(c) for c in wo)
    period = vz / math.hypot(vx, vz)  # one groove period along the screen's horizontal axis
    return render_lambertian_mesh(
        mi,
        ply,
        albedo,
        wi,
        wo,
        max_depth,
        extent=(0.5 * n_periods * period, 3.0),
        distance=50.0,
        spp=spp,
        res=res,
        seed=seed,
    )


def render_lambertian_mesh(
    mi: Any,
    ply: str | os.PathLike,
    albedo: float,
    wi: np.ndarray,
    wo: np.ndarray,
    max_depth: int,
    *,
    extent: tuple[float, float],
    distance: float,
    spp: int,
    res: int,
    seed: int = 0,
) -> np.ndarray:
    """A Lambertian mesh (``ply``, face normals) under a directional light of irradiance 1
    from ``wi``, seen from ``wo`` by an orthographic camera at ``distance`` whose film spans
    ±``extent`` (x, y) around the origin; Mitsuba's ``path`` integrator with ``max_depth``.
    The scene of the groove renders and of :mod:`roughdiffuse.simulate.heightfield`.

    Returns the image's first channel, shape (res, res).
    """
    origin = distance * np.asarray(wo, dtype=float)
    to_world = mi.ScalarTransform4f().look_at(
        origin=origin.tolist(), target=[0.0, 0.0, 0.0], up=[0.0, 1.0, 0.0]
    ) @ mi.ScalarTransform4f().scale([extent[0], extent[1], 1.0])
    scene = mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": int(max_depth)},
            "sensor": orthographic_sensor(to_world, res, spp),
            "emitter": {
                "type": "directional",
                "direction": (-np.asarray(wi, dtype=float)).tolist(),
                "irradiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]},
            },
            "surface": {
                "type": "ply",
                "filename": str(ply),
                "face_normals": True,
                "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}},
            },
        }
    )
    return np.array(mi.render(scene, seed=seed))[..., 0]
