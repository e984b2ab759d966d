"""An independent Monte Carlo ray tracer of one V-cavity's cross-section (test helper).

Written apart from ``roughdiffuse.simulate.cavity`` and sharing no code with it: rays enter
the cavity opening uniformly, hit a facet, and the radiance there is estimated by path
tracing with next-event estimation towards the directional light (a shadow ray) and
cosine-weighted Lambertian bounces. The cavity is infinitely long, so rays are traced in the
2-D cross-section; a 3-D cosine-weighted direction projects to an in-plane angle ψ from the
facet normal with density cos ψ / 2 (sin ψ uniform on [−1, 1]).
"""

from __future__ import annotations

import math

import numpy as np


def _facets(theta_a: float):
    """End points (rim, vertex) and inward unit normals of the two facets, width 1."""
    depth = 0.5 * math.tan(theta_a)
    vertex = np.array([0.0, -depth])
    left = (np.array([-0.5, 0.0]), vertex, np.array([math.sin(theta_a), math.cos(theta_a)]))
    right = (np.array([0.5, 0.0]), vertex, np.array([-math.sin(theta_a), math.cos(theta_a)]))
    return left, right


def _hit(o: np.ndarray, d: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Ray parameter t of o + t d on segment ab (inf if missed); o, d of shape (N, 2)."""
    e = b - a
    den = d[:, 0] * (-e[1]) - d[:, 1] * (-e[0])
    rx, ry = a[0] - o[:, 0], a[1] - o[:, 1]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (rx * (-e[1]) - ry * (-e[0])) / den
        u = (d[:, 0] * ry - d[:, 1] * rx) / den
    ok = (np.abs(den) > 1e-15) & (t > 1e-9) & (u >= 0.0) & (u <= 1.0)
    return np.where(ok, t, np.inf)


def cavity_radiance_mc(
    theta_a: float,
    phi_a: float,
    wi: np.ndarray,
    wo: np.ndarray,
    albedo: float,
    bounces: int | None,
    n_paths: int,
    rng: np.random.Generator,
) -> tuple[float, float]:
    """Mean radiance of the cavity per unit irradiance and its standard error.

    ``bounces`` None means all (paths run until they leave the cavity or their weight falls
    below 1e-12).
    """
    a3 = np.array([math.cos(phi_a), math.sin(phi_a), 0.0])
    z3 = np.array([0.0, 0.0, 1.0])
    facets = _facets(theta_a)
    # 3-D facet normals (for the Lambertian cosine with the light)
    n3 = [
        math.sin(theta_a) * a3 + math.cos(theta_a) * z3,
        -math.sin(theta_a) * a3 + math.cos(theta_a) * z3,
    ]
    l2 = np.array([wi @ a3, wi @ z3])
    v2 = np.array([wo @ a3, wo @ z3])
    l2 = l2 / np.linalg.norm(l2)
    v2 = v2 / np.linalg.norm(v2)
    x = rng.uniform(-0.5, 0.5, n_paths)
    o = np.stack([x, np.zeros(n_paths)], axis=1)
    d = np.broadcast_to(-v2, (n_paths, 2)).copy()
    estimate = np.zeros(n_paths)
    weight = np.ones(n_paths)
    alive = np.ones(n_paths, bool)
    depth = 0
    while alive.any():
        depth += 1
        t0 = _hit(o, d, facets[0][0], facets[0][1])
        t1 = _hit(o, d, facets[1][0], facets[1][1])
        which = np.where(t0 <= t1, 0, 1)
        t = np.minimum(t0, t1)
        alive &= np.isfinite(t)
        if not alive.any():
            break
        p = o + np.where(np.isfinite(t), t, 0.0)[:, None] * d
        normal = np.where(which[:, None] == 0, facets[0][2], facets[1][2])
        mu_l = np.where(which == 0, n3[0] @ wi, n3[1] @ wi)
        # next-event estimation: shadow ray towards the light, blocked by either facet
        lit = (mu_l > 0) & (l2[1] > 0)
        ls = np.broadcast_to(l2, (n_paths, 2))
        blocked = np.isfinite(_hit(p, ls, facets[0][0], facets[0][1])) | np.isfinite(
            _hit(p, ls, facets[1][0], facets[1][1])
        )
        lit &= ~blocked
        estimate += np.where(alive & lit, weight * albedo / math.pi * np.maximum(mu_l, 0.0), 0.0)
        if bounces is not None and depth >= bounces:
            break
        # Lambertian bounce: in-plane angle from the normal with sin ψ uniform on [-1, 1]
        s = rng.uniform(-1.0, 1.0, n_paths)
        c = np.sqrt(1.0 - s * s)
        tangent = np.stack([normal[:, 1], -normal[:, 0]], axis=1)
        d = c[:, None] * normal + s[:, None] * tangent
        o = p
        weight = weight * albedo
        alive &= weight > 1e-12
    mean = float(estimate.mean())
    se = float(estimate.std(ddof=1) / math.sqrt(n_paths))
    return mean, se
