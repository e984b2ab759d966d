"""Numba kernels of :mod:`roughdiffuse.stereo.coated_table`: the table's value with its
derivatives, and the per-pixel Levenberg–Marquardt over it (parallel over the pixels).

Imported on first use (it imports Numba); compiled once and cached on disk in the fast
path's private cache folder (:func:`roughdiffuse.engine.cache.private_cache_dir`), in memory
without one.
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np

from ..engine.cache import Compiled, private_cache_dir

__all__ = ["solve", "sweep_shadows", "table_value"]

FAST = {"nsz", "arcp", "contract", "afn", "reassoc"}
"""LLVM fast-math flags of the table solver's kernels: reassociation, reciprocals, fused
multiply-adds and approximate functions (a tenth less time); not ``nnan`` and ``ninf``, so
that tests of NaN and infinity stay exact (the shadow sweep, which relies on −∞, has none)."""


def _jit(entry: bool = False, **flags: Any) -> Any:
    """``numba.njit`` with ``flags``, cached in the private cache folder when there is one;
    an ``entry`` (a kernel called from Python) compiles a new signature under the cache's
    lock (:class:`~roughdiffuse.engine.cache.Compiled`)."""
    directory = private_cache_dir()

    def wrap(fn: Any) -> Any:
        if directory is None:
            kernel = numba.njit(**flags)(fn)
        else:
            old = numba.config.CACHE_DIR
            numba.config.CACHE_DIR = str(directory / "stereo_coated_table")
            try:  # Numba reads the folder when the dispatcher is made
                kernel = numba.njit(cache=True, **flags)(fn)
            finally:
                numba.config.CACHE_DIR = old
        return Compiled(kernel) if entry else kernel

    return wrap


@_jit(nogil=True, error_model="numpy", fastmath=FAST)
def _cell(frames, a2, nu, nt, k, n0, n1, n2):  # noqa: ANN001, ANN202
    """The table cell of normal n for light k: indices and weights in (u, t), and the
    gradients du/dn, dt/dn (3 each; 0 outside the lit side, z ≤ 0)."""
    h0, h1, h2 = frames[k, 0], frames[k, 1], frames[k, 2]
    b0, b1, b2 = frames[k, 3], frames[k, 4], frames[k, 5]
    z = n0 * h0 + n1 * h1 + n2 * h2
    x = n0 * b0 + n1 * b1 + n2 * b2
    if z <= 1e-9:
        return -1, 0.0, 0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    s2 = max(1.0 - z * z, 0.0)
    s = math.sqrt(s2)
    t = 0.0
    if s > 1e-12:
        t = min(max(x / s, -1.0), 1.0)
    den = s2 + a2 * z * z
    u = 0.5 * (1.0 - z) + 0.5 * s2 / den
    dudz = -0.5 - z * a2 / (den * den)
    fu = u * (nu - 1)
    iu = min(max(int(fu), 0), nu - 2)
    wu = fu - iu
    ft = (t + 1.0) * 0.5 * (nt - 1)
    it = min(max(int(ft), 0), nt - 2)
    wt = ft - it
    # t = x / s, s = √(1 − z²): dt/dn = b / s + t z h / s² (0 where t is clipped)
    gt0 = gt1 = gt2 = 0.0
    if s > 1e-9 and abs(x) < s:
        gt0 = b0 / s + t * z * h0 / s2
        gt1 = b1 / s + t * z * h1 / s2
        gt2 = b2 / s + t * z * h2 / s2
    return iu, wu, it, wt, dudz * h0, dudz * h1, dudz * h2, gt0, gt1, gt2


@_jit(nogil=True, error_model="numpy", fastmath=FAST)
def _poly(flat, o, d, rho):  # noqa: ANN001, ANN202
    """The polynomial in ρ of degree ``d`` whose coefficients start at ``flat[o]``, and its
    derivative (Horner)."""
    p = flat[o + d]
    dp = 0.0
    for j in range(d - 1, -1, -1):
        dp = dp * rho + p
        p = p * rho + flat[o + j]
    return p, dp


@_jit(nogil=True, error_model="numpy", fastmath=FAST)
def _interp(flat, nu, nt, nd, k, iu, wu, it, wt, rho):  # noqa: ANN001, ANN202
    """Bilinear value F, its slopes along u and t (per unit of u and t), and dF/dρ, from
    the table's coefficients ``flat`` (its (K, U, T, D + 1) array flattened: one index per
    load, not four)."""
    o = ((k * nu + iu) * nt + it) * nd
    p00, d00 = _poly(flat, o, nd - 1, rho)
    p01, d01 = _poly(flat, o + nd, nd - 1, rho)
    p10, d10 = _poly(flat, o + nt * nd, nd - 1, rho)
    p11, d11 = _poly(flat, o + (nt + 1) * nd, nd - 1, rho)
    f = (1.0 - wu) * ((1.0 - wt) * p00 + wt * p01) + wu * ((1.0 - wt) * p10 + wt * p11)
    fu = ((1.0 - wt) * (p10 - p00) + wt * (p11 - p01)) * (nu - 1)
    ft = ((1.0 - wu) * (p01 - p00) + wu * (p11 - p10)) * (nt - 1) * 0.5
    fr = (1.0 - wu) * ((1.0 - wt) * d00 + wt * d01) + wu * ((1.0 - wt) * d10 + wt * d11)
    return f, fu, ft, fr


@_jit(entry=True, nogil=True, error_model="numpy")
def table_value(values, frames, a2, k, n0, n1, n2, rho):  # noqa: ANN001, ANN201
    """The table's F of light k at the unit normal n and albedo ρ."""
    iu, wu, it, wt, _, _, _, _, _, _ = _cell(frames, a2, values.shape[1], values.shape[2], k,
                                             n0, n1, n2)
    if iu < 0:
        return 0.0
    nu, nt, nd = values.shape[1], values.shape[2], values.shape[3]
    return _interp(values.reshape(-1), nu, nt, nd, k, iu, wu, it, wt, rho)[0]


@_jit(nogil=True, error_model="numpy")
def _basis(n0, n1, n2):  # noqa: ANN001, ANN202
    """Orthonormal t1, t2 ⟂ n (Duff et al., JCGT 6(1), 2017, Listing 3; as
    :func:`roughdiffuse.stereo.rough._tangent_basis`)."""
    sgn = 1.0 if n2 >= 0 else -1.0
    a = -1.0 / (sgn + n2)
    b = n0 * n1 * a
    return (1.0 + sgn * n0 * n0 * a, sgn * b, -sgn * n0, b, sgn + n1 * n1 * a, -n1)


@_jit(nogil=True, error_model="numpy", fastmath=FAST)
def _system(flat, nu, nt, nd, frames, a2, e, obs, w, p, n, rho, amat, grad):  # noqa: ANN001, ANN202, PLR0913
    """Cost Σ r² of pixel p at normal n (3,) and albedos ρ (C,), with JᵀJ in ``amat`` and
    Jᵀr in ``grad`` (tangent offsets first, then the albedos); ``flat`` the table's
    coefficients flattened (sizes ``nu``, ``nt``, ``nd`` = D + 1), ``obs`` (P, K, C) and ``w``
    (P, K) pixel by pixel (each pixel's values side by side in memory)."""
    kk, c_count = obs.shape[1], obs.shape[2]
    m = 2 + c_count
    for i in range(m):
        grad[i] = 0.0
        for j in range(m):
            amat[i, j] = 0.0
    t10, t11, t12, t20, t21, t22 = _basis(n[0], n[1], n[2])
    n0, n1, n2 = n[0], n[1], n[2]
    # the normal's block in scalars (registers), the albedos' entries in the arrays
    cost = a00 = a01 = a11 = g0 = g1 = 0.0
    for k in range(kk):
        if w[p, k] == 0.0:
            continue
        iu, wu, it, wt, gu0, gu1, gu2, gt0, gt1, gt2 = _cell(frames, a2, nu, nt, k, n0, n1, n2)
        if iu < 0:
            for c in range(c_count):
                r = obs[p, k, c]
                cost += r * r
            continue
        # du/dn and dt/dn along the tangents
        ua, ub = gu0 * t10 + gu1 * t11 + gu2 * t12, gu0 * t20 + gu1 * t21 + gu2 * t22
        ta, tb = gt0 * t10 + gt1 * t11 + gt2 * t12, gt0 * t20 + gt1 * t21 + gt2 * t22
        for c in range(c_count):
            f, fu, ft, fr = _interp(flat, nu, nt, nd, k, iu, wu, it, wt, rho[c])
            ek = e[k, c]
            ja = ek * (fu * ua + ft * ta)
            jb = ek * (fu * ub + ft * tb)
            jr = ek * fr
            r = ek * f - obs[p, k, c]
            cost += r * r
            a00 += ja * ja
            a01 += ja * jb
            a11 += jb * jb
            g0 += ja * r
            g1 += jb * r
            amat[0, 2 + c] += ja * jr
            amat[1, 2 + c] += jb * jr
            amat[2 + c, 2 + c] += jr * jr
            grad[2 + c] += jr * r
    amat[0, 0], amat[0, 1], amat[1, 1] = a00, a01, a11
    grad[0], grad[1] = g0, g1
    for i in range(m):
        for j in range(i):
            amat[i, j] = amat[j, i]
    return cost


@_jit(nogil=True, error_model="numpy", fastmath=FAST)
def _cholesky_solve(a, b, lam, x, low):  # noqa: ANN001, ANN202
    """Solve (A + λ diag(A)) x = b for a small symmetric A (in place in ``x``; ``low``
    scratch); False when the damped matrix is not positive definite."""
    m = b.shape[0]
    for i in range(m):
        for j in range(i + 1):
            acc = a[i, j] + (lam * max(a[i, i], 1e-30) if i == j else 0.0)
            for q in range(j):
                acc -= low[i, q] * low[j, q]
            if i == j:
                if acc <= 0.0:
                    return False
                low[i, i] = math.sqrt(acc)
            else:
                low[i, j] = acc / low[j, j]
    for i in range(m):
        acc = b[i]
        for q in range(i):
            acc -= low[i, q] * x[q]
        x[i] = acc / low[i, i]
    for i in range(m - 1, -1, -1):
        acc = x[i]
        for q in range(i + 1, m):
            acc -= low[q, i] * x[q]
        x[i] = acc / low[i, i]
    return True


@_jit(entry=True, parallel=True, nogil=True, error_model="numpy", fastmath=FAST)
def solve(values, frames, a2, e, obs, w, ok, normals, albedo, iterations, tol, cost_out,  # noqa: ANN001, ANN201, PLR0913
          a_inv_out, steps_out):
    """Levenberg–Marquardt per pixel (see :func:`.coated_table.solve_pixels`), in place in
    ``normals`` and ``albedo``."""
    p_count, c_count = obs.shape[0], obs.shape[2]
    m = 2 + c_count
    nu, nt, nd = values.shape[1], values.shape[2], values.shape[3]
    flat = values.reshape(-1)
    for p in numba.prange(p_count):
        if not ok[p]:
            continue
        amat = np.zeros((m, m))
        grad = np.zeros(m)
        trial_a = np.zeros((m, m))
        trial_g = np.zeros(m)
        low = np.zeros((m, m))
        step = np.zeros(m)
        n = normals[p].copy()
        rho = albedo[p].copy()
        trial_n = np.zeros(3)
        trial_rho = np.zeros(c_count)
        cost = _system(flat, nu, nt, nd, frames, a2, e, obs, w, p, n, rho, amat, grad)
        lam = 1e-3
        taken = 0
        for _ in range(iterations):
            taken += 1
            if not _cholesky_solve(amat, grad, lam, step, low):
                lam *= 10.0
                if lam > 1e9:
                    break
                continue
            da = min(max(-step[0], -0.5), 0.5)
            db = min(max(-step[1], -0.5), 0.5)
            t10, t11, t12, t20, t21, t22 = _basis(n[0], n[1], n[2])
            trial_n[0] = n[0] + da * t10 + db * t20
            trial_n[1] = n[1] + da * t11 + db * t21
            trial_n[2] = n[2] + da * t12 + db * t22
            norm = math.sqrt(trial_n[0] ** 2 + trial_n[1] ** 2 + trial_n[2] ** 2)
            for i in range(3):
                trial_n[i] /= norm
            size = max(abs(da), abs(db))
            for c in range(c_count):
                trial_rho[c] = min(max(rho[c] - step[2 + c], 0.0), 1.0)
                size = max(size, abs(trial_rho[c] - rho[c]))
            if size < tol:
                # converged: the step from the current system is below the tolerance
                # (taking it, or damping it further, would change nothing that matters)
                break
            trial = _system(flat, nu, nt, nd, frames, a2, e, obs, w, p, trial_n, trial_rho,
                            trial_a, trial_g)
            if trial < cost:
                cost = trial
                n[:] = trial_n
                rho[:] = trial_rho
                amat[:, :] = trial_a
                grad[:] = trial_g
                lam = max(lam * 0.3, 1e-9)
            else:
                lam *= 10.0
                if lam > 1e9:
                    break
        normals[p] = n
        albedo[p] = rho
        cost_out[p] = cost
        steps_out[p] = taken
        # the diagonal of (JᵀJ)⁻¹, column by column
        unit = np.zeros(m)
        for i in range(m):
            unit[:] = 0.0
            unit[i] = 1.0
            if _cholesky_solve(amat, unit, 0.0, step, low):
                a_inv_out[p, i] = step[i]
            else:
                a_inv_out[p, i] = np.inf


@_jit(nogil=True, error_model="numpy")
def _horizon(height, step, cross, rise, out):  # noqa: ANN001, ANN202
    """``out[a, b]``: the highest the surface ``height`` (−∞ outside the object) stands
    above a ray from (a, b) stepping ``step`` (±1) along the second axis and ``cross``
    along the first per step, rising ``rise`` per step (−∞: nothing ahead). One sweep,
    from the far side: out = G(ahead) − rise, G = max(height, out), G between the two
    nearest entries of the column ahead taken linearly (the nearest one where one of them
    is −∞; −∞ beyond the array)."""
    na, nb = height.shape
    g = np.empty(na)
    first = nb - 1 if step > 0 else 0
    # the ray from entry a meets the column ahead at a + cross: between entries a + shift
    # and a + shift + 1, at the same fraction for every a
    shift = int(math.floor(cross))
    frac = cross - shift
    for a in range(na):
        out[a, first] = -np.inf
    for i in range(1, nb):
        b = first - i * step
        ahead = b + step
        for a in range(na):
            g[a] = max(height[a, ahead], out[a, ahead])
        for a in range(na):
            got = -np.inf
            at = a + cross
            if at > -0.5 and at < na - 0.5:
                a0, a1, f = a + shift, a + shift + 1, frac
                if a0 < 0:  # within half an entry of the first: that entry
                    a0, f = 0, 0.0
                if a1 > na - 1:
                    a1, f = na - 1, 0.0
                lo, hi = g[a0], g[a1]
                if np.isfinite(lo) and np.isfinite(hi):
                    got = lo * (1.0 - f) + hi * f
                else:
                    got = hi if f > 0.5 else lo
            out[a, b] = got - rise


@_jit(entry=True, parallel=True, nogil=True, error_model="numpy")
def sweep_shadows(height, rows, cols, z0, directions, tolerance, normals, keep, out):  # noqa: ANN001, ANN201, PLR0913
    """``out[k, p]``: 1 where observation (k, p) is kept, 0 where the surface ``height``
    (−∞ outside the object) stands more than ``tolerance`` above the ray from pixel p (row,
    column, start height z0) towards light k (see
    :func:`roughdiffuse.stereo.coated.cast_shadows`), where ``keep[k, p]`` is False, or,
    with ``normals`` (P, 3) of any rows, where the light is behind the pixel's normal
    (n·l ≤ 0, NaN included). One sweep of the image per light (:func:`_horizon`), across
    columns or rows whichever the light's direction in the image runs along more; parallel
    over the lights; the weights written in the same pass (no (K, P) temporaries)."""
    h, w = height.shape
    flipped = np.ascontiguousarray(height.T)
    lit_test = normals.shape[0] == rows.shape[0]
    for k in numba.prange(directions.shape[0]):
        lx, ly, lz = directions[k, 0], directions[k, 1], directions[k, 2]
        across = abs(lx) >= abs(ly)
        axis = math.hypot(lx, ly) < 1e-9  # on the view axis: a height field casts no shadow
        top = np.empty((1, 1))
        if not axis and across:  # one column per step; rows grow downwards (−y)
            top = np.empty((h, w))
            _horizon(height, 1 if lx > 0 else -1, -ly / abs(lx), lz / abs(lx), top)
        elif not axis:  # one row per step, on the transposed map
            top = np.empty((w, h))
            _horizon(flipped, -1 if ly > 0 else 1, lx / abs(ly), lz / abs(ly), top)
        for p in range(rows.shape[0]):
            ok = keep[k, p]
            if ok and lit_test:
                ok = normals[p, 0] * lx + normals[p, 1] * ly + normals[p, 2] * lz > 0.0
            if ok and not axis:
                above = top[rows[p], cols[p]] if across else top[cols[p], rows[p]]
                ok = not above > z0[p] + tolerance
            out[k, p] = 1.0 if ok else 0.0
