"""Regenerate ``src/roughdiffuse/data/coat_interface.npz``: the rough coat's own reflectance
from above and from below, by the layered walk's multiple-scattering interface.

``python scripts/coat_interface_tables.py [--samples 40000]``

For GGX and Beckmann, α in :data:`ALPHAS`, η in :data:`ETAS` and μ = cos θ on 12
Gauss–Legendre nodes in [0, 1]: the fraction R of the light arriving at θ that the
interface (Heitz, Hanika, d'Eon and Dachsbacher 2016, :func:`roughdiffuse.simulate.layered.
interface_reflectance`) sends back to the side it came from, from above (the coat's directional
albedo E_spec(μ); T = 1 − E_spec enters the layer) and from below (the internal reflectance).
Then the coefficients of ``Coated``'s correction to its own single-scattering quadrature
(:func:`roughdiffuse.models.coated.ms_ratio`), fitted to these values (:func:`fit`) and
stored in the file as ``coef``; ``--refit`` refits the file's own table without running
the walk. Seeded: the same file for the same arguments. Written whole or not at all.
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import numpy as np
from tqdm import tqdm

from roughdiffuse.io.atomic import write_bytes
from roughdiffuse.models import coated
from roughdiffuse.quadrature import gauss_legendre
from roughdiffuse.simulate import layered

ALPHAS = (0.025, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0)
ETAS = (1.05, 1.15, 1.3, 1.5, 1.75, 2.0, 2.5, 3.0)
OUT = (Path(__file__).resolve().parent.parent / "src" / "roughdiffuse" / "data"
       / "coat_interface.npz")


def fit(distribution: str, table: dict[str, np.ndarray]) -> np.ndarray:
    """The coefficients of ``ms_ratio`` for ``distribution`` from ``table`` (this script's
    arrays): least squares (weight √μ E_ss, the reflectance each relative error multiplies,
    seen at cosine μ) of c = ΔE/E_ss, ΔE the walk's reflectance from above minus the
    single-scattering E_ss of ``interface_albedo``, in the monomials x^i α^j (1 − μ)^k of
    ``coated._FIT_POWERS`` (x = 1 − 1/η)."""
    d = coated.COAT_DISTRIBUTIONS.index(distribution)
    r = np.asarray(table["reflectance"], np.float64)[d, 0]
    e, a, m = (g.ravel() for g in np.meshgrid(table["etas"], table["alphas"], table["mu"],
                                              indexing="ij"))
    ess = coated.interface_albedo(np, m, e, a, distribution)
    y = (r.ravel() - ess) / ess
    x, u, w = 1.0 - 1.0 / e, 1.0 - m, np.sqrt(m) * ess
    cols = np.stack([x**i * a**j * u**k for i, j, k in coated._FIT_POWERS], axis=-1)
    return np.linalg.lstsq(cols * w[:, None], y * w, rcond=None)[0]


def _write(path: Path, table: dict[str, np.ndarray]) -> None:
    """``table`` with the fitted coefficients (``coef``, one row per distribution) to
    ``path``, whole or not at all."""
    coef = np.stack([fit(d, table) for d in coated.COAT_DISTRIBUTIONS])
    buf = io.BytesIO()
    np.savez_compressed(buf, **table, coef=coef)
    write_bytes(path, buf.getvalue())
    print(f"wrote {path} ({path.stat().st_size:,} bytes)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=40_000)
    ap.add_argument("--out", type=Path, default=OUT)
    ap.add_argument("--refit", action="store_true",
                    help="refit the coefficients of the table in --out, without the walk")
    args = ap.parse_args()
    if args.refit:
        with np.load(args.out) as t:
            table = {k: t[k] for k in t.files if k != "coef"}
        _write(args.out, table)
        return
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
    _write(args.out, {
        "reflectance": r.astype(np.float32), "mu": mu, "etas": np.array(ETAS),
        "alphas": np.array(ALPHAS), "samples": np.array(args.samples),
        "axes": np.array("distribution (ggx, beckmann), side (above, below), eta, alpha, mu")})

if __name__ == "__main__":
    main()
