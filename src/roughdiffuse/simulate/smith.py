"""The Smith microsurface with Lambertian facets: a second ground truth next to the V-cavities.

The surface: microfacets of albedo ρ that reflect like Lambert's law, heights uncorrelated
(Smith's assumption), slopes isotropic Beckmann or GGX of roughness α
(:mod:`.smith_slopes`).

* **One bounce**, deterministic (:func:`single_scattering`): with the height-correlated
  masking-shadowing G2 = 1 / (1 + Λ(ωi) + Λ(ωo)) (Heitz 2014, JCGT 3(2), eq. 99) and the
  visible-normal form of the diffuse microfacet BRDF (Heitz & Dupuy 2015, "Implementing a
  simple anisotropic rough diffuse material with stochastic evaluation", eq. 3),

      f1(ωi, ωo) = ρ / (π cos θi cos θo (1 + Λi + Λo)) ∫ ⟨ωi, ωm⟩⁺ ⟨ωo, ωm⟩⁺ D(ωm) dωm,

  integrated by Gauss–Legendre rules over the projected-area measure D cos θm dωm: in
  v = tan θm / α for Beckmann (cut at v = 8.6), in s with tan θm = :func:`.slope_cdf_inverse`
  (s) for GGX (so that its tail stays finite), split where a facet can turn away from
  ωi or ωo (θm = π/2 − θi, π/2 − θo), and in φm split at the azimuths where it does.
* **N bounces or all** (:func:`random_walk`, :func:`brdf`): the height-space random walk of
  Heitz, Hanika, d'Eon and Dachsbacher (SIGGRAPH 2016, "Multiple-scattering microfacet
  BSDFs with the Smith model", Sec. 4 and 6, their diffuse material). Heights are carried
  as u = C1(h) ∈ (0, 1], the height CDF, which makes the walk independent of the height
  distribution (their Sec. 3.2). A ray leaving height u in direction ω escapes with
  probability G1 = u^Λ(ω) (ω upward) and otherwise meets the surface at
  u' = u (1 − U)^(−1/Λ(ω)) (their eq. 7 inverted; downward rays always meet it); the facet is
  drawn from the visible normals of −ω and the new direction from its cosine lobe. At every
  event the next-event estimate ⟨ωo, ωm⟩⁺/π · u^Λ(ωo) (times ρ^k at order k) scores
  f cos θo. The walk runs with ρ = 1 and weights the order k by ρ^k, so one walk gives every
  albedo and every bounce count. Two engines trace it: the compiled walk
  (:mod:`.smith_walk_numba`, Numba threads, a counter-based generator; the default when Numba
  is installed) and this module's NumPy walk (the reference), both made of the formulas of
  :mod:`.smith_formulas`.

Heights uncorrelated: a real surface (a Gaussian heightfield, :mod:`.heightfield`) has
correlated heights; how close Smith comes to one is measured in docs/accuracy.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._validate import ParameterError, check_range
from ..quadrature import gauss_legendre
from .cavity import Bounces, check_bounces
from .smith_formulas import numpy_formulas
from .smith_slopes import (
    check_distribution,
    sample_visible_normals,
    slope_cdf,
    slope_cdf_inverse,
    smith_lambda,
)

__all__ = [
    "ALPHA_MAX",
    "ENGINES",
    "WalkResult",
    "brdf",
    "directional_albedo",
    "random_walk",
    "single_scattering",
]

ALPHA_MAX = 2.0
"""Largest roughness accepted (Beckmann α = 2: RMS slope angle about 50°)."""

THETA_GRAZING = math.pi / 2 - 1e-7
"""θi and θr are clamped to this (the BRDF at 90° is its finite limit)."""

MAX_ORDER = 512
"""A walk is cut after this many scattering events (its remaining energy is below 1e-12
for every α ≤ ALPHA_MAX: measured escape probability per event ≥ 0.2 at ρ = 1)."""

_F = numpy_formulas()
_BATCH = 1 << 17
_V_MAX = 8.6
"""Beckmann quadrature cut-off in tan θm / α: the projected area beyond is exp(−8.6²) < 1e-32."""


ENGINES: tuple[str, ...] = ("auto", "compiled", "numpy")
"""Random-walk engines: "compiled" (Numba, :mod:`.smith_walk_numba`), "numpy" (the
reference), "auto" (compiled when Numba is installed, else NumPy)."""


def _check_engine(engine: object) -> str:
    """The engine to run: "compiled" or "numpy" (``ValueError`` for another name)."""
    if engine not in ENGINES:
        raise ParameterError(f"engine must be one of {ENGINES} (got {engine!r})")
    if engine == "auto":
        import importlib.util

        return "compiled" if importlib.util.find_spec("numba") is not None else "numpy"
    if engine == "compiled":
        import importlib.util

        if importlib.util.find_spec("numba") is None:
            raise ParameterError("engine='compiled' needs Numba (pip install numba); use 'numpy'")
    return str(engine)


def _check_alpha(alpha: object) -> float:
    check_range("alpha", alpha, 0.0, ALPHA_MAX)
    return float(alpha)  # type: ignore[arg-type]


def check_angles(theta_i, theta_r, delta_phi):
    """θi, θr in [0, π/2] and a finite Δφ, refused by name otherwise; returns them flat, with
    θ capped at ``THETA_GRAZING``, and their broadcast shape (shared by the walks)."""
    ti, tr, dp = np.broadcast_arrays(
        *(np.asarray(a, dtype=np.float64) for a in (theta_i, theta_r, delta_phi))
    )
    for name, val in (("theta_i", ti), ("theta_r", tr)):
        check_range(name, val, 0.0, math.pi / 2, unit="radians", scalar=False)
    if not np.all(np.isfinite(dp)):
        raise ParameterError("delta_phi must be finite")
    shape = ti.shape
    ti = np.minimum(ti.reshape(-1), THETA_GRAZING)
    tr = np.minimum(tr.reshape(-1), THETA_GRAZING)
    return ti, tr, dp.reshape(-1), shape


def _check_count(name: str, value: object, lo: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < lo:
        raise ParameterError(f"{name} must be an integer >= {lo} (got {value!r})")
    return int(value)


def _directions(ti, tr, dp):
    wi = np.stack([np.sin(ti), np.zeros_like(ti), np.cos(ti)], axis=-1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], axis=-1)
    return wi, wo


def _pieces(edges: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss–Legendre nodes and weights on each interval of sorted ``edges`` (..., E)."""
    t, w = gauss_legendre(n)
    a, b = edges[..., :-1, None], edges[..., 1:, None]
    shape = edges.shape[:-1] + (-1,)
    return (a + (b - a) * t).reshape(shape), ((b - a) * w).reshape(shape)


def _phi_kinks(theta_m, theta, phi0):
    """Azimuths φ where ⟨ω, ωm⟩ = 0 for ω at (θ, φ0) and ωm at (θm, φ), mod 2π (2π: none)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        c = -np.cos(theta) * np.cos(theta_m) / (np.sin(theta) * np.sin(theta_m))
    ok = np.abs(c) <= 1.0
    d = np.arccos(np.clip(c, -1.0, 1.0))
    two_pi = 2.0 * math.pi
    return [np.where(ok, np.remainder(phi0 + s * d, two_pi), two_pi) for s in (1.0, -1.0)]


def single_scattering(
    theta_i,
    theta_r,
    delta_phi,
    alpha: float,
    albedo: float = 1.0,
    distribution: str = "beckmann",
    *,
    n_theta: int = 32,
    n_phi: int = 16,
) -> np.ndarray:
    """One-bounce BRDF of the Smith Lambertian microsurface by quadrature, in 1/sr.

    f1 = ρ / (π cos θi cos θo (1 + Λi + Λo)) ∫ ⟨ωi, ωm⟩⁺ ⟨ωo, ωm⟩⁺ D(ωm) dωm (module
    docstring; Heitz & Dupuy 2015 eq. 3 with Heitz 2014 eq. 99). ``n_theta`` Gauss–Legendre
    points per θm piece (at most 3 pieces), ``n_phi`` per φm piece (at most 5): the defaults
    agree with doubled rules to 1e-5 relative (measured: ≤ 1e-6; the φm-integrated function
    has kinks in θm where the azimuths of the two turn-away lines cross;
    tests/test_simulate_smith.py).

    Examples
    --------
    >>> round(float(single_scattering(0.4, 0.7, 1.0, alpha=0.0, albedo=0.5) * math.pi), 12)
    0.5
    """
    alpha = _check_alpha(alpha)
    check_range("albedo", albedo, 0.0, 1.0)
    distribution = check_distribution(distribution)
    n_theta = _check_count("n_theta", n_theta)
    n_phi = _check_count("n_phi", n_phi)
    ti, tr, dp, shape = check_angles(theta_i, theta_r, delta_phi)
    if alpha == 0.0:
        return np.full(shape, albedo / math.pi)
    out = np.empty_like(ti)
    for a in range(0, ti.size, 64):
        sl = slice(a, a + 64)
        out[sl] = _single(ti[sl], tr[sl], dp[sl], alpha, distribution, n_theta, n_phi)
    return (albedo * out).reshape(shape)


def _single(ti, tr, dp, alpha, dist, n_theta, n_phi) -> np.ndarray:
    """f1 / ρ for flat arrays of geometries."""
    # θm pieces, split where tan θm = cot θ (a facet can turn away from ωi or ωo)
    with np.errstate(divide="ignore"):
        cot = [1.0 / np.tan(t) for t in (ti, tr)]
    if dist == "beckmann":  # in v = tan θm / α, projected-area measure 2v exp(−v²) dv
        top = _V_MAX
        cuts = [np.minimum(c / alpha, top) for c in cot]
    else:  # in s, u = 1 − s² (GGX tail: the integrand stays finite at s → 0)
        top = 1.0
        cuts = [slope_cdf(dist, c, alpha) for c in cot]
    edges = np.sort(np.stack([np.zeros_like(ti), *cuts, np.full_like(ti, top)], axis=-1), axis=-1)
    x, wx = _pieces(edges, n_theta)  # (G, 3 n)
    if dist == "beckmann":
        tan_m, dens = alpha * x, 2.0 * x * np.exp(-x * x)
    else:
        tan_m, dens = slope_cdf_inverse(dist, x, alpha), 2.0 * x
    theta_m = np.arctan(tan_m)
    cos_m, sin_m = np.cos(theta_m), np.sin(theta_m)
    # φm pieces, split where a facet turns away from ωi (azimuth 0) or ωo (azimuth Δφ)
    tim, trm, dpm = (x[:, None] for x in (ti, tr, dp))
    kinks = _phi_kinks(theta_m, tim, 0.0) + _phi_kinks(theta_m, trm, dpm)
    k = np.sort(np.stack(kinks, axis=-1), axis=-1)
    zero = np.zeros(k.shape[:-1] + (1,))
    ph, wph = _pieces(np.concatenate([zero, k, zero + 2.0 * math.pi], axis=-1), n_phi)
    sm, cm = sin_m[..., None], cos_m[..., None]
    dot_i = np.sin(tim)[..., None] * sm * np.cos(ph) + np.cos(tim)[..., None] * cm
    dot_o = (
        np.sin(trm)[..., None] * sm * np.cos(ph - dpm[..., None]) + np.cos(trm)[..., None] * cm
    )
    inner = np.sum(np.maximum(dot_i, 0.0) * np.maximum(dot_o, 0.0) * wph, axis=-1) / (2 * math.pi)
    # ∫ ⟨⟩⁺⟨⟩⁺ D dωm = ∫ ⟨⟩⁺⟨⟩⁺ / cos θm dP, dP = D cos θm dωm the projected-area measure
    integral = np.sum(inner / cos_m * dens * wx, axis=-1)
    lam_i = smith_lambda(dist, np.cos(ti), alpha)
    lam_o = smith_lambda(dist, np.cos(tr), alpha)
    return integral / (math.pi * np.cos(ti) * np.cos(tr) * (1.0 + lam_i + lam_o))


def _cosine_about(m: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Cosine-distributed directions about unit normals ``m`` (N, 3), m_z > 0
    (:mod:`.smith_formulas`' ``cosine_about``)."""
    u = rng.random((2, m.shape[0]))
    return np.stack(_F.cosine_about(m[:, 0], m[:, 1], m[:, 2], u[0], u[1]), axis=1)


@dataclass(frozen=True)
class WalkResult:
    """Result of :func:`random_walk` (arrays in the broadcast shape of the angles).

    Attributes
    ----------
    albedos : tuple of float
        Facet albedos, in the order of the first axis of ``values``.
    values, stderr : ndarray, shape (A, ...)
        f (1/sr) summed over the requested bounces, one row per albedo, and its Monte Carlo
        standard error (from the per-path totals).
    orders, orders_stderr : ndarray, shape (K, ...)
        f of each scattering order k = 1..K at ρ = 1 (multiply by ρ^k for albedo ρ) and its
        standard error; K = ``max_order``.
    samples : int
        Paths per geometry.
    segments : int
        Path segments traced (rays from one height to the next or out), for all geometries.
    """

    albedos: tuple[float, ...]
    values: np.ndarray
    stderr: np.ndarray
    orders: np.ndarray
    orders_stderr: np.ndarray
    samples: int
    segments: int = 0


def _walk(
    wi: np.ndarray,
    wo: np.ndarray,
    weight: np.ndarray,
    group: np.ndarray,
    n_groups: int,
    alpha: float,
    dist: str,
    albedos: tuple[float, ...],
    bounces: int,
    orders: int,
    rng: np.random.Generator,
    sums: dict[str, np.ndarray],
) -> int:
    """One batch of paths; adds per-group sums of the scores into ``sums``.

    ``weight`` multiplies each path's next-event estimates (1/cos θo for a BRDF, 2π for an
    albedo with uniformly drawn ωo). Returns the number of path segments traced.
    """
    n = wi.shape[0]
    lam_o = smith_lambda(dist, wo[:, 2], alpha)
    rho = np.asarray(albedos)[:, None]
    total = np.zeros((len(albedos), n))
    idx = np.arange(n)
    wr = -wi
    h = np.zeros(n)  # ln u, u = C1(height) (module docstring)
    segments = 0
    for k in range(1, bounces + 1):
        segments += idx.size
        lam = smith_lambda(dist, wr[:, 2], alpha)
        e = rng.random(idx.size)
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            escape, h_new = _F.height_step(h, lam, wr[:, 2], e)
        stay = ~escape
        idx, wr, h = idx[stay], wr[stay], h_new[stay]
        if idx.size == 0:
            break
        m = sample_visible_normals(dist, -wr, alpha, rng)
        wo_k = wo[idx]
        with np.errstate(under="ignore"):
            score = _F.next_event(*wo_k.T, *m.T, h, lam_o[idx]) * weight[idx]
        total[:, idx] += rho**k * score
        if k <= orders:
            g = group[idx]
            sums["order1"][k - 1] += np.bincount(g, score, minlength=n_groups)
            sums["order2"][k - 1] += np.bincount(g, score * score, minlength=n_groups)
        wr = _cosine_about(m, rng)
    for a in range(len(albedos)):
        sums["sum1"][a] += np.bincount(group, total[a], minlength=n_groups)
        sums["sum2"][a] += np.bincount(group, total[a] ** 2, minlength=n_groups)
    return segments


def _run(
    wi_fn,
    n_groups: int,
    samples: int,
    alpha: float,
    dist: str,
    albedos: tuple[float, ...],
    bounces: int,
    orders: int,
    seed: int,
    progress: bool = False,
    workers: int = 1,
):
    """Trace ``samples`` paths for each of ``n_groups`` groups in batches.

    ``wi_fn(group, rng)`` returns (wi, wo, weight) for the paths of the given groups.
    Returns the means and standard errors, and the number of segments traced.
    """
    a_n = len(albedos)

    def zeros():
        return {
            "sum1": np.zeros((a_n, n_groups)),
            "sum2": np.zeros((a_n, n_groups)),
            "order1": np.zeros((orders, n_groups)),
            "order2": np.zeros((orders, n_groups)),
        }

    total = n_groups * samples
    starts = range(0, total, _BATCH)
    # one generator per batch, spawned from the seed: the numbers do not depend on workers
    seeds = np.random.SeedSequence(seed).spawn(len(starts))

    def batch(b: int):
        rng = np.random.default_rng(seeds[b])
        group = np.arange(starts[b], min(starts[b] + _BATCH, total)) // samples
        part = zeros()
        wi, wo, weight = wi_fn(group, rng)
        n = _walk(wi, wo, weight, group, n_groups, alpha, dist, albedos, bounces, orders, rng, part)
        return part, n, group.size

    sums = zeros()
    segments = 0
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=total, unit="path", desc="Smith random walk")
    pool = None
    if workers > 1 and len(starts) > 1:
        from concurrent.futures import ThreadPoolExecutor

        pool = ThreadPoolExecutor(workers)  # NumPy's loops release the GIL
    try:
        results = pool.map(batch, range(len(starts))) if pool else map(batch, range(len(starts)))
        for part, n, count in results:  # in batch order: the same sums for any workers
            for key in sums:
                sums[key] += part[key]
            segments += n
            if bar is not None:
                bar.update(count)
    finally:
        if pool is not None:
            pool.shutdown(cancel_futures=True)
        if bar is not None:
            bar.close()

    return _results(sums, samples, segments)


def _results(sums: dict[str, np.ndarray], samples: int, segments: int):
    """Means and standard errors from the per-group sums of scores and of their squares."""

    def stats(s1, s2):
        mean = s1 / samples
        var = np.maximum(s2 / samples - mean * mean, 0.0) * samples / max(samples - 1, 1)
        return mean, np.sqrt(var / samples)

    values, stderr = stats(sums["sum1"], sums["sum2"])
    ords, ords_se = stats(sums["order1"], sums["order2"])
    return values, stderr, ords, ords_se, segments


def _run_compiled(
    wi: np.ndarray,
    wo: np.ndarray,
    weight: np.ndarray,
    uniform_wo: bool,
    samples: int,
    alpha: float,
    dist: str,
    albedos: tuple[float, ...],
    bounces: int,
    orders: int,
    seed: int,
    progress: bool = False,
    workers: int | None = None,
):
    """:func:`_run` on the compiled engine (:mod:`.smith_walk_numba`).

    The walk runs in calls of about 2^18 paths (progress, Ctrl-C between calls); within one,
    Numba's threads (``workers`` of them, default all) trace blocks of paths. The block sums are
    added in block order, so the values do not depend on ``workers``.
    """
    import numba

    from . import smith_walk_numba as k

    n_groups = wi.shape[0]
    per_group = -(-samples // k.BLOCK)
    n_blocks = n_groups * per_group
    step = max(1, (1 << 18) // k.BLOCK)
    rho = np.asarray(albedos, dtype=np.float64)
    a_n = rho.size
    key = np.uint64(seed % (1 << 64))  # the generator's key is 64 bits
    sums = {
        "sum1": np.zeros((a_n, n_groups)),
        "sum2": np.zeros((a_n, n_groups)),
        "order1": np.zeros((orders, n_groups)),
        "order2": np.zeros((orders, n_groups)),
    }
    arrays = [np.ascontiguousarray(x, dtype=np.float64) for x in (wi, wo, weight)]
    segments = 0
    bar = None
    if progress:
        from tqdm import tqdm

        bar = tqdm(total=n_groups * samples, unit="path", desc="Smith random walk")
    threads = numba.get_num_threads()
    if workers is not None:
        numba.set_num_threads(max(1, min(workers, numba.config.NUMBA_NUM_THREADS)))
    try:
        for first in range(0, n_blocks, step):
            count = min(step, n_blocks - first)
            s1, s2 = np.zeros((count, a_n)), np.zeros((count, a_n))
            o1, o2 = np.zeros((count, orders)), np.zeros((count, orders))
            seg = np.zeros(count, dtype=np.int64)
            k.run_blocks(
                *arrays, bool(uniform_wo), samples, first, count, alpha, dist == "ggx", rho,
                bounces, orders, key, s1, s2, o1, o2, seg,
            )
            group = np.arange(first, first + count) // per_group
            for name, part in (("sum1", s1), ("sum2", s2), ("order1", o1), ("order2", o2)):
                for b in range(count):  # in block order: the same sums for any thread count
                    sums[name][:, group[b]] += part[b]
            segments += int(seg.sum())
            if bar is not None:
                done = np.minimum((np.arange(first, first + count) % per_group + 1) * k.BLOCK,
                                  samples) - (np.arange(first, first + count) % per_group) * k.BLOCK
                bar.update(int(done.sum()))
    finally:
        numba.set_num_threads(threads)
        if bar is not None:
            bar.close()
    return _results(sums, samples, segments)


def _walk_settings(alpha, albedo, bounces, distribution, samples, seed, max_order):
    alpha = _check_alpha(alpha)
    albedos = tuple(float(a) for a in np.atleast_1d(np.asarray(albedo, dtype=np.float64)))
    check_range("albedo", np.asarray(albedos), 0.0, 1.0, scalar=False)
    bounces = check_bounces(bounces)
    depth = MAX_ORDER if bounces == "all" else bounces
    distribution = check_distribution(distribution)
    samples = _check_count("samples", samples, 2)
    seed = _check_count("seed", seed, 0)
    max_order = _check_count("max_order", max_order)
    return alpha, albedos, depth, distribution, samples, seed, min(max_order, depth)


def random_walk(
    theta_i,
    theta_r,
    delta_phi,
    alpha: float,
    albedo: float | tuple[float, ...] = 1.0,
    bounces: Bounces = "all",
    distribution: str = "beckmann",
    *,
    samples: int = 100_000,
    seed: int = 0,
    max_order: int = 8,
    progress: bool = False,
    workers: int | None = None,
    engine: str = "auto",
) -> WalkResult:
    """The Smith Lambertian microsurface's BRDF by the random walk of Heitz et al. 2016.

    Parameters
    ----------
    theta_i, theta_r : array_like
        Incidence and viewing angles in [0, π/2] radians (broadcast together).
    delta_phi : array_like
        Azimuth difference φr − φi, radians (0: viewer on the light's side).
    alpha : float
        Roughness α in [0, 2] (Beckmann: RMS slope α/√2 per axis; GGX: Trowbridge–Reitz α).
    albedo : float or tuple of float
        Facet albedo(s) ρ in [0, 1]; one walk (at ρ = 1, order k weighted by ρ^k) serves all.
    bounces : int >= 1 or "all"
        Scattering orders summed (all: until every path has left, at most MAX_ORDER).
    distribution : {"beckmann", "ggx"}
        Slope distribution.
    samples : int
        Paths per geometry (≥ 2); the standard error falls as 1/√samples.
    seed : int
        Seed of the random numbers: the same arguments (and engine) give the same numbers
        (the compiled engine uses it modulo 2^64).
    max_order : int
        Orders reported one by one in ``WalkResult.orders``.
    progress : bool
        Show a progress bar (tqdm).
    workers : int or None
        Threads. Compiled engine: Numba's threads (default: all of them), each tracing
        blocks of paths whose random numbers are keyed by (seed, path, draw)
        (:mod:`.smith_walk_numba`). NumPy engine: threads tracing batches of 2^17 paths at
        once (default 1; NumPy releases the GIL in its loops), each batch with its own
        generator spawned from ``seed``. Either way the values do not depend on ``workers``.
    engine : {"auto", "compiled", "numpy"}
        "compiled": the Numba walk (millions of segments per second, bench/RESULTS.md);
        "numpy": the NumPy reference walk; "auto": compiled when Numba is installed. The two
        engines draw different random numbers: their values agree within the standard errors
        (tests/test_smith_walk_compiled.py), not to the last digit.

    Returns
    -------
    WalkResult
    """
    alpha, albedos, depth, dist, samples, seed, orders = _walk_settings(
        alpha, albedo, bounces, distribution, samples, seed, max_order
    )
    engine = _check_engine(engine)
    ti, tr, dp, shape = check_angles(theta_i, theta_r, delta_phi)
    n_groups = ti.size
    if alpha == 0.0:  # a flat Lambertian plane: exactly ρ/π, one bounce
        vals = np.broadcast_to(np.asarray(albedos)[:, None] / math.pi, (len(albedos), n_groups))
        ords = np.zeros((orders, n_groups))
        ords[0] = 1.0 / math.pi
        z = np.zeros_like
        return WalkResult(
            albedos,
            vals.reshape((-1, *shape)),
            z(vals).reshape((-1, *shape)),
            ords.reshape((-1, *shape)),
            z(ords).reshape((-1, *shape)),
            samples,
        )
    wi_all, wo_all = _directions(ti, tr, dp)
    inv_cos = 1.0 / wo_all[:, 2]
    if workers is not None:
        workers = _check_count("workers", workers)
    if engine == "compiled":
        values, stderr, ords, ords_se, segments = _run_compiled(
            wi_all, wo_all, inv_cos, False, samples, alpha, dist, albedos, depth, orders, seed,
            progress, workers,
        )
    else:

        def paths(group, rng):
            return wi_all[group], wo_all[group], inv_cos[group]

        values, stderr, ords, ords_se, segments = _run(
            paths, n_groups, samples, alpha, dist, albedos, depth, orders, seed, progress,
            workers or 1,
        )
    return WalkResult(
        albedos,
        values.reshape((-1, *shape)),
        stderr.reshape((-1, *shape)),
        ords.reshape((-1, *shape)),
        ords_se.reshape((-1, *shape)),
        samples,
        segments,
    )


def brdf(
    theta_i,
    theta_r,
    delta_phi,
    alpha: float,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    distribution: str = "beckmann",
    *,
    samples: int = 100_000,
    seed: int = 0,
    method: str = "auto",
    return_stderr: bool = False,
    engine: str = "auto",
):
    """BRDF of the Smith microsurface with Lambertian facets, f(θi, θr, Δφ; α, ρ), in 1/sr.

    The calling convention of :func:`roughdiffuse.simulate.brdf` (the V-cavity solver) with
    the roughness α and the slope ``distribution`` in place of σ.

    Parameters
    ----------
    theta_i, theta_r, delta_phi : array_like
        Angles in radians, as in :func:`random_walk`.
    alpha : float
        Roughness in [0, 2]; 0 is the Lambert limit ρ/π.
    albedo : float
        Facet albedo ρ in [0, 1].
    bounces : int >= 1 or "all"
        Scattering orders summed.
    distribution : {"beckmann", "ggx"}
        Slope distribution.
    samples, seed : int
        Paths per geometry and the generator's seed (random walk).
    method : {"auto", "quadrature", "walk"}
        "auto": the deterministic quadrature for one bounce (standard error 0), the random
        walk otherwise; "walk" forces the walk (also for one bounce).
    return_stderr : bool
        Also return the Monte Carlo standard error of each value.
    engine : {"auto", "compiled", "numpy"}
        The random walk's engine (:func:`random_walk`).

    Returns
    -------
    ndarray, or (ndarray, ndarray) with ``return_stderr``

    Examples
    --------
    >>> f, se = brdf(0.5, 0.3, 2.0, alpha=0.4, albedo=0.8, samples=20_000, return_stderr=True)
    >>> bool(0.2 < f * math.pi < 0.9 and se < 0.01)
    True
    """
    if method not in ("auto", "quadrature", "walk"):
        raise ParameterError(f"method must be 'auto', 'quadrature' or 'walk' (got {method!r})")
    b = check_bounces(bounces)
    if method == "quadrature" and b != 1:
        raise ParameterError("method='quadrature' computes one bounce only: pass bounces=1")
    _check_engine(engine)
    if b == 1 and method != "walk":
        f = single_scattering(theta_i, theta_r, delta_phi, alpha, albedo, distribution)
        return (f, np.zeros_like(f)) if return_stderr else f
    if np.ndim(albedo) != 0:
        raise ParameterError("albedo must be a scalar in [0, 1] (random_walk takes several)")
    r = random_walk(
        theta_i,
        theta_r,
        delta_phi,
        alpha,
        albedo,
        bounces,
        distribution,
        samples=samples,
        seed=seed,
        max_order=1,
        engine=engine,
    )
    return (r.values[0], r.stderr[0]) if return_stderr else r.values[0]


def directional_albedo(
    theta_i,
    alpha: float,
    albedo: float = 1.0,
    bounces: Bounces = "all",
    distribution: str = "beckmann",
    *,
    samples: int = 100_000,
    seed: int = 0,
    engine: str = "auto",
) -> tuple[np.ndarray, np.ndarray]:
    """Directional albedo ∫ f cos θo dωo of the Smith Lambertian microsurface, with its s.e.

    Each path draws its own ωo uniformly on the upper hemisphere and scores 2π times its
    next-event estimates of f cos θo, so the integral over ωo is part of the Monte Carlo
    estimate (the white-furnace check: ρ = 1, all bounces gives 1). ``engine``: as in
    :func:`random_walk`.

    Returns
    -------
    (ndarray, ndarray)
        Albedo and standard error, each of the shape of ``theta_i``.
    """
    alpha, albedos, depth, dist, samples, seed, orders = _walk_settings(
        alpha, albedo, bounces, distribution, samples, seed, 1
    )
    engine = _check_engine(engine)
    ti = np.asarray(theta_i, dtype=np.float64)
    check_range("theta_i", ti, 0.0, math.pi / 2, unit="radians", scalar=False)
    shape = ti.shape
    ti = np.minimum(ti.reshape(-1), THETA_GRAZING)
    if alpha == 0.0:
        return np.full(shape, albedos[0]), np.zeros(shape)
    wi_all = np.stack([np.sin(ti), np.zeros_like(ti), np.cos(ti)], axis=-1)
    if engine == "compiled":
        values, stderr, *_ = _run_compiled(
            wi_all, wi_all, np.ones(ti.size), True, samples, alpha, dist, albedos, depth, 1, seed
        )
        return values[0].reshape(shape), stderr[0].reshape(shape)

    def paths(group, rng):
        u = rng.random((2, group.size))
        z, phi = u[0], 2.0 * math.pi * u[1]
        r = np.sqrt(np.maximum(1.0 - z * z, 0.0))
        wo = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
        return wi_all[group], wo, np.full(group.size, 2.0 * math.pi)

    values, stderr, *_ = _run(paths, ti.size, samples, alpha, dist, albedos, depth, 1, seed)
    return values[0].reshape(shape), stderr[0].reshape(shape)
