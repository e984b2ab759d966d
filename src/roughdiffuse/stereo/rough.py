"""Photometric stereo with a rough-diffuse model: a batched per-pixel nonlinear fit.

Lambertian photometric stereo (:mod:`.lambertian`) is biased on rough matte objects: their
brightness does not follow n·l (Oren and Nayar, "Generalization of Lambert's reflectance
model", SIGGRAPH 1994; for shape from shading, Ju, Tozza, Breuß, Bruhn and Kleefeld, "Shape
from Shading for Rough Surfaces: Analysis of the Oren–Nayar Model", BMVC 2012). Here every
object pixel p gets its own normal n_p and albedo ρ_p (per channel), and the roughness of the
chosen model is either one value for the whole object or one per pixel. The image model is
the renderer's: I_kc = E_kc f_r(l_k, v; n_p, ρ_pc, σ) max(n_p·l_k, 0), with v = +z.

The fit minimises Σ w_kp (I_kc − Î_kc)² by Levenberg–Marquardt, vectorised over the pixels
with ``jax.vmap`` and forward-mode Jacobians (``jax.jacfwd``) of the model's own formula.
A normal is updated in its tangent plane (two parameters, renormalised after each step), so
no parametrisation is singular. A global roughness couples every pixel: its Gauss–Newton step
uses the Schur complement of the block-diagonal per-pixel system (the reduced camera system of
bundle adjustment; Triggs et al., "Bundle Adjustment — A Modern Synthesis", 2000, Sec. 6.1),
after the per-pixel parameters have been refined for the current roughness.

Standard errors are the Gauss–Newton ones, s² (JᵀJ)⁻¹ with s² the residual variance, per
pixel; for the global roughness from the Schur complement, with s² over all pixels.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..models.base import Model
from .inputs import StereoInput
from .lambertian import LambertianResult, lambertian, observation_weights

__all__ = ["RoughResult", "roughness_parameter", "rough"]

CHUNK = 1 << 14
"""Pixels per compiled step (bounds the Jacobian's memory: CHUNK × K × C × parameters)."""


def roughness_parameter(model: Model) -> str:
    """Name of the model's roughness parameter: its one numeric parameter besides albedo."""
    names = [f for f in model.array_fields if f != "albedo"]
    if "albedo" not in model.array_fields or len(names) != 1:
        raise ValueError(
            f"{type(model).__name__} has no single roughness parameter beside an albedo "
            f"(numeric parameters: {', '.join(model.array_fields) or 'none'}); "
            "name it with roughness=..."
        )
    return names[0]


@dataclass
class RoughResult:
    """Per-pixel results of rough photometric stereo (P object pixels).

    Attributes
    ----------
    normals : array (P, 3)
        Unit normals, camera frame.
    albedo : array (P, C)
    roughness : float or array (P,)
        The fitted roughness: one value, or one per pixel.
    roughness_name : str
        The model parameter it is (e.g. ``"sigma"``).
    roughness_se : float or array (P,)
        Its standard error.
    normal_se : array (P,)
        Angular standard error of each normal, radians.
    albedo_se : array (P, C)
    residual : array (P,)
        RMS residual over the kept observations, relative to the pixel's mean value.
    weights : array (K, P)
        Observations used (shadows and invalid values left out).
    iterations : int
    """

    normals: np.ndarray
    albedo: np.ndarray
    roughness: Any
    roughness_name: str
    roughness_se: Any
    normal_se: np.ndarray
    albedo_se: np.ndarray
    residual: np.ndarray
    weights: np.ndarray
    iterations: int


def _tangent_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Orthonormal t1, t2 ⟂ n (Frisvad's construction, branch on the sign of z)."""
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    s = np.where(z >= 0, 1.0, -1.0)
    a = -1.0 / (s + z)
    b = x * y * a
    t1 = np.stack([1.0 + s * x * x * a, s * b, -s * x], axis=-1)
    t2 = np.stack([b, s + y * y * a, -y], axis=-1)
    return t1, t2


def _make_steps(model: Model, name: str, channels: int, per_pixel: bool) -> dict[str, Any]:
    """Compiled residual/Jacobian functions for one (model, roughness, channels) setting."""
    import jax
    import jax.numpy as jnp

    def predict(theta: Any, s: Any, n0: Any, t1: Any, t2: Any, l: Any, e: Any) -> Any:
        n = n0 + theta[0] * t1 + theta[1] * t2
        n = n / jnp.sqrt(jnp.sum(n * n))
        rho = theta[2 : 2 + channels]
        m = dataclasses.replace(model, albedo=rho if channels > 1 else rho[0], **{name: s})
        mu_i = l @ n  # (K,)
        mu_o = n[2] + 0.0 * mu_i
        cos_io = l[:, 2]
        f = m.brdf_cosines(mu_i, mu_o, cos_io)  # (K,) or (K, C)
        f = f if channels > 1 else f[:, None]
        return e * f * jnp.maximum(mu_i, 0.0)[:, None]  # (K, C)

    def resid(theta: Any, g: Any, n0: Any, t1: Any, t2: Any, l: Any, e: Any, obs: Any, w: Any):
        s = theta[-1] if per_pixel else g
        r = (predict(theta, s, n0, t1, t2, l, e) - obs) * jnp.sqrt(w)[:, None]
        return r.reshape(-1)

    jac_local = jax.jacfwd(resid, argnums=0)
    jac_global = jax.jacfwd(resid, argnums=1)

    def one(theta, g, n0, t1, t2, l, e, obs, w):  # noqa: ANN001, ANN202
        r = resid(theta, g, n0, t1, t2, l, e, obs, w)
        ju = jac_local(theta, g, n0, t1, t2, l, e, obs, w)
        jg = jac_global(theta, g, n0, t1, t2, l, e, obs, w)
        return r, ju, jg

    axes = (0, None, 0, 0, 0, None, None, 1, 1)
    batched = jax.jit(jax.vmap(one, in_axes=axes))
    cost = jax.jit(jax.vmap(lambda *a: jnp.sum(resid(*a) ** 2), in_axes=axes))
    return {"batched": batched, "cost": cost}


def rough(
    data: StereoInput,
    model: Model,
    *,
    roughness: str | None = None,
    per_pixel: bool = False,
    start: LambertianResult | None = None,
    initial_roughness: float | None = None,
    shadow: float = 0.02,
    iterations: int = 30,
    progress: bool = False,
) -> RoughResult:
    """Fit normals, albedo and roughness of a rough-diffuse ``model`` to every object pixel.

    Parameters
    ----------
    data : StereoInput
        K ≥ 3 images with their lights and mask.
    model : Model
        The reflectance model, e.g. ``OrenNayar(variant="full")``; its albedo and roughness
        are fitted, its other parameters are kept.
    roughness : str, optional
        Name of the roughness parameter (default: the model's one numeric parameter besides
        the albedo, see :func:`roughness_parameter`).
    per_pixel : bool
        One roughness per pixel instead of one for the object.
    start : LambertianResult, optional
        Starting normals and albedo (default: Lambertian photometric stereo).
    initial_roughness : float, optional
        Starting roughness (default: a quarter of the parameter's upper bound, or 0.3).
    shadow : float
        Observations darker than this fraction of the pixel's brightest are left out.
    iterations : int
        Outer iterations (each: a few per-pixel LM steps, then a roughness step).
    progress : bool
        Show a progress bar.

    Returns
    -------
    RoughResult
    """
    import jax
    import jax.numpy as jnp

    from .._array import double_precision

    if not isinstance(model, Model):
        raise ValueError(f"model must be a roughdiffuse Model (got {type(model).__name__})")
    name = roughness or roughness_parameter(model)
    if name not in model.array_fields:
        raise ValueError(f"{type(model).__name__} has no numeric parameter {name!r}")
    if not isinstance(iterations, int) or iterations < 1:
        raise ValueError(f"iterations must be a positive integer (got {iterations!r})")
    hi = _upper_bound(model, name)
    s0 = float(initial_roughness) if initial_roughness is not None else min(0.3, 0.25 * hi)
    if not 0.0 <= s0 <= hi:
        raise ValueError(f"initial_roughness must be in [0, {hi:g}] (got {s0:g})")
    start = lambertian(data, shadow=shadow) if start is None else start
    w = observation_weights(data, shadow)  # (K, P)
    m = data.mask
    obs = data.images[:, m, :]  # (K, P, C)
    p_count, c = obs.shape[1], data.channels
    ok = np.all(np.isfinite(start.normals), axis=1) & (w.sum(axis=0) >= 3)
    n0 = np.where(ok[:, None], np.nan_to_num(start.normals), [0.0, 0.0, 1.0])
    n0[:, 2] = np.maximum(n0[:, 2], 1e-3)
    n0 /= np.linalg.norm(n0, axis=1, keepdims=True)
    rho = np.clip(np.nan_to_num(start.albedo, nan=0.5), 1e-3, None)
    nu = 2 + c + (1 if per_pixel else 0)
    theta = np.zeros((p_count, nu))
    theta[:, 2 : 2 + c] = rho
    if per_pixel:
        theta[:, -1] = s0
    wk = np.where(ok[None, :], w, 0.0)

    with double_precision(jnp):
        steps = _make_steps(model, name, c, per_pixel)
        l = jnp.asarray(data.directions)
        e = jnp.asarray(data.intensities)
        lam = np.full(p_count, 1e-3)
        g = s0
        tr = 0.25 * hi  # trust region of the global step
        bar = _progress(iterations, progress)
        done = 0
        for it in range(iterations):
            done = it + 1
            # 1. per-pixel LM for the current roughness
            for _ in range(4):
                theta, n0, lam = _local_step(
                    steps, theta, n0, lam, g, l, e, obs, wk, c, hi, per_pixel
                )
            if per_pixel:
                bar.update(1)
                continue
            # 2. the global roughness: Schur-complement Gauss–Newton step
            cost0, step = _global_step(steps, theta, n0, g, l, e, obs, wk)
            step = float(np.clip(step, -tr, tr))
            g_new = float(np.clip(g + step, 0.0, hi))
            theta_new, n_new, lam_new = theta, n0, lam.copy()
            for _ in range(2):
                theta_new, n_new, lam_new = _local_step(
                    steps, theta_new, n_new, lam_new, g_new, l, e, obs, wk, c, hi, per_pixel
                )
            cost1 = _total_cost(steps, theta_new, n_new, g_new, l, e, obs, wk)
            if cost1 <= cost0:
                converged = abs(g_new - g) < 1e-7 and cost0 - cost1 <= 1e-10 * max(cost0, 1e-300)
                theta, n0, lam, g = theta_new, n_new, lam_new, g_new
                tr = min(2.0 * tr, 0.25 * hi)
                bar.update(1)
                if converged:
                    break
            else:
                tr *= 0.25
                bar.update(1)
                if tr < 1e-9:
                    break
        bar.close()
        # standard errors at the solution
        r, ju, jg = _jacobians(steps, theta, n0, g, l, e, obs, wk)
        _ = jax  # (jax imported for the compiled functions above)
    dof_p = np.maximum(wk.sum(axis=0) * c - nu, 1)
    cost_p = np.sum(r * r, axis=1)
    a = np.einsum("pri,prj->pij", ju, ju)
    a_inv = np.linalg.pinv(a)
    s2_p = cost_p / dof_p
    var_local = a_inv[:, np.arange(nu), np.arange(nu)] * s2_p[:, None]
    normal_se = np.sqrt(np.maximum(var_local[:, 0] + var_local[:, 1], 0.0))
    albedo_se = np.sqrt(np.maximum(var_local[:, 2 : 2 + c], 0.0))
    if per_pixel:
        rough_val: Any = theta[:, -1].copy()
        rough_se: Any = np.sqrt(np.maximum(var_local[:, -1], 0.0))
    else:
        b = np.einsum("pri,pr->pi", ju, jg)
        schur = float(np.sum(jg * jg) - np.einsum("pi,pij,pj->", b, a_inv, b))
        dof = max(float(wk.sum() * c - ok.sum() * nu - 1), 1.0)
        s2 = float(np.sum(cost_p)) / dof
        rough_val = g
        rough_se = math.sqrt(s2 / schur) if schur > 0 else math.inf
    kept = wk.sum(axis=0) * c
    mean = np.einsum("kp,kpc->p", wk, obs) / np.maximum(kept, 1)
    rel = np.sqrt(cost_p / np.maximum(kept, 1)) / np.maximum(mean, 1e-30)
    normals = np.where(ok[:, None], n0, np.nan)
    return RoughResult(
        normals=normals,
        albedo=np.where(ok[:, None], theta[:, 2 : 2 + c], np.nan),
        roughness=rough_val,
        roughness_name=name,
        roughness_se=rough_se,
        normal_se=np.where(ok, normal_se, np.nan),
        albedo_se=np.where(ok[:, None], albedo_se, np.nan),
        residual=np.where(ok, rel, np.nan),
        weights=wk,
        iterations=done,
    )


def _upper_bound(model: Model, name: str) -> float:
    """The parameter's declared upper bound (π/2 for an angle when none is declared)."""
    for p in getattr(model, "params", ()) or ():
        if getattr(p, "name", None) == name and getattr(p, "max", None) is not None:
            hi = float(p.max)
            if math.isfinite(hi):
                return hi
    return math.pi / 2 if name == "sigma" else 1.0


def _progress(total: int, show: bool) -> Any:
    from tqdm.auto import tqdm

    return tqdm(total=total, desc="rough photometric stereo", unit="it", disable=not show)


def _chunks(p: int) -> list[slice]:
    return [slice(s, min(s + CHUNK, p)) for s in range(0, p, CHUNK)]


def _pad(a: np.ndarray, size: int, axis: int) -> np.ndarray:
    extra = size - a.shape[axis]
    if extra <= 0:
        return a
    pad = [(0, 0)] * a.ndim
    pad[axis] = (0, extra)
    return np.pad(a, pad, mode="edge")


def _call(fn: Any, theta, n0, g, l, e, obs, w, sl: slice) -> Any:  # noqa: ANN001
    """``fn`` on one chunk of pixels, padded to CHUNK rows so that it compiles once."""
    t1, t2 = _tangent_basis(n0[sl])
    n = sl.stop - sl.start
    size = CHUNK if n > CHUNK // 4 else 1 << max(int(math.ceil(math.log2(max(n, 1)))), 4)
    args = (
        _pad(theta[sl], size, 0),
        g,
        _pad(n0[sl], size, 0),
        _pad(t1, size, 0),
        _pad(t2, size, 0),
        l,
        e,
        _pad(obs[:, sl], size, 1),
        _pad(w[:, sl], size, 1),
    )
    out = fn(*args)
    if isinstance(out, tuple):
        return tuple(np.asarray(o)[:n] for o in out)
    return np.asarray(out)[:n]


def _jacobians(steps, theta, n0, g, l, e, obs, w):  # noqa: ANN001, ANN202
    parts = [_call(steps["batched"], theta, n0, g, l, e, obs, w, sl) for sl in _chunks(len(theta))]
    return tuple(np.concatenate([p[k] for p in parts]) for k in range(3))


def _costs(steps, theta, n0, g, l, e, obs, w) -> np.ndarray:  # noqa: ANN001
    return np.concatenate(
        [_call(steps["cost"], theta, n0, g, l, e, obs, w, sl) for sl in _chunks(len(theta))]
    )


def _total_cost(steps, theta, n0, g, l, e, obs, w) -> float:  # noqa: ANN001
    return float(np.sum(_costs(steps, theta, n0, g, l, e, obs, w)))


def _retract(theta: np.ndarray, n0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Move the tangent-plane offsets into the normal: n0 <- normalise(n0 + a t1 + b t2)."""
    t1, t2 = _tangent_basis(n0)
    n = n0 + theta[:, :1] * t1 + theta[:, 1:2] * t2
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    out = theta.copy()
    out[:, :2] = 0.0
    return out, n


def _clamp(theta: np.ndarray, c: int, hi: float, per_pixel: bool) -> np.ndarray:
    out = theta.copy()
    out[:, :2] = np.clip(out[:, :2], -0.5, 0.5)  # at most ~27° per step
    out[:, 2 : 2 + c] = np.maximum(out[:, 2 : 2 + c], 0.0)
    if per_pixel:
        out[:, -1] = np.clip(out[:, -1], 0.0, hi)
    return out


def _local_step(steps, theta, n0, lam, g, l, e, obs, w, c, hi, per_pixel):  # noqa: ANN001, ANN202
    """One Levenberg–Marquardt step of every pixel's own parameters (accepted per pixel)."""
    r, ju, _ = _jacobians(steps, theta, n0, g, l, e, obs, w)
    a = np.einsum("pri,prj->pij", ju, ju)
    grad = np.einsum("pri,pr->pi", ju, r)
    cost0 = np.sum(r * r, axis=1)
    diag = np.einsum("pii->pi", a)
    damped = a + (lam[:, None] * np.maximum(diag, 1e-12))[:, :, None] * np.eye(a.shape[1])
    try:
        delta = -np.linalg.solve(damped, grad[..., None])[..., 0]
    except np.linalg.LinAlgError:
        delta = -(np.linalg.pinv(damped) @ grad[..., None])[..., 0]
    trial = _clamp(theta + delta, c, hi, per_pixel)
    cost1 = _costs(steps, trial, n0, g, l, e, obs, w)
    better = cost1 < cost0
    theta = np.where(better[:, None], trial, theta)
    lam = np.where(better, np.maximum(lam * 0.3, 1e-9), np.minimum(lam * 10.0, 1e9))
    theta, n0 = _retract(theta, n0)
    return theta, n0, lam


def _global_step(steps, theta, n0, g, l, e, obs, w) -> tuple[float, float]:  # noqa: ANN001
    """Gauss–Newton step of the global roughness with the per-pixel parameters eliminated."""
    r, ju, jg = _jacobians(steps, theta, n0, g, l, e, obs, w)
    a = np.einsum("pri,prj->pij", ju, ju)
    a += 1e-9 * np.maximum(np.einsum("pii->pi", a), 1e-12)[:, :, None] * np.eye(a.shape[1])
    a_inv = np.linalg.pinv(a)
    b = np.einsum("pri,pr->pi", ju, jg)
    gu = np.einsum("pri,pr->pi", ju, r)
    schur = float(np.sum(jg * jg) - np.einsum("pi,pij,pj->", b, a_inv, b))
    rhs = float(np.sum(jg * r) - np.einsum("pi,pij,pj->", b, a_inv, gu))
    step = -rhs / schur if schur > 0 else 0.0
    return float(np.sum(r * r)), step
