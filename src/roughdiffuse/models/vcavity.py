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
from typing import Any, ClassVar

import numpy as np

from .._array import Array, clip
from .base import Model
from .declaration import param

__all__ = ["VCavity", "THETA_CAP", "vcavity_table"]

THETA_CAP = math.radians(89.0)
"""θi and θr are clamped to this before the table is read (see :class:`VCavity`)."""

TABLE_THETA = 20
"""Nodes of the θi and θr axes, on [0, :data:`THETA_CAP`], denser towards grazing."""

TABLE_PHI = 13
"""Nodes of the Δφ axis, uniform on [0, π] (15° apart)."""


def _theta_nodes() -> np.ndarray:
    """θ_k = θcap sin(πk / 2(N − 1)): the index k is a closed-form function of θ."""
    k = np.arange(TABLE_THETA) / (TABLE_THETA - 1)
    return THETA_CAP * np.sin(0.5 * math.pi * k)


@functools.lru_cache(maxsize=8)
def vcavity_table(sigma: float, albedo: float, bounces: str, measure: str) -> np.ndarray:
    """log f on the table's nodes, with one ghost node at each end of every axis.

    f is computed by :func:`roughdiffuse.simulate.brdf` (default settings, 1e-4) at
    :data:`TABLE_THETA` θi × :data:`TABLE_THETA` θr (:func:`_theta_nodes`) ×
    :data:`TABLE_PHI` Δφ nodes, θi ≤ θr only (reciprocity gives the rest). The ghosts follow
    from symmetries, so the cubic stencil needs no one-sided rule: f is even in Δφ about 0
    and π; a negative polar angle is the azimuth turned by π, f(−θi, θr, Δφ) =
    f(θi, θr, π − Δφ); and the node coordinate is even about the cap (dθ/dk = 0 there).
    Cached per parameter set; shape (N + 2, N + 2, M + 2).
    """
    from ..simulate import Settings, brdf

    n, m = TABLE_THETA, TABLE_PHI
    th = _theta_nodes()
    dp = np.linspace(0.0, math.pi, m)
    i, j = np.triu_indices(n)
    b: int | str = bounces if bounces == "all" else int(bounces)
    f = np.asarray(
        brdf(
            np.repeat(th[i], m),
            np.repeat(th[j], m),
            np.tile(dp, i.size),
            sigma,
            albedo,
            b,
            Settings(measure=measure),
        )
    ).reshape(-1, m)
    table = np.empty((n + 2, n + 2, m + 2))
    core = table[1:-1, 1:-1, 1:-1]
    core[i, j] = np.log(f)
    core[j, i] = np.log(f)
    table[1:-1, 1:-1, 0] = table[1:-1, 1:-1, 2]  # Δφ = −step: even about 0
    table[1:-1, 1:-1, -1] = table[1:-1, 1:-1, -3]  # Δφ = π + step: even about π
    table[0] = table[2, :, ::-1]  # θi = −θ_1: Δφ → π − Δφ
    table[-1] = table[-3]  # beyond the cap: the node coordinate is even there
    table[:, 0] = table[:, 2, ::-1]
    table[:, -1] = table[:, -3]
    return table


def _cubic_weights(t: Array) -> tuple[Array, Array, Array, Array]:
    """Lagrange weights of nodes −1, 0, 1, 2 at t ∈ [0, 1]."""
    return (
        -t * (t - 1.0) * (t - 2.0) / 6.0,
        (t + 1.0) * (t - 1.0) * (t - 2.0) / 2.0,
        -(t + 1.0) * t * (t - 2.0) / 2.0,
        (t + 1.0) * t * (t - 1.0) / 6.0,
    )


def _cell(xp: Any, u: Array, cells: int) -> tuple[Array, Array]:
    """Cell index (int) and offset in it of node coordinate u ∈ [0, cells]."""
    i = xp.floor(u)
    i = xp.where(i < 0.0, 0.0, xp.where(i > cells - 1.0, cells - 1.0, i))
    return xp.astype(i, xp.int32), u - i


class VCavity(Model):
    """The exact V-cavity surface (Oren & Nayar 1994): shadowing, masking, interreflection.

    f(θi, θr, Δφ; σ, ρ) of long symmetric V-cavities with Lambertian facets, slopes Gaussian
    of standard deviation σ (truncated at π/2), computed by the exact solver
    :func:`roughdiffuse.simulate.brdf` (docs/accuracy.md) and interpolated from a table
    (:func:`vcavity_table`: tricubic in log f on 20 × 20 × 13 nodes, computed once per
    parameter set, a few seconds with all bounces). The interpolation agrees with the
    solver within 1% (tests/test_models_vcavity.py; measured: median 1e-5, largest 6e-3
    over 40 random geometries below 85°, at the retroreflection ridge θi = θr, Δφ = 0
    and towards grazing, where f has kinks that a cubic rounds).

    Grazing limit: the V-cavity f diverges like 1/cos θ where θi and θr are both grazing
    (the radiance L = f E0 cos θi stays finite; docs/developer/ground-truth.md). Here θi and θr are
    clamped to :data:`THETA_CAP` = 89° before the table is read, so f is finite everywhere
    and, beyond 89°, equals its value at 89°.

    The interpolation is array-API code (gathers), so the model runs on NumPy, JAX (also
    under ``jax.jit``, as the renderer calls it), PyTorch and Dr.Jit: the Mitsuba 3 plugin
    ``roughdiffuse_v_cavity`` (:mod:`roughdiffuse.integrations.mitsuba`, class attribute
    ``mitsuba = True``) reads the same table with ``dr.gather``. σ and ρ are static, not
    differentiable: gradients with respect to them do not exist here. The compiled fast
    path (:mod:`roughdiffuse.engine.fastpath`) refuses it with a ``TypeError`` (class attribute
    ``closed_form = False``: its scalar Numba code has no gather).

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

    albedo: float | Array = param("facet albedo ρ", min=0.0, max=1.0, default=1.0, example=0.8)
    sigma: float | Array = param(
        "standard deviation σ of the facet slope angle",
        unit="radians",
        min=0.0,
        max=math.pi / 2,
        default=0.3,
    )
    bounces: str = param(
        "light paths kept: 1 (shadowing and masking), up to 2 or 3, or all",
        choices=("all", "1", "2", "3"),
        default="all",
    )
    measure: str = param(
        "reading of the slope measure: per solid angle of normals, or per slope angle",
        choices=("solid-angle", "angle"),
        default="solid-angle",
    )

    ids: ClassVar[dict[str, dict[str, Any]]] = {"v-cavity": {}}
    labels: ClassVar[dict[str, str]] = {"v-cavity": "V-cavity surface (exact)"}
    reference: ClassVar[str] = (
        "M. Oren, S. K. Nayar, Generalization of Lambert's reflectance model, SIGGRAPH 1994 "
        "(Sec. 3-4); solved exactly by roughdiffuse.simulate"
    )
    order: ClassVar[int] = 170
    closed_form: ClassVar[bool] = False
    """A table, not a closed form: the compiled fast path (scalar Numba code) cannot trace
    its gathers, and ``compare_models`` leaves it out."""
    mitsuba: ClassVar[bool] = True
    """A Mitsuba plugin all the same: the Dr.Jit namespace gathers from the table
    (``xp.take``), σ and ρ are fixed when the BSDF is loaded."""
    array_fields: ClassVar[tuple[str, ...]] = ()
    symbols: ClassVar[dict[str, str]] = {
        "albedo": r"\rho",
        "sigma": r"\sigma",
    }
    formula: ClassVar[str | dict[str, str]] = r"""
        ```{math}
        f_r(\omega_i,\omega_o) =
        \frac{1}{E_0\cos\theta_i}\int_0^{\pi/2}\!\frac{1}{\pi}\int_0^{\pi}
        L_{\mathrm{cavity}}(\theta_a,\phi_a;\omega_i,\omega_o,\rho)\,\mathrm{d}\phi_a\;P(\theta_a)\,\mathrm{d}\theta_a
        ```
        ```{math}
        P(\theta_a) \propto e^{-\theta_a^2/2\sigma^2}\ (\text{measure angle}),
        ```
        ```{math}
        P(\theta_a) \propto e^{-\theta_a^2/2\sigma^2}\sin\theta_a
        \ (\text{measure solid-angle})
        ```

        Oren and Nayar (1994, Sec. 3–4): long symmetric V-cavities with Lambertian facets of
        albedo ρ and slope θa, azimuth φa uniform, {math}`L_{\mathrm{cavity}}` the radiance of
        one cavity with shadowing, masking and ``bounces`` orders of interreflection, P
        truncated to θa < π/2 and normalised there. Computed exactly by
        {func}`roughdiffuse.simulate.brdf` and interpolated (tricubic in log f) from a table
        per (σ, ρ, bounces, measure).
        """
    """No pytree leaves: σ and ρ select a table, they are static under ``jax.jit``."""

    def __post_init__(self) -> None:
        b = self.bounces
        if isinstance(b, int | np.integer) and not isinstance(b, bool):
            object.__setattr__(self, "bounces", str(int(b)))  # bounces=1 as well as "1"
        super().__post_init__()

    # ------------------------------------------------------------------ evaluation
    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array) -> Array:
        """f from the local cosines: tricubic interpolation of log f in the table.

        Array-API code with gathers (``take``), so it runs under ``jax.jit`` (the renderer);
        σ, ρ, bounces and measure are static (no pytree leaves: the table is computed from
        their concrete values). The fast path's scalar tracer has no ``take`` and is refused.
        """
        from ..engine.trace import TraceNamespace

        if isinstance(xp, TraceNamespace) or not hasattr(xp, "take"):
            raise TypeError(
                "VCavity is tabulated from the exact solver, not a closed form: the compiled "
                "fast path cannot trace it (closed_form = False); call its brdf or radiance"
            )
        rho, sig = float(self.albedo), float(self.sigma)
        zero = 0.0 * (mu_i + mu_o + cos_io)
        if rho == 0.0 or sig == 0.0:
            return zero + rho / math.pi
        table = vcavity_table(sig, rho, self.bounces, self.measure)
        mu_i, mu_o, cos_io = xp.broadcast_arrays(mu_i, mu_o, cos_io)
        n, m = TABLE_THETA, TABLE_PHI
        si = xp.sqrt(clip(xp, 1.0 - mu_i * mu_i, 0.0, 1.0))
        so = xp.sqrt(clip(xp, 1.0 - mu_o * mu_o, 0.0, 1.0))
        den = si * so
        ok = den > 1e-12
        cos_dp = xp.where(ok, (cos_io - mu_i * mu_o) / xp.where(ok, den, 1.0), 1.0)
        dp = xp.acos(clip(xp, cos_dp, -1.0, 1.0))
        scale = (n - 1) * 2.0 / math.pi
        coords = [
            _cell(xp, scale * xp.asin(clip(xp, xp.acos(mu) / THETA_CAP, 0.0, 1.0)), n - 1)
            for mu in (mu_i, mu_o)
        ] + [_cell(xp, dp * ((m - 1) / math.pi), m - 1)]
        (ia, ta), (ib, tb), (ic, tc) = coords
        wa, wb, wc = (_cubic_weights(t) for t in (ta, tb, tc))
        flat = xp.asarray(table.reshape(-1), dtype=mu_i.dtype)
        sa, sb = (n + 2) * (m + 2), m + 2
        base = ia * sa + ib * sb + ic  # the stencil's first node (ghost offset included)
        shape = tuple(base.shape)
        base = xp.reshape(base, (-1,))
        total = 0.0
        for a in range(4):
            for b in range(4):
                wab = xp.reshape(wa[a] * wb[b], (-1,))
                for c in range(4):
                    v = xp.take(flat, base + (a * sa + b * sb + c), axis=0)
                    total = total + (wab * xp.reshape(wc[c], (-1,))) * v
        return xp.exp(xp.reshape(total, shape)) + zero
