"""A dielectric coat over a rough-diffuse base: the exact BRDF by position-free Monte Carlo.

The layer: a dielectric interface of relative index η (smooth, or rough with GGX or Beckmann
normals of roughness α) over a base that is any sampleable registry model (Lambert,
Oren–Nayar, EON, the V-cavity table, ...), with optional absorption between them. The layer
is thin and laterally uniform, so a path is a sequence of *directions* only: the
position-free Monte Carlo of Guo, Hašan and Zhao ("Position-free Monte Carlo simulation for
arbitrary layered BSDFs", ACM TOG 37(6), SIGGRAPH Asia 2018, Sec. 4), with next-event
estimation at every vertex on the base.

The walk, for light arriving from ωi and a viewer at ωo (both above the layer):

* **Entry.** The light is refracted into the layer: smooth, along the Snell direction with
  weight 1 − F(cos θi, η); rough, through a facet normal m drawn from the visible normals of
  ωi (Heitz 2018) with weight (1 − F(ωi·m, η)) G1(t), t the refracted direction: Walter,
  Marschner, Li and Torrance 2007 (EGSR, "Microfacet models for refraction through rough
  surfaces", eq. 21) with separable Smith masking, sampled by its visible normals. The
  part reflected at the interface is the interface's own BRDF (0 off the mirror direction
  when smooth; Walter eq. 20, F D G1 G1 / (4 μi μo), when rough) and is added in closed form.
* **Base.** At each arrival on the base (incident from −d), the next-event estimate
  scores the light that leaves towards ωo after this vertex: a facet m drawn from the visible
  normals of ωo (once per path: each vertex's estimate stays unbiased, and the standard
  error, taken over whole paths, counts their correlation) gives the internal direction ω'
  (ωo refracted inwards) and the score
  β (1 − F(ωo·m, η)) G1(ω') f_base(−d, ω') e^{−τ/μ'} / η² (the 1/η² is the radiance's change
  across the interface; with the generalised reciprocity of the refraction BTDF, Walter eq. 21,
  this is the transmission weight seen from outside). Then the path continues: ω is drawn
  from the base's own sampler (its ``sample``, by reciprocity of the base), β ← β f cos / pdf.
* **Internal reflection.** Going up (absorption e^{−τ/μ}), the part that leaves is already
  counted by the estimates, so the path continues with the internally reflected part:
  smooth, weight F(μ, 1/η) (1 above the critical angle) and the mirror direction; rough, a
  facet drawn from the visible normals of the interface's underside, weight F(·, 1/η) G1 (a
  reflection that goes up again, which needs a second interface event, is dropped, as in a
  single-scattering microfacet interface). Going down, e^{−τ/μ} again.

**The rough interface** (``interface``, :data:`INTERFACES`). Above, the single-scattering
interface (``"single"``): one facet event per crossing, which loses the light a second
facet event would return (30 % of a white furnace at α = 0.3, η = 1.5; 66 % at α = 1),
as pbrt-v4's ``LayeredBxDF`` and Mitsuba 3's ``roughdielectric`` do. The default,
``"multiple"``, is exact for a Smith microsurface: every crossing is the random walk on the
dielectric microsurface of Heitz, Hanika, d'Eon and Dachsbacher 2016 ("Multiple-scattering
microfacet BSDFs with the Smith model", ACM TOG 35(4), SIGGRAPH), reflection or refraction
at each facet event with probability F, from above and from below
(:func:`~.layered_walk_numba._ms_walk`). The entry is a walk from ωi (its next events
towards ωo score the interface's own reflection, with the masking at the event's height);
the next events' exit direction is the end of a walk from ωo that reaches the dielectric
(weight 1, with the 1/η² above); the internal reflection is a walk from below that ends in
the dielectric again (weight 1; a walk that leaves upwards ends the path, its light counted
by the next events). No light is lost: the white furnace gives 1 for any α. Both engines
run it: the compiled walk path by path, the NumPy walk (:func:`_ms_walk`) on arrays of
walks, with the same formulas (:mod:`.layered_formulas`, :mod:`.smith_formulas`), so that
each checks the other and a base the compiled walk cannot run has the exact interface too.

β is the irradiance on the base per unit irradiance on the layer (no lateral spreading, so
power fractions are irradiance fractions). Every vertex's estimate is an unbiased estimate of
its scattering order, and the walk sums them. A path stops after ``bounces`` arrivals on the
base or when β falls below :data:`BETA_CUT` (the energy left is then below 1e-9 of the input
for every channel; the bias is below that).

Absorption: τ = thickness × absorption coefficient (per colour channel), Beer–Lambert along
the path length, τ / |cos θ| per crossing.

A scattering coat (``medium_albedo`` > 0): τ is then the medium's optical thickness
(extinction) and a fraction ω of it scatters, with the Henyey–Greenstein phase function of
asymmetry ``medium_g``: the homogeneous slab of pbrt-v4's ``coateddiffuse``
(``LayeredBxDF``, ``src/pbrt/bxdfs.h``: albedo, g, thickness). The compiled walk draws free
paths in the slab, scatters, and takes next events towards the exit direction from every
scattering as from every arrival on the base (:func:`~.layered_walk_numba._medium_path`);
with ω = 0 the walk is the absorbing one above.

Anchors (``tests/test_simulate_layered.py``): Mitsuba 3's own ``plastic`` (a smooth coat over
a Lambertian base, its internal reflections summed in closed form), the white furnace (ρ = 1,
no absorption: directional albedo 1 with the specular reflection), the limits η → 1 and ρ = 0,
and reciprocity.
"""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import numpy as np

from .._validate import ParameterError, check_range
from .cavity import Bounces, check_bounces
from .layered_formulas import MS_MAX_EVENTS
from .layered_formulas import build as _build_interface
from .smith import _check_engine, check_angles
from .smith_formulas import numpy_formulas
from .smith_slopes import sample_visible_normals, smith_lambda

__all__ = [
    "BETA_CUT",
    "ETA_RANGE",
    "INTERFACES",
    "INTERFACE_DISTRIBUTIONS",
    "brdf",
    "check_base",
    "directional_albedo",
    "fresnel_dielectric",
    "interface_brdf",
    "interface_reflectance",
]

BETA_CUT = 1e-9
"""A path stops when its throughput falls below this in every channel."""

MAX_BOUNCES = 100_000
"""Arrivals on the base traced at most with ``bounces="all"`` (the cut above stops paths far
earlier: at η = 3 and ρ = 1 the throughput falls by at least 0.1 % per round trip)."""

ETA_RANGE = (0.0, 1e3)
"""η is accepted in (0, 1000]; η < 1 (a coat thinner optically than air) has total internal
reflection on the way in."""

INTERFACE_DISTRIBUTIONS = ("ggx", "beckmann")

INTERFACES = ("multiple", "single")
"""The rough interface: ``"multiple"``, the multiple-scattering dielectric microsurface of
Heitz, Hanika, d'Eon and Dachsbacher 2016 (exact for a Smith microsurface: it conserves
energy), the default; ``"single"``, one facet event per crossing (a reflection that needs a
second facet event is dropped), the interface of pbrt-v4's ``LayeredBxDF`` and of
Mitsuba 3's ``roughdielectric``, kept to compare with them. The same for a smooth coat."""

_BATCH = 1 << 16

_F = numpy_formulas()
_I = _build_interface(
    SimpleNamespace(jit=lambda f: f, where=np.where, maximum=np.maximum, minimum=np.minimum,
                    sqrt=np.sqrt, exp=np.exp),
    _F.smith_lambda,
)


def fresnel_dielectric(cos_t: np.ndarray, eta: float) -> np.ndarray:
    """Unpolarised Fresnel reflectance of a dielectric of relative index η at cos θ, from the
    s and p amplitudes (Born and Wolf, Sec. 1.5.2; :mod:`.layered_formulas`, shared with the
    compiled walk); 1 under total internal reflection. Written from the amplitudes, not
    shared with the models' form (Cook and Torrance's), so that the truth and the closed
    forms check each other."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(_I.fresnel(np.asarray(cos_t, dtype=np.float64), eta), dtype=np.float64)


def check_base(base: object) -> Any:
    """The base model, or ``ValueError`` naming why it cannot be one.

    A base must be a roughdiffuse model (it has ``brdf_cosines`` and ``sampling_strategy``)
    that can be sampled and evaluated at any pair of directions: not a simulation
    (``SmithDiffuse``: every value is a Monte Carlo run of its own, ``traceable`` False) and
    not a coat itself (a coat on a coat is not supported).
    """
    if isinstance(base, str) or not all(
        hasattr(base, a) for a in ("brdf_cosines", "sampling_strategy", "parameter_arrays")
    ):
        raise ParameterError(f"base must be a roughdiffuse model (got {base!r})")
    if getattr(type(base), "is_coat", False):
        raise ParameterError(f"base {type(base).__name__}: a coat on a coat is not supported")
    if not (getattr(type(base), "traceable", True) or getattr(type(base), "closed_form", True)):
        raise ParameterError(
            f"base {type(base).__name__} cannot be a base: it is a simulation that cannot be "
            "sampled or evaluated at arbitrary directions (use a closed form or VCavity)"
        )
    return base


def _check_interface(eta: object, roughness: object, distribution: object) -> tuple[float, float]:
    check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1], lo_open=True)
    check_range("roughness", roughness, 0.0, 2.0)
    if distribution not in INTERFACE_DISTRIBUTIONS:
        raise ParameterError(
            f"distribution must be one of {INTERFACE_DISTRIBUTIONS} (got {distribution!r})"
        )
    return float(eta), float(roughness)  # type: ignore[arg-type]


def _check_absorption(absorption: object) -> np.ndarray:
    a = np.atleast_1d(np.asarray(absorption, dtype=np.float64))
    if a.ndim != 1 or not np.all(np.isfinite(a)) or np.any(a < 0):
        raise ParameterError(
            "absorption (thickness × absorption coefficient) must be finite and >= 0, a number "
            f"or one per channel (got {absorption!r})"
        )
    return a


def _check_medium(medium_albedo: object, medium_g: object) -> tuple[np.ndarray, float]:
    """The medium's single-scattering albedo (per channel, each in [0, 1]) and its
    Henyey–Greenstein g in (−1, 1), checked by name."""
    w = np.atleast_1d(np.asarray(medium_albedo, dtype=np.float64))
    if w.ndim != 1 or not np.all(np.isfinite(w)) or np.any(w < 0) or np.any(w > 1):
        raise ParameterError(
            "medium_albedo (the medium's single-scattering albedo) must be in [0, 1], a number "
            f"or one per channel (got {medium_albedo!r})")
    try:
        g = float(medium_g)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        g = math.nan
    if not abs(g) < 1.0:  # NaN too
        raise ParameterError(
            f"medium_g (Henyey–Greenstein asymmetry) must be in (-1, 1) (got {medium_g!r})")
    return w, g


def _directions(theta_i, theta_r, delta_phi):
    """The checked angles (the Smith walk's rules) as unit vectors wi, wo, and their shape."""
    ti, tr, dp, shape = check_angles(theta_i, theta_r, delta_phi)
    wi = np.stack([np.sin(ti), 0.0 * ti, np.cos(ti)], axis=-1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], axis=-1)
    return wi, wo, shape


# ---------------------------------------------------------------------------- the interface
def _g1(distribution: str, z: np.ndarray, alpha: float) -> np.ndarray:
    """Smith's G1 = 1 / (1 + Λ(|z|)) on the side the direction lies (1 for α = 0)."""
    if alpha == 0.0:
        return np.ones_like(z)
    lam = smith_lambda(distribution, np.clip(np.abs(z), 1e-12, 1.0), alpha)
    return 1.0 / (1.0 + lam)


def _ndf(distribution: str, cos_h: np.ndarray, alpha: float) -> np.ndarray:
    """D(h), normalised so that ∫ D (n·h) dωh = 1 (GGX: Walter eq. 33; Beckmann: eq. 25)."""
    c2 = np.clip(cos_h, 1e-12, 1.0) ** 2
    tan2 = (1.0 - c2) / c2
    a2 = alpha * alpha
    if distribution == "ggx":
        d = a2 / (math.pi * c2 * c2 * (a2 + tan2) ** 2)
    else:
        d = np.exp(-tan2 / a2) / (math.pi * a2 * c2 * c2)
    return np.where(cos_h > 0, d, 0.0)


def interface_brdf(wi: np.ndarray, wo: np.ndarray, eta: float, roughness: float,
                   distribution: str = "ggx") -> np.ndarray:
    """The coat's own reflection f = F(ωi·h, η) D(h) G1(ωi) G1(ωo) / (4 μi μo) (Walter et al.
    2007, eq. 20, separable Smith masking); 0 for a smooth coat (its mirror reflection is a
    Dirac delta, F(μi, η) of the light, that no BRDF value holds)."""
    wi, wo = np.asarray(wi, np.float64), np.asarray(wo, np.float64)
    if roughness == 0.0:
        return np.zeros(np.broadcast_shapes(wi.shape, wo.shape)[:-1])
    h = wi + wo
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    mu_i, mu_o = wi[..., 2], wo[..., 2]
    c = np.sum(wi * h, axis=-1)
    f = fresnel_dielectric(np.clip(c, 0.0, 1.0), eta)
    d = _ndf(distribution, h[..., 2], roughness)
    g = _g1(distribution, mu_i, roughness) * _g1(distribution, mu_o, roughness)
    with np.errstate(divide="ignore", invalid="ignore"):
        val = f * d * g / (4.0 * mu_i * mu_o)
    return np.where((mu_i > 0) & (mu_o > 0), val, 0.0)


def _refract_in(w: np.ndarray, m: np.ndarray, eta: float) -> tuple[np.ndarray, np.ndarray]:
    """The direction into the layer of light arriving from ``w`` (above) through a facet of
    normal ``m``, and the transmission 1 − F(w·m, η); 0 where no light is refracted."""
    with np.errstate(divide="ignore", invalid="ignore"):
        tx, ty, tz, trans = _I.refract_in(w[:, 0], w[:, 1], w[:, 2], m[:, 0], m[:, 1], m[:, 2],
                                          eta)
    return np.stack([tx, ty, tz], axis=-1), trans


def _enter(w: np.ndarray, eta: float, alpha: float, dist: str, rng) -> tuple[np.ndarray, Any]:
    """Directions into the layer (z < 0) from ``w`` and their weights (transmission × G1)."""
    if alpha == 0.0:
        m = np.zeros_like(w)
        m[:, 2] = 1.0
    else:
        m = sample_visible_normals(dist, w, alpha, rng)
    t, trans = _refract_in(w, m, eta)
    weight = trans * _g1(dist, t[:, 2], alpha) * (t[:, 2] < 0)
    t[:, 2] = np.minimum(t[:, 2], -1e-12)
    return t / np.linalg.norm(t, axis=-1, keepdims=True), weight


def _reflect_inside(w: np.ndarray, eta: float, alpha: float, dist: str, rng):
    """Light going up (``w``, z > 0) reflected down at the underside of the interface: the
    direction and the weight F(·, 1/η) (times G1 when rough; 0 if it goes up again)."""
    if alpha == 0.0:
        r = w * np.array([1.0, 1.0, -1.0])
        return r, fresnel_dielectric(w[:, 2], 1.0 / eta)
    # the underside seen along −w is the top side seen along w mirrored in z
    v = w * np.array([-1.0, -1.0, 1.0])
    m = sample_visible_normals(dist, v, alpha, rng) * np.array([1.0, 1.0, -1.0])
    c = np.sum(w * m, axis=-1)  # < 0: the facet faces the ray
    r = w - 2.0 * c[:, None] * m
    f = fresnel_dielectric(np.clip(-c, 0.0, 1.0), 1.0 / eta)
    weight = f * _g1(dist, r[:, 2], alpha) * (r[:, 2] < 0)
    r[:, 2] = np.minimum(r[:, 2], -1e-12)
    return r / np.linalg.norm(r, axis=-1, keepdims=True), weight


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def _other_side(h: np.ndarray) -> np.ndarray:
    """ln C1 on the other side of the surface, ln(1 − e^h) (floored at −700)."""
    with np.errstate(divide="ignore"):
        return np.maximum(np.log1p(-np.exp(h)), -700.0)


def _ms_walk(w: np.ndarray, outside: bool, eta: float, alpha: float, dist: str, rng,
             o: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """The random walk on the dielectric microsurface of Heitz, Hanika, d'Eon and
    Dachsbacher 2016 (Sec. 5) for rays travelling along ``w`` (N, 3), all arriving from the
    air side (``outside``) or all from the dielectric: the NumPy twin of the compiled walk's
    :func:`~.layered_walk_numba._ms_walk`, step for step on the arrays of walks still on the
    surface, with the same formulas (:func:`~.smith_formulas.build`'s ``height_step``,
    the visible normals, :mod:`.layered_formulas`' ``refract_in`` and ``phase_out``).

    Returns (the directions the walks leave along (N, 3), whether each leaves on the air
    side, whether it is lost (still on the surface after :data:`MS_MAX_EVENTS` events),
    the next-event sums (N,) towards ``o`` (N, 3, above the surface; zeros without ``o``),
    the facet events traced).
    """
    n = w.shape[0]
    ggx = dist == "ggx"
    w = w.copy()
    side = np.full(n, bool(outside))
    h = np.zeros(n)
    total = np.zeros(n)
    lam_o = None if o is None else _F.smith_lambda(ggx, o[:, 2], alpha)
    idx = np.arange(n)
    events = 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        for _ in range(MS_MAX_EVENTS):
            if idx.size == 0:
                break
            wa, sa = w[idx], side[idx]
            sz = np.where(sa, wa[:, 2], -wa[:, 2])
            escape, hn = _F.height_step(h[idx], _F.smith_lambda(ggx, sz, alpha), sz,
                                        rng.random(idx.size))
            h[idx] = hn
            stay = ~escape
            idx, wa, sa, ha = idx[stay], wa[stay], sa[stay], hn[stay]
            if idx.size == 0:
                break
            events += idx.size
            # the facet met: a visible normal of −ω on the ray's side (negated below)
            m = sample_visible_normals(dist, np.where(sa[:, None], -wa, wa), alpha, rng)
            m = np.where(sa[:, None], m, -m)
            if o is not None:
                h_air = np.where(sa, ha, _other_side(ha))
                g1 = np.where(h_air < 0.0, np.exp(lam_o[idx] * np.minimum(h_air, 0.0)), 1.0)
                oa = o[idx]
                total[idx] += _I.phase_out(ggx, sa, *(-wa).T, *oa.T, eta, alpha) * g1
            rel = np.where(sa, eta, 1.0 / eta)
            tx, ty, tz, trans = _I.refract_in(*(-wa).T, *m.T, rel)
            through = rng.random(idx.size) < trans
            refl = wa - 2.0 * np.sum(wa * m, axis=-1, keepdims=True) * m
            t = np.stack([tx, ty, tz], axis=-1)
            w[idx] = _unit(np.where(through[:, None], t, refl))
            side[idx] = sa ^ through
            h[idx] = np.where(through, _other_side(ha), ha)
    lost = np.zeros(n, dtype=bool)
    lost[idx] = True
    return w, side, lost, total, events


# ---------------------------------------------------------------------------- the walk
def _as_channels(x: Any, n: int) -> np.ndarray:
    x = np.asarray(x, dtype=np.float64)
    return x[:, None] if x.ndim == 1 else x.reshape(n, -1)


def _base_f(base: Any, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The base's BRDF for unit directions a, b (P, 3) above the horizon (its compiled
    ``brdf_cosines``: the cosines are known here)."""
    return np.asarray(base.brdf_cosines(a[:, 2], b[:, 2], np.sum(a * b, axis=-1)))


def _base_sample(base: Any, strategy: Any, params: dict, u: np.ndarray, wo: np.ndarray):
    """A direction from the base's own sampler for light leaving towards ``wo`` (by
    reciprocity, where light from ``wo`` goes) and its weight f cos / pdf (P, C); 0 for an
    invalid sample (pdf 0 or below the horizon), as :func:`~roughdiffuse.models.sampling.
    sample_model` gives."""
    x, y, z, pdf = strategy.sample(np, u[0], u[1], wo[:, 0], wo[:, 1], wo[:, 2], params)
    w = np.stack([x, y, np.maximum(z, 1e-12)], axis=-1)
    w = w / np.linalg.norm(w, axis=-1, keepdims=True)
    valid = (pdf > 0) & (z > 0)
    f = _as_channels(_base_f(base, w, wo), w.shape[0])
    ratio = np.where(valid, w[:, 2] / np.where(valid, pdf, 1.0), 0.0)
    return w, f * ratio[:, None]


def _ms_down(w: np.ndarray, outside: bool, eta: float, alpha: float, dist: str, rng,
             o: np.ndarray | None = None) -> tuple[np.ndarray, ...]:
    """A walk on the multiple-scattering interface (:func:`_ms_walk`) whose path goes on
    only if it ends in the dielectric, going down (entering from above, or reflected from
    below): (the direction, weight 1 if it does and 0 if it leaves on the air side or is
    lost (its direction then straight down), whether it left on the air side, the
    next-event sums, the facet events). The light of a walk that leaves upwards from below
    is counted by the next events."""
    d, air, lost, nee, events = _ms_walk(w, outside, eta, alpha, dist, rng, o)
    inside = ~air & ~lost
    d[~inside] = (0.0, 0.0, -1.0)
    return d, inside.astype(np.float64), air & ~lost, nee, events


def _walk(base: Any, wi: np.ndarray, wo: np.ndarray, eta: float, alpha: float, dist: str,
          tau: np.ndarray, max_k: int, rng, ms: bool = False,
          albedo: bool = False) -> tuple[np.ndarray, int]:
    """Per-path sums of the next-event scores (P, C) for paths with directions wi, wo (P, 3);
    and the number of path segments (arrivals on the base, and facet events with ``ms``)
    traced. ``ms``: the multiple-scattering interface, its own reflection included (its next
    events towards ωo, or with ``albedo`` (ωo cosine-distributed, scored π f) 1/π for a walk
    that leaves upwards)."""
    c = max(tau.size, base.channels, 1)  # an RGB base under a grey layer: three channels
    segments = 0
    if ms:
        d, beta, up, nee, ev = _ms_down(-wi, True, eta, alpha, dist, rng,
                                         None if albedo else wo)
        spec = up / math.pi if albedo else nee / wo[:, 2]
        # the next events' exit: ω' (down, inside) of a walk from ωo, one per path
        t_exit, w_exit_all, _, _, ev_exit = _ms_down(-wo, True, eta, alpha, dist, rng)
        segments += ev + ev_exit
    else:
        d, beta = _enter(wi, eta, alpha, dist, rng)
        spec = np.zeros(wi.shape[0])
        # the next events' exit: ω' (up, inside) for the view ωo, one facet per path
        t_exit, w_exit_all = _enter(wo, eta, alpha, dist, rng)
    beta = beta[:, None] * np.exp(-tau[None, :] / np.abs(d[:, 2:3])) * np.ones(c)
    score = np.zeros_like(beta) + spec[:, None]
    strategy = base.sampling_strategy()
    params = base.parameter_arrays(np, np.float64)
    alive = np.flatnonzero(np.any(beta > BETA_CUT, axis=1))
    inv_eta2 = 1.0 / (eta * eta)
    for _ in range(max_k):
        if alive.size == 0:
            break
        segments += alive.size
        b, dd = beta[alive], d[alive]
        up_in = -dd  # the base's light direction
        u, w_exit = -t_exit[alive], w_exit_all[alive]
        f = _as_channels(_base_f(base, up_in, u), alive.size)
        att = np.exp(-tau[None, :] / u[:, 2:3])
        score[alive] += b * (w_exit * inv_eta2)[:, None] * f * att
        # continue: sample the base (its own strategy), go up, reflect inside, come down
        w, wgt = _base_sample(base, strategy, params, rng.random((2, alive.size)), up_in)
        if ms:
            r, refl, _, _, ev = _ms_down(w, False, eta, alpha, dist, rng)
            segments += ev
        else:
            r, refl = _reflect_inside(w, eta, alpha, dist, rng)
        b = b * wgt * refl[:, None] * np.exp(-tau[None, :] / w[:, 2:3])
        b = b * np.exp(-tau[None, :] / np.abs(r[:, 2:3]))
        beta[alive], d[alive] = b, r
        alive = alive[np.any(b > BETA_CUT, axis=1)]
    return score, segments


def _run(base, wi, wo, eta, alpha, dist, tau, bounces, samples, seed, engine,
         per_geometry_wo=True, ms=False, medium=None):
    max_k = MAX_BOUNCES if bounces == "all" else int(bounces)
    omega, g = medium if medium is not None else (np.zeros(1), 0.0)
    channels = max(base.channels, tau.size if tau.size > 1 else 0,
                   omega.size if omega.size > 1 else 0)
    c = max(channels, 1)
    if tau.size not in (1, c):
        raise ParameterError(f"absorption has {tau.size} channels, the base {base.channels}")
    if omega.size not in (1, c):
        raise ParameterError(f"medium_albedo has {omega.size} channels where the walk has {c}")
    scatters = bool(np.any(omega > 0) and np.any(tau > 0))
    sums = None
    if engine != "numpy":
        sums = _run_compiled(base, wi, wo, eta, alpha, dist, tau, max_k, samples, seed, c,
                             per_geometry_wo, required=engine == "compiled" or scatters,
                             ms=ms, medium=(omega, g))
    if sums is None:
        sums = _run_numpy(base, wi, wo, eta, alpha, dist, tau, max_k, samples, seed, c,
                          per_geometry_wo, ms)
    sum1, sum2, segments = sums
    mean = sum1 / samples
    var = np.maximum(sum2 / samples - mean * mean, 0.0)
    se = np.sqrt(var / max(samples - 1, 1))
    return mean, se, channels, segments


def _run_compiled(base, wi, wo, eta, alpha, dist, tau, max_k, samples, seed, c, per_geometry_wo,
                  required, ms=False, medium=None):
    """The sums of the compiled walk (:mod:`.layered_walk_numba`), or ``None`` (with
    ``required`` False) for a base it cannot compile: a table or a simulation, or a model
    whose code the trace cannot express."""
    from ..engine.trace import TraceError

    medium = (np.zeros(1), 0.0) if medium is None else medium
    why = None
    if not getattr(type(base), "closed_form", False):
        why = "it is not a closed form"
    else:
        from . import layered_walk_numba

        try:
            return layered_walk_numba.run(
                base, wi, wo, not per_geometry_wo, samples, eta, alpha, dist == "ggx", tau,
                max_k, seed, BETA_CUT, c, ms, omega=medium[0], hg_g=medium[1])
        except TraceError as exc:
            why = str(exc)
    if required and np.any(medium[0] > 0) and np.any(tau > 0):
        raise ParameterError(
            f"a scattering medium (medium_albedo > 0) runs on the compiled walk, which cannot "
            f"run base {type(base).__name__}: {why}")
    if required:
        raise ParameterError(
            f"engine='compiled' cannot run base {type(base).__name__}: {why}; use 'numpy'")
    return None


def _run_numpy(base, wi, wo, eta, alpha, dist, tau, max_k, samples, seed, c, per_geometry_wo,
               ms=False):
    g = wi.shape[0]
    sum1 = np.zeros((g, c))
    sum2 = np.zeros((g, c))
    rng = np.random.default_rng(seed)
    idx = np.repeat(np.arange(g), samples)
    segments = 0
    for start in range(0, idx.size, _BATCH):
        gi = idx[start:start + _BATCH]
        if per_geometry_wo:
            o = wo[gi]
            scale = 1.0
        else:  # directional albedo: ωo cosine-distributed, f cos / pdf = π f
            u = rng.random((gi.size, 2))
            r = np.sqrt(u[:, 0])
            o = np.stack([r * np.cos(2 * np.pi * u[:, 1]), r * np.sin(2 * np.pi * u[:, 1]),
                          np.sqrt(np.maximum(1.0 - u[:, 0], 1e-24))], axis=-1)
            scale = math.pi
        sc, seg = _walk(base, wi[gi], o, eta, alpha, dist, tau, max_k, rng, ms,
                        not per_geometry_wo)
        segments += seg
        sc = np.broadcast_to(sc, (gi.size, c)) * scale
        for ch in range(c):
            sum1[:, ch] += np.bincount(gi, weights=sc[:, ch], minlength=g)
            sum2[:, ch] += np.bincount(gi, weights=sc[:, ch] ** 2, minlength=g)
    return sum1, sum2, segments


def _finish(value, stderr, shape, channels, return_stderr):
    if channels:
        value, stderr = value.reshape(*shape, channels), stderr.reshape(*shape, channels)
    else:
        value, stderr = value[:, 0].reshape(shape), stderr[:, 0].reshape(shape)
    return (value, stderr) if return_stderr else value


def brdf(
    theta_i,
    theta_r,
    delta_phi,
    base: Any,
    eta: float = 1.5,
    roughness: float = 0.0,
    distribution: str = "ggx",
    absorption: float | np.ndarray = 0.0,
    bounces: Bounces = "all",
    *,
    medium_albedo: float | np.ndarray = 0.0,
    medium_g: float = 0.0,
    interface: str = "multiple",
    samples: int = 100_000,
    seed: int = 0,
    return_stderr: bool = False,
    return_segments: bool = False,
    engine: str = "auto",
):
    """BRDF of a dielectric coat over ``base``, f(θi, θr, Δφ), in 1/sr, by Monte Carlo.

    The calling convention of :func:`roughdiffuse.simulate.smith.brdf`: ωi at (θi, φ = 0),
    ωo at (θr, Δφ), radians.

    Parameters
    ----------
    theta_i, theta_r, delta_phi : array_like
        Angles in radians (θ in [0, π/2]); they broadcast.
    base : Model
        The base: a sampleable model (:func:`check_base`), possibly with RGB albedo.
    eta : float
        Relative refractive index η of the coat, in (0, 1000].
    roughness : float
        The interface's roughness α in [0, 2] (0: smooth).
    distribution : {"ggx", "beckmann"}
        The interface's facet distribution when rough.
    absorption : float or array (C,)
        Optical depth τ = thickness × absorption coefficient at normal incidence, ≥ 0, per
        channel; light crossing the layer at angle θ keeps e^{−τ/|cos θ|}. With a
        scattering medium, its optical thickness (extinction).
    medium_albedo : float or array (C,)
        The medium's single-scattering albedo ω in [0, 1], per channel (0: it only absorbs;
        > 0 runs on the compiled walk).
    medium_g : float
        The Henyey–Greenstein asymmetry g of the medium's phase function, in (−1, 1).
    bounces : int >= 1 or "all"
        Arrivals on the base summed (1: one base bounce, no internal reflection).
    interface : {"multiple", "single"}
        The rough interface (:data:`INTERFACES`): "multiple" (default), the exact
        multiple-scattering microsurface of Heitz et al. 2016, its own reflection estimated
        by the walk's next events (standard error included); "single", one facet event per
        crossing, its reflection Walter's eq. 20 in closed form. Alike for a smooth coat.
        Both engines run both.
    samples, seed : int
        Paths per geometry and the generator's seed.
    return_stderr : bool
        Also return the standard error of each value.
    return_segments : bool
        Also return the number of path segments traced (for benchmarks).
    engine : {"auto", "compiled", "numpy"}
        "compiled": the Numba walk (:mod:`.layered_walk_numba`), for a closed-form base
        whose code the fast path can trace (Lambert, Oren–Nayar, EON, ...); "numpy": the
        vectorised reference walk, for any base; "auto": compiled where it can run. The
        engines draw different random numbers: their values agree within the standard
        errors.

    Returns
    -------
    ndarray (...) or (..., C), and its standard error with ``return_stderr``; the coat's own
    reflection (:func:`interface_brdf`) is included, exactly (standard error 0 from it).

    Examples
    --------
    A smooth coat over a white Lambertian base at normal incidence and view:

    >>> from roughdiffuse import Lambert
    >>> f, se = brdf(0.0, 0.0, 0.0, Lambert(1.0), eta=1.5, samples=20_000,
    ...              return_stderr=True)
    >>> bool(abs(f * math.pi - 0.96 * 0.96 / 1.5**2 / (1 - 0.596)) < 5 * se * math.pi + 3e-3)
    True
    """
    base, eta, alpha, tau, bounces, engine, ms, medium = _checked(
        base, eta, roughness, distribution, absorption, bounces, samples, engine, interface,
        medium_albedo, medium_g)
    wi, wo, shape = _directions(theta_i, theta_r, delta_phi)
    mean, se, channels, segments = _run(
        base, wi, wo, eta, alpha, str(distribution), tau, bounces, int(samples), seed, engine,
        ms=ms, medium=medium)
    if not ms:
        mean = mean + interface_brdf(wi, wo, eta, alpha, str(distribution))[:, None]
    out = _finish(mean, se, shape, channels, return_stderr)
    if return_segments:
        return (*out, segments) if return_stderr else (out, segments)
    return out


def _check_samples(samples: object) -> None:
    if isinstance(samples, bool) or not isinstance(samples, int | np.integer) or samples < 2:
        raise ParameterError(f"samples must be an integer >= 2 (got {samples!r})")


def _checked(base, eta, roughness, distribution, absorption, bounces, samples, engine,
             interface="multiple", medium_albedo=0.0, medium_g=0.0):
    """The walk's arguments checked by name, as :func:`brdf` and :func:`directional_albedo`
    take them: (base, η, α, τ, bounces, engine, whether the interface scatters multiply,
    the medium's (ω, g));
    the engine stays "auto" where Numba can run (the compiled walk, the NumPy one for a base
    it cannot compile)."""
    base = check_base(base)
    eta, alpha = _check_interface(eta, roughness, distribution)
    if interface not in INTERFACES:
        raise ParameterError(f"interface must be one of {INTERFACES} (got {interface!r})")
    ms = interface == "multiple" and alpha > 0.0
    tau = _check_absorption(absorption)
    medium = _check_medium(medium_albedo, medium_g)
    if np.any(medium[0] > 0) and np.any(tau > 0) and engine == "numpy":
        raise ParameterError("a scattering medium (medium_albedo > 0) runs on the compiled "
                             "walk: use engine 'auto' or 'compiled'")
    bounces = check_bounces(bounces)
    _check_samples(samples)
    resolved = _check_engine(engine)
    auto = engine == "auto" and resolved == "compiled"
    return base, eta, alpha, tau, bounces, "auto" if auto else resolved, ms, medium


def directional_albedo(
    theta_i,
    base: Any,
    eta: float = 1.5,
    roughness: float = 0.0,
    distribution: str = "ggx",
    absorption: float | np.ndarray = 0.0,
    bounces: Bounces = "all",
    *,
    medium_albedo: float | np.ndarray = 0.0,
    medium_g: float = 0.0,
    interface: str = "multiple",
    samples: int = 100_000,
    seed: int = 0,
    return_stderr: bool = False,
    return_segments: bool = False,
    engine: str = "auto",
):
    """∫ f cos θr dωr for light from θi, the coat's reflection included, by the same walk.

    ωo is drawn cosine-distributed for every path (score π f). The coat's reflection is
    added as its own albedo: F(cos θi, η) for a smooth coat (its mirror reflection), by a
    visible-normal Monte Carlo (weight F(ωi·m) G1(ωr)) for a rough one. With a white base and
    no absorption a smooth coat conserves energy exactly: the white furnace gives 1. With
    ``interface="multiple"`` (default) the rough coat's reflection is the walk's own: each
    path that the microsurface sends back up scores 1, and a rough coat conserves energy
    exactly too. ``medium_albedo``, ``medium_g`` (a scattering coat), ``interface``,
    ``engine``, ``return_segments``: as in :func:`brdf`.
    """
    base, eta, alpha, tau, bounces, engine, ms, medium = _checked(
        base, eta, roughness, distribution, absorption, bounces, samples, engine, interface,
        medium_albedo, medium_g)
    ti = np.asarray(theta_i, dtype=np.float64)
    check_range("theta_i", ti, 0.0, math.pi / 2, unit="radians", scalar=False)
    wi, _, shape = _directions(ti, 0.0 * ti, 0.0 * ti)
    mean, se, channels, segments = _run(
        base, wi, wi, eta, alpha, str(distribution), tau, bounces, int(samples), seed, engine,
        per_geometry_wo=False, ms=ms, medium=medium,
    )
    if not ms:
        spec, spec_se = _interface_albedo(wi, eta, alpha, str(distribution), int(samples),
                                          seed)
        mean = mean + spec[:, None]
        se = np.sqrt(se * se + spec_se[:, None] ** 2)
    out = _finish(mean, se, shape, channels, return_stderr)
    if return_segments:
        return (*out, segments) if return_stderr else (out, segments)
    return out


def _interface_albedo(wi, eta, alpha, dist, samples, seed):
    mu = wi[:, 2]
    if alpha == 0.0:
        return fresnel_dielectric(mu, eta), np.zeros_like(mu)
    rng = np.random.default_rng([seed, 1])
    out, err = np.empty_like(mu), np.empty_like(mu)
    for k in range(mu.size):
        w = np.repeat(wi[k:k + 1], samples, axis=0)
        m = sample_visible_normals(dist, w, alpha, rng)
        c = np.sum(w * m, axis=-1)
        r = 2.0 * c[:, None] * m - w
        val = fresnel_dielectric(np.clip(c, 0, 1), eta) * _g1(dist, r[:, 2], alpha)
        val = np.where(r[:, 2] > 0, val, 0.0)
        out[k], err[k] = val.mean(), val.std() / math.sqrt(samples)
    return out, err


def interface_reflectance(
    theta,
    eta: float = 1.5,
    roughness: float = 0.3,
    distribution: str = "ggx",
    *,
    side: str = "above",
    samples: int = 100_000,
    seed: int = 0,
    return_stderr: bool = False,
    return_events: bool = False,
):
    """The rough interface alone (the multiple-scattering microsurface of Heitz et al. 2016):
    the fraction R(θ) of light arriving at θ from ``side`` ("above": from the air; "below":
    from inside the coat, θ measured from the inward normal) that leaves on that side again,
    by counting the walks (:func:`~.layered_walk_numba.interface_sums`). Each walk leaves on
    one side or the other with weight 1, so the transmittance is T = 1 − R (a walk still on
    the surface after :data:`~.layered_formulas.MS_MAX_EVENTS` facet events would count
    in neither; none does). From above, R is the coat's own directional albedo E_spec(μ);
    from below it is the internal reflectance.

    Returns R (shape of ``theta``), with its standard error (``return_stderr``) and the mean
    facet events per walk (``return_events``).
    """
    eta, alpha = _check_interface(eta, roughness, distribution)
    if alpha == 0.0:
        raise ParameterError("roughness must be > 0 for interface_reflectance (a smooth "
                             "interface reflects F(μ, η): fresnel_dielectric)")
    if side not in ("above", "below"):
        raise ParameterError(f"side must be 'above' or 'below' (got {side!r})")
    _check_samples(samples)
    ti = np.asarray(theta, dtype=np.float64)
    check_range("theta", ti, 0.0, math.pi / 2, unit="radians", scalar=False)
    from . import layered_walk_numba

    mu = np.cos(ti).ravel()
    sums = layered_walk_numba.interface_sums(mu, side == "above", int(samples), eta, alpha,
                                             distribution == "ggx", seed)
    r = sums[:, 0] / samples
    out: list[Any] = [r.reshape(ti.shape)]
    if return_stderr:
        out.append(np.sqrt(r * (1.0 - r) / (samples - 1)).reshape(ti.shape))
    if return_events:
        out.append((sums[:, 1] / samples).reshape(ti.shape))
    return out[0] if len(out) == 1 else tuple(out)
