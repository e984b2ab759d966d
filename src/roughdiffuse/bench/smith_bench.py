"""Speed of the Smith random walk (roughdiffuse.simulate.smith): path segments per second.

A segment is one ray from a height to the next intersection or out of the surface (the work
unit of Heitz et al. 2016's walk: one height sample, one visible-normal sample, one next-event
estimate and one cosine-lobe direction). Measured, all bounces at ρ = 1 (the longest walks),
48 random geometries, for Beckmann and GGX at α = 0.3 and 1.0, the two engines interleaved
run by run in the same process:

* the compiled walk (``engine="compiled"``, Numba) on 1 and on 2 threads (``workers``);
* the NumPy reference walk (``engine="numpy"``) with 1 and 2 workers (threads tracing
  batches at once; NumPy releases the GIL in its loops).

Besides wall-clock rates it records the process's CPU time (all threads): on a shared machine
the segments per CPU-second are the steadier number, and CPU time / 2 is about what an idle
2-core machine would take. The ratios compiled / NumPy compare runs of the same moment.

Usage::

    python -m roughdiffuse.bench.smith_bench                      # prints the table
    python -m roughdiffuse.bench.smith_bench --write RESULTS.md   # and replaces its section
    python bench/smith_bench.py --write     # from a checkout: its section of bench/RESULTS.md

``bench/run.py`` rewrites ``RESULTS.md`` whole: run this after it.
"""

from __future__ import annotations

import os

if __name__ == "__main__":  # one BLAS thread per process: the walk is element-wise NumPy
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import math  # noqa: E402
import platform  # noqa: E402
import time  # noqa: E402
from datetime import UTC, datetime  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from roughdiffuse.bench.timing import summary, write_section  # noqa: E402

CASES = (("beckmann", 0.3), ("beckmann", 1.0), ("ggx", 0.3), ("ggx", 1.0))
GEOMETRIES = 48
BEGIN = "<!-- smith_bench: begin -->"
END = "<!-- smith_bench: end -->"


def _geometries(n: int):
    rng = np.random.default_rng(0)
    return rng.uniform(0, 1.4, n), rng.uniform(0, 1.4, n), rng.uniform(0, 2 * math.pi, n)


VARIANTS = (("compiled", 1), ("compiled", 2), ("numpy", 1), ("numpy", 2))


def walk(
    dist: str, alpha: float, paths: int, seed: int, engine: str, workers: int
) -> tuple[int, float, float]:
    """(segments, wall seconds, CPU seconds) of one all-bounce walk, ``paths`` per geometry."""
    from roughdiffuse.simulate.smith import random_walk

    ti, tr, dp = _geometries(GEOMETRIES)
    t0, c0 = time.perf_counter(), time.process_time()
    r = random_walk(
        ti, tr, dp, alpha, 1.0, "all", dist, samples=paths, seed=seed, workers=workers,
        engine=engine,
    )
    return r.segments, time.perf_counter() - t0, time.process_time() - c0


def run(paths: int, repeat: int) -> list[dict]:
    rows = []
    for dist, alpha in CASES:
        wall: dict = {v: [] for v in VARIANTS}
        cpu: dict = {v: [] for v in VARIANTS}
        for engine, workers in VARIANTS:  # warm-up (and the compiled kernel's load)
            walk(dist, alpha, max(paths // 16, 16), 0, engine, workers)
        for r in range(repeat):
            order = VARIANTS[r % len(VARIANTS) :] + VARIANTS[: r % len(VARIANTS)]
            for engine, workers in order:
                seg, t, c = walk(dist, alpha, paths, r, engine, workers)
                wall[(engine, workers)].append(seg / t / 1e6)
                cpu[(engine, workers)].append(seg / c / 1e6)
        rows.append(
            {
                "case": f"{dist}, α = {alpha:g}",
                "segments_per_path": seg / (paths * GEOMETRIES),
                "wall": {v: summary(x) for v, x in wall.items()},
                "cpu": {v: summary(x) for v, x in cpu.items()},
            }
        )
    return rows


def _fmt(s: dict) -> str:
    return f"{s['median']:.2f} ({s['min']:.2f}–{s['max']:.2f})"


def markdown(rows: list[dict], paths: int) -> str:
    import numba

    cpu = platform.processor() or platform.machine()
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    lines = [
        BEGIN,
        "## Smith random walk",
        "",
        f"`python -m roughdiffuse.bench.smith_bench` on {datetime.now(UTC):%Y-%m-%d %H:%M} UTC, "
        f"{os.cpu_count()} cores ({cpu}, load average {load:.1f} at the end: shared), "
        f"NumPy {np.__version__}, Numba {numba.__version__}: "
        "`roughdiffuse.simulate.smith.random_walk`, "
        f"all bounces at ρ = 1, {GEOMETRIES} random geometries × {paths:,} paths, in million "
        "path segments per second, median of the runs (min–max); the compiled walk "
        "(`engine=\"compiled\"`) and the NumPy reference walk (`engine=\"numpy\"`) "
        "interleaved in the same run, each with 1 and 2 threads (`workers`). Wall-clock rates "
        "first, then segments per CPU-second (the process's CPU time, all threads: the "
        "steadier number on a shared machine).",
        "",
        "| case | segments per path | compiled, 1 thread | compiled, 2 threads "
        "| NumPy, 1 worker | NumPy, 2 workers | compiled / NumPy, 1 | compiled / NumPy, 2 |",
        "| --- | ---: | --- | --- | --- | --- | ---: | ---: |",
    ]
    for r in rows:
        w = r["wall"]
        lines.append(
            f"| {r['case']} | {r['segments_per_path']:.2f} | {_fmt(w[('compiled', 1)])} | "
            f"{_fmt(w[('compiled', 2)])} | {_fmt(w[('numpy', 1)])} | {_fmt(w[('numpy', 2)])} | "
            f"{w[('compiled', 1)]['median'] / w[('numpy', 1)]['median']:.0f} | "
            f"{w[('compiled', 2)]['median'] / w[('numpy', 2)]['median']:.0f} |"
        )
    lines += [
        "",
        "Per CPU-second (million segments per second of CPU time, all threads):",
        "",
        "| case | compiled, 1 thread | compiled, 2 threads | NumPy, 1 worker "
        "| NumPy, 2 workers | compiled / NumPy, 1 |",
        "| --- | --- | --- | --- | --- | ---: |",
    ]
    for r in rows:
        c = r["cpu"]
        lines.append(
            f"| {r['case']} | {_fmt(c[('compiled', 1)])} | {_fmt(c[('compiled', 2)])} | "
            f"{_fmt(c[('numpy', 1)])} | {_fmt(c[('numpy', 2)])} | "
            f"{c[('compiled', 1)]['median'] / c[('numpy', 1)]['median']:.0f} |"
        )
    lines.append(END)
    return "\n".join(lines)


def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    p = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0])
    p.add_argument("--paths", type=int, default=8192, help="paths per geometry (default 8192)")
    p.add_argument("--repeat", type=int, default=3)
    p.add_argument(
        "--write", metavar="RESULTS.md", help="replace (or append) this table's section there"
    )
    a = p.parse_args(argv)
    text = markdown(run(a.paths, a.repeat), a.paths)
    print(text)
    if a.write:
        write_section(Path(a.write), text, BEGIN, END)


if __name__ == "__main__":
    main()
