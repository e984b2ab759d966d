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
and subtracted path by path. ``Coated`` (:mod:`roughdiffuse.models.coated`) fits its
multiple-scattering lobe to these values (and to ``coat_interface.npz``'s directional
reflectances) on first use. Seeded: the same file for the same arguments. Written whole or
not at all; each (distribution, η, α) is cached in ``--cache`` while the script runs, so an
interrupted run resumes.
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
from roughdiffuse.simulate import layered_walk_numba as walk

DISTRIBUTIONS = ("ggx", "beckmann")
ETAS = (1.2, 1.5, 2.0, 3.0)
ALPHAS = (0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.4, 0.5, 0.7, 1.0)
_SEED_ORDER = (0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.7, 1.0, 0.15, 0.25)
"""The α in the order they were added to the table: each configuration's seed takes the
index of its α here (so that adding an α leaves the others' values as they were)."""
THETAS = (0.0, 20.0, 35.0, 50.0, 60.0, 68.0, 75.0, 80.0, 85.0)
PHIS = (0.0, 60.0, 110.0, 150.0, 170.0, 180.0)
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=40_000)
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--cache", type=Path, default=None,
                    help="folder of per-configuration results, to resume")
    args = ap.parse_args()
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
    buf = io.BytesIO()
    np.savez_compressed(buf, f_ms=f_ms.astype(np.float32), stderr=se.astype(np.float32),
                        theta_i=ti, theta_r=tr, delta_phi=dp,
                        etas=np.array(ETAS), alphas=np.array(ALPHAS), samples=args.samples,
                        axes=np.array("distribution (ggx, beckmann), eta, alpha, geometry"))
    write_bytes(args.out, buf.getvalue())
    print(f"wrote {args.out} ({args.out.stat().st_size:,} bytes)")


if __name__ == "__main__":
    main()
