"""Speed of the V-cavity solver (roughdiffuse.simulate): cavities per second, table times.

Run from the repository root::

    python bench/simulate_bench.py     # prints a table, writes bench/simulate_results.md
    python bench/simulate_bench.py --json bench/simulate_results.json

Measured:

* cavity evaluations per second, one bounce (closed form) and all bounces (radiosity, K = 16
  elements per facet, Richardson-extrapolated from K and 2K), for cavities that share one
  slope θa (as the surface quadrature calls them) and for cavities of all-different θa;
* surface BRDF evaluations per second with the default settings (those that give 1e-4, see
  docs/accuracy.md) for σ = 0.3 and 0.7, one bounce and all bounces, on random geometries;
* from those rates, the time of a 90 × 90 × 180 × 1 table (θi, θr, Δφ at 1°, one σ) on 2
  cores, assuming two worker processes scale linearly (the chunks are independent).

BLAS runs single-threaded here (set before NumPy is imported): the solver's matrices are small
(2K ≤ 256), and two BLAS threads per process on 2 shared cores ran it 3× slower. Dask workers
(``--workers``) get one BLAS thread each by default; for a single process, set
``OPENBLAS_NUM_THREADS=1`` yourself.

``bench/run.py`` may import :func:`bench_simulate` and add its rows to its report.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
TABLE_SIZE = 90 * 90 * 180


def _rate(fn, n: int, repeat: int) -> float:
    fn()  # warm-up
    best = math.inf
    for _ in range(repeat):
        t = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t)
    return n / best


def _dirs(rng, n):
    th = rng.uniform(0, 1.4, n)
    ph = rng.uniform(0, 2 * math.pi, n)
    return np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)


def bench_simulate(repeat: int = 3, n_surface: int = 48) -> list[dict]:
    """Time the cases; one dict per case with evaluations per second."""
    from roughdiffuse.simulate import Settings, brdf, cavity_radiance
    from roughdiffuse.simulate.cavity import InterreflectionSolver, _Facets

    rng = np.random.default_rng(0)
    rows = []
    n = 200_000
    ta = rng.uniform(0, 1.4, n)
    pa = rng.uniform(0, 2 * math.pi, n)
    wi, wo = _dirs(rng, n), _dirs(rng, n)
    r = _rate(lambda: cavity_radiance(ta, pa, wi, wo, 0.9, 1), n, repeat)
    rows.append({"case": "cavity, 1 bounce (closed form)", "per_second": r})

    n2 = 50_000
    l = tuple(wi[:n2, k] for k in range(3))
    v = tuple(wo[:n2, k] for k in range(3))
    for k in (16, 32):
        solver = InterreflectionSolver(0.8, 0.9, "all", k, True)

        def shared(solver=solver):
            f = _Facets(0.8, np.cos(pa[:n2]), np.sin(pa[:n2]), l, v, 0.9)
            return f.single + solver(f)

        rows.append(
            {
                "case": f"cavity, all bounces, K={k} (+2K), shared θa",
                "per_second": _rate(shared, n2, repeat),
            }
        )
    n3 = 2000
    r = _rate(lambda: cavity_radiance(ta[:n3], pa[:n3], wi[:n3], wo[:n3], 0.9, "all", 16), n3, 1)
    rows.append({"case": "cavity, all bounces, K=16 (+2K), distinct θa", "per_second": r})

    ti, tr = rng.uniform(0, 1.5, (2, n_surface))
    dp = rng.uniform(0, math.pi, n_surface)
    for sigma in (0.3, 0.7):
        for bounces in (1, "all"):
            rate = _rate(
                lambda s=sigma, b=bounces: brdf(ti, tr, dp, s, 0.9, b, Settings()), n_surface, 1
            )
            rows.append(
                {
                    "case": f"surface BRDF, σ={sigma}, bounces={bounces}",
                    "per_second": rate,
                    "table_90x90x180_hours_2_cores": TABLE_SIZE / rate / 2 / 3600,
                }
            )
    return rows


def markdown(rows: list[dict]) -> str:
    lines = [
        "# V-cavity solver speed (bench/simulate_bench.py)",
        "",
        f"Machine: {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
        f"Python {platform.python_version()}, NumPy {np.__version__}. Best of repeated runs; "
        "the machine is shared, so the figures are lower bounds of its speed.",
        "",
        "| case | evaluations / s | 90×90×180 table on 2 cores (h, extrapolated) |",
        "| --- | --- | --- |",
    ]
    for r in rows:
        t = r.get("table_90x90x180_hours_2_cores")
        lines.append(f"| {r['case']} | {r['per_second']:.4g} | {'' if t is None else f'{t:.3g}'} |")
    lines.append("")
    return "\n".join(lines)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument("--json", type=Path, help="also write the rows as JSON")
    p.add_argument("--output", type=Path, default=HERE / "simulate_results.md")
    args = p.parse_args()
    rows = bench_simulate(args.repeat)
    text = markdown(rows)
    print(text)
    tmp = args.output.with_suffix(".tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, args.output)
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
