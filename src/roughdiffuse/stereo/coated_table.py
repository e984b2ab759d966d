"""The coated model tabulated per light, and a compiled per-pixel Gauss–Newton over the table.

Once the object's σ, α and η are known (:func:`roughdiffuse.stereo.coated.coated` fits them
on a subsample of the pixels), what remains per pixel is its normal n and albedo ρ. The value
of light k at a pixel, per unit intensity,

    F_k(n, ρ) = f_r(l_k, v; n, ρ, σ, α, η) max(n·l_k, 0),   v = +z,

depends on n through two numbers only: with h_k = (l_k + v)/|l_k + v| and
b_k = (l_k − v)/|l_k − v| (orthogonal to h_k), θd the half angle between l_k and v, and
z = n·h_k, x = n·b_k, the model's arguments are μi = z cos θd + x sin θd,
μo = z cos θd − x sin θd and cos_io = l_k·v (fixed per light). So each light gets a table
over (z, x) and ρ, filled by :class:`~roughdiffuse.models.coated.Coated`'s own evaluation
(compiled, :func:`roughdiffuse.engine.fastpath.brdf_cosines`): no formula of the model is
written here.

* The axis of z is u(z) = ½ (1 − z) + ½ q/(1 + q), q = tan²θh/α² (cos θh = z): q/(1 + q) is
  the fraction of a GGX coat's projected facet area within θh of the normal, which spreads
  the highlight (width about α) over half the axis at any α; 1 − z spreads the rest. u is
  uniform on [0, 1] with :data:`U_NODES` nodes (z = 0 at u = 1: beyond it μi + μo ≤ 0).
* The axis of x is t = x / sin θh ∈ [−1, 1] (the cosine of n's azimuth about h_k), uniform
  with :data:`T_NODES` nodes.
* In ρ the table holds the coefficients of the polynomial of degree :data:`DEGREE` through
  the model's values at the Chebyshev–Lobatto nodes of [0, 1] (ρ = 0 among them: the coat's
  own reflection, the highlight, exactly).

Values between nodes are bilinear in (u, t), and their derivatives those of the bilinear
interpolant (chain rule through u(z) and t(z, x)). :func:`coated_table` measures the table's
error against the model on random normals (within 80° of the view) and albedos
(:attr:`CoatedTable.error`): with the default sizes, under DiLiGenT's 96 lights, 0.8e-3 of
the light's brightest value for α = 0.1, 2.7e-3 for α = 0.3 and 3.5e-3 for α = 0.6 (the
base's kinks, e.g. Oren–Nayar's at 90° of azimuth, limit the bilinear interpolation);
tests/test_stereo_coated_fast.py checks it against the model's reference evaluation and
holds it below :data:`ERROR_BOUND`.

:func:`solve_pixels` runs Levenberg–Marquardt per pixel (the normal in its tangent plane,
the albedo per channel, clipped to [0, 1], the model's range) on the table, compiled by
Numba and parallel over the pixels: each observation costs four table cells.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["CoatedTable", "coated_table", "solve_pixels", "table_error", "table_values"]

U_NODES = 129
"""Nodes of the table's z axis, u(z) (see the module's docstring)."""

T_NODES = 25
"""Nodes of the table's azimuth axis t ∈ [−1, 1]."""

DEGREE = 6
"""Degree of the table's polynomial in the albedo ρ."""

ALPHA_AXIS_FLOOR = 0.02
"""Smallest α of the z axis's stretch (a smooth coat has no highlight in the BRDF value)."""

CHECK_VIEW = math.cos(math.radians(80.0))
"""Smallest n·v of the error check: normals up to 80° from the view (the synthetic renders'
mask). Nearer grazing the base's value rises steeply as n·v → 0 and the table's error grows
to several per cent of the peak there."""

TOLERANCE = 1e-4
"""A pixel's Levenberg–Marquardt stops when its step is below this: 1e-4 rad (0.006°) and
1e-4 of albedo, under a tenth of the smallest standard error of a normal (0.09° on the
512² coated sphere render of the benchmark: 96 lights, 1 % noise, 12 bits). The next step, which the
quadratic convergence near the minimum makes about 1e-8, would change nothing the images
determine; 1e-6 took 4.9 steps a pixel on average instead of 3.3."""

ERROR_BOUND = 5e-3
"""Bound on the table's error, relative to the brightest value of the light, that the tests
hold the measured :attr:`CoatedTable.error` to (over α ≥ 0.1)."""


@dataclass(frozen=True)
class CoatedTable:
    """A coated model tabulated per light (see the module's docstring).

    Attributes
    ----------
    values : float64 array (K, U, T, D + 1)
        Coefficients of ρ^0 … ρ^D at each node (u, t) of each light.
    frames : float64 array (K, 6)
        h_k and b_k of each light.
    alpha_axis : float
        The α of the z axis's stretch.
    error : float
        Largest difference from the model on the random check of :func:`coated_table`,
        relative to the light's brightest tabulated value.
    """

    values: np.ndarray
    frames: np.ndarray
    alpha_axis: float
    error: float


def _frames(directions: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """h_k, b_k (K, 6) and cos θd, sin θd (K,) of each light (v = +z)."""
    l = np.asarray(directions, dtype=np.float64)
    v = np.array([0.0, 0.0, 1.0])
    plus, minus = l + v, l - v
    cos_d = 0.5 * np.linalg.norm(plus, axis=1)
    sin_d = 0.5 * np.linalg.norm(minus, axis=1)
    h = plus / np.maximum(2.0 * cos_d, 1e-300)[:, None]
    # a light on the view axis: sin θd = 0, any b_k ⟂ h_k
    b = np.where(sin_d[:, None] > 1e-12, minus / np.maximum(2.0 * sin_d, 1e-300)[:, None],
                 [1.0, 0.0, 0.0])
    return np.concatenate([h, b], axis=1), cos_d, sin_d


def _axis_u(z: np.ndarray, a2: float) -> np.ndarray:
    """u(z) of the module's docstring (a2 = α²)."""
    v = 1.0 - z * z
    return 0.5 * (1.0 - z) + 0.5 * v / (v + a2 * z * z)


def _z_of_u(u: np.ndarray, a2: float) -> np.ndarray:
    """The inverse of u(z) on [0, 1] (decreasing), by bisection to float64 rounding."""
    lo, hi = np.zeros_like(u), np.ones_like(u)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        above = _axis_u(mid, a2) > u
        lo, hi = np.where(above, mid, lo), np.where(above, hi, mid)
    return 0.5 * (lo + hi)


def _rho_nodes(degree: int) -> np.ndarray:
    """Chebyshev–Lobatto nodes on [0, 1], 0 first."""
    return 0.5 * (1.0 - np.cos(np.pi * np.arange(degree + 1) / degree))


def table_values(build: Any, directions: np.ndarray, mu_i: np.ndarray, mu_o: np.ndarray,
                 rho: float) -> np.ndarray:
    """The model's F = f_r max(μi, 0) of albedo ``rho`` (``build(rho)``, a
    :class:`~roughdiffuse.models.coated.Coated`) at (μi, μo) of the lights ``directions``
    (K, ...), compiled (:func:`roughdiffuse.engine.fastpath.brdf_cosines`)."""
    from ..engine import fastpath

    mi = np.ascontiguousarray(mu_i, dtype=np.float64)
    mo = np.ascontiguousarray(mu_o, dtype=np.float64)
    shape = (-1,) + (1,) * (mi.ndim - 1)
    c = np.broadcast_to(np.asarray(directions, np.float64)[:, 2].reshape(shape), mi.shape)
    f = fastpath.brdf_cosines(build(rho), mi, mo, np.ascontiguousarray(c))
    return np.asarray(f, dtype=np.float64) * np.maximum(mi, 0.0)


def coated_table(build: Any, alpha: float, directions: np.ndarray, *, u_nodes: int = U_NODES,
                 t_nodes: int = T_NODES, degree: int = DEGREE, check: int = 4000,
                 seed: int = 0) -> CoatedTable:
    """Tabulate the coated model ``build(ρ)`` (σ, α, η fixed; α is its coat roughness) for
    each light of ``directions`` (K, 3), and measure the table's error on ``check`` random
    (light, normal, albedo) triples against the model itself."""
    frames, _, _ = _frames(directions)
    a2 = max(float(alpha), ALPHA_AXIS_FLOOR) ** 2
    mu_i, mu_o = _node_cosines(directions, a2, u_nodes, t_nodes)
    nodes = _rho_nodes(degree)
    vals = np.stack([table_values(build, directions, mu_i, mu_o, r) for r in nodes], axis=-1)
    vander = nodes[:, None] ** np.arange(degree + 1)[None, :]
    coef = np.ascontiguousarray(np.linalg.solve(vander, vals.reshape(-1, degree + 1).T).T)
    table = CoatedTable(coef.reshape(vals.shape), frames, math.sqrt(a2), math.nan)
    if check <= 0:
        return table
    # each light's brightest value over the normals the check draws (n·v ≥ CHECK_VIEW): at
    # ρ = 1, the last of the nodes (the model rises with the base's albedo)
    peak = np.max(np.where(mu_o >= CHECK_VIEW, vals[..., -1], 0.0), axis=(1, 2))
    return CoatedTable(table.values, frames, table.alpha_axis,
                       _check_error(table, build, directions, peak, check, seed))


def _node_cosines(directions: np.ndarray, a2: float, u_nodes: int = U_NODES,
                  t_nodes: int = T_NODES) -> tuple[np.ndarray, np.ndarray]:
    """μi and μo (K, U, T) at the table's nodes of each light, for the z axis of α² ``a2``."""
    _, cos_d, sin_d = _frames(directions)
    z = _z_of_u(np.linspace(0.0, 1.0, u_nodes), a2)
    s = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    t = np.linspace(-1.0, 1.0, t_nodes)
    zz, xx = z[:, None], s[:, None] * t[None, :]
    mu_i = zz * cos_d[:, None, None] + xx * sin_d[:, None, None]
    mu_o = zz * cos_d[:, None, None] - xx * sin_d[:, None, None]
    return mu_i, mu_o


def table_error(table: CoatedTable, build: Any, directions: np.ndarray, *, check: int = 4000,
                seed: int = 0) -> float:
    """The error of ``table`` against another model ``build(ρ)`` (e.g. the object's values
    fitted again), measured as :func:`coated_table` measures its own: the largest
    difference on ``check`` random (light, normal, albedo) triples, relative to each light's
    brightest value of ``build(1)`` at the table's nodes (within 80° of the view)."""
    mu_i, mu_o = _node_cosines(directions, table.alpha_axis**2, table.values.shape[1],
                               table.values.shape[2])
    vals = table_values(build, directions, mu_i, mu_o, 1.0)
    peak = np.max(np.where(mu_o >= CHECK_VIEW, vals, 0.0), axis=(1, 2))
    return _check_error(table, build, directions, peak, check, seed)


def _check_error(table: CoatedTable, build: Any, directions: np.ndarray, peak: np.ndarray,
                 count: int, seed: int) -> float:
    """Largest |table − model| / (the light's peak) over random lit normals within 80° of
    the view (:data:`CHECK_VIEW`) and albedos: five albedos, ``count`` normals, lights drawn
    at random."""
    rng = np.random.default_rng(seed)
    l = np.asarray(directions, dtype=np.float64)
    worst = 0.0
    for rho in rng.uniform(0.0, 1.0, 5):
        n = rng.normal(size=(count, 3))
        n[:, 2] = np.abs(n[:, 2])
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        k = rng.integers(0, l.shape[0], count)
        lit = (np.sum(n * l[k], axis=1) > 0) & (n[:, 2] >= CHECK_VIEW)
        n, k = n[lit], k[lit]
        got = evaluate(table, k, n, np.full(k.shape, rho))
        # the model at each drawn (light, normal) only: one light per entry
        ref = table_values(build, l[k], np.sum(n * l[k], axis=1), n[:, 2], float(rho))
        worst = max(worst, float(np.max(np.abs(got - ref) / peak[k])))
    return worst


def evaluate(table: CoatedTable, lights: np.ndarray, normals: np.ndarray,
             albedo: np.ndarray) -> np.ndarray:
    """The table's F of light ``lights[i]`` (indices) at normal ``normals[i]`` (unit) and
    albedo ``albedo[i]``."""
    from .coated_kernels import table_value

    out = np.empty(len(lights))
    a2 = table.alpha_axis**2
    for i, (k, n, rho) in enumerate(zip(lights, normals, albedo, strict=True)):
        out[i] = table_value(table.values, table.frames, a2, int(k), n[0], n[1], n[2],
                             float(rho))
    return out


def solve_pixels(table: CoatedTable, intensities: np.ndarray, obs: np.ndarray,
                 weights: np.ndarray, normals: np.ndarray, albedo: np.ndarray, *,
                 iterations: int = 20, tolerance: float = TOLERANCE) -> dict[str, np.ndarray]:
    """Levenberg–Marquardt of every pixel's normal and albedo on the table.

    Parameters
    ----------
    table : CoatedTable
    intensities : array (K, C)
        Each light's intensity, times the object's light scale.
    obs : array (K, P, C)
        The observations.
    weights : array (K, P)
        0/1 weights (shadows and invalid values 0).
    normals, albedo : arrays (P, 3), (P, C)
        The start; pixels with a non-finite normal or fewer than three weighted observations
        are left out (NaN).
    iterations : int
        Most LM steps per pixel.
    tolerance : float
        A pixel stops when its accepted step is below this (radians and albedo units;
        default :data:`TOLERANCE`).

    Returns
    -------
    dict
        ``normals`` (P, 3), ``albedo`` (P, C), ``cost`` (P,) the sum of squared residuals,
        ``a_inv_diag`` (P, 2 + C) the diagonal of (JᵀJ)⁻¹ (tangent offsets, albedos),
        ``steps`` (P,) the LM steps taken.
    """
    from .coated_kernels import solve

    p, c = obs.shape[1], obs.shape[2]
    n = np.ascontiguousarray(np.nan_to_num(normals), dtype=np.float64).copy()
    rho = np.ascontiguousarray(np.clip(np.nan_to_num(albedo, nan=0.5), 0.0, 1.0),
                               dtype=np.float64).copy()
    # pixel by pixel: a pixel's observations side by side in memory
    w = np.ascontiguousarray(np.asarray(weights).T, dtype=np.float64)
    ok = np.all(np.isfinite(normals), axis=1) & (w.sum(axis=1) >= 3) & (n[:, 2] > 0)
    cost = np.zeros(p)
    a_inv = np.zeros((p, 2 + c))
    steps = np.zeros(p, dtype=np.int64)
    solve(table.values, table.frames, table.alpha_axis**2,
          np.ascontiguousarray(intensities, dtype=np.float64),
          np.ascontiguousarray(np.asarray(obs).transpose(1, 0, 2), dtype=np.float64), w, ok,
          n, rho, int(iterations),
          float(tolerance), cost, a_inv, steps)
    n[~ok] = np.nan
    rho[~ok] = np.nan
    return {"normals": n, "albedo": rho, "cost": np.where(ok, cost, np.nan),
            "a_inv_diag": np.where(ok[:, None], a_inv, np.nan), "steps": steps, "ok": ok}
