"""Regenerate ``src/roughdiffuse/data/coat_interface.npz``: the rough coat's own reflectance
from above and from below, by the layered walk's multiple-scattering interface.

``python scripts/coat_interface_tables.py [--samples 40000]``

For GGX and Beckmann, α in :data:`ALPHAS`, η in :data:`ETAS` and μ = cos θ on 12
Gauss–Legendre nodes in [0, 1]: the fraction R of the light arriving at θ that the
interface (Heitz, Hanika, d'Eon and Dachsbacher 2016, :func:`roughdiffuse.simulate.layered.
interface_reflectance`) sends back to the side it came from, from above (the coat's directional
albedo E_spec(μ); T = 1 − E_spec enters the layer) and from below (the internal reflectance).
``Coated`` (:mod:`roughdiffuse.models.coated`) fits a smooth correction to its own
single-scattering quadrature on these values on first use. Seeded: the same file for
the same arguments. Written whole or not at all.
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import numpy as np
from tqdm import tqdm

from roughdiffuse.io.atomic import write_bytes
from roughdiffuse.quadrature import gauss_legendre
from roughdiffuse.simulate import layered

ALPHAS = (0.025, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
ETAS = (1.05, 1.15, 1.3, 1.5, 1.75, 2.0, 2.5, 3.0)
OUT = (Path(__file__).resolve().parent.parent / "src" / "roughdiffuse" / "data"
       / "coat_interface.npz")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=40_000)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    mu, _ = gauss_legendre(12)
    theta = np.arccos(mu)
    shape = (2, 2, len(ETAS), len(ALPHAS), mu.size)  # distribution, side, η, α, μ
    r = np.zeros(shape)
    jobs = [(d, s, e, a) for d in range(2) for s in range(2) for e in range(len(ETAS))
            for a in range(len(ALPHAS))]
    for d, s, e, a in tqdm(jobs, desc="interface"):
        r[d, s, e, a] = layered.interface_reflectance(
            theta, ETAS[e], ALPHAS[a], ("ggx", "beckmann")[d], side=("above", "below")[s],
            samples=args.samples, seed=1000 * d + 100 * s + 10 * e + a)
    buf = io.BytesIO()
    np.savez_compressed(buf, reflectance=r.astype(np.float32), mu=mu, etas=np.array(ETAS),
                        alphas=np.array(ALPHAS), samples=args.samples,
                        axes=np.array("distribution (ggx, beckmann), side (above, below), "
                                      "eta, alpha, mu"))
    write_bytes(args.out, buf.getvalue())
    print(f"wrote {args.out} ({args.out.stat().st_size:,} bytes)")


if __name__ == "__main__":
    main()
