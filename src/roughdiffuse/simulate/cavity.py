"""One symmetric V-cavity with Lambertian facets: shadowing, masking and interreflection.

The microsurface of Oren and Nayar (SIGGRAPH 1994, Sec. 3–4): a long symmetric V-cavity of
facet slope θa (facet normal's angle from the macroscopic normal z) and orientation φa. Its
facet normals are n± = (±sin θa cos φa, ±sin θa sin φa, cos θa). The cavity is infinitely long,
so shadowing, masking and interreflection are problems in its cross-section, where a direction
enters through its projection; the Lambertian cosines use the 3-D vectors.

Cross-section (x along a = (cos φa, sin φa, 0), y = z, width w = 1): facet "+" (normal
(sin θa, cos θa)) runs from the rim (−1/2, 0) to the vertex (0, −tan θa / 2), facet "−" from
(1/2, 0) to the vertex. A facet point is at fraction s ∈ [0, 1] of the way from its rim.

* Shadowing and masking (Torrance & Sparrow, JOSA 1967, V-groove geometry): the lit part of a
  facet is the segment s ∈ [0, g_l] with g_l = min(1, 2 cos θa (n·l) / (n_f·l)) where
  n_f·l > 0, else 0; the visible part likewise with v.
* One bounce, closed form: L1 / E0 = Σ_f ρ/π (n_f·l) min(g_l, g_v) ℓ (n_f·v) / (n·v),
  ℓ = 1 / (2 cos θa) the facet length (Oren & Nayar 1994, Sec. 3).
* Interreflection: radiosity between the two facets, K elements each, exact element-to-element
  view factors from Hottel's crossed-strings rule (Modest, *Radiative Heat Transfer*, §4.8).
  The direct term stays exact (closed form above); only the interreflected radiosity is
  piecewise constant on the elements.
* Tabulated interreflection: the element solution depends on a cavity's geometry only
  through, per facet, the lit and visible fractions (times the lit exitance and the
  projected visible length), so per slope it is tabulated once as a function of (g_v, g_l)
  (:class:`ResponseTable`, :func:`tabulated_interreflected`); the surface solver uses it by
  default, :class:`InterreflectionSolver` is the per-cavity reference.

Radiances here are per unit irradiance E0 on a plane facing the source.
"""

from __future__ import annotations

import functools
import math
import numbers
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from .._array import (
    Array,
    asarray,
    clip,
    concrete,
    double_precision,
    is_jax,
    is_tracer,
    maximum,
    minimum,
    namespace,
)
from .._validate import ParameterError, check_range

__all__ = [
    "Bounces",
    "cavity_radiance",
    "check_bounces",
    "check_elements",
    "element_edges",
    "elements_for_slope",
    "radiosity_operator",
    "InterreflectionSolver",
    "ResponseTable",
    "response_table",
    "segment_factors",
    "tabulated_interreflected",
    "view_factors",
]

Bounces = int | Literal["all"]

COS_FLOOR = 1e-12
"""Floor of n·l and n·v: a direction exactly on the horizon gives a zero radiance, not 0/0."""


def check_bounces(bounces: Bounces) -> Bounces:
    """Validate ``bounces``: an integer ≥ 1 or ``"all"``."""
    if isinstance(bounces, str):
        if bounces != "all":
            raise ParameterError(f"bounces must be an integer >= 1 or 'all' (got {bounces!r})")
        return bounces
    if isinstance(bounces, bool) or not isinstance(bounces, int | np.integer) or bounces < 1:
        raise ParameterError(f"bounces must be an integer >= 1 or 'all' (got {bounces!r})")
    return int(bounces)


def check_elements(elements: int) -> int:
    """Validate the number of radiosity elements per facet K (an integer ≥ 1)."""
    if isinstance(elements, bool) or not isinstance(elements, int | np.integer) or elements < 1:
        raise ParameterError(f"elements (K) must be an integer >= 1 (got {elements!r})")
    return int(elements)


def element_edges(elements: int) -> np.ndarray:
    """Edges s_k ∈ [0, 1] of the K elements of a facet (rim at 0, vertex at 1).

    Cosine spacing, s_k = (1 − cos(πk/K)) / 2: fine at the rim, where the lit and visible
    segments end in deep cavities, and at the vertex, where the facets meet. Measured against
    K = 256, this spacing converged fastest of uniform, vertex-graded, rim-graded and cosine.
    """
    k = np.arange(elements + 1) / elements
    return 0.5 * (1.0 - np.cos(math.pi * k))


def elements_for_slope(theta_a: float, elements: int) -> int:
    """Elements per facet used at slope θa: K, 2K where tan θa > 3, 4K where tan θa > 12.

    Deep cavities (long facets per unit width) need finer elements for the same accuracy.
    """
    t = math.tan(theta_a)
    return elements * (4 if t > 12.0 else 2 if t > 3.0 else 1)


def radiosity_operator(
    theta_a: float, albedo: float, bounces: Bounces, edges: np.ndarray
) -> np.ndarray | None:
    """Matrix M with B = M B_2 for the 2K facet elements ("+" first, then "−").

    B_2 is the element-averaged radiosity (exitance) of the second bounce, computed exactly
    from the lit segments (:func:`segment_factors`); B, the radiosity of bounces 2 to N, is
    Σ_{k=0}^{N-2} (ρF)^k B_2 for N bounces (M = None, the identity, for N ≤ 2) and
    (I − ρF)^{-1} B_2 for all bounces. F is the element view-factor matrix.
    """
    if bounces != "all" and bounces <= 2:
        return None
    f = view_factors(theta_a, edges)
    k = f.shape[0]
    full = np.zeros((2 * k, 2 * k))
    full[:k, k:] = f
    full[k:, :k] = f  # mirror symmetry: F from "-" element i to "+" element j is f[i, j]
    rf = albedo * full
    eye = np.eye(2 * k)
    if bounces == "all":
        return np.linalg.inv(eye - rf)
    m = np.zeros_like(rf)
    power = eye
    for _ in range(int(bounces) - 1):
        m = m + power
        power = power @ rf
    return m


def slope_function(xp: Any, name: str, theta_a: float | Array) -> float | Array:
    """``math.<name>`` of a number, ``xp.<name>`` of an array (a slope traced by JAX).

    The slope of a group of cavities is a Python float in loops and a 0-d array under
    ``jax.lax.scan``; functions of it stay Python floats where they can.
    """
    if isinstance(theta_a, numbers.Real):
        return getattr(math, name)(theta_a)
    return getattr(xp, name)(theta_a)


def _points(tan_a, s, sign: float):
    """Cross-section points at fractions s of facet "+" (sign 1) or "−" (sign −1)."""
    return sign * (-0.5 + 0.5 * s), -0.5 * tan_a * s


def _strings(theta_a: float, a0, a1, b0, b1) -> np.ndarray:
    """A F between segment [a0, a1] of facet "+" and [b0, b1] of facet "−" (crossed strings).

    Hottel's rule for 2-D surfaces that see each other without obstruction: A_1 F_12 =
    (crossed strings − uncrossed strings) / 2 (Modest, *Radiative Heat Transfer*, §4.8).
    Lengths are per unit cavity width; the facets of a V see each other entirely.
    """
    t = math.tan(theta_a)
    pa0, pa1 = _points(t, a0, 1.0), _points(t, a1, 1.0)
    pb0, pb1 = _points(t, b0, -1.0), _points(t, b1, -1.0)

    def d(p, q):
        return np.hypot(p[0] - q[0], p[1] - q[1])

    return 0.5 * np.abs(d(pa0, pb1) + d(pa1, pb0) - d(pa0, pb0) - d(pa1, pb1))


def view_factors(theta_a: float, edges: np.ndarray) -> np.ndarray:
    """View factors F[i, j] from element i of facet "+" to element j of facet "−".

    Crossed-strings rule (:func:`_strings`). By the mirror symmetry of the cavity the same
    matrix gives F from "−" to "+"; with equal element lengths on the two facets it is
    symmetric (reciprocity A_i F_ij = A_j F_ji).
    """
    e0, e1 = edges[:-1], edges[1:]
    af = _strings(theta_a, e0[:, None], e1[:, None], e0[None, :], e1[None, :])
    return af / (np.diff(edges) * 0.5 / math.cos(theta_a))[:, None]


def _const(xp: Any, a: np.ndarray | float) -> Array:
    """A float64 constant of the solver (element edges, operators) in namespace ``xp``."""
    return xp.asarray(np.asarray(a, dtype=np.float64), dtype=xp.float64)


def segment_factors(theta_a: float | Array, edges: np.ndarray, g: Array, xp: Any = None) -> Array:
    """A_j F_j→S: area times view factor from each element j of one facet to the segment
    S = [0, g] of the other; shape (..., K) for ``g`` of shape (...).

    By reciprocity it is also A_S F_S→j, and the irradiance that S, emitting uniformly with
    exitance B, sends to element j is B A_j F_j→S / A_j. ``theta_a`` is a float or a 0-d
    array (a traced slope under ``jax.lax.scan``).
    """
    xp = xp or namespace(g)
    tan_a = slope_function(xp, "tan", theta_a)
    # crossed strings as in _strings, with the distances shared between adjacent elements
    # and those from the fixed rim computed once
    ex, ey = _points(tan_a, _const(xp, edges), -1.0)
    d0 = xp.sqrt((ex + 0.5) ** 2 + ey**2)  # from the other facet's rim (-1/2, 0)
    gx, gy = _points(tan_a, g[..., None], 1.0)
    dx, dy = ex - gx, ey - gy
    dg = xp.sqrt(dx * dx + dy * dy)
    return 0.5 * xp.abs(d0[1:] + dg[..., :-1] - d0[:-1] - dg[..., 1:])


def _facet_terms(xp: Any, scale: Array, mu_f: Array) -> Array:
    """Lit (or visible) fraction g = min(1, 2 cos θa μ / μ_f) where μ_f > 0, else 0.

    ``scale`` is 2 cos θa μ (> 0: μ is floored at :data:`COS_FLOOR`). A negative ratio (μ_f < 0)
    clips to 0; μ_f = 0 gives +inf, clipped to 1, where the facet's exitance or projected
    length max(μ_f, 0) is 0, so the value never counts.
    """
    return clip(xp, scale / mu_f, 0.0, 1.0)


class _Facets:
    """Per-facet quantities of cavities lit from l and seen from v (no bounce yet).

    ``theta_a`` is a float or an array, ``cos_phi``, ``sin_phi`` and the components of ``l``
    and ``v`` arrays of one namespace (NumPy, JAX or PyTorch), broadcast together. Factors
    that do not depend on φa (functions of θa, l_z, v_z) are formed before they meet the
    φa arrays, so that each full-size operation is one pass.
    """

    def __init__(
        self,
        theta_a,
        cos_phi,
        sin_phi,
        l,
        v,
        albedo: float,
        xp: Any = None,
        single: bool = True,
        terms: bool = True,
        clamp: bool = True,
    ) -> None:
        """``single``: form the one-bounce radiance :attr:`single`; ``terms``: the per-facet
        (g_l, g_v, exitance, projected length) of :attr:`terms`, the last two clamped at 0
        (``clamp``) or not (for a caller that multiplies them by a g that is 0 there)."""
        xp = xp or namespace(cos_phi, *l, *v)
        self.xp = xp
        with np.errstate(divide="ignore"):  # μ_f = 0 in _facet_terms (NumPy warns, no harm)
            self._build(theta_a, cos_phi, sin_phi, l, v, albedo, single, terms, clamp)

    def _build(self, theta_a, cos_phi, sin_phi, l, v, albedo, single, terms, clamp) -> None:
        xp = self.xp
        sa, ca = slope_function(xp, "sin", theta_a), slope_function(xp, "cos", theta_a)
        lx, ly, lz = l
        vx, vy, vz = v
        lz = maximum(xp, lz, COS_FLOOR)
        vz = maximum(xp, vz, COS_FLOOR)
        # components along a (the cross-section's x axis), times sin θa (l_y = 0 skipped)
        sla = (sa * lx) * cos_phi
        if not (isinstance(ly, numbers.Real) and ly == 0):
            sla = sla + (sa * ly) * sin_phi
        sva = (sa * vx) * cos_phi + (sa * vy) * sin_phi
        cl, cv = ca * lz, ca * vz
        scale_l, scale_v = 2.0 * cl, 2.0 * cv
        inv_vz = 1.0 / vz
        self.facet_len = 0.5 / ca
        weight = (albedo / math.pi) * self.facet_len * inv_vz
        self.single = 0.0
        self.terms = []
        for sign in (1.0, -1.0):
            mu_l = cl + sla if sign > 0 else cl - sla
            mu_v = cv + sva if sign > 0 else cv - sva
            g_l = _facet_terms(xp, scale_l, mu_l)
            g_v = _facet_terms(xp, scale_v, mu_v)
            if single:  # μ_l μ_v min(g_l, g_v): where a μ < 0 its g is 0, no clamp needed
                self.single = self.single + weight * (mu_l * mu_v) * minimum(xp, g_l, g_v)
            if terms:
                if clamp:
                    mu_l, mu_v = maximum(xp, mu_l, 0.0), maximum(xp, mu_v, 0.0)
                # exitance of the lit segment per E0; (n_f·v)/(n·v), projected length per length
                self.terms.append((g_l, g_v, albedo * mu_l, mu_v * inv_vz))


def _interreflected(
    theta_a: float | Array,
    facets: _Facets,
    albedo: float,
    operator: Array | None,
    edges: np.ndarray,
) -> Array:
    """Radiance / E0 of bounces 2..N of cavities of slope ``theta_a`` (a float or a 0-d array).

    ``operator`` is :func:`radiosity_operator`'s matrix (NumPy or ``facets.xp``; ``None``
    for the identity).
    """
    xp = facets.xp
    (gl_p, gv_p, b1_p, view_p), (gl_m, gv_m, b1_m, view_m) = facets.terms
    lengths = _const(xp, np.diff(edges)) * facets.facet_len
    # bounce 2 on the elements, exact: what each element receives from the other facet's
    # lit segment (exitance ρ μl), then bounces 3..N by the element operator
    s_lp = segment_factors(theta_a, edges, gl_p, xp)
    s_lm = segment_factors(theta_a, edges, gl_m, xp)
    scale = albedo / lengths
    b2 = xp.concat([b1_m[..., None] * s_lm * scale, b1_p[..., None] * s_lp * scale], axis=-1)
    if operator is not None:  # one 2-D product (stacked matmul is far slower in NumPy)
        op = _const(xp, operator) if isinstance(operator, np.ndarray) else operator
        flat = xp.reshape(b2, (-1, b2.shape[-1]))
        b2 = xp.reshape(xp.matmul(flat, xp.matrix_transpose(op)), b2.shape)
    # seen: element radiosity over the visible segment (keeps the discrete energy balance)
    lo, hi = _const(xp, edges[:-1]), _const(xp, edges[1:])
    seen = xp.concat(
        [
            (clip(xp, gv_p[..., None], lo, hi) - lo) * view_p[..., None],
            (clip(xp, gv_m[..., None], lo, hi) - lo) * view_m[..., None],
        ],
        axis=-1,
    )
    return facets.facet_len / math.pi * xp.sum(b2 * seen, axis=-1)


class InterreflectionSolver:
    """Bounces 2..N of cavities of one slope θa, for K elements (and 2K if extrapolating).

    K is raised for deep cavities by :func:`elements_for_slope`.

    With ``extrapolate`` the result is Richardson's (4 L_2K − L_K)/3: the element error falls
    as K^-2 (measured), and a linear combination of two energy-conserving solutions conserves
    energy too. :attr:`difference` evaluations return L_2K − L_K as well.
    """

    def __init__(
        self, theta_a: float, albedo: float, bounces: Bounces, elements: int, extrapolate: bool
    ) -> None:
        self.theta_a = float(theta_a)
        self.albedo = albedo
        k = elements_for_slope(self.theta_a, elements)
        ks = (k, 2 * k) if extrapolate else (k,)
        self.levels = []
        for k in ks:
            edges = element_edges(k)
            self.levels.append((edges, radiosity_operator(self.theta_a, albedo, bounces, edges)))

    def __call__(self, facets: _Facets, difference: bool = False):
        best, diff = extrapolated(self.theta_a, facets, self.albedo, self.levels)
        return (best, diff) if difference else best


def extrapolated(theta_a, facets: _Facets, albedo: float, levels) -> tuple[Array, Array | None]:
    """Bounces 2..N at each (edges, operator) level; with two levels (K and 2K),
    Richardson's (4 L_2K − L_K)/3.

    Returns the value and L_2K − L_K (``None`` for one level).
    """
    vals = [_interreflected(theta_a, facets, albedo, op, e) for e, op in levels]
    if len(vals) == 1:
        return vals[0], None
    return (4.0 * vals[1] - vals[0]) / 3.0, vals[1] - vals[0]


def _components(xp: Any, w: Array, shape: tuple[int, ...]) -> tuple[Array, Array, Array]:
    return tuple(xp.broadcast_to(w[..., k], shape) for k in range(3))


def cavity_radiance(
    theta_a: Array | float,
    phi_a: Array | float,
    wi: Array,
    wo: Array,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    elements: int = 32,
    extrapolate: bool = True,
) -> Array:
    """Radiance of one V-cavity seen from ``wo``, lit from ``wi``, per unit irradiance E0.

    L = Σ_f ∫_visible L_f(x) (n_f·v) dx / (w (n·v)) (Oren & Nayar 1994, Sec. 4).
    Divide by cos θi for the cavity's BRDF.

    Array-API code: NumPy, JAX and PyTorch arrays give a float64 result of their own kind
    (JAX computes in float64 whether or not ``jax_enable_x64`` is set). One bounce runs under
    ``jax.jit``; more bounces need concrete values of ``theta_a`` (the cavities are grouped by
    slope, each group with its own radiosity operator).

    Parameters
    ----------
    theta_a : float or array
        Facet slope θa in [0, π/2) radians.
    phi_a : float or array
        Cavity orientation φa (azimuth of the "+" facet normal), radians.
    wi, wo : array (..., 3)
        Unit directions towards the light and the viewer, z the macroscopic normal.
    albedo : float
        Facet albedo ρ in [0, 1].
    bounces : int >= 1 or "all"
        1: the closed form (shadowing and masking only); N: exactly N bounces; "all":
        the radiosity solution.
    elements : int >= 1
        Radiosity elements per facet K (unused for one bounce). The interreflected part
        converges as K^-2, except where the visible segment ends inside an element (K^-1):
        K = 32 is within about 1e-3 of the limit for θa <= 1.4 (tests/test_simulate_cavity.py).
    extrapolate : bool
        Richardson extrapolation from K and 2K elements (see :class:`InterreflectionSolver`).

    Returns
    -------
    array
        Broadcast shape of θa, φa, wi[..., 0], wo[..., 0]; 0 where l or v is below the
        horizon.

    Examples
    --------
    A flat cavity is a Lambertian plane: L = ρ/π cos θi.

    >>> import numpy as np
    >>> wi = np.array([np.sin(0.5), 0.0, np.cos(0.5)])
    >>> L = cavity_radiance(0.0, 0.0, wi, np.array([0.0, 0.0, 1.0]), albedo=1.0, bounces=1)
    >>> bool(np.isclose(L, np.cos(0.5) / np.pi))
    True
    """
    check_range("albedo", albedo, 0.0, 1.0)
    bounces = check_bounces(bounces)
    elements = check_elements(elements)
    check_range("theta_a", theta_a, 0.0, math.pi / 2, unit="radians", scalar=False)
    th_value = concrete(theta_a)
    if th_value is not None and np.any(th_value >= math.pi / 2):
        raise ParameterError("theta_a must be in [0, π/2) radians (got π/2)")
    xp = namespace(theta_a, phi_a, wi, wo)
    with double_precision(xp):
        theta_a, phi_a, wi, wo = (asarray(xp, a, xp.float64) for a in (theta_a, phi_a, wi, wo))
        for name, w in (("wi", wi), ("wo", wo)):
            if tuple(w.shape[-1:]) != (3,):
                raise ParameterError(f"{name} must have shape (..., 3) (got {tuple(w.shape)})")
        shape = tuple(
            np.broadcast_shapes(
                tuple(theta_a.shape), tuple(phi_a.shape), tuple(wi.shape[:-1]), tuple(wo.shape[:-1])
            )
        )
        th = xp.broadcast_to(theta_a, shape)
        ph = xp.broadcast_to(phi_a, shape)
        l, v = _components(xp, wi, shape), _components(xp, wo, shape)
        if is_jax(xp) and not any(is_tracer(a) for a in (th, ph, wi, wo)):
            out = _single_jitted(albedo)(th, ph, l, v)  # one compiled pass, not op by op
        else:
            out = _single(xp, th, ph, l, v, albedo)
        if bounces != 1:
            inter = _interreflected_grouped(
                xp, th, ph, l, v, albedo, bounces, elements, extrapolate
            )
            out = xp.where((l[2] >= 0) & (v[2] >= 0), out + inter, 0.0)
        return out


def _single(xp: Any, th, ph, l, v, albedo: float) -> Array:
    """One bounce (closed form), 0 where l or v is below the horizon."""
    out = _Facets(th, xp.cos(ph), xp.sin(ph), l, v, albedo, xp, terms=False).single
    return xp.where((l[2] >= 0) & (v[2] >= 0), out, 0.0)


@functools.lru_cache(maxsize=16)
def _single_jitted(albedo: float):
    import jax
    import jax.numpy as jnp

    return jax.jit(lambda th, ph, l, v: _single(jnp, th, ph, l, v, albedo))


def _interreflected_grouped(xp, th, ph, l, v, albedo, bounces, elements, extrapolate) -> Array:
    """Bounces 2..N of cavities of any slopes: one radiosity operator per distinct θa.

    The cavities are sorted by θa, each run of equal slopes is solved at once, and the
    results are put back in place (``take`` with the inverse permutation: no in-place update,
    so JAX and PyTorch run the same code).
    """
    values = concrete(th)
    if values is None:
        raise ParameterError(
            "cavity_radiance with bounces > 1 needs concrete theta_a values (not a jax.jit "
            "tracer): each slope gets its own radiosity operator"
        )
    flat = values.reshape(-1)
    order = np.argsort(flat, kind="stable")
    slopes, starts = np.unique(flat[order], return_index=True)
    ends = list(starts[1:]) + [flat.size]
    idx = xp.asarray(order)
    rows = [xp.take(xp.reshape(c, (-1,)), idx) for c in (ph, *l, *v)]
    parts = []
    for t, a, b in zip(slopes, starts, ends, strict=True):
        sub = [r[int(a) : int(b)] for r in rows]
        facets = _Facets(float(t), xp.cos(sub[0]), xp.sin(sub[0]), sub[1:4], sub[4:7], albedo, xp)
        parts.append(
            InterreflectionSolver(float(t), albedo, bounces, elements, extrapolate)(facets)
        )
    inverse = xp.asarray(np.argsort(order, kind="stable"))
    return xp.reshape(xp.take(xp.concat(parts), inverse), th.shape)


TABLE_NODES = 256
"""Cells of the lit-fraction axis of a :class:`ResponseTable` (uniform in t = arccos(1 − 2g)/π).

Cubic interpolation on 256 cells reproduced the element solution to 1e-7–6e-7 of the largest
interreflected value for θa from 0.3 to 1.5 (K = 16 to 64; 1e-6–6e-6 with 128 cells).
"""


@dataclass(frozen=True)
class ResponseTable:
    """The interreflected response of cavities of one slope θa, as a function of (g_v, g_l).

    Once the direct term is taken out (closed form), bounces 2..N of a cavity depend on its
    geometry only through, per facet, the visible fraction g_v, the lit fraction g_l, the
    exitance ρ(n_f·l) of the lit segment and the projected length (n_f·v)/(n·v) of the
    visible one (:func:`_interreflected`)::

        L / E0 = ℓ/π Σ_{a, b ∈ {+, −}} view_a b1_b T_{ab}(g_v,a, g_l,b),

    T = T_opposite where the seen facet a is not the lit facet b, T_same where it is. With
    the element radiosity of :func:`_interreflected`, T(g_v, g_l) = u(g_v)ᵀ M s(g_l): the
    segment factors s of the lit segment (:func:`segment_factors`, scaled to exitance), the
    radiosity operator M (:func:`radiosity_operator`) and the seen weights u, which are
    piecewise linear in g_v with kinks at the element edges. So T / g_l is tabulated exactly
    in g_v (linear on the finest level's elements, which contain the coarser level's edges,
    so the Richardson combination (4 T_2K − T_K)/3 is linear there too) and by a cubic
    polynomial in t = arccos(1 − 2 g_l)/π on ``nodes`` uniform cells of t (the cosine-spaced
    elements' own coordinate; the function is even about t = 0 and t = 1, which gives the
    end cells their outer neighbours). Dividing by g_l keeps the relative accuracy where
    g_l → 0 (grazing incidence, where f = L / cos θi magnifies L); at g_l = 0 the table holds
    the limit, from the derivative of the crossed strings (:func:`_segment_factor_slopes`).

    Attributes
    ----------
    cells : int
        Elements of the finest level (the g_v axis).
    nodes : int
        Cells of the t axis.
    opposite, same : ndarray (nodes * cells, 8)
        Per (t cell j, element i), row j * cells + i: α_0..α_3, β_0..β_3 with
        T = g_l Σ_p (α_p + β_p g_v) τ^p, τ = t·nodes − j.
    opposite_difference, same_difference : ndarray or None
        The same for T_2K − T_K (None without extrapolation).
    """

    cells: int
    nodes: int
    opposite: np.ndarray
    same: np.ndarray
    opposite_difference: np.ndarray | None
    same_difference: np.ndarray | None


def _segment_factor_slopes(theta_a: float, edges: np.ndarray) -> np.ndarray:
    """d/dg of :func:`segment_factors` at g = 0 (the limit of s(g)/g), shape (K,).

    With p(g) the point at fraction g of facet "+" and q_m the edges of "−", each string
    |p(g) − q_m| has derivative (p − q_m)·p′ / |p − q_m| at g = 0, p′ = (1/2, −tan θa / 2).
    """
    t = math.tan(theta_a)
    dx, dy = -1.0 + 0.5 * edges, 0.5 * t * edges  # p(0) − q_m
    dd = (0.5 * dx - 0.5 * t * dy) / np.hypot(dx, dy)
    return 0.5 * np.abs(dd[:-1] - dd[1:])


def _cumulative_response(theta_a: float, albedo: float, bounces: Bounces, k: int, g: np.ndarray):
    """T_opposite / g_l and T_same / g_l of one element level at the edges (g_v) and lit
    fractions g (the limit g → 0 where g = 0)."""
    edges = element_edges(k)
    op = radiosity_operator(theta_a, albedo, bounces, edges)
    lengths = np.diff(edges)
    zero = g == 0.0
    s = segment_factors(theta_a, edges, g, np) / np.where(zero, 1.0, g)[:, None]
    s[zero] = _segment_factor_slopes(theta_a, edges)
    s *= albedo / (lengths * 0.5 / math.cos(theta_a))
    # s[:, j]: what element j of facet "+" receives from the lit segment [0, g] of "−"
    w_opp = s if op is None else s @ op[:k, :k].T
    w_same = np.zeros_like(s) if op is None else s @ op[k:, :k].T
    zero = np.zeros((g.size, 1))
    return edges, [
        np.concatenate([zero, np.cumsum(w * lengths, axis=1)], axis=1) for w in (w_opp, w_same)
    ]


def _cubic_rows(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    """Per-cell coefficients (α_0..α_3, β_0..β_3) from values at (t nodes with one ghost
    row each side, element edges)."""
    pm, p0, p1, p2 = values[:-3], values[1:-2], values[2:-1], values[3:]
    # cubic Lagrange through τ = −1, 0, 1, 2, in powers of τ
    c = np.stack(
        [
            p0,
            -pm / 3.0 - p0 / 2.0 + p1 - p2 / 6.0,
            pm / 2.0 - p0 + p1 / 2.0,
            -pm / 6.0 + p0 / 2.0 - p1 / 2.0 + p2 / 6.0,
        ],
        axis=-1,
    )  # (nodes, cells + 1, 4)
    beta = (c[:, 1:] - c[:, :-1]) / np.diff(edges)[None, :, None]
    alpha = c[:, :-1] - beta * edges[None, :-1, None]
    rows = np.concatenate([alpha, beta], axis=-1)  # (nodes, cells, 8)
    return np.ascontiguousarray(rows.reshape(-1, 8))


def response_table(
    theta_a: float,
    albedo: float,
    bounces: Bounces,
    elements: int,
    extrapolate: bool,
    nodes: int = TABLE_NODES,
) -> ResponseTable:
    """Tabulate the interreflected response of cavities of slope θa (:class:`ResponseTable`).

    Same elements as :class:`InterreflectionSolver` (K from :func:`elements_for_slope`, and
    2K with Richardson extrapolation), so :func:`tabulated_interreflected` reproduces it up to
    the cubic interpolation in the lit fraction.
    """
    theta_a = float(theta_a)
    k = elements_for_slope(theta_a, elements)
    ks = (k, 2 * k) if extrapolate else (k,)
    t = np.arange(-1, nodes + 2) / nodes
    g = 0.5 * (1.0 - np.cos(math.pi * t))  # t = −1/n and 1 + 1/n mirror t = 1/n and 1 − 1/n
    levels = [_cumulative_response(theta_a, albedo, bounces, n, g) for n in ks]
    fine = levels[-1][0]

    def on_fine(edges, c):
        """Values at the coarse edges, linearly interpolated to the fine ones (one product:
        the coarse edges are the even fine edges)."""
        if edges.size == fine.size:
            return c
        weights = np.zeros((fine.size, edges.size))
        j = np.minimum(np.searchsorted(edges, fine, side="right") - 1, edges.size - 2)
        a = (fine - edges[j]) / (edges[j + 1] - edges[j])
        rows = np.arange(fine.size)
        weights[rows, j] = 1.0 - a
        weights[rows, j + 1] += a
        return c @ weights.T

    if extrapolate:
        (e1, (o1, s1)), (_, (o2, s2)) = levels
        o1, s1 = on_fine(e1, o1), on_fine(e1, s1)
        parts = [(4.0 * o2 - o1) / 3.0, (4.0 * s2 - s1) / 3.0, o2 - o1, s2 - s1]
    else:
        parts = list(levels[0][1]) + [None, None]
    rows = [None if p is None else _cubic_rows(p, fine) for p in parts]
    return ResponseTable(fine.size - 1, nodes, *rows)


def _table_index(xp: Any, g: Array, count: int) -> tuple[Array, Array]:
    """Cell of fraction g on ``count`` uniform cells of t = arccos(1 − 2g)/π, and t·count."""
    t = xp.acos(clip(xp, 1.0 - 2.0 * g, -1.0, 1.0)) * (count / math.pi)
    i = clip(xp, xp.floor(t), 0.0, count - 1.0)
    return xp.astype(i, xp.int64), t - i


def _table_value(xp: Any, rows: Array, cell: Array, gv: Array, tau: Array) -> Array:
    """T at the cells ``cell`` (flat row index) for visible fractions gv and offsets tau."""
    shape = tuple(gv.shape)
    r = xp.take(rows, xp.reshape(cell, (-1,)), axis=0)
    gv, tau = xp.reshape(gv, (-1,)), xp.reshape(tau, (-1,))
    c = [r[:, p] + r[:, 4 + p] * gv for p in range(4)]
    return xp.reshape(((c[3] * tau + c[2]) * tau + c[1]) * tau + c[0], shape)


def tabulated_interreflected(
    facets: _Facets, table: ResponseTable | tuple[Array, ...], difference: bool = False
) -> tuple[Array, Array | None]:
    """Bounces 2..N of cavities of one slope from its :class:`ResponseTable`.

    ``table`` is a :class:`ResponseTable` or its arrays ``(opposite, same,
    opposite_difference, same_difference)`` in ``facets.xp`` (a slope traced under
    ``jax.lax.scan``), as ``(cells, nodes, arrays)``. Returns the value and, with
    ``difference``, L_2K − L_K (None without it or without extrapolation).
    """
    xp = facets.xp
    if isinstance(table, ResponseTable):
        cells, nodes = table.cells, table.nodes
        arrays = (table.opposite, table.same, table.opposite_difference, table.same_difference)
        arrays = tuple(None if a is None else _const(xp, a) for a in arrays)
    else:
        cells, nodes, arrays = table
    (gl_p, gv_p, b1_p, view_p), (gl_m, gv_m, b1_m, view_m) = facets.terms
    iv_p, _ = _table_index(xp, gv_p, cells)
    iv_m, _ = _table_index(xp, gv_m, cells)
    il_p, tau_p = _table_index(xp, gl_p, nodes)
    il_m, tau_m = _table_index(xp, gl_m, nodes)
    # the tables hold T / g_l; b1 g_l is 0 where the facet faces away (g_l = 0) and T is 0
    # at g_v = 0, so the facets' terms may come unclamped (_Facets(clamp=False))
    lit_p, lit_m = b1_p * gl_p, b1_m * gl_m
    pairs = (  # (seen facet's weight × lit exitance × g_l, table, g_v cell, g_v, g_l cell, τ)
        (view_p * lit_m, 0, iv_p, gv_p, il_m, tau_m),
        (view_p * lit_p, 1, iv_p, gv_p, il_p, tau_p),
        (view_m * lit_p, 0, iv_m, gv_m, il_p, tau_p),
        (view_m * lit_m, 1, iv_m, gv_m, il_m, tau_m),
    )
    difference = difference and arrays[2] is not None
    out = []
    for offset in (0, 2) if difference else (0,):
        total = 0.0
        for weight, kind, iv, gv, il, tau in pairs:
            rows = arrays[offset + kind]
            total = total + weight * _table_value(xp, rows, il * cells + iv, gv, tau)
        out.append(facets.facet_len / math.pi * total)
    return out[0], (out[1] if difference else None)
