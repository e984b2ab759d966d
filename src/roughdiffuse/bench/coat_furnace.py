"""The white furnace of the layered walk's rough coat, the full grid:
``python bench/coat_furnace.py [--samples 3000000] [--write]``.

A white Lambertian base (ρ = 1) under a rough coat, no absorption: the directional albedo
(:func:`roughdiffuse.simulate.layered.directional_albedo`, the interface's own reflection
included) must be 1. For η in {1.1, 1.5, 2.5}, GGX and Beckmann, α in {0.1, 0.3, 0.6, 1.0},
θi in {0, 30, 60, 75, 85}°, with the multiple-scattering interface (the default) and, for
comparison, the single-scattering one (a tenth of the paths). Per row: the largest |A − 1|
over θi, the largest |A − 1| / standard error, the largest standard error. The check of
the target: |A − 1| < 0.2 % and < 4 standard errors everywhere (multiple scattering).

Prints Markdown; ``--write`` replaces the marked section of bench/RESULTS.md.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

import roughdiffuse as rd
from roughdiffuse.bench.layered_bench import _run_line
from roughdiffuse.bench.timing import write_section
from roughdiffuse.simulate import layered

BEGIN = "<!-- coat_furnace: begin -->"
END = "<!-- coat_furnace: end -->"
ETAS = (1.1, 1.5, 2.5)
ALPHAS = (0.1, 0.3, 0.6, 1.0)
THETA_DEG = (0.0, 30.0, 60.0, 75.0, 85.0)


def rows(samples: int) -> tuple[list[str], bool]:
    theta = np.radians(THETA_DEG)
    out, ok = [], True
    try:
        from tqdm import tqdm
    except ImportError:  # pragma: no cover - tqdm is a dependency
        def tqdm(x, **_):
            return x
    grid = [(d, e, a) for d in ("ggx", "beckmann") for e in ETAS for a in ALPHAS]
    for dist, eta, alpha in tqdm(grid, desc="furnace"):
        kw = dict(eta=eta, roughness=alpha, distribution=dist, return_stderr=True)
        t0 = time.process_time()
        a, se = layered.directional_albedo(theta, rd.Lambert(1.0), samples=samples, seed=11,
                                           **kw)
        cpu = time.process_time() - t0
        s = layered.directional_albedo(theta, rd.Lambert(1.0), samples=max(samples // 10, 2),
                                       seed=12, interface="single", **kw)[0]
        dev = np.abs(a - 1.0)
        z = dev / se
        good = bool(np.all(dev < 2e-3) and np.all(z < 4.0))
        ok &= good
        out.append(f"| {dist} | {eta} | {alpha} | {dev.max() * 100:.3f} % | {z.max():.2f} | "
                   f"{se.max() * 100:.3f} % | {'yes' if good else 'NO'} | "
                   f"{s.min():.3f} – {s.max():.3f} | {cpu:.0f} |")
    return out, ok


def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    ap = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0])
    ap.add_argument("--samples", type=int, default=3_000_000)
    ap.add_argument("--write", metavar="RESULTS.md", help="replace its section of this file")
    args = ap.parse_args(argv)
    lines, ok = rows(args.samples)
    text = "\n".join([
        BEGIN,
        _run_line(f"python bench/coat_furnace.py --samples {args.samples} --write")
        + f" White furnace (Lambert ρ = 1, no absorption) of the layered walk's rough coat, "
        f"θi in {THETA_DEG}°, {args.samples:,} paths per angle (multiple-scattering "
        "interface, the default) and a tenth of that for the single-scattering one; "
        f"every row within 0.2 % and 4 standard errors: {'yes' if ok else 'NO'}.",
        "",
        "| distribution | η | α | max abs(A − 1) | max z | max std. error | within | "
        "single interface: A | CPU s |",
        "| --- | ---: | ---: | ---: | ---: | ---: | --- | --- | ---: |",
        *lines,
        END,
    ])
    print(text, flush=True)
    if args.write:
        write_section(Path(args.write), text, BEGIN, END)


if __name__ == "__main__":
    main()
