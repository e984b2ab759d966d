"""Time fitting (ρ, σ) to a one-megapixel image (the issue's target: under 2 seconds).

Run from the repository root::

    python bench/fit_bench.py                   # 3 cases, 5 warm runs each
    python bench/fit_bench.py --repeat 9 --json bench/fit_results.json

The image: a sphere seen along −z under a light at 30°, 1200 × 1200 pixels, normals from the
exact formula n = (x, y, √(1 − x² − y²)), radiance from the model's own ``radiance`` with 1%
Gaussian noise, so that more than 10^6 pixels see both the light and the viewer. For each case
it reports the first call (JAX tracing and compilation of the residual, its Jacobian and the
normal equations included) and the median, min and max of ``--repeat`` warm calls of
:func:`roughdiffuse.fit.fit` on ready :class:`~roughdiffuse.fit.Measurements`; and, once, the
time to build those measurements from the image and its normal map.

``bench/run.py`` may import :func:`bench_fit` and add its rows to its report.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

TARGET_S = 2.0
SIZE = 1200

CASES: list[dict[str, Any]] = [
    {
        "name": "Oren-Nayar qualitative, absolute noise",
        "variant": "qualitative",
        "noise": "absolute",
    },
    {
        "name": "Oren-Nayar qualitative, relative noise",
        "variant": "qualitative",
        "noise": "relative",
    },
    {"name": "Oren-Nayar full, relative noise", "variant": "full", "noise": "relative"},
]


def sphere_image(variant: str, size: int = SIZE, seed: int = 0) -> tuple[Any, ...]:
    """(image, normals, light, view) of a noisy Oren–Nayar sphere (ρ = 0.7, σ = 0.4)."""
    import numpy as np

    import roughdiffuse as rd

    c = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(c, -c)
    r2 = x * x + y * y
    inside = r2 < 1
    n = np.stack([x, y, np.sqrt(np.clip(1 - r2, 0, 1))], axis=-1) * inside[..., None]
    light = rd.spherical_to_vector(math.radians(30.0), 0.0)
    view = np.array([0.0, 0.0, 1.0])
    img = np.zeros((size, size))
    img[inside] = np.asarray(rd.OrenNayar(0.7, 0.4, variant).radiance(n[inside], light, view))
    rng = np.random.default_rng(seed)
    img *= 1 + 0.01 * rng.standard_normal(img.shape)
    return img.astype(np.float32), n, light, view


def bench_fit(repeat: int = 5, cases: list[dict[str, Any]] | None = None) -> list[dict]:
    """Time each case; returns one dict per case (seconds, pixels, fitted values)."""
    import roughdiffuse as rd
    from roughdiffuse.fit import fit, image_measurements

    rows = []
    for case in cases or CASES:
        img, n, light, view = sphere_image(case["variant"])
        t0 = time.perf_counter()
        data = image_measurements(img, n, light, view)
        prep = time.perf_counter() - t0

        def once(data: Any = data, case: dict[str, Any] = case) -> Any:
            return fit(rd.OrenNayar, data, fixed={"variant": case["variant"]}, noise=case["noise"])

        t0 = time.perf_counter()
        result = once()
        first = time.perf_counter() - t0
        times = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            result = once()
            times.append(time.perf_counter() - t0)
        rows.append(
            {
                "name": case["name"],
                "pixels": data.size,
                "image": f"{SIZE}x{SIZE}",
                "prepare_s": prep,
                "first_s": first,
                "median_s": statistics.median(times),
                "min_s": min(times),
                "max_s": max(times),
                "albedo": float(result.values[0]),
                "albedo_err": float(result.errors[0]),
                "sigma": float(result.values[1]),
                "sigma_err": float(result.errors[1]),
                "target_s": TARGET_S,
                "pass": statistics.median(times) < TARGET_S,
            }
        )
    return rows


def table(rows: list[dict]) -> str:
    """Markdown table of :func:`bench_fit` rows."""
    lines = [
        "| case | fitted pixels | build data (s) | first fit (s) | warm fit median (min–max) s "
        "| ρ ± err | σ ± err | < 2 s |",
        "| --- | ---: | ---: | ---: | --- | --- | --- | --- |",
    ]
    for r in rows:
        lines.append(
            f"| {r['name']} | {r['pixels']:,} | {r['prepare_s']:.2f} | {r['first_s']:.2f} | "
            f"{r['median_s']:.2f} ({r['min_s']:.2f}–{r['max_s']:.2f}) | "
            f"{r['albedo']:.5f} ± {r['albedo_err']:.1e} | {r['sigma']:.5f} ± "
            f"{r['sigma_err']:.1e} | {'yes' if r['pass'] else 'NO'} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="warm runs per case (default 5)")
    parser.add_argument("--json", type=Path, help="also write the rows as JSON (atomically)")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error("--repeat must be >= 1")
    rows = bench_fit(args.repeat)
    print(table(rows))
    if args.json:
        fd, tmp = tempfile.mkstemp(dir=args.json.parent or ".", suffix=".json")
        with os.fdopen(fd, "w") as fh:
            json.dump(rows, fh, indent=2)
        os.replace(tmp, args.json)
    return 0 if all(r["pass"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
