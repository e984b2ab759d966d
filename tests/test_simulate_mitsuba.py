"""A real renderer's check of the cavity solver: Mitsuba 3 renders of explicit V-groove meshes.

A plane covered with parallel V-grooves (one θa, grooves along y, Lambertian ``diffuse``
facets), a ``directional`` emitter of unit irradiance, an orthographic camera, the ``path``
integrator with max_depth 2 (direct light: 1 bounce), 3 (2 bounces) and 64 (all). The camera's
horizontal axis is perpendicular to the grooves and the view, and spans an exact number of
projected groove periods, so the image mean is the flux-weighted mean radiance of a groove,
which is what :func:`cavity_radiance` computes. The solver's orientation φa is applied by
rotating l and v about z by −φa instead of rotating the mesh.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughdiffuse.simulate.cavity import cavity_radiance

mi = pytest.importorskip("mitsuba")

WIDTH = 1.0
HALF_GROOVES = 150


def _groove_ply(path, theta_a: float) -> None:
    """Write an ASCII PLY of 2 × HALF_GROOVES grooves of width 1 along y, rims at z = 0."""
    depth = 0.5 * WIDTH * math.tan(theta_a)
    y0, y1 = -400.0, 400.0
    verts, faces = [], []
    for k in range(-HALF_GROOVES, HALF_GROOVES):
        x0 = k * WIDTH
        xm, x1 = x0 + 0.5 * WIDTH, x0 + WIDTH
        for (ax, az), (bx, bz) in (((x0, 0.0), (xm, -depth)), ((xm, -depth), (x1, 0.0))):
            n = len(verts)
            verts += [(ax, y0, az), (bx, y0, bz), (bx, y1, bz), (ax, y1, az)]
            # counter-clockwise seen from above the facet: the normal points out of the groove
            faces += [(n, n + 1, n + 2), (n, n + 2, n + 3)]
    with open(path, "w") as fh:
        fh.write("ply\nformat ascii 1.0\n")
        fh.write(
            f"element vertex {len(verts)}\nproperty float x\nproperty float y\nproperty float z\n"
        )
        fh.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in verts:
            fh.write(f"{v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
        for f in faces:
            fh.write(f"3 {f[0]} {f[1]} {f[2]}\n")


def _render(ply, albedo, wi, wo, max_depth: int, spp: int = 32, res: int = 48):
    vx, vy, vz = wo
    # screen horizontal axis u ∝ y × v; one groove period projects to P = vz / |(vx, vz)|
    period = WIDTH * vz / math.hypot(vx, vz)
    n_periods = 12
    scale_x = 0.5 * n_periods * period
    origin = 50.0 * np.asarray(wo)
    to_world = mi.ScalarTransform4f().look_at(
        origin=origin.tolist(), target=[0.0, 0.0, 0.0], up=[0.0, 1.0, 0.0]
    ) @ mi.ScalarTransform4f().scale([scale_x, 3.0, 1.0])
    scene = mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": max_depth},
            "sensor": {
                "type": "orthographic",
                "to_world": to_world,
                "film": {
                    "type": "hdrfilm",
                    "width": res,
                    "height": res,
                    "rfilter": {"type": "box"},
                    "pixel_format": "rgb",
                },
                "sampler": {"type": "independent", "sample_count": spp},
            },
            "emitter": {
                "type": "directional",
                "direction": (-np.asarray(wi)).tolist(),
                "irradiance": {"type": "rgb", "value": [1.0, 1.0, 1.0]},
            },
            "grooves": {
                "type": "ply",
                "filename": str(ply),
                "face_normals": True,
                "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": albedo}},
            },
        }
    )
    img = np.array(mi.render(scene, seed=max_depth))[..., 0]
    rows = img.mean(axis=1)  # each row spans exactly n_periods projected periods
    return float(rows.mean()), float(rows.std(ddof=1) / math.sqrt(rows.size))


def _dir(theta: float, phi: float) -> np.ndarray:
    return np.array(
        [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
    )


def test_mitsuba_v_grooves_match_cavity_radiance(tmp_path):
    mi.set_variant("scalar_rgb")
    rng = np.random.default_rng(11)
    geometries = []
    for ta in (0.3, 0.7, 1.0):
        for _ in range(7):
            ti, tr = rng.uniform(0.0, 1.45, 2)
            geometries.append((ta, rng.uniform(0, 2 * math.pi), ti, rng.uniform(0, 6.3), tr))
    geometries[0] = (0.7, 0.3, math.radians(85.0), 2.0, math.radians(80.0))  # grazing
    geometries[1] = (1.0, 0.0, math.radians(80.0), math.pi, math.radians(85.0))  # grazing, back
    checked = 0
    for ta, pa, ti, phi_rel, tr in geometries:
        ply = tmp_path / f"g{ta:.2f}.ply"
        if not ply.exists():
            _groove_ply(ply, ta)
        wi, wo = _dir(ti, 0.0), _dir(tr, phi_rel)
        rot = np.array(
            [[math.cos(-pa), -math.sin(-pa), 0], [math.sin(-pa), math.cos(-pa), 0], [0, 0, 1]]
        )
        for depth, bounces in ((2, 1), (3, 2), (64, "all")):
            mean, se = _render(ply, 0.8, rot @ wi, rot @ wo, depth)
            exact = float(cavity_radiance(ta, pa, wi, wo, 0.8, bounces, 64))
            tol = max(0.01 * exact, 3.0 * se, 1e-6)
            assert abs(mean - exact) <= tol, (ta, pa, ti, tr, phi_rel, bounces, mean, exact, se)
        checked += 1
    assert checked >= 20
