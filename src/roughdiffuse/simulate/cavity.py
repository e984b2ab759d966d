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
  ℓ = 1 / (2 cos θa) the facet length (DESIGN.md, "The V-cavity microsurface").
* Interreflection: radiosity between the two facets, K elements each, exact element-to-element
  view factors from Hottel's crossed-strings rule (Modest, *Radiative Heat Transfer*, §4.8).
  The direct term stays exact (closed form above); only the interreflected radiosity is
  piecewise constant on the elements.

Radiances here are per unit irradiance E0 on a plane facing the source.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np

from .._validate import check_range

__all__ = [
    "Bounces",
    "cavity_radiance",
    "check_bounces",
    "check_elements",
    "element_edges",
    "elements_for_slope",
    "radiosity_operator",
    "InterreflectionSolver",
    "segment_factors",
    "view_factors",
]

Bounces = int | Literal["all"]

COS_FLOOR = 1e-12
"""Floor of n·l and n·v: a direction exactly on the horizon gives a zero radiance, not 0/0."""


def check_bounces(bounces: Bounces) -> Bounces:
    """Validate ``bounces``: an integer ≥ 1 or ``"all"``."""
    if isinstance(bounces, str):
        if bounces != "all":
            raise ValueError(f"bounces must be an integer >= 1 or 'all' (got {bounces!r})")
        return bounces
    if isinstance(bounces, bool) or not isinstance(bounces, int | np.integer) or bounces < 1:
        raise ValueError(f"bounces must be an integer >= 1 or 'all' (got {bounces!r})")
    return int(bounces)


def check_elements(elements: int) -> int:
    """Validate the number of radiosity elements per facet K (an integer ≥ 1)."""
    if isinstance(elements, bool) or not isinstance(elements, int | np.integer) or elements < 1:
        raise ValueError(f"elements (K) must be an integer >= 1 (got {elements!r})")
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


def _points(theta_a: float, s: np.ndarray, sign: float) -> tuple[np.ndarray, np.ndarray]:
    """Cross-section points at fractions s of facet "+" (sign 1) or "−" (sign −1)."""
    return sign * (-0.5 + 0.5 * s), -0.5 * math.tan(theta_a) * s


def _strings(theta_a: float, a0, a1, b0, b1) -> np.ndarray:
    """A F between segment [a0, a1] of facet "+" and [b0, b1] of facet "−" (crossed strings).

    Hottel's rule for 2-D surfaces that see each other without obstruction: A_1 F_12 =
    (crossed strings − uncrossed strings) / 2 (Modest, *Radiative Heat Transfer*, §4.8).
    Lengths are per unit cavity width; the facets of a V see each other entirely.
    """
    pa0, pa1 = _points(theta_a, a0, 1.0), _points(theta_a, a1, 1.0)
    pb0, pb1 = _points(theta_a, b0, -1.0), _points(theta_a, b1, -1.0)

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


def segment_factors(theta_a: float, edges: np.ndarray, g: np.ndarray) -> np.ndarray:
    """A_j F_j→S: area times view factor from each element j of one facet to the segment
    S = [0, g] of the other; shape (..., K) for ``g`` of shape (...).

    By reciprocity it is also A_S F_S→j, and the irradiance that S, emitting uniformly with
    exitance B, sends to element j is B A_j F_j→S / A_j.
    """
    # crossed strings as in _strings, with the distances shared between adjacent elements
    # and those from the fixed rim computed once
    ex, ey = _points(theta_a, edges, -1.0)
    d0 = np.sqrt((ex + 0.5) ** 2 + ey**2)  # from the rim of the other facet, (-1/2, 0)
    gx, gy = _points(theta_a, np.asarray(g)[..., None], 1.0)
    dx, dy = ex - gx, ey - gy
    dg = np.sqrt(dx * dx + dy * dy)
    return 0.5 * np.abs(d0[1:] + dg[..., :-1] - d0[:-1] - dg[..., 1:])


def _overlap(edges: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Length of [s_k, s_{k+1}] ∩ [0, g] per element, shape (..., K)."""
    lo, hi = edges[:-1], edges[1:]
    return np.clip(g[..., None], lo, hi) - lo


def _facet_terms(cos_a, mu_f: np.ndarray, mu_n: np.ndarray) -> np.ndarray:
    """Lit (or visible) fraction g = min(1, 2 cos θa μ / μ_f) where μ_f > 0, else 0."""
    pos = mu_f > 0
    g = np.where(pos, 2.0 * cos_a * mu_n / np.where(pos, mu_f, 1.0), 0.0)
    return np.clip(g, 0.0, 1.0)


class _Facets:
    """Per-facet quantities of cavities lit from l and seen from v (no bounce yet)."""

    def __init__(self, theta_a, cos_phi, sin_phi, l, v, albedo: float) -> None:
        sa, ca = np.sin(theta_a), np.cos(theta_a)
        lx, ly, lz = l
        vx, vy, vz = v
        lz = np.maximum(lz, COS_FLOOR)
        vz = np.maximum(vz, COS_FLOOR)
        la = lx * cos_phi + ly * sin_phi  # components along a (the cross-section's x axis)
        va = vx * cos_phi + vy * sin_phi
        self.facet_len = 0.5 / ca
        self.single = 0.0
        self.terms = []
        for sign in (1.0, -1.0):
            mu_l = sign * sa * la + ca * lz
            mu_v = sign * sa * va + ca * vz
            g_l = _facet_terms(ca, mu_l, lz)
            g_v = _facet_terms(ca, mu_v, vz)
            b1 = albedo * np.maximum(mu_l, 0.0)  # exitance of the lit segment, per E0
            view = np.maximum(mu_v, 0.0) / vz  # (n_f·v)/(n·v): projected length per length
            self.single = self.single + b1 / math.pi * np.minimum(g_l, g_v) * self.facet_len * view
            self.terms.append((g_l, g_v, b1, view))


def _interreflected(
    theta_a: float,
    facets: _Facets,
    albedo: float,
    operator: np.ndarray | None,
    edges: np.ndarray,
) -> np.ndarray:
    """Radiance / E0 of bounces 2..N (``operator`` from :func:`radiosity_operator`)."""
    (gl_p, gv_p, b1_p, view_p), (gl_m, gv_m, b1_m, view_m) = facets.terms
    lengths = np.diff(edges) * facets.facet_len
    # bounce 2 on the elements, exact: what each element receives from the other facet's
    # lit segment (exitance ρ μl), then bounces 3..N by the element operator
    s_lp, s_lm = segment_factors(theta_a, edges, gl_p), segment_factors(theta_a, edges, gl_m)
    b2 = albedo * np.concatenate([b1_m[..., None] * s_lm, b1_p[..., None] * s_lp], axis=-1)
    b2 = b2 / np.concatenate([lengths, lengths])
    if operator is not None:  # one 2-D product (stacked matmul is far slower in NumPy)
        b2 = (b2.reshape(-1, b2.shape[-1]) @ operator.T).reshape(b2.shape)
    b = b2
    # seen: element radiosity over the visible segment (keeps the discrete energy balance)
    seen = np.concatenate(
        [_overlap(edges, gv_p) * view_p[..., None], _overlap(edges, gv_m) * view_m[..., None]],
        axis=-1,
    )
    return facets.facet_len / math.pi * np.sum(b * seen, axis=-1)


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
        vals = [_interreflected(self.theta_a, facets, self.albedo, op, e) for e, op in self.levels]
        if len(vals) == 1:
            return (vals[0], None) if difference else vals[0]
        best = (4.0 * vals[1] - vals[0]) / 3.0
        return (best, vals[1] - vals[0]) if difference else best


def cavity_radiance(
    theta_a: np.ndarray | float,
    phi_a: np.ndarray | float,
    wi: np.ndarray,
    wo: np.ndarray,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    elements: int = 32,
    extrapolate: bool = True,
) -> np.ndarray:
    """Radiance of one V-cavity seen from ``wo``, lit from ``wi``, per unit irradiance E0.

    L = Σ_f ∫_visible L_f(x) (n_f·v) dx / (w (n·v)) (DESIGN.md, "The V-cavity microsurface";
    Oren & Nayar 1994, Sec. 4). Divide by cos θi for the cavity's BRDF.

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
    ndarray
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
    theta_a = np.asarray(theta_a, dtype=float)
    check_range("theta_a", theta_a, 0.0, math.pi / 2, unit="radians", scalar=False)
    if np.any(theta_a >= math.pi / 2):
        raise ValueError("theta_a must be in [0, π/2) radians (got π/2)")
    wi = np.asarray(wi, dtype=float)
    wo = np.asarray(wo, dtype=float)
    for name, w in (("wi", wi), ("wo", wo)):
        if w.shape[-1:] != (3,):
            raise ValueError(f"{name} must have shape (..., 3) (got {w.shape})")
    phi_a = np.asarray(phi_a, dtype=float)
    shape = np.broadcast_shapes(theta_a.shape, phi_a.shape, wi.shape[:-1], wo.shape[:-1])
    th = np.broadcast_to(theta_a, shape)
    ph = np.broadcast_to(phi_a, shape)
    l = tuple(np.broadcast_to(wi[..., k], shape) for k in range(3))
    v = tuple(np.broadcast_to(wo[..., k], shape) for k in range(3))
    above = (l[2] >= 0) & (v[2] >= 0)
    facets = _Facets(th, np.cos(ph), np.sin(ph), l, v, albedo)
    out = np.array(np.broadcast_to(facets.single, shape), dtype=float)
    if bounces != 1:
        for t in np.unique(th):
            sel = th == t
            sub = _Facets(
                t,
                np.cos(ph[sel]),
                np.sin(ph[sel]),
                [c[sel] for c in l],
                [c[sel] for c in v],
                albedo,
            )
            solver = InterreflectionSolver(float(t), albedo, bounces, elements, extrapolate)
            out[sel] += solver(sub)
    return np.where(above, out, 0.0)
