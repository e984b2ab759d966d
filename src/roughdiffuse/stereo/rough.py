"""Photometric stereo with a rough-diffuse model: a batched per-pixel nonlinear fit.

Lambertian photometric stereo (:mod:`.lambertian`) is biased on rough matte objects: their
brightness does not follow n·l (Oren and Nayar, "Generalization of Lambert's reflectance
model", SIGGRAPH 1994; for shape from shading, Ju, Tozza, Breuß, Bruhn and Kleefeld, "Shape
from Shading for Rough Surfaces: Analysis of the Oren–Nayar Model", BMVC 2012). Here every
object pixel p gets its own normal n_p and albedo ρ_p (per channel), and the roughness of the
chosen model is either one value for the whole object or one per pixel. The image model is
the renderer's: I_kc = E_kc f_r(l_k, v; n_p, ρ_pc, σ) max(n_p·l_k, 0), with v = +z.

The fit minimises Σ w_kp (I_kc − Î_kc)² by Levenberg–Marquardt, on whole arrays of pixels,
with forward-mode Jacobians (``jax.jvp`` with a batch of tangents) of the model's own formula.
A normal is updated in its tangent plane (two parameters, renormalised after each step), so
no parametrisation is singular. A global roughness couples every pixel: its Gauss–Newton step
uses the Schur complement of the block-diagonal per-pixel system (the reduced camera system of
bundle adjustment; Triggs et al., "Bundle Adjustment — A Modern Synthesis", 2000, Sec. 6.1),
after the per-pixel parameters have been refined for the current roughness; its start comes
from the same fit on a random subset of the pixels.

Speed (:mod:`roughdiffuse.bench.stereo_bench`): the pixels go in cache-sized chunks, each
running several LM steps in one compiled loop, on as many threads as there are cores; the
model's terms that depend only on the pixel (n·v) or only on the light (l·v) are evaluated once
per pixel or light, and the roughness's Jacobian column comes out of the same forward pass as
the others.

Standard errors are the Gauss–Newton ones, s² (JᵀJ)⁻¹ with s² the residual variance, per
pixel; for the global roughness the pixels' sandwich S⁻¹ B S⁻¹ (S the Schur complement, B
the spread of the pixels' profiled scores: :func:`_sandwich_diagonal`), which holds when the
model misfits a pixel as a whole and its errors are correlated across the lights.
"""

from __future__ import annotations

import contextlib
import dataclasses
import math
import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..models.base import Model
from ..progress import finish
from .footprint import smoothest, view_spread
from .inputs import StereoInput
from .lambertian import LambertianResult, lambertian, observation_weights

__all__ = [
    "Family",
    "PixelFit",
    "RoughResult",
    "fit_box",
    "fit_pixels",
    "roughness_parameter",
    "rough",
]

CHUNK = 1 << 13
"""Pixels per compiled call. Small enough that a chunk's K × CHUNK arrays stay in the CPU's
cache across the many fused loops of an LM step (measured: bench/RESULTS.md, "Thresholds")."""

SMALL_CHUNK = 1 << 8
"""Fewer pixels than :data:`CHUNK` but at least twice this many are cut into one chunk per
core (e.g. the coated table solver's subsample of 512), so that each core has one."""

_WARM: set[Any] = set()
"""(compiled function, chunk size, dtype) that have run once: compiled already, so their
chunks can all start at once."""

SUBSET = 1 << 13
"""Pixels of the random subset that gives the global roughness its starting value."""


def roughness_parameter(model: Model) -> str:
    """Name of the model's roughness parameter: its one numeric parameter besides albedo."""
    names = [f for f in model.array_fields if f != "albedo"]
    if "albedo" not in model.array_fields or len(names) != 1:
        raise ParameterError(
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


def _tangent_basis(xp: Any, n: Any) -> tuple[Any, Any]:
    """Orthonormal t1, t2 ⟂ n (Frisvad's construction with Duff et al.'s sign fix, "Building
    an Orthonormal Basis, Revisited", JCGT 6(1), 2017, Listing 3), n of shape (..., 3)."""
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    s = xp.where(z >= 0, 1.0, -1.0)
    a = -1.0 / (s + z)
    b = x * y * a
    t1 = xp.stack([1.0 + s * x * x * a, s * b, -s * x], axis=-1)
    t2 = xp.stack([b, s + y * y * a, -y], axis=-1)
    return t1, t2


def _cholesky_solve(xp: Any, a: Any, b: Any) -> Any:
    """Solve a x = b for many small symmetric positive-definite systems at once.

    ``a`` is an n × n nested list of (P,) arrays and ``b`` a list of n (P,) arrays (n static,
    at most 6 here): the Cholesky factorisation is unrolled into elementwise operations, so
    XLA runs it as a few loops over P instead of a LAPACK call per pixel. Returns (n, P).
    """
    n = len(b)
    lo = [[None] * n for _ in range(n)]
    for i in range(n):
        for j in range(i + 1):
            acc = a[i][j]
            for k in range(j):
                acc = acc - lo[i][k] * lo[j][k]
            if i == j:
                lo[i][i] = xp.sqrt(xp.maximum(acc, 1e-30))
            else:
                lo[i][j] = acc / lo[j][j]
    y = [None] * n
    for i in range(n):
        acc = b[i]
        for k in range(i):
            acc = acc - lo[i][k] * y[k]
        y[i] = acc / lo[i][i]
    x = [None] * n
    for i in reversed(range(n)):
        acc = y[i]
        for k in range(i + 1, n):
            acc = acc - lo[k][i] * x[k]
        x[i] = acc / lo[i][i]
    return xp.stack(x)


@dataclass(frozen=True)
class Family:
    """The models a stereo fit varies: ``model`` with its albedo (per channel) and the
    parameters ``names``, each in its box ``bounds`` (lower, upper); the others are kept.

    :meth:`build` gives the model of one channel's albedo and the fitted values (arrays
    over the pixels, or one value each for the object). A subclass changes where they go:
    :class:`roughdiffuse.stereo.coated.CoatedFamily` puts the albedo and σ on the coat's
    base and α on the coat, and may fit one factor on every light's intensity
    (:meth:`scale`).
    """

    model: Model
    names: tuple[str, ...]
    bounds: tuple[tuple[float, float], ...]

    def build(self, albedo: Any, values: Sequence[Any]) -> Model:
        """The model with this albedo and these values of :attr:`names`."""
        return dataclasses.replace(
            self.model, albedo=albedo, **dict(zip(self.names, values, strict=True))
        )

    def scale(self, values: Sequence[Any]) -> Any:
        """The factor on every light's intensity for these values: 1 (the intensities are
        absolute); :class:`roughdiffuse.stereo.coated.CoatedFamily` may fit one."""
        del values
        return 1.0

    def key(self) -> str:
        """What the compiled steps depend on: the model with the fitted values at their
        lower bounds (its kept parameters, e.g. the variant or the coat's η)."""
        return repr(self.build(0.5, [lo for lo, _ in self.bounds]))

    @property
    def lower(self) -> np.ndarray:
        return np.array([lo for lo, _ in self.bounds], dtype=np.float64)

    @property
    def upper(self) -> np.ndarray:
        return np.array([hi for _, hi in self.bounds], dtype=np.float64)


_STEPS: dict[Any, dict[str, Any]] = {}


def _steps_for(family: Family, channels: int, per_pixel: bool, precision: str) -> dict[str, Any]:
    """:func:`_make_steps`, compiled once per family (model class and kept parameters) and
    setting."""
    key = (type(family), family.key(), family.names, family.bounds, channels, per_pixel, precision)
    if key not in _STEPS:
        if len(_STEPS) > 16:
            _STEPS.clear()
        _STEPS[key] = _make_steps(family, channels, per_pixel)
    return _STEPS[key]


class _Steps:
    """Compiled steps over a chunk of pixels for one (family, channels, setting).

    Written on whole arrays, structure of arrays (each parameter a (P,) array, each image a
    (K, P) array), so that XLA runs large elementwise loops: the Jacobian column of each
    parameter is one forward-mode derivative (``jax.jvp``) over every pixel, JᵀJ is a sum of
    products over the lights, and the small per-pixel systems are solved by
    :func:`_cholesky_solve` on (P,) arrays. :meth:`local` is a Levenberg–Marquardt step with
    its trial cost and acceptance (one pass over the data), :meth:`pieces` the pieces of the
    Schur complement for the G global parameters with the standard errors' diagonal. The
    methods are plain Python traced by ``jax.jit`` (:func:`_make_steps`): splitting them
    costs nothing at run time.
    """

    def __init__(self, family: Family, channels: int, per_pixel: bool) -> None:
        self.family, self.channels, self.per_pixel = family, channels, per_pixel
        self.g_count = len(family.names)
        self.nu = 2 + channels + (self.g_count if per_pixel else 0)

    def resid(self, theta: Any, g: Any, n0: Any, l: Any, e: Any, obs: Any, w: Any) -> Any:
        """Weighted residuals (K, C, P) for parameters ``theta`` (nu, P), normals n0 (3, P)
        and the global values ``g`` (G,)."""
        import jax.numpy as jnp

        t1, t2 = _tangent_basis(jnp, n0.T)
        n = n0 + theta[0] * t1.T + theta[1] * t2.T  # (3, P)
        n = n / jnp.sqrt(jnp.sum(n * n, axis=0))
        first = 2 + self.channels
        if self.per_pixel:
            values = [theta[first + j][None, :] for j in range(self.g_count)]
        else:
            values = [g[j] for j in range(self.g_count)]
        mu_i = l[:, 0:1] * n[0] + l[:, 1:2] * n[1] + l[:, 2:3] * n[2]  # (K, P)
        # n·v depends on the pixel only and l·v on the light only: kept as (1, P) and (K, 1),
        # the model's broadcasting evaluates their terms (an arctangent) once per pixel/light
        mu_o = n[2][None, :]
        cos_io = l[:, 2:3]
        lit = jnp.maximum(mu_i, 0.0) * self.family.scale(values)
        out = []
        for c in range(self.channels):
            m = self.family.build(theta[2 + c][None, :], values)
            f = m.brdf_cosines(mu_i, mu_o, cos_io)  # (K, P)
            out.append((e[:, c : c + 1] * f * lit - obs[:, :, c]) * w)  # w is 0 or 1
        return jnp.stack(out, axis=1)

    def jacobian(self, theta: Any, g: Any, *data: Any) -> tuple[Any, Any]:
        """Residuals and the Jacobian columns (nu, K, C, P) of the per-pixel parameters,
        followed by the global values' columns (nu + G in all) when they are fitted: one
        forward-mode pass with a batch of tangents, so the model's value (its arctangents
        and sines) is computed once for all the columns."""
        import jax
        import jax.numpy as jnp

        g = jnp.asarray(g, theta.dtype)
        count = self.nu if self.per_pixel else self.nu + self.g_count
        eye = jnp.eye(count, dtype=theta.dtype)
        tan_theta = eye[:, : self.nu, None] * jnp.ones_like(theta)[None]
        if self.per_pixel:
            tan_g = jnp.zeros((count, self.g_count), theta.dtype)
        else:
            tan_g = eye[:, self.nu :]

        def column(tt: Any, tg: Any) -> Any:
            return jax.jvp(lambda t, gg: self.resid(t, gg, *data), (theta, g), (tt, tg))

        return jax.vmap(column, out_axes=(None, 0))(tan_theta, tan_g)

    def normal_matrix(self, cols: Any) -> list[list[Any]]:
        import jax.numpy as jnp

        a = [[None] * self.nu for _ in range(self.nu)]
        for i in range(self.nu):
            for j in range(i + 1):
                a[i][j] = a[j][i] = jnp.sum(cols[i] * cols[j], axis=(0, 1))
        return a

    def clamp(self, theta: Any) -> Any:
        import jax.numpy as jnp

        rows = [jnp.clip(theta[0], -0.5, 0.5), jnp.clip(theta[1], -0.5, 0.5)]  # ≤ ~27°/step
        rows += [jnp.maximum(theta[2 + c], 0.0) for c in range(self.channels)]
        if self.per_pixel:
            first = 2 + self.channels
            rows += [
                jnp.clip(theta[first + j], lo, hi) for j, (lo, hi) in enumerate(self.family.bounds)
            ]
        return jnp.stack(rows)

    def reduced(self, cols: Any, r: Any, a: Any, grad: Any) -> tuple[Any, Any]:
        """A pixel's terms of the reduced system of the global values (their Jacobian
        columns jg = ``cols[nu:]``): jgᵀjg − BᵀA⁻¹B (P, G·G) and jgᵀr − BᵀA⁻¹gu (P, G),
        with B = Jᵀjg."""
        import jax.numpy as jnp

        nu, count = self.nu, self.g_count
        jg = [cols[nu + j] for j in range(count)]
        b = [[jnp.sum(cols[i] * jg[j], axis=(0, 1)) for i in range(nu)] for j in range(count)]
        a_inv_b = [_cholesky_solve(jnp, a, b[j]) for j in range(count)]
        sch = [
            jnp.sum(jg[j] * jg[k], axis=(0, 1)) - sum(b[j][i] * a_inv_b[k][i] for i in range(nu))
            for j in range(count)
            for k in range(count)
        ]
        rhs = [
            jnp.sum(jg[j] * r, axis=(0, 1)) - sum(grad[i] * a_inv_b[j][i] for i in range(nu))
            for j in range(count)
        ]
        return jnp.stack(sch, axis=-1), jnp.stack(rhs, axis=-1)

    def _no_reduced(self, cost: Any) -> tuple[Any, Any]:
        import jax.numpy as jnp

        g = self.g_count
        return jnp.zeros(cost.shape + (g * g,), cost.dtype), jnp.zeros(
            cost.shape + (g,), cost.dtype
        )

    def step(self, theta, lam, n0, g, data):  # noqa: ANN001, ANN202
        """One LM step of every pixel ((nu, P) layout); also the pixel's terms of the reduced
        system of the global values at the starting point (:meth:`reduced`)."""
        import jax.numpy as jnp

        nu = self.nu
        r, cols = self.jacobian(theta, g, n0, *data)
        a = self.normal_matrix(cols)
        grad = [jnp.sum(cols[i] * r, axis=(0, 1)) for i in range(nu)]
        cost0 = jnp.sum(r * r, axis=(0, 1))
        damped = [
            [a[i][j] + (lam * jnp.maximum(a[i][i], 1e-12) if i == j else 0.0) for j in range(nu)]
            for i in range(nu)
        ]
        trial = self.clamp(theta - _cholesky_solve(jnp, damped, grad))
        r1 = self.resid(trial, g, n0, *data)
        cost1 = jnp.sum(r1 * r1, axis=(0, 1))
        better = jnp.isfinite(cost1) & (cost1 < cost0)
        theta = jnp.where(better[None], trial, theta)
        lam = jnp.where(better, jnp.maximum(lam * 0.3, 1e-9), jnp.minimum(lam * 10.0, 1e9))
        # move the tangent-plane offsets into the normal
        t1, t2 = _tangent_basis(jnp, n0.T)
        n = n0 + theta[0] * t1.T + theta[1] * t2.T
        n = n / jnp.sqrt(jnp.sum(n * n, axis=0))
        theta = theta.at[:2].set(0.0)
        cost = jnp.where(better, cost1, cost0)
        if self.per_pixel:
            return theta, lam, n, cost, *self._no_reduced(cost0)
        sch, rhs = self.reduced(cols, r, a, grad)
        return theta, lam, n, cost, sch, rhs

    def local(self, theta, lam, g, n0, l, e, obs, w, count):  # noqa: ANN001, ANN202
        """``count`` LM steps of every pixel of the chunk in one compiled loop; returns the
        new state, the costs, and the reduced system's terms at the start of the last step."""
        import jax

        data = (l, e, obs, w)

        def body(_: Any, carry: Any) -> Any:
            th, lm, nn = carry
            return self.step(th, lm, nn, g, data)[:3]

        carry = jax.lax.fori_loop(0, count - 1, body, (theta.T, lam, n0.T))
        th, lm, nn, cost, sch, rhs = self.step(*carry, g, data)
        return th.T, lm, nn.T, cost, sch, rhs

    def pieces(self, theta, g, n0, l, e, obs, w):  # noqa: ANN001, ANN202
        """Per-pixel terms of the reduced system (:meth:`reduced`), the cost, and the
        diagonal of A⁻¹ (for the standard errors)."""
        import jax.numpy as jnp

        nu = self.nu
        theta, n0 = theta.T, n0.T
        r, cols = self.jacobian(theta, g, n0, l, e, obs, w)
        a = self.normal_matrix(cols)
        cost0 = jnp.sum(r * r, axis=(0, 1))
        # the diagonal of A⁻¹ column by column with the unrolled Cholesky solve (XLA shares
        # the factorisation): no LAPACK call (with one, chunks on two threads stalled)
        eye = [
            [jnp.ones_like(cost0) if i == j else jnp.zeros_like(cost0) for j in range(nu)]
            for i in range(nu)
        ]
        a_inv_diag = jnp.stack([_cholesky_solve(jnp, a, eye[i])[i] for i in range(nu)], axis=-1)
        gu = [jnp.sum(cols[i] * r, axis=(0, 1)) for i in range(nu)]
        if self.per_pixel:
            return *self._no_reduced(cost0), cost0, a_inv_diag
        sch, rhs = self.reduced(cols, r, a, gu)
        return sch, rhs, cost0, a_inv_diag


def _make_steps(family: Family, channels: int, per_pixel: bool) -> dict[str, Any]:
    """The jitted ``local`` and ``pieces`` steps of :class:`_Steps` for this setting."""
    import jax

    steps = _Steps(family, channels, per_pixel)
    return {"local": jax.jit(steps.local), "pieces": jax.jit(steps.pieces)}


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
    precision: str = "single",
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
    precision : {"single", "double"}
        Arithmetic of the fit: float32 (default, faster) or float64. A least-squares fit
        resolves its parameters to about the square root of the format's rounding: in
        float32 the normals of noise-free images converge to about 0.03° (√(6e-8) rad), in
        float64 to 1e-4° or better. Image noise of 0.1% or more dominates either.
    progress : bool
        Show a progress bar.

    Returns
    -------
    RoughResult
    """
    name, box, s0 = _check_arguments(model, roughness, precision, iterations, initial_roughness)
    start = lambertian(data, shadow=shadow) if start is None else start
    trusted = None if per_pixel else _smoother(data.mask, np.asarray(start.normals))
    fit = fit_pixels(
        data,
        Family(model, (name,), (box,)),
        start=start,
        weights=observation_weights(data, shadow),
        initial=np.array([s0]),
        per_pixel=per_pixel,
        subset_start=initial_roughness is None,
        iterations=iterations,
        precision=precision,
        progress=progress,
        trusted=trusted,
    )
    return RoughResult(
        normals=fit.normals,
        albedo=fit.albedo,
        roughness=fit.values[:, 0] if per_pixel else float(fit.values[0]),
        roughness_name=name,
        roughness_se=fit.values_se[:, 0] if per_pixel else float(fit.values_se[0]),
        normal_se=fit.normal_se,
        albedo_se=fit.albedo_se,
        residual=fit.residual,
        weights=fit.weights,
        iterations=fit.iterations,
    )


def _smoother(mask: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """The pixels (P,) bool whose terms give the object's roughness: the :data:`TRUSTED`
    fraction of those with finite normals whose normals turn least across the pixel, for
    their angle to the view (:func:`.footprint.view_spread` of the start's normals)."""
    ok = np.flatnonzero(np.all(np.isfinite(normals), axis=1))
    out = np.zeros(normals.shape[0], dtype=bool)
    out[smoothest(view_spread(mask, normals), ok, TRUSTED)] = True
    return out


def _check_arguments(
    model: Model,
    roughness: str | None,
    precision: str,
    iterations: int,
    initial_roughness: float | None,
) -> tuple[str, tuple[float, float], float]:
    """Refuse bad arguments of :func:`rough`; (roughness name, its fit box, its start)."""
    if not isinstance(model, Model):
        raise ParameterError(f"model must be a roughdiffuse Model (got {type(model).__name__})")
    name = roughness or roughness_parameter(model)
    if name not in model.array_fields:
        raise ParameterError(f"{type(model).__name__} has no numeric parameter {name!r}")
    check_fit_options(precision, iterations)
    box = fit_box(model, name)
    hi = box[1]
    s0 = float(initial_roughness) if initial_roughness is not None else min(0.3, 0.25 * hi)
    if not 0.0 <= s0 <= hi:
        raise ParameterError(f"initial_roughness must be in [0, {hi:g}] (got {s0:g})")
    return name, box, s0


def check_fit_options(precision: str, iterations: int) -> None:
    """Refuse a precision other than single or double, and iterations that are not a
    positive integer."""
    if precision not in ("single", "double"):
        raise ParameterError(f"precision must be 'single' or 'double' (got {precision!r})")
    if not isinstance(iterations, int) or iterations < 1:
        raise ParameterError(f"iterations must be a positive integer (got {iterations!r})")


@dataclass
class PixelFit:
    """What :func:`fit_pixels` returns, P object pixels, G fitted values besides the
    normals and albedo (:attr:`Family.names`). The other attributes (normals, albedo,
    their standard errors, residual, weights, iterations) are as :class:`RoughResult`'s.

    Attributes
    ----------
    values : array (G,) or (P, G)
        The fitted values: one each for the object, or one per pixel.
    values_se : array like ``values``
        Their standard errors.
    """

    normals: np.ndarray
    albedo: np.ndarray
    values: np.ndarray
    values_se: np.ndarray
    normal_se: np.ndarray
    albedo_se: np.ndarray
    residual: np.ndarray
    weights: np.ndarray
    iterations: int


def fit_pixels(
    data: StereoInput,
    family: Family,
    *,
    start: Any,
    weights: np.ndarray,
    initial: np.ndarray,
    per_pixel: bool = False,
    subset_start: bool = True,
    iterations: int = 30,
    precision: str = "single",
    progress: bool = False,
    label: str = "rough photometric stereo",
    trusted: np.ndarray | None = None,
) -> PixelFit:
    """The batched per-pixel fit of :func:`rough` for any :class:`Family`.

    Parameters
    ----------
    data : StereoInput
    family : Family
        The model and the parameters fitted besides the normals and albedo.
    start : object with ``normals`` (P, 3) and ``albedo`` (P, C)
        Starting normals and albedo (a :class:`LambertianResult`, a :class:`RoughResult`).
    weights : array (K, P)
        0/1 weights of the observations (shadows and invalid values 0).
    initial : array (G,) or (P, G)
        Starting values of :attr:`Family.names` (one per pixel only with ``per_pixel``).
    per_pixel : bool
        The values per pixel instead of one each for the object.
    subset_start : bool
        Start the global values from a fit to a random subset of the pixels (large objects).
    iterations, precision, progress
        As :func:`rough`.
    label : str
        The progress bar's text.
    trusted : array (P,) bool, optional
        The pixels whose terms give the object's values and their standard errors (the
        others are fitted for their normal and albedo at those values); default all, and
        all when none of them is fitted.
    """
    check_fit_options(precision, iterations)
    setup = _Setup.of(data, start, weights, initial, per_pixel, len(family.names))
    if trusted is not None:
        if np.shape(trusted) != setup.ok.shape:
            raise ParameterError(f"trusted must have shape {setup.ok.shape} (object pixels; "
                                 f"got {np.shape(trusted)})")
        if (setup.ok & trusted).any():
            setup.trusted = setup.ok & np.asarray(trusted, dtype=bool)
    g0 = np.asarray(initial, dtype=np.float64)
    g0 = g0 if g0.ndim == 1 else np.median(g0, axis=0)
    g, done, (sch, score, costs, a_diag) = _solve(
        data,
        family,
        g0,
        setup,
        per_pixel,
        subset_start,
        iterations,
        precision,
        _progress(iterations, progress, label),
    )
    return _result(setup, g, done, (sch, score), costs, a_diag, per_pixel)


@dataclass
class _Setup:
    """The fit's data and starting point, pixels in mask order: observations ``obs``
    (K, P, C), weights ``wk`` (K, P; 0 for pixels left out), the pixels fitted ``ok``, the
    per-pixel parameters ``theta`` (P, nu: two tangent offsets, C albedos, the G values when
    per pixel) and normals ``n0`` (P, 3); ``trusted`` (P,) bool, the pixels whose terms give
    the global values (None: every pixel fitted)."""

    obs: np.ndarray
    wk: np.ndarray
    ok: np.ndarray
    theta: np.ndarray
    n0: np.ndarray
    channels: int
    nu: int
    trusted: np.ndarray | None = None

    @classmethod
    def of(
        cls,
        data: StereoInput,
        start: Any,
        w: np.ndarray,
        initial: np.ndarray,
        per_pixel: bool,
        g_count: int,
    ) -> _Setup:
        obs = data.observations  # (K, P, C)
        p_count, c = obs.shape[1], data.channels
        if w.shape != obs.shape[:2]:
            raise ParameterError(f"weights must have shape {obs.shape[:2]} (got {w.shape})")
        ok = np.all(np.isfinite(start.normals), axis=1) & (w.sum(axis=0) >= 3)
        n0 = np.where(ok[:, None], np.nan_to_num(start.normals), [0.0, 0.0, 1.0])
        n0[:, 2] = np.maximum(n0[:, 2], 1e-3)
        n0 /= np.linalg.norm(n0, axis=1, keepdims=True)
        rho = np.clip(np.nan_to_num(start.albedo, nan=0.5), 1e-3, None)
        nu = 2 + c + (g_count if per_pixel else 0)
        theta = np.zeros((p_count, nu))
        theta[:, 2 : 2 + c] = rho
        if per_pixel:
            theta[:, 2 + c :] = np.nan_to_num(np.broadcast_to(initial, (p_count, g_count)))
        wk = np.where(ok[None, :], w, 0.0)
        return cls(obs=obs, wk=wk, ok=ok, theta=theta, n0=n0, channels=c, nu=nu)


def _solve(
    data: StereoInput,
    family: Family,
    g0: np.ndarray,
    setup: _Setup,
    per_pixel: bool,
    subset_start: bool,
    iterations: int,
    precision: str,
    bar: Any,
) -> tuple[np.ndarray, int, tuple[Any, Any, Any, Any]]:
    """Run the fit in the chosen precision; ``setup.theta`` and ``setup.n0`` become the
    fitted values. Returns the global values, the iterations and the pieces of the error
    estimates per pixel (Schur terms, profiled scores, costs, diagonal of A⁻¹)."""
    import jax.numpy as jnp

    from .._array import double_precision

    p_count, c, ok, obs, wk = setup.theta.shape[0], setup.channels, setup.ok, setup.obs, setup.wk
    g_count = len(family.names)
    dt = jnp.float64 if precision == "double" else jnp.float32
    ctx = double_precision(jnp) if precision == "double" else contextlib.nullcontext()
    with ctx:
        steps = _steps_for(family, c, per_pixel, precision)
        chunks = _Chunks(p_count, dt, data.directions, data.intensities, obs, wk, g_count)
        state = {
            "theta": setup.theta.astype(dt),
            "lam": np.full(p_count, 1e-3, dtype=dt),
            "n0": setup.n0.astype(dt),
        }
        # convergence: relative change of the values and of the cost, near each format's
        # rounding of a sum over many pixels (float32: ~1e-6)
        tol = 1e-9 if precision == "double" else 1e-5
        g = g0
        if per_pixel:
            done = iterations
            chunks.local(steps["local"], state, g, 4 + 2 * (iterations - 1))
            bar.update(iterations)
        else:
            use = ok if setup.trusted is None else setup.trusted
            if subset_start and int(use.sum()) > 4 * SUBSET:
                # start from a fit to a random subset of the pixels (the same loop, a few
                # percent of the work), so the whole object needs one or two global steps
                pick = np.sort(np.random.default_rng(0).choice(np.flatnonzero(use), SUBSET, False))
                sub = _Chunks(
                    SUBSET,
                    dt,
                    data.directions,
                    data.intensities,
                    obs[:, pick],
                    wk[:, pick],
                    g_count,
                )
                sub_state = {k: v[pick].copy() for k, v in state.items()}
                g, _ = _fit_globals(sub, steps["local"], sub_state, g, family, tol, iterations)
            g, done = _fit_globals(chunks, steps["local"], state, g, family, tol, iterations, bar,
                                   setup.trusted)
            if done < iterations:
                finish(bar, f"converged after {done} of {iterations} iterations")
        bar.close()
        sch, score, costs, a_diag = chunks.pieces(steps["pieces"], state, g)
    setup.theta, setup.n0 = state["theta"].astype(np.float64), state["n0"].astype(np.float64)
    return np.asarray(g, dtype=np.float64), done, (sch, score, costs, a_diag)


def _result(
    setup: _Setup,
    g: np.ndarray,
    done: int,
    reduced: tuple[Any, Any],
    costs: Any,
    a_diag: Any,
    per_pixel: bool,
) -> PixelFit:
    """The fitted values with their standard errors: Gauss–Newton's, s² (JᵀJ)⁻¹, per pixel;
    for the global values the pixels' sandwich (:func:`_sandwich_diagonal`) from the
    ``reduced`` system's terms of each pixel (Schur complement, profiled score)."""
    theta, n0, ok, wk, obs = setup.theta, setup.n0, setup.ok, setup.wk, setup.obs
    c, nu = setup.channels, setup.nu
    cost_p = costs.astype(np.float64)
    dof_p = np.maximum(wk.sum(axis=0) * c - nu, 1)
    s2_p = cost_p / dof_p
    var_local = a_diag.astype(np.float64) * s2_p[:, None]
    normal_se = np.sqrt(np.maximum(var_local[:, 0] + var_local[:, 1], 0.0))
    albedo_se = np.sqrt(np.maximum(var_local[:, 2 : 2 + c], 0.0))
    if per_pixel:
        values = np.where(ok[:, None], theta[:, 2 + c :], np.nan)
        values_se = np.where(ok[:, None], np.sqrt(np.maximum(var_local[:, 2 + c :], 0.0)), np.nan)
    else:
        use = ok if setup.trusted is None else setup.trusted
        sch, score = (np.asarray(t, dtype=np.float64)[use] for t in reduced)
        count = g.shape[0]
        values = g.copy()
        values_se = np.sqrt(_sandwich_diagonal(sch.sum(axis=0).reshape(count, count), score))
    kept = wk.sum(axis=0) * c
    mean = np.einsum("kp,kpc->p", wk, obs) / np.maximum(kept, 1)
    rel = np.sqrt(cost_p / np.maximum(kept, 1)) / np.maximum(mean, 1e-30)
    return PixelFit(
        normals=np.where(ok[:, None], n0, np.nan),
        albedo=np.where(ok[:, None], theta[:, 2 : 2 + c], np.nan),
        values=values,
        values_se=values_se,
        normal_se=np.where(ok, normal_se, np.nan),
        albedo_se=np.where(ok[:, None], albedo_se, np.nan),
        residual=np.where(ok, rel, np.nan),
        weights=wk,
        iterations=done,
    )


def _sandwich_diagonal(s: np.ndarray, score: np.ndarray) -> np.ndarray:
    """The variances of the global values: the diagonal of the pixels' sandwich
    n/(n−1) S⁻¹ B S⁻¹, S the Schur complement summed over the n pixels and B = Σ (u_p − ū)
    (u_p − ū)ᵀ of their profiled scores u_p (the reduced gradient, (n, G)): the
    cluster-robust covariance with each pixel a cluster (Liang & Zeger 1986, Biometrika 73,
    eq. 2; White 1980). Unlike s² S⁻¹ it holds when a pixel's errors are correlated across
    its lights, as where the model misfits a pixel as a whole (a pixel's footprint averaging
    a curved surface's highlight: on the α = 0.1 renders of ``scripts/stereo_renders.py``,
    σ from different draws of 512 pixels spread three times s² S⁻¹'s standard error), and
    reduces to it in expectation when the errors are independent with one variance.

    Over the values the images determine (those whose diagonal entry of S is not ~0: e.g.
    σ of Oren–Nayar at σ = 0, where its derivative vanishes); infinite for the others, and
    for all when the rest is not positive definite."""
    d = np.diag(s)
    out = np.full(s.shape[0], math.inf)
    n = score.shape[0]
    if n < 2 or not (np.all(np.isfinite(s)) and np.all(np.isfinite(score))):
        return out
    live = d > 1e-9 * max(float(d.max()), 1e-300)
    sub = s[np.ix_(live, live)]
    if live.any() and np.linalg.eigvalsh(sub).min() > 1e-12 * np.abs(sub).max():
        inv = np.linalg.inv(sub)
        u = score[:, live] - score[:, live].mean(axis=0)
        out[live] = np.diag(inv @ (u.T @ u) @ inv) * n / (n - 1)
    return out


def _newton_step(
    s: np.ndarray, rhs: np.ndarray, g: np.ndarray, lo: np.ndarray, hi: np.ndarray
) -> np.ndarray:
    """−S⁻¹ rhs on the directions where S is positive, for the values free to move: a value
    at a bound of its box that the step would push out is held there and the step solved
    for the others (a projected Gauss–Newton step)."""
    step = np.zeros_like(rhs)
    if not np.all(np.isfinite(s)) or not np.all(np.isfinite(rhs)):
        return step
    free = np.ones(rhs.shape[0], dtype=bool)
    for _ in range(rhs.shape[0]):
        step[:] = 0.0
        sub = s[np.ix_(free, free)]
        w, v = np.linalg.eigh(sub)
        inv = np.where(w > 1e-9 * max(abs(w).max(), 1e-300), 1.0 / np.where(w > 0, w, 1.0), 0.0)
        step[free] = -(v * inv) @ (v.T @ rhs[free])
        blocked = free & (((g <= lo) & (step < 0)) | ((g >= hi) & (step > 0)))
        if not blocked.any():
            return step
        free &= ~blocked
        if not free.any():
            break
    return np.zeros_like(rhs)


TRUSTED = 0.75
"""The fraction of an object's pixels, those whose normals turn least across the pixel for
their angle to the view (:func:`.footprint.view_spread`), from which the rough fit draws
the object's roughness: near the limb a pixel's footprint spans normals several degrees
apart and the mean of the full Oren–Nayar model over them is not the model at their mean.
The matte renders of ``scripts/stereo_renders.py`` at 128² (σ 0.4): sphere 0.3988 ± 0.0002
from every pixel, 0.3999 ± 0.0002 from these; blob 0.3997 ± 0.0004, vase 0.4003 ± 0.0003."""

LAM_CAP = 1e-3
"""The damping λ of every pixel's Levenberg–Marquardt is brought down to at most this (its
start) whenever the global values move (:func:`_fit_globals`). A converged pixel's steps
are rejected by rounding (float32 above all), and each rejection multiplies its λ by 10: at
1e9 the pixel can no longer follow the values, the step of the values (which assumed it
would) raises the cost and is refused, and the fit stops short along the valley of σ and α
(the α = 0.1 vase render's subsample at 128²: σ 0.438 in float32 against 0.395 in float64
from the same start; with the cap, 0.4027 and 0.4025)."""


def _fit_globals(
    chunks: _Chunks,
    fn: Any,
    state: dict[str, np.ndarray],
    g: np.ndarray,
    family: Family,
    tol: float,
    iterations: int,
    bar: Any = None,
    use: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """Alternate per-pixel LM steps and Schur-complement Gauss–Newton steps of the global
    values (in a box trust region), updating ``state`` in place; returns them and the
    iterations.

    Each iteration runs a few LM steps of every pixel at the current values; the last of them
    also returns the reduced system of the values, whose step gives the next ones. They are
    kept if the cost after the next iteration's LM steps is not larger, else the state goes
    back and the trust region shrinks. Converged when every value or the cost changes by less
    than ``tol`` (relative). ``use`` (P,) bool: the pixels whose costs and terms count
    (default all).
    """
    lo, hi = family.lower, family.upper
    width = hi - lo
    tr = 0.25 * width
    count = 4
    g = np.asarray(g, dtype=np.float64).copy()
    best: tuple[dict[str, np.ndarray], np.ndarray, float, np.ndarray] | None = None
    done = 0
    for it in range(iterations):
        done = it + 1
        state["lam"] = np.minimum(state["lam"], LAM_CAP)
        costs, sch_p, rhs_p = chunks.local(fn, state, g, count)
        if use is not None:
            costs, sch_p, rhs_p = costs[use], sch_p[use], rhs_p[use]
        count = 2
        cost = float(np.sum(costs, dtype=np.float64))
        if bar is not None:
            bar.update(1)
        if best is not None and not cost <= best[2]:  # the step made the fit worse
            state.update({k: v.copy() for k, v in best[0].items()})
            tr = tr * 0.25
            # by less than the rounding of the sum (converged: shrinking the region only
            # repeats the same values), or the region has shrunk to nothing
            if cost - best[2] <= tol * best[2] or np.all(tr < 1e-7 * width):
                g = best[1]
                break
        else:
            converged = best is not None and (
                bool(np.all(np.abs(g - best[1]) < tol * np.maximum(width, 1.0)))
                or best[2] - cost <= tol * max(best[2], 1e-300)
            )
            if best is not None:
                tr = np.minimum(2.0 * tr, 0.25 * width)
            n = g.shape[0]
            schur = np.sum(sch_p, axis=0, dtype=np.float64).reshape(n, n)
            step = _newton_step(schur, np.sum(rhs_p, axis=0, dtype=np.float64), g, lo, hi)
            best = ({k: v.copy() for k, v in state.items()}, g.copy(), cost, step)
            if converged:
                break
        g = np.clip(best[1] + np.clip(best[3], -tr, tr), lo, hi)
    else:
        if best is not None and np.any(g != best[1]):  # out of iterations with untried values
            state.update({k: v.copy() for k, v in best[0].items()})
            g = best[1]
    return g, done


def fit_box(model: Model, name: str) -> tuple[float, float]:
    """The parameter's fit box, as :mod:`roughdiffuse.fit` uses it
    (:attr:`~roughdiffuse.models.declaration.Param.bounds`)."""
    box = next((p.bounds for p in model.params if p.name == name), None)
    if box is None:
        raise ParameterError(f"{type(model).__name__}.{name} has no bounded range to fit in")
    return (float(box[0]), float(box[1]))


def _progress(total: int, show: bool, label: str) -> Any:
    from ..progress import progress

    return progress(total, label, unit="it", enabled=show)


class _Chunks:
    """The pixels cut into chunks of :data:`CHUNK` (the last one padded, so each function
    compiles once), with the per-chunk data already on the device."""

    def __init__(self, p: int, dt: Any, l: Any, e: Any, obs: Any, w: Any, g_count: int = 1) -> None:
        import jax.numpy as jnp

        from .._array import double_precision

        self.p, self.g_count = p, g_count
        self.workers = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else 1
        # fewer pixels than a chunk: one chunk per worker, so that every core has one
        share = p if p < 2 * SMALL_CHUNK else -(-p // self.workers)
        size = CHUNK if p > CHUNK else max(16, 1 << int(math.ceil(math.log2(max(share, 1)))))
        self.size = size
        self.slices = [slice(s, min(s + size, p)) for s in range(0, p, size)]
        self.l = jnp.asarray(l, dt)
        self.e = jnp.asarray(e, dt)
        self.obs = [jnp.asarray(_pad(obs[:, sl], size, 1), dt) for sl in self.slices]
        self.w = [jnp.asarray(_pad(w[:, sl], size, 1), dt) for sl in self.slices]
        double = jnp.dtype(dt) == jnp.float64
        # JAX's precision setting is per thread: the worker threads enter it again
        self.context = (lambda: double_precision(jnp)) if double else contextlib.nullcontext

    def local(
        self, fn: Any, state: dict[str, np.ndarray], g: Any, count: int
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``count`` LM steps of every pixel, in place in ``state``; returns the costs (P,)
        and the pixels' terms of the global values' reduced system, (P, G·G) and (P, G)."""
        dt = state["theta"].dtype
        gc = self.g_count
        out = [np.empty(self.p, dt), np.empty((self.p, gc * gc), dt), np.empty((self.p, gc), dt)]

        def run(k: int) -> None:
            sl = self.slices[k]
            n = sl.stop - sl.start
            with self.context():
                th, lam, nn, cost, sch, rhs = fn(
                    _pad(state["theta"][sl], self.size, 0),
                    _pad(state["lam"][sl], self.size, 0),
                    np.asarray(g, dtype=dt),
                    _pad(state["n0"][sl], self.size, 0),
                    self.l,
                    self.e,
                    self.obs[k],
                    self.w[k],
                    count,
                )
                state["theta"][sl] = np.asarray(th)[:n]
                state["lam"][sl] = np.asarray(lam)[:n]
                state["n0"][sl] = np.asarray(nn)[:n]
                for i, v in enumerate((cost, sch, rhs)):
                    out[i][sl] = np.asarray(v)[:n]

        self.map(run, (fn, self.size, dt))
        return out[0], out[1], out[2]

    def map(self, run: Any, key: Any) -> None:
        """``run(k)`` for every chunk k on :attr:`workers` threads, one chunk each at a
        time; the first chunk alone first, in this thread, when ``key`` (the compiled
        function and its shapes) has not run yet (it compiles). XLA's CPU code runs a
        chunk's loops mostly on one core, so the threads are what can use the others; JAX
        releases the GIL while a compiled function runs."""
        first = key not in _WARM
        if first:
            run(0)
            if len(_WARM) > 64:
                _WARM.clear()
            _WARM.add(key)
        rest = range(1 if first else 0, len(self.slices))
        if self.workers < 2 or len(rest) < 2:
            for k in rest:
                run(k)
            return
        pool = ThreadPoolExecutor(self.workers, thread_name_prefix="roughdiffuse-stereo")
        try:
            for future in [pool.submit(run, k) for k in rest]:
                future.result()
        finally:
            pool.shutdown(wait=True, cancel_futures=True)  # on Ctrl-C too: no chunk left behind

    def pieces(self, fn: Any, state: dict[str, np.ndarray], g: Any) -> tuple[np.ndarray, ...]:
        """The reduced system's terms, the costs and the diagonal of A⁻¹ of every pixel."""
        parts: list[Any] = [None] * len(self.slices)

        def run(k: int) -> None:
            sl = self.slices[k]
            n = sl.stop - sl.start
            with self.context():
                out = fn(
                    _pad(state["theta"][sl], self.size, 0),
                    np.asarray(g, dtype=state["theta"].dtype),
                    _pad(state["n0"][sl], self.size, 0),
                    self.l,
                    self.e,
                    self.obs[k],
                    self.w[k],
                )
                parts[k] = [np.asarray(o)[:n] for o in out]

        self.map(run, (fn, self.size, state["theta"].dtype))
        return tuple(np.concatenate([p[i] for p in parts]) for i in range(4))


def _pad(a: np.ndarray, size: int, axis: int) -> np.ndarray:
    extra = size - a.shape[axis]
    if extra <= 0:
        return a
    pad = [(0, 0)] * a.ndim
    pad[axis] = (0, extra)
    return np.pad(a, pad, mode="edge")
