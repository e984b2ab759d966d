"""Benchmark: rough photometric stereo against a per-pixel SciPy loop.

An object of about a million pixels (a sphere rendered by roughdiffuse's renderer, full
Oren–Nayar, σ = 0.5, ρ = 0.7) under 8 lights is fitted by :func:`roughdiffuse.stereo.rough`
(batched Levenberg–Marquardt, one σ for the object; first call with compilation, then warm).
The reference is what a researcher writes without it: ``scipy.optimize.least_squares`` per
pixel on the same residual, evaluated with NumPy (normal as two angles, albedo, σ per pixel),
timed on a random subset of pixels and extrapolated. Both are timed in the same run; the
section "Photometric stereo" of ``bench/RESULTS.md`` is rewritten::

    python bench/stereo_bench.py [--size 1152] [--subset 200] [--no-write]

``--size 400`` (about 0.1 Mpx) is a quick check. The machine may be shared: each step is
also timed in CPU seconds of this process (all its threads), and the load average is noted.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import time
from pathlib import Path

import numpy as np

import roughdiffuse as rd
from roughdiffuse import stereo
from roughdiffuse.io.atomic import write_text
from roughdiffuse.render import Sphere

HERE = Path(__file__).resolve().parent


def scipy_loop(data: stereo.StereoInput, start: stereo.LambertianResult, idx: np.ndarray) -> float:
    """Seconds to fit the pixels ``idx`` one by one with SciPy (4 parameters each)."""
    from scipy.optimize import least_squares

    obs = data.images[:, data.mask, 0]
    w = stereo.observation_weights(data)
    l = data.directions

    def residual(x: np.ndarray, k: int) -> np.ndarray:
        th, ph, rho, sig = x
        n = np.array([math.sin(th) * math.cos(ph), math.sin(th) * math.sin(ph), math.cos(th)])
        m = rd.OrenNayar(rho, sig, "full")
        mu = l @ n
        f = m.brdf_cosines(mu, np.full_like(mu, n[2]), l[:, 2])
        return (f * np.maximum(mu, 0) - obs[:, k]) * w[:, k]

    t = time.perf_counter()
    for k in idx:
        n = start.normals[k]
        x0 = [math.acos(min(max(n[2], -1), 1)), math.atan2(n[1], n[0]), start.albedo[k, 0], 0.3]
        least_squares(
            residual,
            x0,
            args=(k,),
            bounds=([0, -4 * math.pi, 0, 0], [math.pi / 2, 4 * math.pi, 1, math.pi / 2]),
        )
    return time.perf_counter() - t


def _row(name: str, wall: float, cpu: float, pixels: int, digits: int) -> str:
    per = 1e6 / pixels
    return (
        f"| {name} | {wall:.{digits}f} | {wall * per:.{digits}f} | {cpu:.{digits}f} | "
        f"{cpu * per:.{digits}f} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=1152, help="image side (1152² ≈ 1 Mpx)")
    parser.add_argument("--subset", type=int, default=200, help="pixels fitted by SciPy")
    parser.add_argument("--no-write", action="store_true", help="print, do not write RESULTS.md")
    args = parser.parse_args()
    model = rd.OrenNayar(0.7, 0.5, "full")
    data, normals = stereo.render_stereo(model, Sphere(), stereo.default_lights(8), args.size)
    pixels = int(data.mask.sum())
    load = os.getloadavg()[0]
    t, c = time.perf_counter(), time.process_time()
    lam = stereo.lambertian(data)
    t_lam, c_lam = time.perf_counter() - t, time.process_time() - c
    times, cpu = [], []
    for _ in range(2):
        t, c = time.perf_counter(), time.process_time()
        res = stereo.rough(data, rd.OrenNayar(variant="full"), start=lam)
        times.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    load = max(load, os.getloadavg()[0])
    err = float(np.nanmean(stereo.angular_error(res.normals, normals[data.mask])))
    rng = np.random.default_rng(0)
    idx = rng.choice(pixels, size=min(args.subset, pixels), replace=False)
    c = time.process_time()
    t_sub = scipy_loop(data, lam, idx)
    c_scipy = (time.process_time() - c) / len(idx) * pixels
    t_scipy = t_sub / len(idx) * pixels
    cores = len(os.sched_getaffinity(0))
    lines = [
        "## Photometric stereo",
        "",
        f"`python bench/stereo_bench.py` ({cores} cores, load average up to {load:.1f} during "
        f"the run, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}): a {args.size} × "
        f"{args.size} sphere, {pixels:,} object pixels, 8 images, full Oren–Nayar (σ = 0.5), "
        "float32 fit.",
        "",
        "| step | seconds | per Mpx | CPU seconds | CPU per Mpx |",
        "| --- | ---: | ---: | ---: | ---: |",
        _row("Lambertian least squares (start)", t_lam, c_lam, pixels, 2),
        _row("rough fit, first call (compiles)", times[0], cpu[0], pixels, 1),
        _row("rough fit, warm", times[1], cpu[1], pixels, 1),
        _row(
            f"SciPy `least_squares` per pixel ({len(idx)} pixels, extrapolated)",
            t_scipy,
            c_scipy,
            pixels,
            0,
        ),
        "",
        f"Warm fit {t_scipy / times[1]:.0f}× faster than the per-pixel SciPy loop "
        f"({c_scipy / cpu[1]:.0f}× in CPU time); "
        f"{res.iterations} iterations, fitted σ = {res.roughness:.5f}, mean angular error "
        f"{err:.3f}° (noise-free images).",
        "",
    ]
    text = "\n".join(lines)
    print(text)
    if args.no_write:
        return
    replace_section(HERE / "RESULTS.md", "## Photometric stereo", text)


def replace_section(path: Path, heading: str, text: str) -> None:
    """Replace the section under ``heading`` (to the next ``## `` heading) of ``path`` by
    ``text``, or add it at the end; written whole or not at all."""
    old = path.read_text(encoding="utf-8") if path.exists() else "# Benchmarks\n\n"
    pattern = re.compile(re.escape(heading) + r"\n.*?(?=\n## |\Z)", re.S)
    new = (
        pattern.sub(lambda _: text.rstrip("\n") + "\n", old)
        if pattern.search(old)
        else old.rstrip("\n") + "\n\n" + text
    )
    write_text(path, new)


if __name__ == "__main__":
    main()
