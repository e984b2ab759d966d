"""The V-cavity surface: cavity radiance averaged over the slope distribution (Oren & Nayar).

Oren and Nayar (SIGGRAPH 1994, Sec. 4, "slope-area distribution") average the radiance of
V-cavities over a Gaussian distribution of the facet slope θa of standard deviation σ, isotropic
in the orientation φa. The surface BRDF is that average radiance divided by E0 cos θi.

Two readings of the measure (DESIGN.md, "The V-cavity microsurface"), selectable by name:

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

import math
from dataclasses import asdict, dataclass
from typing import Literal

import numpy as np

from .._validate import check_range
from .cavity import (
    Bounces,
    InterreflectionSolver,
    _Facets,
    check_bounces,
    check_elements,
)

__all__ = [
    "MEASURES",
    "Measure",
    "Settings",
    "brdf",
    "quadrature_convergence",
    "slope_weight",
]

Measure = Literal["angle", "solid-angle"]
MEASURES: tuple[str, ...] = ("angle", "solid-angle")

THETA_GRAZING = math.pi / 2 - 1e-7
"""θi and θr are clamped to this: f at exactly 90° is the (finite) limit, not 0/0."""

SIGMA_MAX = math.pi / 2


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
    """

    measure: Measure = "solid-angle"
    elements: int = 16
    extrapolate: bool = True
    n_theta: int = 16
    n_phi: int = 16
    n_theta_inter: int = 32

    def __post_init__(self) -> None:
        if self.measure not in MEASURES:
            raise ValueError(f"measure must be one of {MEASURES} (got {self.measure!r})")
        check_elements(self.elements)
        for name in ("n_theta", "n_phi", "n_theta_inter"):
            val = getattr(self, name)
            if isinstance(val, bool) or not isinstance(val, int | np.integer) or val < 1:
                raise ValueError(f"{name} must be an integer >= 1 (got {val!r})")

    def doubled(self) -> Settings:
        """The same settings with every rule and K doubled (for convergence checks)."""
        d = asdict(self)
        for k in ("elements", "n_theta", "n_phi", "n_theta_inter"):
            d[k] *= 2
        return Settings(**d)


def slope_weight(theta_a: np.ndarray, sigma: float, measure: Measure) -> np.ndarray:
    """Unnormalised slope density at θa: exp(−θa²/2σ²), times sin θa for "solid-angle"."""
    w = np.exp(-0.5 * (theta_a / sigma) ** 2)
    return w * np.sin(theta_a) if measure == "solid-angle" else w


def _gauss(n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _pieces(edges: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on each interval of sorted ``edges`` (..., E)."""
    t, w = _gauss(n)
    a, b = edges[..., :-1, None], edges[..., 1:, None]
    nodes = a + (b - a) * t
    weights = (b - a) * w
    shape = edges.shape[:-1] + (-1,)
    return nodes.reshape(shape), weights.reshape(shape)


def _solve_kinks(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> list[np.ndarray]:
    """Both roots φ of a cos φ + b sin φ = c (NaN where none)."""
    r = np.hypot(a, b)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(r > 0, c / np.where(r > 0, r, 1.0), np.inf)
        ok = np.abs(ratio) <= 1.0
        d = np.arccos(np.clip(ratio, -1.0, 1.0))
    delta = np.arctan2(b, a)
    return [np.where(ok, delta + d, np.nan), np.where(ok, delta - d, np.nan)]


def _phi_edges(theta_a, ti, tr, dphi) -> np.ndarray:
    """Sorted φa piece edges in [0, π] (kinks of the cavity radiance, mod π), shape (..., E).

    E ≤ 12: columns of kinks that exist for none of the geometries are left out.

    Conditions for the facet of normal azimuth φ (the other facet is φ + π, hence mod π),
    with l at azimuth 0 and v at azimuth Δφ: n_f·l = 0, n_f·l = 2 cos θa cos θi (shadowing
    starts), the same two for v, and cos θi (n_f·v) = cos θr (n_f·l) (lit and visible
    fractions equal).
    """
    sa, ca = np.sin(theta_a), np.cos(theta_a)
    si, ci, sr, cr = np.sin(ti), np.cos(ti), np.sin(tr), np.cos(tr)
    cd, sd = np.cos(dphi), np.sin(dphi)
    zero = np.zeros_like(sa * si * sr * cd)
    roots = []
    for sign in (-1.0, 1.0):
        roots += _solve_kinks(sa * si + zero, zero, sign * ca * ci + zero)
        roots += _solve_kinks(sa * sr * cd + zero, sa * sr * sd + zero, sign * ca * cr + zero)
    roots += _solve_kinks(ci * sr * cd - cr * si + zero, ci * sr * sd + zero, zero)
    k = np.stack(roots, axis=-1)
    k = np.where(np.isnan(k), math.pi, np.mod(k, math.pi))
    k = np.sort(k, axis=-1)
    # kinks that do not exist sit at π: drop the columns where no row has a real one
    n = int(np.max(np.sum(k < math.pi, axis=-1), initial=0))
    k = k[..., :n]
    zero = np.zeros(k.shape[:-1] + (1,))
    return np.concatenate([zero, k, zero + math.pi], axis=-1)


def _directions(ti, tr, dphi):
    l = (np.sin(ti), np.zeros_like(ti), np.cos(ti))
    v = (np.sin(tr) * np.cos(dphi), np.sin(tr) * np.sin(dphi), np.cos(tr))
    return l, v


def _single_bounce(ti, tr, dphi, sigma, albedo, s: Settings) -> np.ndarray:
    """∫∫ P L1 dθa dφa / cos θi for flat arrays of geometries (one bounce, closed form)."""
    theta_max = min(SIGMA_MAX, 10.0 * sigma)
    c1 = np.clip(math.pi / 2 - ti, 0.0, theta_max)
    c2 = np.clip(math.pi / 2 - tr, 0.0, theta_max)
    edges = np.sort(
        np.stack([np.zeros_like(ti), c1, c2, np.full_like(ti, theta_max)], axis=-1), axis=-1
    )
    th, wth = _pieces(edges, s.n_theta)  # (M, 3 n)
    wth = wth * slope_weight(th, sigma, s.measure)
    norm = np.sum(wth, axis=-1)
    ti_, tr_, dp_ = (a[:, None] for a in (ti, tr, dphi))
    ph, wph = _pieces(_phi_edges(th, ti_, tr_, dp_), s.n_phi)  # (M, 3n, 11 n_phi)
    l, v = _directions(ti_[..., None], tr_[..., None], dp_[..., None])
    facets = _Facets(th[..., None], np.cos(ph), np.sin(ph), l, v, albedo)
    inner = np.sum(facets.single * wph, axis=-1) / math.pi
    return np.sum(inner * wth, axis=-1) / norm / np.cos(ti)


def _interreflected(ti, tr, dphi, sigma, albedo, bounces, s: Settings, difference: bool):
    """Bounces 2..N of the surface BRDF (and the K vs 2K change if ``difference``)."""
    theta_max = min(SIGMA_MAX, 10.0 * sigma)
    t, w = _gauss(s.n_theta_inter)
    nodes, weights = theta_max * t, theta_max * w * slope_weight(theta_max * t, sigma, s.measure)
    weights = weights / weights.sum()
    out = np.zeros_like(ti)
    diff = np.zeros_like(ti)
    for ta, wa in zip(nodes, weights, strict=True):
        solver = InterreflectionSolver(ta, albedo, bounces, s.elements, s.extrapolate)
        ph, wph = _pieces(_phi_edges(ta, ti, tr, dphi), s.n_phi)
        l, v = _directions(ti[:, None], tr[:, None], dphi[:, None])
        facets = _Facets(ta, np.cos(ph), np.sin(ph), l, v, albedo)
        val, dk = solver(facets, difference=True)
        out += wa * np.sum(val * wph, axis=-1) / math.pi
        if dk is not None:
            diff += wa * np.sum(dk * wph, axis=-1) / math.pi
    return out / np.cos(ti), diff / np.cos(ti)


def _validate(sigma, albedo, bounces, settings) -> tuple[float, float, Bounces, Settings]:
    check_range("sigma", sigma, 0.0, SIGMA_MAX, unit="radians")
    check_range("albedo", albedo, 0.0, 1.0)
    bounces = check_bounces(bounces)
    if settings is None:
        settings = Settings()
    elif not isinstance(settings, Settings):
        raise ValueError(f"settings must be a Settings instance (got {type(settings).__name__})")
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
    chunk: int = 256,
    return_difference: bool = False,
):
    """Exact BRDF of the V-cavity surface, f(θi, θr, φr − φi; σ, ρ, bounces), in 1/sr.

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
        Geometries evaluated at once (memory: about chunk × 2000 × 4K doubles).
    return_difference : bool
        Also return f(K) − f(2K) elementwise for the interreflected part (zeros for one
        bounce or without extrapolation).

    Returns
    -------
    ndarray
        f_r, broadcast shape of the angles (and the K difference if asked).

    Examples
    --------
    >>> import numpy as np
    >>> round(float(brdf(0.3, 0.5, 1.0, sigma=0.0, albedo=0.5) * np.pi), 12)
    0.5
    """
    sigma, albedo, bounces, s = _validate(sigma, albedo, bounces, settings)
    for name, val in (("theta_i", theta_i), ("theta_r", theta_r)):
        check_range(name, val, 0.0, math.pi / 2, unit="radians", scalar=False)
    ti, tr, dp = np.broadcast_arrays(
        *(np.asarray(a, dtype=float) for a in (theta_i, theta_r, delta_phi))
    )
    shape = ti.shape
    if not np.all(np.isfinite(dp)):
        raise ValueError("delta_phi must be finite")
    ti = np.minimum(ti.ravel(), THETA_GRAZING)
    tr = np.minimum(tr.ravel(), THETA_GRAZING)
    dp = dp.ravel()
    out = np.empty(ti.shape)
    diff = np.zeros(ti.shape)
    if sigma == 0.0:
        out[:] = albedo / math.pi
    else:
        for a in range(0, ti.size, chunk):
            sl = slice(a, a + chunk)
            out[sl] = _single_bounce(ti[sl], tr[sl], dp[sl], sigma, albedo, s)
            if bounces != 1 and albedo > 0:
                inter, dk = _interreflected(ti[sl], tr[sl], dp[sl], sigma, albedo, bounces, s, True)
                out[sl] += inter
                diff[sl] = -dk
    if return_difference:
        return out.reshape(shape), diff.reshape(shape)
    return out.reshape(shape)


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
