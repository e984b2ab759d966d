"""The exact V-cavity surface as a model: the ground truth the other models approximate.

Oren and Nayar's microsurface (SIGGRAPH 1994, Sec. 3–4): long symmetric V-cavities with
Lambertian facets of albedo ρ, slopes Gaussian with standard deviation σ. Its BRDF is computed
exactly (shadowing, masking, all interreflections) by :func:`roughdiffuse.simulate.brdf`, at
a few hundred values per second; this model tabulates it once per (σ, ρ, bounces, measure)
on a grid of (θi, θr, Δφ) and interpolates, so it can be rendered, fitted and plotted like any
closed-form model.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._array import Array, concrete, is_jax, is_numpy
from .base import Model, register_pytree
from .declaration import Param

__all__ = ["VCavity", "THETA_CAP", "vcavity_table"]

THETA_CAP = math.radians(89.0)
"""θi and θr are clamped to this before the table is read (see :class:`VCavity`)."""

TABLE_THETA = 20
"""Nodes of the θi and θr axes, on [0, :data:`THETA_CAP`], denser towards grazing."""

TABLE_PHI = 13
"""Nodes of the Δφ axis, uniform on [0, π] (15° apart)."""


def _theta_nodes() -> np.ndarray:
    k = np.arange(TABLE_THETA) / (TABLE_THETA - 1)
    return THETA_CAP * np.sin(0.5 * math.pi * k)


@functools.lru_cache(maxsize=8)
def vcavity_table(sigma: float, albedo: float, bounces: str, measure: str) -> Any:
    """The interpolant of log f over (θi, θr, Δφ): a tensor cubic B-spline (SciPy NdBSpline).

    f is computed by :func:`roughdiffuse.simulate.brdf` (default quadrature, 1e-4) on
    :data:`TABLE_THETA` × :data:`TABLE_THETA` × :data:`TABLE_PHI` nodes, θi ≤ θr only
    (reciprocity, f(θi, θr) = f(θr, θi), gives the rest). The logarithm is interpolated:
    f grows steeply towards grazing and stays positive for ρ > 0. Cached per parameter set.
    """
    from scipy.interpolate import NdBSpline, make_interp_spline

    from ..simulate import Settings, brdf

    th = _theta_nodes()
    dp = np.linspace(0.0, math.pi, TABLE_PHI)
    i, j = np.triu_indices(TABLE_THETA)
    ti = np.repeat(th[i], TABLE_PHI)
    tr = np.repeat(th[j], TABLE_PHI)
    dps = np.tile(dp, i.size)
    b: int | str = bounces if bounces == "all" else int(bounces)
    f = np.asarray(brdf(ti, tr, dps, sigma, albedo, b, Settings(measure=measure)))
    values = np.empty((TABLE_THETA, TABLE_THETA, TABLE_PHI))
    values[i, j] = f.reshape(-1, TABLE_PHI)
    values[j, i] = f.reshape(-1, TABLE_PHI)
    c = np.log(values)
    knots = []
    for axis, x in enumerate((th, th, dp)):
        spline = make_interp_spline(x, c, k=3, axis=axis)
        c = np.moveaxis(spline.c, 0, axis)
        knots.append(spline.t)
    return NdBSpline(tuple(knots), c, 3)


@register_pytree
@dataclass(frozen=True)
class VCavity(Model):
    """The exact V-cavity surface (Oren & Nayar 1994): shadowing, masking, interreflection.

    f(θi, θr, Δφ; σ, ρ) of long symmetric V-cavities with Lambertian facets, slopes Gaussian
    of standard deviation σ (truncated at π/2), computed by the exact solver
    :func:`roughdiffuse.simulate.brdf` (docs/accuracy.md) and interpolated from a table
    (:func:`vcavity_table`: cubic in log f, 20 × 20 × 13 nodes, computed once per parameter
    set, a few seconds with all bounces). The interpolation agrees with the solver to about
    1e-3 relative away from grazing (tests/test_models_vcavity.py).

    Grazing limit: the V-cavity f diverges like 1/cos θ where θi and θr are both grazing
    (the radiance L = f E0 cos θi stays finite; README, "Ground truth"). Here θi and θr are
    clamped to :data:`THETA_CAP` = 89° before the table is read, so f is finite everywhere
    and, beyond 89°, equals its value at 89°.

    Not an array-API closed form: it runs on NumPy (JAX and PyTorch arrays with concrete
    values are converted and the result returned in their namespace), and ``jax.jit``, the
    gradient and the compiled fast path (:mod:`roughdiffuse.fastpath`) refuse it with a
    ``TypeError`` (class attribute ``compiled = False``).

    Parameters
    ----------
    albedo : float
        Facet albedo ρ in [0, 1] (one channel: interreflection is not linear in ρ).
    sigma : float
        Standard deviation σ of the facet slope, in [0, π/2] radians (0 is Lambert).
    bounces : {"all", "1", "2", "3"}
        Light paths kept: one bounce (shadowing and masking only), up to N, or all.
    measure : {"solid-angle", "angle"}
        Reading of the slope measure (:mod:`roughdiffuse.simulate.surface`).

    Examples
    --------
    σ = 0 is a flat Lambertian facet, f = ρ/π:

    >>> import numpy as np
    >>> n = np.array([0.0, 0.0, 1.0])
    >>> round(float(VCavity(albedo=0.5, sigma=0.0).brdf(n, n)) * np.pi, 12)
    0.5
    """

    albedo: float | Array = 1.0
    sigma: float | Array = 0.3
    bounces: str = "all"
    measure: str = "solid-angle"

    params: ClassVar[tuple[Param, ...]] = (
        Param("albedo", "facet albedo ρ", min=0.0, max=1.0, default=1.0, example=0.8),
        Param(
            "sigma",
            "standard deviation σ of the facet slope angle",
            unit="radians",
            min=0.0,
            max=math.pi / 2,
            default=0.3,
        ),
        Param(
            "bounces",
            "light paths kept: 1 (shadowing and masking), up to 2 or 3, or all",
            choices=("all", "1", "2", "3"),
            default="all",
        ),
        Param(
            "measure",
            "reading of the slope measure: per solid angle of normals, or per slope angle",
            choices=("solid-angle", "angle"),
            default="solid-angle",
        ),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"v-cavity": {}}
    labels: ClassVar[dict[str, str]] = {"v-cavity": "V-cavity surface (exact)"}
    reference: ClassVar[str] = (
        "M. Oren, S. K. Nayar, Generalization of Lambert's reflectance model, SIGGRAPH 1994 "
        "(Sec. 3-4); solved exactly by roughdiffuse.simulate"
    )
    glsl: ClassVar[bool] = False
    compiled: ClassVar[bool] = False
    """Not compilable (fast path, ``jax.jit``): evaluated from a table on NumPy."""

    def __post_init__(self) -> None:
        b = self.bounces
        if isinstance(b, int | np.integer) and not isinstance(b, bool):
            object.__setattr__(self, "bounces", str(int(b)))  # bounces=1 as well as "1"
        super().__post_init__()

    # ------------------------------------------------------------------ evaluation
    def _table(self) -> Any:
        return vcavity_table(float(self.sigma), float(self.albedo), self.bounces, self.measure)

    def _kernel(
        self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, albedo: Array, sigma: Array
    ) -> Array:
        """f from the local cosines (NumPy; see the class docstring for other namespaces)."""
        out = _to_numpy(xp, mu_i, mu_o, cos_io)
        mi, mo, c = np.broadcast_arrays(*out)
        rho, sig = float(self.albedo), float(self.sigma)
        if rho == 0.0:
            f = np.zeros(mi.shape)
        elif sig == 0.0:
            f = np.full(mi.shape, rho / math.pi)
        else:
            ti, tr = (np.arccos(np.clip(m, 0.0, 1.0)) for m in (mi, mo))
            den = np.sin(ti) * np.sin(tr)
            ti, tr = np.minimum(ti, THETA_CAP), np.minimum(tr, THETA_CAP)
            cos_dp = np.where(den > 1e-12, (c - mi * mo) / np.where(den > 1e-12, den, 1.0), 1.0)
            dp = np.arccos(np.clip(cos_dp, -1.0, 1.0))
            pts = np.stack([ti.reshape(-1), tr.reshape(-1), dp.reshape(-1)], axis=-1)
            f = np.exp(self._table()(pts)).reshape(mi.shape) if pts.size else np.zeros(mi.shape)
        return _from_numpy(xp, f)

    def brdf(self, wi: Array, wo: Array) -> Array:
        """BRDF f_r(wi, wo) in 1/sr (see :meth:`Model.brdf`); never compiled."""
        from .._array import result_dtype
        from ..frames import local_cosines

        xp = self._xp(wi, wo)
        _refuse_tracers(xp, wi, wo)
        dtype = result_dtype(xp, wi, wo)
        mu_i, mu_o, cos_io = local_cosines(xp, wi, wo, dtype)
        return self._eval(xp, mu_i, mu_o, cos_io, dtype)

    def brdf_cosines(self, mu_i: Array, mu_o: Array, cos_io: Array) -> Array:
        """The BRDF from the local cosines (see :meth:`Model.brdf_cosines`); never compiled."""
        from .._array import asarray, result_dtype

        xp = self._xp(mu_i, mu_o, cos_io)
        _refuse_tracers(xp, mu_i, mu_o, cos_io)
        dtype = result_dtype(xp, mu_i, mu_o, cos_io)
        mu_i, mu_o, cos_io = (asarray(xp, a, dtype) for a in (mu_i, mu_o, cos_io))
        return self._eval(xp, mu_i, mu_o, cos_io, dtype)

    def radiance(self, n: Array, l: Array, v: Array, irradiance: Array | float = 1.0) -> Array:
        """Radiance L = f_r E0 cos θi (see :meth:`Model.radiance`); never compiled."""
        from .._array import asarray, clip, result_dtype
        from ..frames import world_cosines
        from .base import _check_irradiance

        _check_irradiance(irradiance)
        xp = self._xp(n, l, v, irradiance)
        _refuse_tracers(xp, n, l, v)
        dtype = result_dtype(xp, n, l, v)
        mu_i, mu_o, cos_io = world_cosines(xp, n, l, v, dtype)
        f = self._eval(xp, mu_i, mu_o, cos_io, dtype)
        cos_i = clip(xp, mu_i, 0.0, 1.0)
        e0 = asarray(xp, irradiance, dtype)
        if e0.ndim == 1:
            f, cos_i = f[..., None], cos_i[..., None]
        return f * e0 * cos_i


def _refuse_tracers(xp: Any, *arrays: Any) -> None:
    """TypeError for symbols (``jax.jit`` tracers, the fast path's tracer): no closed form."""
    if is_numpy(xp) or all(concrete(a) is not None for a in arrays if a is not None):
        return
    raise TypeError(
        "VCavity is tabulated from the exact solver, not an array-API closed form: "
        "jax.jit, gradients and the compiled fast path cannot trace it; call its brdf or "
        "radiance on concrete arrays"
    )


def _to_numpy(xp: Any, *arrays: Any) -> list[np.ndarray]:
    out = []
    for a in arrays:
        value = concrete(a)
        if value is None:
            _refuse_tracers(xp, a)
        out.append(np.asarray(value, dtype=np.float64))
    return out


def _from_numpy(xp: Any, f: np.ndarray) -> Array:
    if is_numpy(xp):
        return f
    if is_jax(xp):
        return xp.asarray(f)
    return xp.asarray(f, dtype=xp.float64)

