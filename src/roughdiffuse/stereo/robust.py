"""Robust Lambertian photometric stereo: L1, sparse-Bayesian and low-rank (RPCA) solvers.

Specular highlights and shadows break the Lambertian model I_k / E_k = l_k · b (b = ρ/π n,
see :mod:`.lambertian`) at a few lights per pixel. The robust solvers treat them as sparse
errors e, I / E = L b + e, and recover b without a threshold on brightness:

``l1``
    min_b ‖L b − m‖₁ per pixel (Ikehata, Wipf, Matsushita and Aizawa, "Robust photometric
    stereo using sparse regression", CVPR 2012: the convex relaxation of its ℓ0
    problem), solved by iteratively reweighted least squares with weights 1/|r_k|, finished
    at the vertex of the linear programme it reaches, and solved as that linear programme
    (HiGHS) where the vertex fails the optimality condition.
``sparse``
    sparse Bayesian learning (Ikehata, Wipf, Matsushita and Aizawa, "Photometric stereo
    using sparse Bayesian regression for general diffuse surfaces", IEEE TPAMI 36(9), 2014,
    with the Lambertian inlier model): each error e_k has a zero-mean Gaussian prior of its
    own variance γ_k; the EM updates alternate
    b = (Lᵀ Γ⁻¹ L + λ₂ I)⁻¹ Lᵀ Γ⁻¹ m and γ_k = e_k² + l_kᵀ (Lᵀ Γ⁻¹ L + λ₁ I)⁻¹ l_k,
    with e = m − L b, λ₁ = 1 and λ₂ = 10⁻⁶ (the values of the authors' code).
``rpca``
    low-rank matrix completion and recovery (Wu, Ganesh, Shi, Matsushita, Wang and Ma,
    "Robust photometric stereo via low-rank matrix completion and recovery", ACCV 2010):
    the K × P observation matrix D = A + E with A of rank 3 and E sparse,
    min ‖A‖_* + λ ‖E‖₁ subject to A + E = D on the observed entries, λ = 1/√max(K, P),
    by the inexact augmented Lagrange multiplier method (Lin, Chen and Ma, UIUC
    UILU-ENG-09-2215, 2009, Algorithm 5); then b = least squares of L b = A per pixel.

The observations used are the valid ones (finite, unsaturated); with ``shadow`` also the
dark ones are left out before the fit, as :func:`.lambertian.observation_weights` does, and
for ``rpca`` they become missing entries (the completion of Wu et al.). An
observation counts as rejected when its recovered error |e_k| exceeds both ``outlier`` times
the pixel's brightest used value and 3 robust standard deviations of the pixel's errors
(1.4826 × their median |e|): the result's ``weights`` are 0 there.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validate import ParameterError
from .inputs import StereoInput
from .lambertian import LambertianResult, albedo_and_residual, observation_weights

__all__ = ["ROBUST_METHODS", "robust"]

ROBUST_METHODS = ("l1", "sparse", "rpca")
"""The robust solvers of :func:`robust`."""

SBL_LAMBDA1 = 1.0
"""λ₁ of the sparse-Bayesian γ update (the prior variance scale of b in Σ_e)."""
SBL_LAMBDA2 = 1.0e-6
"""λ₂ of the sparse-Bayesian b update (a ridge keeping the normal equations regular)."""
GAMMA_FLOOR = 1.0e-8
"""Smallest γ_k: the variance of an inlier error is kept above it (numerical stability)."""
IRLS_FLOOR = 1.0e-8
"""Smallest √|r_k| in the IRLS weight 1/|r_k| (a floor of 10⁻¹⁶ on |r_k|)."""


def robust(
    data: StereoInput,
    method: str,
    *,
    shadow: float | None = None,
    outlier: float = 0.02,
    iterations: int = 1000,
    tol: float | None = None,
    progress: bool = False,
) -> LambertianResult:
    """Robust Lambertian photometric stereo on every object pixel.

    Parameters
    ----------
    data : StereoInput
        Images, lights and mask.
    method : {"l1", "sparse", "rpca"}
        The solver (see the module's description).
    shadow : float in [0, 1), optional
        Leave out, before the fit, observations darker than this fraction of the pixel's
        brightest; None (default) fits every valid observation, shadows included, as the
        papers do.
    outlier : float > 0
        An observation is rejected (weight 0) when its recovered error exceeds this fraction
        of the pixel's brightest used value, and 3 robust standard deviations of the
        pixel's errors.
    iterations : int
        Most iterations (IRLS, EM or ALM steps).
    tol : float, optional
        Convergence: per pixel ‖b − b_previous‖ < tol (``l1``, ``sparse``; default 1e-8) or
        ‖D − A − E‖_F / ‖D‖_F < tol (``rpca``; default 1e-6).
    progress : bool
        Show a progress bar.

    Returns
    -------
    LambertianResult
        Normals (NaN where fewer than 3 observations are used), albedo, residual over the
        kept observations, and ``weights`` (K, P): 1 kept, 0 left out or rejected.
    """
    if method not in ROBUST_METHODS:
        raise ParameterError(f"method must be one of {', '.join(ROBUST_METHODS)} (got {method!r})")
    if not (math.isfinite(outlier) and outlier > 0):
        raise ParameterError(f"outlier must be a finite number > 0 (got {outlier:g})")
    if int(iterations) != iterations or iterations < 1:
        raise ParameterError(f"iterations must be an integer >= 1 (got {iterations})")
    if tol is not None and not (math.isfinite(tol) and tol > 0):
        raise ParameterError(f"tol must be a finite number > 0 (got {tol:g})")
    grey = data.grey  # (K, P)
    used = data.observed if shadow is None else observation_weights(data, shadow) > 0
    l = data.directions
    if method == "rpca":
        b, err = _rpca(grey, used, l, int(iterations), 1e-6 if tol is None else tol, progress)
    else:
        solve = _irls_l1 if method == "l1" else _sbl
        b = solve(grey, used, l, int(iterations), 1e-8 if tol is None else tol, progress)
        err = grey - l @ np.nan_to_num(b).T
    enough = used.sum(axis=0) >= 3
    length = np.linalg.norm(b, axis=-1)
    ok = enough & np.isfinite(length) & (length > 0)
    normals = np.where(ok[:, None], b / np.where(ok, length, 1.0)[:, None], np.nan)
    kept = used & (np.abs(err) <= _outlier_bound(err, used, grey, outlier))
    return albedo_and_residual(data, normals, kept.astype(np.float64))


MAD_SCALE = 1.4826
"""σ of a normal distribution per median absolute deviation (1 / Φ⁻¹(3/4))."""


def _outlier_bound(err: np.ndarray, used: np.ndarray, grey: np.ndarray, outlier: float) -> Any:
    """Per pixel, the largest error |e_k| of an inlier: ``outlier`` times the brightest used
    value, or 3 robust standard deviations of the used errors (1.4826 × their median
    absolute value) if that is larger. At least half the used observations are inliers."""
    top = np.max(np.where(used, grey, 0.0), axis=0)
    a = np.where(used, np.abs(err), np.nan)
    spread = np.zeros(err.shape[1])
    some = used.any(axis=0)
    spread[some] = 3.0 * MAD_SCALE * np.nanmedian(a[:, some], axis=0)
    return np.maximum(outlier * top, spread)[None, :]


def _bar(total: int, desc: str, show: bool) -> Any:
    from ..progress import progress

    return progress(total, desc, unit="iteration", enabled=show)


PAIRS = ((0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2))
"""The 6 entries (i, j) of a symmetric 3 × 3 matrix, diagonal first."""


def _outer6(l: np.ndarray) -> np.ndarray:
    """(K, 6): the entries :data:`PAIRS` of l_k l_kᵀ."""
    return np.stack([l[:, i] * l[:, j] for i, j in PAIRS], axis=1)


def _sym_inverse(g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Inverse (n, 6) and determinant (n,) of symmetric 3 × 3 matrices given as (n, 6)
    (:data:`PAIRS`), by the adjugate: faster than batched LAPACK at this size."""
    a, d, f, b, c, e = (g[:, k] for k in range(6))  # [[a, b, c], [b, d, e], [c, e, f]]
    adj = np.stack(
        [d * f - e * e, a * f - c * c, a * d - b * b, c * e - b * f, b * e - c * d, b * c - a * e],
        axis=1,
    )
    det = a * adj[:, 0] + b * adj[:, 3] + c * adj[:, 4]
    safe = np.where(det != 0, det, np.nan)
    return adj / safe[:, None], det


def _sym_apply(inv: np.ndarray, v: np.ndarray) -> np.ndarray:
    """(n, 3): symmetric matrices (n, 6) times vectors (n, 3)."""
    a, d, f, b, c, e = (inv[:, k] for k in range(6))
    x, y, z = v[:, 0], v[:, 1], v[:, 2]
    return np.stack([a * x + b * y + c * z, b * x + d * y + e * z, c * x + e * y + f * z], axis=1)


def _sqrt_weighted_solve(sw: np.ndarray, l: np.ndarray, m: np.ndarray) -> np.ndarray:
    """b per pixel minimising Σ_k (sw_k (l_k·b − m_k))²; sw, m (K, P).

    Solved by a QR factorisation of diag(sw) L per pixel, not the normal equations: the
    weights of IRLS span 16 orders of magnitude near the solution, and squaring them
    would lose every digit.
    """
    a = sw.T[:, :, None] * l[None]  # (P, K, 3)
    q, r = np.linalg.qr(a)
    rhs = np.einsum("pki,kp->pi", q, sw * m)
    out = np.full((sw.shape[1], 3), np.nan)
    diag = np.abs(np.diagonal(r, axis1=1, axis2=2))
    good = np.all(diag > 1e-12 * np.maximum(diag.max(axis=1, keepdims=True), 1e-300), axis=1)
    out[good] = np.linalg.solve(r[good], rhs[good][..., None])[..., 0]
    return out


def _irls_l1(
    m: np.ndarray, used: np.ndarray, l: np.ndarray, iterations: int, tol: float, show: bool
) -> np.ndarray:
    """min_b Σ_k |l_k·b − m_k| over the used observations, every pixel at once.

    IRLS: the weighted least squares of weights 1/|r_k| has the L1 cost as its fixed point
    (a majoriser of |r| at the current r). Its end is polished: the minimum of a linear
    programme in 3 unknowns lies at a vertex where 3 residuals vanish, so the 3 smallest
    residuals are made exactly 0 when that does not raise the cost.
    """
    from ..progress import finish

    k, p = m.shape
    uw = used.astype(np.float64)
    b = np.ones((p, 3))  # the reference's start, x = 1
    sw = uw.copy()  # square roots of the weights
    active = np.ones(p, dtype=bool)
    with _bar(iterations, "l1 (IRLS)", show) as bar:
        for it in range(iterations):
            idx = np.flatnonzero(active)
            new = _sqrt_weighted_solve(sw[:, idx], l, m[:, idx])
            step = np.linalg.norm(new - b[idx], axis=-1)
            b[idx] = new
            r = m[:, idx] - l @ np.nan_to_num(new).T
            sw[:, idx] = uw[:, idx] / np.maximum(np.sqrt(np.abs(r)), IRLS_FLOOR)
            active[idx[~(step >= tol)]] = False  # converged, or NaN (too few observations)
            bar.update(1)
            if not active.any():
                finish(bar, f"converged after {it + 1} of {iterations} iterations")
                break
    b = _vertex_polish(m, used, l, b)
    return _lp_finish(m, used, l, b)


def _vertex_polish(m: np.ndarray, used: np.ndarray, l: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Move each b to the LP vertex through its 3 smallest used residuals if that is cheaper."""
    ok = np.all(np.isfinite(b), axis=-1) & (used.sum(axis=0) >= 3)
    if not ok.any():
        return b
    idx = np.flatnonzero(ok)
    r = np.abs(m[:, idx] - l @ b[idx].T)
    r = np.where(used[:, idx], r, np.inf)
    three = np.argsort(r, axis=0)[:3]  # (3, n)
    a = l[three].transpose(1, 0, 2)  # (n, 3, 3)
    rhs = np.take_along_axis(m[:, idx], three, axis=0).T  # (n, 3)
    regular = np.abs(np.linalg.det(a)) > 1e-12
    cand = b[idx].copy()
    cand[regular] = np.linalg.solve(a[regular], rhs[regular][..., None])[..., 0]
    u = used[:, idx]
    cost_old = np.sum(np.where(u, np.abs(m[:, idx] - l @ b[idx].T), 0.0), axis=0)
    cost_new = np.sum(np.where(u, np.abs(m[:, idx] - l @ cand.T), 0.0), axis=0)
    better = regular & (cost_new <= cost_old)
    out = b.copy()
    out[idx[better]] = cand[better]
    return out


def _not_optimal(m: np.ndarray, used: np.ndarray, l: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Pixels whose b is not shown to minimise the L1 cost (P,): off a vertex, or at one
    that fails the optimality condition.

    At a vertex where the residuals of the set B (the 3 smallest) vanish, b is optimal iff
    some u ∈ [−1, 1]³ balances the other residuals' signs: Σ_{k∉B} sign(r_k) l_k + L_Bᵀ u = 0
    (the subgradient condition of min ‖L b − m‖₁).
    """
    ok = np.all(np.isfinite(b), axis=-1) & (used.sum(axis=0) >= 3)
    bad = np.zeros(b.shape[0], dtype=bool)
    idx = np.flatnonzero(ok)
    if idx.size == 0:
        return bad
    r = np.where(used[:, idx], m[:, idx] - l @ b[idx].T, 0.0)
    three = np.argsort(np.where(used[:, idx], np.abs(r), np.inf), axis=0)[:3]
    sign = np.sign(r)
    np.put_along_axis(sign, three, 0.0, axis=0)
    g = -(sign.T @ l)  # (n, 3)
    lb = l[three].transpose(1, 2, 0)  # (n, 3, 3): columns l_k, k in B
    regular = np.abs(np.linalg.det(lb)) > 1e-12
    u = np.full((idx.size, 3), np.inf)
    u[regular] = np.linalg.solve(lb[regular], g[regular][..., None])[..., 0]
    small = np.take_along_axis(np.abs(r), three, axis=0).max(axis=0)
    off_vertex = small > 1e-12 * (1.0 + np.max(np.abs(m[:, idx]), axis=0))
    bad[idx] = off_vertex | (np.max(np.abs(u), axis=-1) > 1.0 + 1e-9)
    return bad


def _lp_finish(m: np.ndarray, used: np.ndarray, l: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Solve min ‖L b − m‖₁ as a linear programme (HiGHS) where IRLS stopped short.

    IRLS can stall at a vertex that is not optimal: a residual that reached 0 gets a weight
    of 10¹⁶ and stays 0. Those few pixels (:func:`_not_optimal`) are solved exactly:
    min Σ t_k subject to −t ≤ L b − m ≤ t over the used observations.
    """
    from scipy.optimize import linprog

    out = b.copy()
    for j in np.flatnonzero(_not_optimal(m, used, l, b)):
        keep = used[:, j]
        lk, mk = l[keep], m[keep, j]
        k = lk.shape[0]
        c = np.r_[np.zeros(3), np.ones(k)]
        a = np.block([[lk, -np.eye(k)], [-lk, -np.eye(k)]])
        bounds = [(None, None)] * 3 + [(0, None)] * k
        lp = linprog(c, A_ub=a, b_ub=np.r_[mk, -mk], bounds=bounds, method="highs")
        if lp.status == 0:
            out[j] = lp.x[:3]
    return out


def _sbl(
    m: np.ndarray, used: np.ndarray, l: np.ndarray, iterations: int, tol: float, show: bool
) -> np.ndarray:
    """Sparse Bayesian learning of b with sparse errors (Ikehata et al. 2014).

    Each pixel runs the EM updates of the module's description until ‖b − b_prev‖ < tol;
    unused observations have Γ⁻¹ = 0 (no information).
    """
    from ..progress import finish

    k, p = m.shape
    uw = used.astype(np.float64)
    gamma = np.ones((k, p))
    b = np.full((p, 3), 1000.0)  # the reference's start
    ll = _outer6(l)  # (K, 6)
    twice = np.array([1.0, 1.0, 1.0, 2.0, 2.0, 2.0])  # off-diagonal entries count twice
    eye = np.array([1.0, 1.0, 1.0, 0.0, 0.0, 0.0])  # I in the entries of PAIRS
    active = np.ones(p, dtype=bool)
    with _bar(iterations, "sparse (SBL)", show) as bar:
        for it in range(iterations):
            idx = np.flatnonzero(active)
            w = uw[:, idx] / gamma[:, idx]  # Γ⁻¹
            gram = w.T @ ll  # (n, 6): Lᵀ Γ⁻¹ L
            inv2, det2 = _sym_inverse(gram + SBL_LAMBDA2 * eye)
            new = _sym_apply(inv2, (w * m[:, idx]).T @ l)
            new[det2 == 0] = np.nan
            step = np.linalg.norm(new - b[idx], axis=-1)
            b[idx] = new
            e = m[:, idx] - l @ np.nan_to_num(new).T
            inv1, _ = _sym_inverse(gram + SBL_LAMBDA1 * eye)
            sigma_e = ll @ (inv1 * twice).T  # (K, n): l_kᵀ (Lᵀ Γ⁻¹ L + λ₁ I)⁻¹ l_k
            gamma[:, idx] = np.maximum(e * e + sigma_e, GAMMA_FLOOR)
            active[idx[~(step >= tol)]] = False
            bar.update(1)
            if not active.any():
                finish(bar, f"converged after {it + 1} of {iterations} iterations")
                break
    return b


def _singular_value_threshold(x: np.ndarray, tau: float) -> np.ndarray:
    """D_τ(X) = U max(S − τ, 0) Vᵀ for a short, wide X (K × P, K ≪ P).

    From the eigenvectors U and eigenvalues S² of the K × K matrix X Xᵀ: D_τ(X) =
    U_r diag(1 − τ/s_r) U_rᵀ X over the singular values s_r > τ, with no P × P or K × P
    factor; a singular value below about 10⁻⁸ of the largest is lost in X Xᵀ, where the
    threshold has already set it to 0.
    """
    w, u = np.linalg.eigh(x @ x.T)
    s = np.sqrt(np.clip(w, 0.0, None))
    keep = s > tau
    ur = u[:, keep]
    return (ur * (1.0 - tau / s[keep])) @ (ur.T @ x)


def _rpca(
    d: np.ndarray, used: np.ndarray, l: np.ndarray, iterations: int, tol: float, show: bool
) -> tuple[np.ndarray, np.ndarray]:
    """Wu et al. 2010: D = A + E by inexact ALM (Lin, Chen and Ma 2009, Algorithm 5).

    Each step: E = S_{λ/μ}(D − A + Y/μ) on the observed entries (soft threshold; on the
    missing ones E takes the whole difference), A = D_{1/μ}(D − E + Y/μ) (singular value
    threshold, :func:`_singular_value_threshold`), Y += μ (D − A − E), μ = min(ρ μ, μ̄)
    with ρ = 1.5, μ₀ = 1.25/‖D‖₂, μ̄ = 10⁷ μ₀. Returns b (P, 3), the least squares of
    L b = A per pixel, and E (K, P).
    """
    from ..progress import finish

    k, p = d.shape
    d = np.where(used, d, 0.0)
    lam = 1.0 / math.sqrt(max(k, p))
    norm_two = float(np.linalg.norm(d, 2))
    if norm_two == 0:
        return np.full((p, 3), np.nan), np.zeros_like(d)
    y = d / max(norm_two, float(np.max(np.abs(d))) / lam)
    a = np.zeros_like(d)
    e = np.zeros_like(d)
    mu = 1.25 / norm_two
    mu_bar = mu * 1e7
    d_norm = float(np.linalg.norm(d))
    with _bar(iterations, "rpca (inexact ALM)", show) as bar:
        for it in range(iterations):
            t = d - a + y / mu
            shrunk = np.maximum(t - lam / mu, 0.0) + np.minimum(t + lam / mu, 0.0)
            e = np.where(used, shrunk, t)
            a = _singular_value_threshold(d - e + y / mu, 1.0 / mu)
            z = d - a - e
            y = y + mu * z
            mu = min(mu * 1.5, mu_bar)
            bar.update(1)
            if np.linalg.norm(z) / d_norm < tol:
                finish(bar, f"converged after {it + 1} of {iterations} iterations")
                break
    b = np.linalg.lstsq(l, a, rcond=None)[0].T
    return b, np.where(used, e, 0.0)
