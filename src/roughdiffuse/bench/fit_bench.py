"""Time fitting (ρ, σ) to a one-megapixel image (the target: under 2 seconds), against
a plain SciPy baseline timed in the same run.

``roughdiffuse bench`` (:mod:`roughdiffuse.bench.run`) runs :func:`bench_fit` and puts its rows
in ``RESULTS.md``; on its own::

    python -m roughdiffuse.bench.fit_bench      # 3 cases, 5 warm runs each; prints the table
    python -m roughdiffuse.bench.fit_bench --size 200 --repeat 1 --json /tmp/fit.json

The image: a sphere seen along −z under a light at 30°, 1200 × 1200 pixels, normals from the
exact formula n = (x, y, √(1 − x² − y²)), radiance from the model's own ``radiance`` with 1%
Gaussian noise, so that more than 10^6 pixels see both the light and the viewer. For each case:

* ``ours`` — :func:`roughdiffuse.fit.fit` on ready :class:`~roughdiffuse.fit.Measurements`:
  the first call (JAX tracing and compilation of the residual, its Jacobian and the normal
  equations included), then the median, min and max of ``--repeat`` warm calls;
* ``scipy`` — the simplest honest baseline: :func:`scipy.optimize.least_squares` (``trf``,
  the same bounds, starting at the centre of the bounds, which is ``fit``'s first start) on
  the same pixels, residuals from ``model.radiance`` on NumPy arrays, default two-point
  finite-difference Jacobian. With relative noise it reweights as ``fit`` does (weights
  1/data, then 1/model of the previous round, clipped to [1/(2 data), 2/data], until the
  parameters move by less than 1e-7).

Both are timed interleaved, run by run (:func:`timing.interleaved`); reported: seconds,
the ratio scipy/ours of the medians, and both fitted (ρ, σ). Also, once, the time to build the
measurements from the image and its normal map.
"""

from __future__ import annotations

import argparse
import functools
import json
import math
import sys
from pathlib import Path
from typing import Any

from .timing import interleaved, summary, timed, write_atomic

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


def scipy_fit(
    variant: str,
    noise: str,
    normals: Any,
    light: Any,
    view: Any,
    value: Any,
    bounds: Any,
) -> Any:
    """The baseline: ``scipy.optimize.least_squares`` on residuals of ``model.radiance``.

    Parameters
    ----------
    variant, noise : str
        Oren–Nayar variant and noise model ("absolute" or "relative").
    normals : ndarray (N, 3)
        World normals of the fitted pixels.
    light, view : ndarray (3,)
        Unit directions (irradiance 1).
    value : ndarray (N,)
        The pixels' radiances.
    bounds : ndarray (2, 2)
        (low, high) of ρ and σ.

    Returns
    -------
    ndarray (2,)
        Fitted (ρ, σ).
    """
    import numpy as np
    from scipy.optimize import least_squares

    import roughdiffuse as rd

    def model(x: np.ndarray) -> np.ndarray:
        return np.asarray(rd.OrenNayar(x[0], x[1], variant).radiance(normals, light, view))

    x = bounds.mean(axis=1)
    weights = np.ones_like(value) if noise == "absolute" else 1.0 / value
    for _ in range(8 if noise == "relative" else 1):
        w = weights
        r = least_squares(
            lambda p, w=w: (model(p) - value) * w,
            x,
            bounds=(bounds[:, 0], bounds[:, 1]),
            x_scale="jac",
            method="trf",
        )
        moved = np.max(np.abs(r.x - x))
        x = r.x
        if noise == "relative":
            weights = 1.0 / np.clip(model(x), 0.5 * value, 2.0 * value)
            if moved < 1e-7:
                break
    return x


def bench_fit(
    repeat: int = 5, cases: list[dict[str, Any]] | None = None, size: int = SIZE
) -> list[dict[str, Any]]:
    """Time each case, ours against the SciPy baseline; one dict per case.

    Parameters
    ----------
    repeat : int
        Warm timed runs of each (after one untimed first call).
    cases : list of dict, optional
        Default :data:`CASES`.
    size : int
        Image side in pixels (1200: 1.05 million fitted pixels).
    """
    import numpy as np

    import roughdiffuse as rd
    from roughdiffuse.fit import DEFAULT_BOUNDS, fit, image_measurements

    box = np.array([DEFAULT_BOUNDS["albedo"], DEFAULT_BOUNDS["sigma"]], dtype=np.float64)
    rows = []
    for case in cases or CASES:
        img, n, light, view = sphere_image(case["variant"], size)
        data, prep = timed(
            lambda img=img, n=n, light=light, view=view: image_measurements(img, n, light, view)
        )
        normals = n.reshape(-1, 3)[data.pixels]
        value = np.asarray(data.value, dtype=np.float64)

        def ours(data: Any = data, case: dict[str, Any] = case) -> Any:
            return fit(rd.OrenNayar, data, fixed={"variant": case["variant"]}, noise=case["noise"])

        baseline = functools.partial(
            scipy_fit, case["variant"], case["noise"], normals, light, view, value, box
        )

        result, first = timed(ours)
        base_x, base_first = timed(baseline)
        times = interleaved({"ours": ours, "scipy": baseline}, repeat)
        t_ours, t_base = summary(times["ours"]), summary(times["scipy"])
        rows.append(
            {
                "name": case["name"],
                "pixels": data.size,
                "image": f"{size}x{size}",
                "prepare_s": prep,
                "first_s": first,
                "ours_s": t_ours,
                "scipy_first_s": base_first,
                "scipy_s": t_base,
                "scipy_over_ours": t_base["median"] / t_ours["median"],
                "albedo": float(result.values[0]),
                "albedo_err": float(result.errors[0]),
                "sigma": float(result.values[1]),
                "sigma_err": float(result.errors[1]),
                "scipy_albedo": float(base_x[0]),
                "scipy_sigma": float(base_x[1]),
                "max_abs_difference_vs_scipy": float(np.max(np.abs(result.values - base_x))),
                "target_s": TARGET_S,
                "pass": t_ours["median"] < TARGET_S,
            }
        )
        print(
            f"fit: {rows[-1]['name']}: ours {t_ours['median']:.2f} s, scipy "
            f"{t_base['median']:.2f} s",
            flush=True,
        )
    return rows


def table(rows: list[dict[str, Any]]) -> str:
    """Markdown table of :func:`bench_fit` rows."""
    lines = [
        "| case | fitted pixels | build data (s) | first fit (s) | warm fit, median (min–max) s "
        "| SciPy baseline, median (min–max) s | SciPy / ours | ρ ± err | σ ± err "
        "| SciPy ρ, σ | < 2 s |",
        "| --- | ---: | ---: | ---: | --- | --- | ---: | --- | --- | --- | --- |",
    ]
    for r in rows:
        o, b = r["ours_s"], r["scipy_s"]
        lines.append(
            f"| {r['name']} | {r['pixels']:,} | {r['prepare_s']:.2f} | {r['first_s']:.2f} | "
            f"{o['median']:.2f} ({o['min']:.2f}–{o['max']:.2f}) | "
            f"{b['median']:.2f} ({b['min']:.2f}–{b['max']:.2f}) | {r['scipy_over_ours']:.1f} | "
            f"{r['albedo']:.5f} ± {r['albedo_err']:.1e} | {r['sigma']:.5f} ± "
            f"{r['sigma_err']:.1e} | {r['scipy_albedo']:.5f}, {r['scipy_sigma']:.5f} | "
            f"{'yes' if r['pass'] else 'NO'} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """``python bench/fit_bench.py [--repeat N] [--size PIXELS] [--json FILE]``."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeat", type=int, default=5, help="warm runs per case (default 5)")
    parser.add_argument("--size", type=int, default=SIZE, help=f"image side (default {SIZE})")
    parser.add_argument("--json", type=Path, help="also write the rows as JSON (atomically)")
    args = parser.parse_args(argv)
    if args.repeat < 1:
        parser.error("--repeat must be >= 1")
    if args.size < 16:
        parser.error("--size must be >= 16")
    rows = bench_fit(args.repeat, size=args.size)
    print(table(rows))
    if args.json:
        write_atomic(args.json, json.dumps(rows, indent=1) + "\n")
    return 0 if all(r["pass"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
