"""Time the renderer: a 1024 x 1024 sphere (the issue's target: well under a second).

Run from the repository root::

    python bench/render_bench.py                  # sphere 1024², spp 1 and 4; vase 512²
    python bench/render_bench.py --repeat 9 --json bench/render_results.json

For each case: the first call (JAX tracing and compilation included) and the median, min and
max of ``--repeat`` warm calls of :func:`roughdiffuse.render.render` (the whole call: ray
set-up, intersection, the model's ``brdf_cosines`` under ``jax.jit``, supersample averaging,
copy back to NumPy). Also reported: million shaded samples per second.

``bench/run.py`` may import :func:`bench_render` and add its rows to its report.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

CASES: list[dict[str, Any]] = [
    {"name": "sphere, Oren-Nayar qualitative", "shape": "sphere", "size": 1024, "spp": 1},
    {"name": "sphere, Oren-Nayar qualitative", "shape": "sphere", "size": 1024, "spp": 4},
    {"name": "sphere, Oren-Nayar full", "shape": "sphere", "size": 1024, "spp": 4, "full": True},
    {"name": "vase (cast shadows), Oren-Nayar", "shape": "vase", "size": 512, "spp": 4},
]


def bench_render(repeat: int = 5, cases: list[dict[str, Any]] | None = None) -> list[dict]:
    """Time each case; returns one dict per case (seconds and Msamples/s)."""
    import roughdiffuse as rd
    from roughdiffuse.render import DistantLight, Sphere, SurfaceOfRevolution, render

    rows = []
    for case in cases or CASES:
        shape = Sphere() if case["shape"] == "sphere" else SurfaceOfRevolution()
        model = rd.OrenNayar(0.8, 0.3, "full" if case.get("full") else "qualitative")
        light = DistantLight(0.5, 0.3)
        size, spp = case["size"], case["spp"]

        def once(model=model, shape=shape, light=light, size=size, spp=spp) -> float:
            t0 = time.perf_counter()
            render(model, shape, light, size=size, samples_per_pixel=spp)
            return time.perf_counter() - t0

        first = once()
        times = [once() for _ in range(repeat)]
        med = statistics.median(times)
        rows.append(
            {
                **case,
                "first_s": first,
                "median_s": med,
                "min_s": min(times),
                "max_s": max(times),
                "msamples_per_s": size * size * spp / med / 1e6,
            }
        )
    return rows


def _table(rows: list[dict]) -> str:
    lines = [
        "| case | size | spp | first call (s) | median (s) | min–max (s) | Msamples/s |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for r in rows:
        lines.append(
            f"| {r['name']} | {r['size']}² | {r['spp']} | {r['first_s']:.2f} | "
            f"{r['median_s']:.3f} | {r['min_s']:.3f}–{r['max_s']:.3f} | "
            f"{r['msamples_per_s']:.1f} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="warm runs per case (default 5)")
    parser.add_argument("--json", metavar="FILE", help="also write the rows as JSON")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error("--repeat must be >= 1")
    rows = bench_render(args.repeat)
    print(_table(rows))
    print(f"\n{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.1f} at the end")
    if args.json:
        out = Path(args.json)
        fd, tmp = tempfile.mkstemp(dir=out.parent, suffix=".json")
        with os.fdopen(fd, "w") as fh:
            json.dump(rows, fh, indent=2)
        os.replace(tmp, out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
