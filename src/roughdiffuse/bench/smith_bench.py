"""Speed of the Smith random walk (roughdiffuse.simulate.smith): path segments per second.

A segment is one ray from a height to the next intersection or out of the surface (the work
unit of Heitz et al. 2016's walk: one height sample, one visible-normal sample, one next-event
estimate and one cosine-lobe direction). Measured, all bounces at ρ = 1 (the longest walks),
48 random geometries, for Beckmann and GGX at α = 0.3 and 1.0:

* one worker (NumPy's element-wise loops use one core);
* two workers (``random_walk(..., workers=2)``: threads tracing batches at once, NumPy
  releases the GIL in its loops; the values are the same as with one);
* the reference, measured in the same run and interleaved with the walks: NumPy's default
  generator drawing the same number of uniform doubles as there were segments, so the
  ratio says what a segment costs in units of one random draw on this machine.

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

from roughdiffuse.bench.timing import summary, write_atomic  # noqa: E402

CASES = (("beckmann", 0.3), ("beckmann", 1.0), ("ggx", 0.3), ("ggx", 1.0))
GEOMETRIES = 48
BEGIN = "<!-- smith_bench: begin -->"
END = "<!-- smith_bench: end -->"


def _geometries(n: int):
    rng = np.random.default_rng(0)
    return rng.uniform(0, 1.4, n), rng.uniform(0, 1.4, n), rng.uniform(0, 2 * math.pi, n)


def walk(dist: str, alpha: float, paths: int, seed: int, workers: int = 1) -> tuple[int, float]:
    """(segments, seconds) of one all-bounce walk with ``paths`` paths per geometry."""
    from roughdiffuse.simulate.smith import random_walk

    ti, tr, dp = _geometries(GEOMETRIES)
    t0 = time.perf_counter()
    r = random_walk(
        ti, tr, dp, alpha, 1.0, "all", dist, samples=paths, seed=seed, workers=workers
    )
    return r.segments, time.perf_counter() - t0


def draws(count: int) -> float:
    """Seconds to draw ``count`` uniform doubles (NumPy default generator, 2^17 at a time)."""
    rng = np.random.default_rng(1)
    t0 = time.perf_counter()
    left = count
    while left > 0:
        rng.random(min(left, 1 << 17))
        left -= 1 << 17
    return time.perf_counter() - t0


def run(paths: int, repeat: int) -> list[dict]:
    rows = []
    for dist, alpha in CASES:
        one, two, ref = [], [], []
        walk(dist, alpha, max(paths // 8, 16), 0)  # warm-up
        for r in range(repeat):
            seg, t = walk(dist, alpha, paths, r)
            one.append(seg / t / 1e6)
            seg2, t2 = walk(dist, alpha, paths, r, workers=2)
            two.append(seg2 / t2 / 1e6)
            ref.append(seg / draws(seg) / 1e6)
        rows.append(
            {
                "case": f"{dist}, α = {alpha:g}",
                "segments": seg,
                "segments_per_path": seg / (paths * GEOMETRIES),
                "one": summary(one),
                "two": summary(two),
                "draws": summary(ref),
            }
        )
    return rows


def _fmt(s: dict) -> str:
    return f"{s['median']:.2f} ({s['min']:.2f}–{s['max']:.2f})"


def markdown(rows: list[dict], paths: int) -> str:
    cpu = platform.processor() or platform.machine()
    lines = [
        BEGIN,
        "## Smith random walk",
        "",
        f"`python -m roughdiffuse.bench.smith_bench` on {datetime.now(UTC):%Y-%m-%d %H:%M} UTC, "
        f"{os.cpu_count()} cores ({cpu}), NumPy {np.__version__}: "
        "`roughdiffuse.simulate.smith.random_walk`, "
        f"all bounces at ρ = 1, {GEOMETRIES} random geometries × {paths:,} paths, in million "
        "path segments per second, median of the runs (min–max). One worker; two workers "
        "(threads, `workers=2`, the same values); and, measured in the same run, NumPy's "
        "default generator drawing as many uniform doubles as there were "
        "segments (a segment's cost in random draws = draws / segments).",
        "",
        "| case | segments per path | 1 worker, M segments/s | 2 workers, M segments/s "
        "| 2 / 1 | M draws/s | draws / segments (1 worker) |",
        "| --- | ---: | --- | --- | ---: | --- | ---: |",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['segments_per_path']:.2f} | {_fmt(r['one'])} | "
            f"{_fmt(r['two'])} | {r['two']['median'] / r['one']['median']:.2f} | "
            f"{_fmt(r['draws'])} | {r['draws']['median'] / r['one']['median']:.0f} |"
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
        path = Path(a.write)
        old = path.read_text(encoding="utf-8") if path.exists() else ""
        if BEGIN in old and END in old:
            new = old[: old.index(BEGIN)] + text + old[old.index(END) + len(END) :]
        else:
            new = old.rstrip("\n") + "\n\n" + text + "\n"
        write_atomic(path, new)


if __name__ == "__main__":
    main()
