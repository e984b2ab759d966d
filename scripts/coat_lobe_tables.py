"""Regenerate ``src/roughdiffuse/data/coat_lobe.npz``: the rough coat's own reflection by two
or more facet events, resolved in direction, by the layered walk's multiple-scattering
interface.

``python scripts/coat_lobe_tables.py [--samples 40000] [--cache /tmp/coat_lobe]``

For GGX and Beckmann, η in :data:`ETAS` and α in :data:`ALPHAS`, on the geometries
θi ≤ θr in :data:`THETAS` × Δφ in :data:`PHIS` (the other half by reciprocity): the walk on
the dielectric microsurface of Heitz, Hanika, d'Eon and Dachsbacher 2016
(:func:`roughdiffuse.simulate.layered_walk_numba._ms_walk`) entered from above at ωi, its
next events towards ωo summed from the second facet event on. That is f_ms(ωi, ωo) μo, the
part of the interface's reflection its single-scattering lobe (Walter et al. 2007, eq. 20,
height-correlated) does not hold, estimated without the first event's noise: the first
event's next event is the single-scattering lobe itself, drawn with the same random numbers
and subtracted path by path.

Then the coefficients of ``Coated``'s multiple-scattering lobe
(:func:`roughdiffuse.models.coated.ms_lobe`), stored in the file as ``coef``: :func:`fit`,
least squares of these values with the lobe's own albedo held to what the coat reflects
beyond its single-scattering lobe (``coat_interface.npz``'s reflectance, through
:func:`~roughdiffuse.models.coated.ms_ratio`). ``--refit`` refits the file's own table
without running the walk (about a minute). Seeded: the same file for the same arguments.
Written whole or not at all; each (distribution, η, α) is cached in ``--cache`` while the
script runs, so an interrupted run resumes.
"""

from __future__ import annotations

import argparse
import io
import math
from pathlib import Path

import numba
import numpy as np
from numba import prange
from tqdm import tqdm

from roughdiffuse.engine.numba_random import path_key, uniform
from roughdiffuse.io.atomic import write_bytes
from roughdiffuse.models import coated
from roughdiffuse.simulate import layered_walk_numba as walk

DISTRIBUTIONS = ("ggx", "beckmann")
ETAS = (1.2, 1.5, 2.0, 3.0)
ALPHAS = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.7, 1.0)
_SEED_ORDER = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 0.15, 0.25)
"""The α in the order they were added to the table: each configuration's seed takes the
index of its α here (so that adding an α leaves the others' values as they were)."""
THETAS = (0.0, 20.0, 35.0, 50.0, 60.0, 68.0, 75.0, 80.0, 85.0)
PHIS = (0.0, 60.0, 110.0, 150.0, 170.0, 180.0)
LOBE_FLOOR = 0.05
"""The diffuse reflectance (1/sr) added to the coat's reflection in the weights of
:func:`fit`: each residual counts relative to the coat's reflection plus a base's light
(a Lambertian base of albedo 0.8 under η = 1.5 gives about 0.17 /sr)."""
ALBEDO_WEIGHT = 2000.0
"""The weight of each albedo condition of :func:`fit`: an albedo residual of 1/2000 counts as
much as a pointwise one of the walk's noise (or 0.3 % of the reflection)."""
FIT_ETAS = (1.05, 1.1, 1.2, 1.35, 1.5, 1.75, 2.0, 2.5, 3.0)
FIT_THETAS = (0.0, 8.0, 16.0, 24.0, 32.0, 40.0, 48.0, 56.0, 64.0, 72.0, 80.0, 83.0, 85.0,
              87.0, 88.0, 89.0)
FIT_SMALL_ALPHAS = (0.01, 0.02, 0.03)
"""The albedo conditions of :func:`fit`: at η in FIT_ETAS, θo in FIT_THETAS (degrees), and
α at the table's nodes, half-way between them and at FIT_SMALL_ALPHAS below the first
(where the weights go linearly to 0)."""
OUT = (Path(__file__).resolve().parent.parent / "src" / "roughdiffuse" / "data"
       / "coat_lobe.npz")


@numba.njit(parallel=True, nogil=True, error_model="numpy")
def _sums(wi, wo, samples, eta, alpha, ggx, seed, out):  # pragma: no cover - compiled
    """out[g] = (Σ s, Σ s², Σ s1, Σ s1²): s the next events of a walk from ωi towards ωo from
    its second facet event on, s1 its first event's (the single-scattering lobe's estimate)."""
    for g in prange(wi.shape[0]):
        ox, oy, oz = wo[g, 0], wo[g, 1], wo[g, 2]
        lam_o = walk._smith_lambda(ggx, oz, alpha)
        s_sum = 0.0
        s_sq = 0.0
        s1_sum = 0.0
        s1_sq = 0.0
        for s in range(samples):
            key = path_key(seed, g * samples + s)
            r = walk._ms_walk(-wi[g, 0], -wi[g, 1], -wi[g, 2], True, eta, alpha, ggx, key, 0,
                              True, ox, oy, oz, lam_o)
            total = r[5]
            # the first event with the walk's own draws: a downward ray from the top meets
            # the surface (draw 0: its height), at a visible normal (draws from 1)
            wz = -wi[g, 2]
            _esc, h = walk._height_step(0.0, walk._smith_lambda(ggx, wz, alpha), wz,
                                        uniform(key, 0))
            nx, ny, nz, _c = walk.visible_normal(ggx, wi[g, 0], wi[g, 1], wi[g, 2], alpha,
                                                 key, 1)
            g1 = math.exp(lam_o * h) if h < 0.0 else 1.0
            first = walk._phase_out(ggx, True, wi[g, 0], wi[g, 1], wi[g, 2], ox, oy, oz, eta,
                                    alpha) * g1
            rest = total - first
            s_sum += rest
            s_sq += rest * rest
            s1_sum += first
            s1_sq += first * first
        out[g, 0] = s_sum
        out[g, 1] = s_sq
        out[g, 2] = s1_sum
        out[g, 3] = s1_sq


def geometries() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """θi, θr, Δφ (radians) of the table: θi ≤ θr."""
    t = np.radians(THETAS)
    rows = [(a, b, p) for i, a in enumerate(t) for b in t[i:] for p in np.radians(PHIS)]
    return tuple(np.array(c) for c in zip(*rows, strict=True))  # type: ignore[return-value]


def lobe(distribution: str, eta: float, alpha: float, samples: int, seed: int,
         geometry: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
         ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """f_ms and its standard error, the walk's estimate of the single-scattering f_ss and its
    standard error, on :func:`geometries` (or on ``geometry``: θi, θr, Δφ in radians)."""
    ti, tr, dp = geometries() if geometry is None else geometry
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], -1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], -1)
    out = np.zeros((ti.size, 4))
    _sums(wi, wo, samples, eta, alpha, distribution == "ggx", np.uint64(seed), out)
    mu_o = np.cos(tr)
    res = []
    for k in (0, 2):
        mean = out[:, k] / samples
        var = np.maximum(out[:, k + 1] / samples - mean * mean, 0.0) / (samples - 1)
        res += [mean / mu_o, np.sqrt(var) / mu_o]
    return res[0], res[1], res[2], res[3]


def _lobe_columns(mu_i: np.ndarray, mu_o: np.ndarray, cos_io: np.ndarray, eta: np.ndarray,
                  alpha: np.ndarray, distribution: str, nodes: tuple[float, ...]) -> np.ndarray:
    """The design matrix of :func:`fit` (..., coefficients): each width's lobe times each
    angular weight times ``_lobe_basis`` (x^i, i = 1..3, times each α node's hat), in
    ``ms_lobe``'s order."""
    basis = coated._lobe_basis(np, eta, alpha, nodes, np.float64)
    cols = []
    for s in coated.LOBE_WIDTHS:
        lobe = coated.coat_reflection(np, mu_i, mu_o, cos_io, eta, alpha * s, distribution)
        for t in coated._lobe_terms(np, mu_i, mu_o):
            cols.append((lobe * t)[..., None] * basis)
    return np.concatenate(cols, axis=-1)


def _albedo_rows(distribution: str, eta: float, alpha: float, mu_o: np.ndarray,
                 nodes: tuple[float, ...]) -> tuple[np.ndarray, np.ndarray]:
    """The albedo ∫ column μi dωi of each column of :func:`_lobe_columns` at each ``mu_o``
    (:func:`~roughdiffuse.models.coated.half_vector_rule`, 128 × 128 nodes), and what the
    multiple-scattering lobe must reflect: the coat's reflectance E (the boosted
    ``interface_albedo``, 1 − its transmittance) minus the single-scattering lobe's albedo
    by the same rule (not ``interface_albedo``'s E_ss, whose 48 nodes miss up to 1.4 % of
    a GGX lobe at grazing: c(μ), fitted to the walk relative to it, holds that)."""
    mu_i, cos_io, w = coated.half_vector_rule(mu_o, alpha, distribution, 128)
    mu_r = np.asarray(mu_o)[:, None, None] + 0.0 * mu_i
    rows = []
    for s in coated.LOBE_WIDTHS:
        lobe = coated.coat_reflection(np, mu_i, mu_r, cos_io, eta, alpha * s, distribution)
        rows += [np.sum(lobe * t * w, axis=(-2, -1)) for t in coated._lobe_terms(np, mu_i, mu_r)]
    single = np.sum(w * coated.coat_reflection(np, mu_i, mu_r, cos_io, eta, alpha,
                                               distribution), axis=(-2, -1))
    basis = coated._lobe_basis(np, np.asarray(eta), np.asarray(alpha), nodes, np.float64)
    rows_all = (np.stack(rows, axis=-1)[..., None] * basis).reshape(len(mu_o), -1)
    target = coated.interface_albedo(np, mu_o, eta, alpha, distribution, boosted=True) - single
    return rows_all, target


def fit(distribution: str, table: dict[str, np.ndarray]) -> np.ndarray:
    """The coefficients of ``ms_lobe`` for ``distribution`` from ``table`` (this script's
    arrays): weighted least squares of the walk's f_ms, each residual relative to
    f_ss + f_ms + :data:`LOBE_FLOOR` and weighted by 1/√(s.e.² + (0.003 × that)²) (the walk's
    noise with a floor of 0.3 % of it), together with the lobe's albedo against what the
    coat reflects beyond its single-scattering lobe (:func:`_albedo_rows`) at the
    conditions of :data:`FIT_ETAS`,
    :data:`FIT_THETAS`, :data:`FIT_SMALL_ALPHAS` (weight :data:`ALBEDO_WEIGHT`). The
    table's six azimuths cannot resolve the lobes of a small α at grazing; the albedo
    conditions keep its integral, and so the white furnace, right there."""
    d = DISTRIBUTIONS.index(distribution)
    f_ms = np.asarray(table["f_ms"], np.float64)[d]
    se = np.asarray(table["stderr"], np.float64)[d]
    ti, tr, dp = table["theta_i"], table["theta_r"], table["delta_phi"]
    nodes = tuple(float(a) for a in table["alphas"])
    e, a = (g[..., None] for g in np.meshgrid(table["etas"], nodes, indexing="ij"))
    mi, mo = np.cos(ti), np.cos(tr)
    cio = mi * mo + np.sin(ti) * np.sin(tr) * np.cos(dp)
    f_ss = coated.coat_reflection(np, mi, mo, cio, e, a, distribution)
    w = 1.0 / np.sqrt(se**2 + (0.003 * (f_ss + f_ms + LOBE_FLOOR)) ** 2)
    cols = _lobe_columns(mi + 0 * e, mo + 0 * e, cio + 0 * e, e + 0 * mi, a + 0 * mi,
                         distribution, nodes)
    n = cols.shape[-1]
    lhs, rhs = [(cols * w[..., None]).reshape(-1, n)], [(f_ms * w).ravel()]
    mids = [0.5 * (p + q) for p, q in zip(nodes[:-1], nodes[1:], strict=True)]
    mu_o = np.cos(np.radians(FIT_THETAS))
    for eta in FIT_ETAS:
        for alpha in sorted({*nodes, *mids, *FIT_SMALL_ALPHAS}):
            rows, target = _albedo_rows(distribution, eta, alpha, mu_o, nodes)
            lhs.append(ALBEDO_WEIGHT * rows)
            rhs.append(ALBEDO_WEIGHT * target)
    return np.linalg.lstsq(np.concatenate(lhs), np.concatenate(rhs), rcond=None)[0]


def _write(path: Path, table: dict[str, np.ndarray]) -> None:
    """``table`` with the fitted coefficients (``coef``, one row per distribution) to
    ``path``, whole or not at all."""
    coef = np.stack([fit(d, table) for d in tqdm(DISTRIBUTIONS, desc="fit")])
    buf = io.BytesIO()
    np.savez_compressed(buf, **table, coef=coef)
    write_bytes(path, buf.getvalue())
    print(f"wrote {path} ({path.stat().st_size:,} bytes)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=40_000)
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--cache", type=Path, default=None,
                    help="folder of per-configuration results, to resume")
    ap.add_argument("--refit", action="store_true",
                    help="refit the coefficients of the table in --out, without the walk")
    args = ap.parse_args()
    if args.refit:
        with np.load(args.out) as t:
            table = {k: t[k] for k in t.files if k != "coef"}
        _write(args.out, table)
        return
    shape = (len(DISTRIBUTIONS), len(ETAS), len(ALPHAS), geometries()[0].size)
    f_ms, se = np.zeros(shape), np.zeros(shape)
    # η = 1.5 (glazes, plastics) first, then the others
    jobs = sorted(((d, e, a) for d in range(len(DISTRIBUTIONS)) for e in range(len(ETAS))
                   for a in range(len(ALPHAS))), key=lambda j: (ETAS[j[1]] != 1.5, j))
    for d, e, a in tqdm(jobs, desc="lobe"):
        name = f"{DISTRIBUTIONS[d]}_{ETAS[e]}_{ALPHAS[a]}_{args.samples}.npy"
        cached = args.cache / name if args.cache else None
        if cached is not None and cached.exists():
            f_ms[d, e, a], se[d, e, a] = np.load(cached)[:2]
            continue
        seed = 100 * d + 10 * e + _SEED_ORDER.index(ALPHAS[a])
        res = lobe(DISTRIBUTIONS[d], ETAS[e], ALPHAS[a], args.samples, seed=seed)
        f_ms[d, e, a], se[d, e, a] = res[:2]
        if cached is not None:
            cached.parent.mkdir(parents=True, exist_ok=True)
            np.save(cached, np.stack(res))
    ti, tr, dp = geometries()
    _write(args.out, {
        "f_ms": f_ms.astype(np.float32), "stderr": se.astype(np.float32), "theta_i": ti,
        "theta_r": tr, "delta_phi": dp, "etas": np.array(ETAS), "alphas": np.array(ALPHAS),
        "samples": np.array(args.samples),
        "axes": np.array("distribution (ggx, beckmann), eta, alpha, geometry")})

if __name__ == "__main__":
    main()
