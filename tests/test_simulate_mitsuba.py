"""A real renderer's check of the cavity solver: Mitsuba 3 renders of explicit V-groove meshes.

The scene (roughdiffuse.simulate.grooves, which shares no code with the solver): a plane
covered with parallel V-grooves (one θa, grooves along y, Lambertian ``diffuse``
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

mi = pytest.importorskip(
    "mitsuba", reason="Mitsuba 3 is an optional extra (pip install mitsuba); CI installs it"
)

from roughdiffuse.simulate.cavity import cavity_radiance  # noqa: E402
from roughdiffuse.simulate.grooves import render_grooves, write_groove_ply  # noqa: E402


def _render(ply, albedo, wi, wo, max_depth: int):
    img = render_grooves(mi, ply, albedo, wi, wo, max_depth, seed=max_depth)
    rows = img.mean(axis=1)  # each row spans exactly 12 projected groove periods
    return float(rows.mean()), float(rows.std(ddof=1) / math.sqrt(rows.size))


def _dir(theta: float, phi: float) -> np.ndarray:
    return np.array(
        [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
    )


@pytest.fixture
def scalar_rgb():
    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    yield
    if previous is not None:  # other test modules may rely on the variant they set
        mi.set_variant(previous)


def test_mitsuba_v_grooves_match_cavity_radiance(tmp_path, scalar_rgb):
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
            write_groove_ply(ply, ta)
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
