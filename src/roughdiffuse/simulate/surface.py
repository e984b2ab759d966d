"""The V-cavity surface: cavity radiance averaged over the slope distribution (Oren & Nayar).

Oren and Nayar (SIGGRAPH 1994, Sec. 4, "slope-area distribution") average the radiance of
V-cavities over a Gaussian distribution of the facet slope θa of standard deviation σ, isotropic
in the orientation φa. The surface BRDF is that average radiance divided by E0 cos θi.

Two readings of Oren & Nayar's (1994, Sec. 3) slope measure, selectable by name
(docs/accuracy.md, finding 1):

* ``"angle"``: P(θa) dθa ∝ exp(−θa²/2σ²) dθa, a density in the slope angle, as in the
  lecture's 1-D Gaussian of the slope (a half-normal in |θa|);
* ``"solid-angle"``: P dω ∝ exp(−θa²/2σ²) sin θa dθa dφa, a density per solid angle of facet
  normals.

Both are truncated to θa < π/2 and normalised there; φa is uniform on [0, π) (a cavity is
symmetric under φa → φa + π).

Quadrature (the rule, and why it reaches 1e-4):

* φa: the integrand is a piecewise-analytic function of φa whose kinks are known in closed
  form (a facet turning away from l or v, shadowing or masking setting in, lit and visible
  fractions crossing: each an equation a cos φ + b sin φ = c). [0, π) is split at every kink
  and each piece gets an ``n_phi``-point Gauss–Legendre rule.
* θa, one bounce: split at the onsets of shadowing and masking (θa = π/2 − θi, π/2 − θr) and
  at the truncation θmax = min(π/2, 10σ); ``n_theta`` Gauss–Legendre points per piece.
* θa, bounces 2..N (the interreflected part, a smooth and smaller term): one Gauss–Legendre
  rule of ``n_theta_inter`` points on [0, θmax], common to all geometries, so that each node's
  radiosity matrix is built once.

:func:`quadrature_convergence` doubles every rule and K and reports the change.
"""

from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np

from .._array import (
    Array,
    asarray,
    clip,
    concrete,
    double_precision,
    is_jax,
    is_numpy,
    is_tracer,
    maximum,
    minimum,
    namespace,
)
from .._validate import ParameterError, check_range
from ..quadrature import gauss_legendre
from .cavity import (
    COS_FLOOR,
    Bounces,
    _const,
    _Facets,
    check_bounces,
    check_elements,
    element_edges,
    elements_for_slope,
    extrapolated,
    radiosity_operator,
    response_table,
    slope_function,
    tabulated_interreflected,
)

__all__ = [
    "MEASURES",
    "METHODS",
    "Measure",
    "Method",
    "Settings",
    "brdf",
    "quadrature_convergence",
    "slope_weight",
]

Measure = Literal["angle", "solid-angle"]
MEASURES: tuple[str, ...] = ("angle", "solid-angle")
Method = Literal["tabulated", "reference"]
METHODS: tuple[str, ...] = ("tabulated", "reference")

THETA_GRAZING = math.pi / 2 - 1e-7
"""θi and θr are clamped to this: f at exactly 90° is the (finite) limit, not 0/0."""

SIGMA_MAX = math.pi / 2

SIGMA_FLAT = 1e-12
"""σ (radians) below which the surface is computed as flat (σ = 0): the BRDF differs from the
flat one by about (σ / cos θ)² relative (measured: 1.1e-10 at σ = 1e-9, θ = 89.994°), below
float64 rounding for σ < 1e-12 and θ < 89.99°; smaller σ would underflow the slope
quadrature's weights (NaN at σ = 1e-200, 0.2 % off at 1e-160)."""


@dataclass(frozen=True)
class Settings:
    """Solver settings (stored with every table).

    Attributes
    ----------
    measure : {"angle", "solid-angle"}
        Reading of the slope-area measure (module docstring). The default, "solid-angle", is
        the one the Oren–Nayar coefficients fit (docs/accuracy.md).
    elements : int
        Radiosity elements per facet K (raised to 2K where tan θa > 3 and 4K where
        tan θa > 12, see :func:`roughdiffuse.simulate.cavity.elements_for_slope`).
    extrapolate : bool
        Richardson extrapolation from K and 2K elements.
    n_theta, n_phi, n_theta_inter : int
        Gauss–Legendre points per θa piece (one bounce), per φa piece, and on [0, θmax] for
        the interreflected part.
    method : {"tabulated", "reference"}
        How each cavity's interreflected part is evaluated. "reference": the element
        radiosity solved per cavity (segment factors by crossed strings, the operator
        product, the seen weights: :class:`~roughdiffuse.simulate.cavity.InterreflectionSolver`).
        "tabulated" (default): the same element solution, tabulated once per slope node as
        a function of the lit and visible fractions
        (:class:`~roughdiffuse.simulate.cavity.ResponseTable`: exact in the visible fraction,
        cubic in the lit one); it agrees with "reference" to about 1e-7 of f
        (tests/test_simulate_surface.py, bench/RESULTS.md) and is some 20× faster.
    """

    measure: Measure = "solid-angle"
    elements: int = 16
    extrapolate: bool = True
    n_theta: int = 16
    n_phi: int = 16
    n_theta_inter: int = 32
    method: Method = "tabulated"

    def __post_init__(self) -> None:
        if self.measure not in MEASURES:
            raise ParameterError(f"measure must be one of {MEASURES} (got {self.measure!r})")
        if self.method not in METHODS:
            raise ParameterError(f"method must be one of {METHODS} (got {self.method!r})")
        check_elements(self.elements)
        for name in ("n_theta", "n_phi", "n_theta_inter"):
            val = getattr(self, name)
            if isinstance(val, bool) or not isinstance(val, int | np.integer) or val < 1:
                raise ParameterError(f"{name} must be an integer >= 1 (got {val!r})")

    def doubled(self) -> Settings:
        """The same settings with every rule and K doubled (for convergence checks)."""
        d = asdict(self)
        for k in ("elements", "n_theta", "n_phi", "n_theta_inter"):
            d[k] *= 2
        return Settings(**d)


def slope_weight(theta_a: Array, sigma: float, measure: Measure) -> Array:
    """Unnormalised slope density at θa: exp(−θa²/2σ²), times sin θa for "solid-angle"."""
    xp = namespace(theta_a)
    w = xp.exp(-0.5 * (theta_a / sigma) ** 2)
    return w * xp.sin(theta_a) if measure == "solid-angle" else w


def _pieces(xp: Any, edges: Array, n: int) -> tuple[Array, Array]:
    """Gauss–Legendre nodes and weights on each interval of sorted ``edges`` (..., E)."""
    t, w = (_const(xp, a) for a in gauss_legendre(n))
    a, b = edges[..., :-1, None], edges[..., 1:, None]
    nodes = a + (b - a) * t
    weights = (b - a) * w
    shape = tuple(edges.shape[:-1]) + (-1,)
    return xp.reshape(nodes, shape), xp.reshape(weights, shape)


def _phi_quadrature(xp: Any, edges: Array, n: int):
    """φa nodes and weights on the pieces of ``edges`` (..., E), without the empty pieces.

    Returns ``(rows, nodes, weights)``. NumPy: only the pieces of nonzero width (about half
    of them, the kinks that do not exist sit at π), as ``(V, n)`` arrays, and ``rows`` (V,)
    the flat index of each piece's leading position (sum with :func:`_sum_rows`). Other
    namespaces (fixed shapes under ``jax.jit``): every piece, ``rows`` None, arrays
    ``(..., (E − 1) n)``.
    """
    if not is_numpy(xp):
        ph, wph = _pieces(xp, edges, n)
        return None, ph, wph
    e = np.asarray(edges)
    e = e.reshape(-1, e.shape[-1])
    width = e[:, 1:] - e[:, :-1]
    rows, piece = np.nonzero(width > 0)
    t, w = gauss_legendre(n)
    h = width[rows, piece][:, None]
    return rows, e[rows, piece][:, None] + h * t, h * w


def _take_rows(xp: Any, rows, a: Array, shape: tuple[int, ...]) -> Array:
    """``a`` broadcast to ``shape``, at the pieces' ``rows`` (a column), or as is (dense)."""
    if rows is None:
        return a[..., None]
    return np.reshape(np.broadcast_to(a, shape), (-1,))[rows][:, None]


def _direction_rows(xp: Any, rows, w, shape: tuple[int, ...]):
    """Components (..., 1) of a direction at the pieces' rows (a Python float stays)."""
    return [c if isinstance(c, float) else _take_rows(xp, rows, c[..., 0], shape) for c in w]


def _sum_rows(xp: Any, rows, values: Array, shape: tuple[int, ...]) -> Array:
    """Sum over the φa nodes back to ``shape`` (see :func:`_phi_quadrature`)."""
    if rows is None:
        return xp.sum(values, axis=-1)
    size = math.prod(shape)
    return np.bincount(rows, weights=np.sum(values, axis=-1), minlength=size).reshape(shape)


def _solve_kinks(xp: Any, a: Array, b: Array, c: Array) -> list[Array]:
    """Both roots φ of a cos φ + b sin φ = c (NaN where none)."""
    r = xp.sqrt(a * a + b * b)
    ratio = xp.where(r > 0, c / xp.where(r > 0, r, 1.0), math.inf)
    ok = xp.abs(ratio) <= 1.0
    d = xp.acos(clip(xp, ratio, -1.0, 1.0))
    delta = xp.atan2(b, a)
    return [xp.where(ok, delta + d, math.nan), xp.where(ok, delta - d, math.nan)]


def _phi_edges(xp: Any, theta_a, ti, tr, dphi) -> Array:
    """Sorted φa piece edges in [0, π] (kinks of the cavity radiance, mod π), shape (..., E).

    E ≤ 12: with concrete values, columns of kinks that exist for none of the geometries are
    left out (under ``jax.jit`` all are kept: a kink that does not exist is a piece of zero
    width at π, with zero weight).

    Conditions for the facet of normal azimuth φ (the other facet is φ + π, hence mod π),
    with l at azimuth 0 and v at azimuth Δφ: n_f·l = 0, n_f·l = 2 cos θa cos θi (shadowing
    starts), the same two for v, and cos θi (n_f·v) = cos θr (n_f·l) (lit and visible
    fractions equal).
    """
    sa, ca = slope_function(xp, "sin", theta_a), slope_function(xp, "cos", theta_a)
    si, ci, sr, cr = xp.sin(ti), xp.cos(ti), xp.sin(tr), xp.cos(tr)
    cd, sd = xp.cos(dphi), xp.sin(dphi)
    zero = xp.zeros_like(sa * si * sr * cd)
    roots = []
    for sign in (-1.0, 1.0):
        roots += _solve_kinks(xp, sa * si + zero, zero, sign * ca * ci + zero)
        roots += _solve_kinks(xp, sa * sr * cd + zero, sa * sr * sd + zero, sign * ca * cr + zero)
    roots += _solve_kinks(xp, ci * sr * cd - cr * si + zero, ci * sr * sd + zero, zero)
    k = xp.stack(roots, axis=-1)
    k = xp.sort(xp.where(xp.isnan(k), math.pi, xp.remainder(k, math.pi)), axis=-1)
    values = concrete(k)
    if values is not None:  # kinks that do not exist sit at π: drop the columns of none
        k = k[..., : int(np.max(np.sum(values < math.pi, axis=-1), initial=0))]
    zero = xp.zeros(tuple(k.shape[:-1]) + (1,), dtype=k.dtype)
    return xp.concat([zero, k, zero + math.pi], axis=-1)


def _directions(xp: Any, ti, tr, dphi):
    l = (xp.sin(ti), 0.0, xp.cos(ti))  # l_y = 0: _Facets skips its terms
    v = (xp.sin(tr) * xp.cos(dphi), xp.sin(tr) * xp.sin(dphi), xp.cos(tr))
    return l, v


def _single_bounce(xp: Any, ti, tr, dphi, sigma, albedo, s: Settings) -> Array:
    """∫∫ P L1 dθa dφa / cos θi for flat arrays of geometries (one bounce, closed form)."""
    theta_max = min(SIGMA_MAX, 10.0 * sigma)
    c1 = clip(xp, math.pi / 2 - ti, 0.0, theta_max)
    c2 = clip(xp, math.pi / 2 - tr, 0.0, theta_max)
    edges = xp.sort(xp.stack([xp.zeros_like(ti), c1, c2, xp.zeros_like(ti) + theta_max], axis=-1))
    th, wth = _pieces(xp, edges, s.n_theta)  # (M, 3 n)
    wth = wth * slope_weight(th, sigma, s.measure)
    norm = xp.sum(wth, axis=-1)
    ti_, tr_, dp_ = (a[:, None] for a in (ti, tr, dphi))
    # first piece, θa < π/2 − max(θi, θr): both facets lit and seen whole (g = 1) for every
    # φa, so L1 = ρ ℓ/(π cos θr) Σ± (n±·l)(n±·v), whose mean over φa is closed form:
    # ρ (2 cos²θa cos θi cos θr + sin²θa sin θi sin θr cos Δφ) / (2π cos θa cos θr)
    n = s.n_theta
    t1 = th[:, :n]
    ca, sa = xp.cos(t1), xp.sin(t1)
    ci, si = xp.cos(ti_), xp.sin(ti_)
    cr = maximum(xp, xp.cos(tr_), COS_FLOOR)
    sr_cd = xp.sin(tr_) * xp.cos(dp_)
    first = albedo * (2.0 * ca * ca * ci * cr + sa * sa * si * sr_cd) / (2.0 * math.pi * ca * cr)
    # the other pieces: the φa rule split at the kinks
    rest = th[:, n:]
    rows, ph, wph = _phi_quadrature(xp, _phi_edges(xp, rest, ti_, tr_, dp_), s.n_phi)
    shape = tuple(rest.shape)
    ti_, tr_, dp_, th_ = (_take_rows(xp, rows, a, shape) for a in (ti_, tr_, dp_, rest))
    l, v = _directions(xp, ti_, tr_, dp_)
    facets = _Facets(th_, xp.cos(ph), xp.sin(ph), l, v, albedo, xp, terms=False)
    inner = _sum_rows(xp, rows, facets.single * wph, shape) / math.pi
    total = xp.sum(first * wth[:, :n], axis=-1) + xp.sum(inner * wth[:, n:], axis=-1)
    return total / norm / xp.cos(ti)


@functools.lru_cache(maxsize=4)
def _slope_nodes(sigma: float, albedo: float, bounces: Bounces, s: Settings):
    """θa nodes of the interreflected part, grouped by element count, with their operators.

    Returns ``[(edges, nodes, weights, operators), ...]``, one entry per element count
    (:func:`elements_for_slope`): the element edges of each level (K and 2K), the nodes and
    normalised weights of the group, and per node either (method "reference") per level the
    radiosity operator (None, the identity, for N <= 2 bounces) or (method "tabulated") its
    :class:`~roughdiffuse.simulate.cavity.ResponseTable`. Cached: every chunk of a table
    uses the same ones (a few tens of MB for the tables of one σ).
    """
    theta_max = min(SIGMA_MAX, 10.0 * sigma)
    t, w = gauss_legendre(s.n_theta_inter)
    nodes, weights = theta_max * t, theta_max * w * slope_weight(theta_max * t, sigma, s.measure)
    weights = weights / weights.sum()
    groups: dict[int, list[tuple[float, float]]] = {}
    for ta, wa in zip(nodes.tolist(), weights.tolist(), strict=True):
        groups.setdefault(elements_for_slope(ta, s.elements), []).append((ta, wa))
    out = []
    for k, members in groups.items():
        edges = [element_edges(n) for n in ((k, 2 * k) if s.extrapolate else (k,))]
        if s.method == "tabulated":
            ops = [
                response_table(ta, albedo, bounces, s.elements, s.extrapolate)
                for ta, _ in members
            ]
        else:
            ops = [
                [radiosity_operator(ta, albedo, bounces, e) for e in edges] for ta, _ in members
            ]
        out.append((edges, [m[0] for m in members], [m[1] for m in members], ops))
    return out


def _table_arrays(tables, xp: Any):
    """Cell counts and per-node arrays of a group's response tables (stacked for JAX)."""
    first = tables[0]
    names = ("opposite", "same", "opposite_difference", "same_difference")
    if is_jax(xp) and len(tables) > 1:
        arrays = tuple(
            None
            if getattr(first, n) is None
            else _const(xp, np.stack([getattr(t, n) for t in tables]))
            for n in names
        )
    else:
        arrays = [tuple(getattr(t, n) for n in names) for t in tables]
    return first.cells, first.nodes, arrays


def _interreflected(
    xp: Any, ti, tr, dphi, sigma, albedo, bounces, s: Settings, difference: bool = True
):
    """Bounces 2..N of the surface BRDF and the change from K to 2K elements.

    Within a group of :func:`_slope_nodes` every node runs the same code with its own slope,
    weight and radiosity operators (or response table): a Python loop, or under JAX one
    ``lax.scan`` (compiled once per group, not per node). Without ``difference`` the
    tabulated method skips the K-to-2K change (returned as zeros).
    """
    l, v = _directions(xp, ti[:, None], tr[:, None], dphi[:, None])
    out = diff = xp.zeros_like(ti)
    for edges, nodes, weights, ops in _slope_nodes(sigma, albedo, bounces, s):
        if s.method == "tabulated":
            cells, count, arrays = _table_arrays(ops, xp)

            def term(ta, wa, arrays, cells=cells, count=count):
                rows, ph, wph = _phi_quadrature(xp, _phi_edges(xp, ta, ti, tr, dphi), s.n_phi)
                shape = tuple(ti.shape)
                lr, vr = (_direction_rows(xp, rows, w, shape) for w in (l, v))
                facets = _Facets(
                    ta, xp.cos(ph), xp.sin(ph), lr, vr, albedo, xp, single=False, clamp=False
                )
                arrays = tuple(_const(xp, a) if isinstance(a, np.ndarray) else a for a in arrays)
                val, dk = tabulated_interreflected(facets, (cells, count, arrays), difference)
                f = wa / math.pi * _sum_rows(xp, rows, val * wph, shape)
                if dk is None:
                    return f, xp.zeros_like(f)
                return f, wa / math.pi * _sum_rows(xp, rows, dk * wph, shape)

            if is_jax(xp) and len(nodes) > 1:
                import jax

                def body(carry, x, term=term):
                    f, d = term(x[0], x[1], x[2])
                    return (carry[0] + f, carry[1] + d), None

                xs = (_const(xp, nodes), _const(xp, weights), arrays)
                (out, diff), _ = jax.lax.scan(body, (out, diff), xs)
            else:
                for ta, wa, arr in zip(nodes, weights, arrays, strict=True):
                    f, d = term(ta, wa, arr)
                    out, diff = out + f, diff + d
            continue

        def term(ta, wa, ops, edges=edges):
            ops = list(ops) or [None] * len(edges)  # () from lax.scan when there are none
            ph, wph = _pieces(xp, _phi_edges(xp, ta, ti, tr, dphi), s.n_phi)
            facets = _Facets(ta, xp.cos(ph), xp.sin(ph), l, v, albedo, xp)
            val, dk = extrapolated(ta, facets, albedo, list(zip(edges, ops, strict=True)))
            dk = xp.zeros_like(val) if dk is None else dk
            return (
                wa / math.pi * xp.sum(val * wph, axis=-1),
                wa / math.pi * xp.sum(dk * wph, axis=-1),
            )

        if is_jax(xp) and len(nodes) > 1:
            import jax

            def body(carry, x, term=term):
                f, d = term(x[0], x[1], x[2])
                return (carry[0] + f, carry[1] + d), None

            stacked = (
                ()
                if ops[0][0] is None
                else tuple(_const(xp, np.stack([o[j] for o in ops])) for j in range(len(edges)))
            )
            xs = (_const(xp, nodes), _const(xp, weights), stacked)
            (out, diff), _ = jax.lax.scan(body, (out, diff), xs)
        else:
            for ta, wa, op in zip(nodes, weights, ops, strict=True):
                f, d = term(ta, wa, op)
                out, diff = out + f, diff + d
    return out / xp.cos(ti), diff / xp.cos(ti)


def _evaluate(xp: Any, ti, tr, dp, sigma, albedo, bounces, s: Settings, difference=True):
    """f and its K-to-2K change for flat float64 arrays of (clamped) geometries."""
    if sigma == 0.0:
        return xp.zeros_like(ti) + albedo / math.pi, xp.zeros_like(ti)
    f = _single_bounce(xp, ti, tr, dp, sigma, albedo, s)
    if bounces == 1 or albedo == 0:
        return f, xp.zeros_like(ti)
    inter, dk = _interreflected(xp, ti, tr, dp, sigma, albedo, bounces, s, difference)
    return f + inter, -dk


@functools.lru_cache(maxsize=32)
def _jitted(sigma: float, albedo: float, bounces: Bounces, s: Settings, difference: bool):
    """:func:`_evaluate` on JAX arrays of one chunk, compiled once per parameter set."""
    import jax
    import jax.numpy as jnp

    return jax.jit(
        lambda ti, tr, dp: _evaluate(jnp, ti, tr, dp, sigma, albedo, bounces, s, difference)
    )


def _validate(sigma, albedo, bounces, settings) -> tuple[float, float, Bounces, Settings]:
    check_range("sigma", sigma, 0.0, SIGMA_MAX, unit="radians")
    check_range("albedo", albedo, 0.0, 1.0)
    if float(sigma) < SIGMA_FLAT:
        sigma = 0.0  # flat to float64 rounding (SIGMA_FLAT)
    bounces = check_bounces(bounces)
    if settings is None:
        settings = Settings()
    elif not isinstance(settings, Settings):
        raise ParameterError(
            f"settings must be a Settings instance (got {type(settings).__name__})"
        )
    return float(sigma), float(albedo), bounces, settings


def brdf(
    theta_i,
    theta_r,
    delta_phi,
    sigma: float,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    settings: Settings | None = None,
    *,
    chunk: int = 32,
    return_difference: bool = False,
):
    """Exact BRDF of the V-cavity surface, f(θi, θr, φr − φi; σ, ρ, bounces), in 1/sr.

    Vectorised over arrays of geometries, written once against the array API: NumPy,
    PyTorch and JAX arrays give a float64 array of their own kind. JAX arrays run the
    compiled path: each chunk of ``chunk`` geometries is one ``jax.jit`` program (compiled
    once per σ, ρ, bounces and settings; the quadrature nodes and radiosity operators are its
    constants), in float64 whether or not ``jax_enable_x64`` is set. Called inside the
    caller's own ``jax.jit``, it is traced like any JAX code (σ, ρ, bounces static).

    Parameters
    ----------
    theta_i, theta_r : array_like
        Incidence and viewing angles in [0, π/2] radians (broadcast together).
    delta_phi : array_like
        Azimuth difference φr − φi, radians.
    sigma : float
        Standard deviation of the facet slope, [0, π/2] radians; 0 is the Lambert limit ρ/π.
    albedo : float
        Facet albedo ρ in [0, 1].
    bounces : int >= 1 or "all"
        Number of bounces (1: shadowing and masking only) or all of them.
    settings : Settings, optional
        Slope measure and quadrature settings (default :class:`Settings`).
    chunk : int
        Geometries evaluated at once (memory: about chunk × 2000 × 4K doubles). Small
        chunks keep the work in the CPU's cache (measured: bench/RESULTS.md, "Thresholds").
    return_difference : bool
        Also return f(K) − f(2K) elementwise for the interreflected part (zeros for one
        bounce or without extrapolation).

    Returns
    -------
    array
        f_r, broadcast shape of the angles (and the K difference if asked).

    Examples
    --------
    >>> import numpy as np
    >>> round(float(brdf(0.3, 0.5, 1.0, sigma=0.0, albedo=0.5) * np.pi), 12)
    0.5

    The same on JAX arrays (compiled):

    >>> import jax.numpy as jnp
    >>> f = brdf(jnp.array([0.3]), 0.5, 1.0, sigma=0.2, albedo=0.5, bounces=1)
    >>> g = brdf(0.3, 0.5, 1.0, sigma=0.2, albedo=0.5, bounces=1)
    >>> bool(abs(float(f[0]) - float(g)) < 1e-9)
    True
    """
    sigma, albedo, bounces, s = _validate(sigma, albedo, bounces, settings)
    for name, val in (("theta_i", theta_i), ("theta_r", theta_r)):
        # π/2 rounded to float32 is a little above π/2 and must pass
        value = concrete(val)
        top = math.pi / 2
        if value is not None and value.dtype == np.float32:
            top = float(np.float32(top))
        check_range(name, val, 0.0, top, unit="radians", scalar=False)
    if isinstance(chunk, bool) or not isinstance(chunk, int | np.integer) or chunk < 1:
        raise ParameterError(f"chunk must be an integer >= 1 (got {chunk!r})")
    dp_value = concrete(delta_phi)
    if dp_value is not None and not np.all(np.isfinite(dp_value)):
        raise ParameterError("delta_phi must be finite")
    xp = namespace(theta_i, theta_r, delta_phi)
    with double_precision(xp):
        ti, tr, dp = xp.broadcast_arrays(
            *(asarray(xp, a, xp.float64) for a in (theta_i, theta_r, delta_phi))
        )
        shape = tuple(ti.shape)
        ti = minimum(xp, xp.reshape(ti, (-1,)), THETA_GRAZING)
        tr = minimum(xp, xp.reshape(tr, (-1,)), THETA_GRAZING)
        dp = xp.reshape(dp, (-1,))
        rows = int(ti.shape[0])
        compiled = is_jax(xp) and not is_tracer(ti) and not is_tracer(dp) and not is_tracer(tr)
        out, diff = [], []
        if compiled:  # few compiled shapes: a power of two up to chunk, the last one padded
            chunk = min(chunk, 1 << max(rows - 1, 0).bit_length())
        for a in range(0, rows, chunk):
            part = [x[a : a + chunk] for x in (ti, tr, dp)]
            n = int(part[0].shape[0])
            if compiled:
                if n < chunk:  # pad with a benign geometry (θi = θr = 0)
                    part = [xp.concat([x, xp.zeros(chunk - n, dtype=x.dtype)]) for x in part]
                f, d = _jitted(sigma, albedo, bounces, s, return_difference)(*part)
            else:
                f, d = _evaluate(xp, *part, sigma, albedo, bounces, s, return_difference)
            out.append(f[:n])
            diff.append(d[:n])
        if rows == 0:
            out, diff = [ti], [ti]
        f = xp.reshape(xp.concat(out), shape)
        if return_difference:
            return f, xp.reshape(xp.concat(diff), shape)
        return f


def quadrature_convergence(
    theta_i,
    theta_r,
    delta_phi,
    sigma: float,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    settings: Settings | None = None,
) -> dict[str, float]:
    """Largest relative change of f when each rule (and K) is doubled, one at a time.

    Returns a dict with keys ``"n_theta"``, ``"n_phi"``, ``"n_theta_inter"``, ``"elements"``
    and ``"all"`` (everything doubled at once), each the max |Δf| / f over the geometries.
    """
    sigma, albedo, bounces, s = _validate(sigma, albedo, bounces, settings)
    base = brdf(theta_i, theta_r, delta_phi, sigma, albedo, bounces, s)
    out = {}
    d = asdict(s)
    for key in ("n_theta", "n_phi", "n_theta_inter", "elements"):
        dd = dict(d)
        dd[key] *= 2
        f = brdf(theta_i, theta_r, delta_phi, sigma, albedo, bounces, Settings(**dd))
        out[key] = float(np.max(np.abs(f - base) / np.maximum(np.abs(f), 1e-300)))
    f = brdf(theta_i, theta_r, delta_phi, sigma, albedo, bounces, s.doubled())
    out["all"] = float(np.max(np.abs(f - base) / np.maximum(np.abs(f), 1e-300)))
    return out
