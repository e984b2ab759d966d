"""Speed of the coat: the layered walk and ``Coated``'s closed form.

1. The layered walk (:func:`roughdiffuse.simulate.layered.brdf`): path segments (arrivals on
   the base, and facet events of the multiple-scattering interface) per CPU second
   (``time.process_time``, every thread counted), compiled (a rough coat with each interface:
   ``"multiple"``, the default, and ``"single"``) and NumPy (the single interface), for a
   Lambertian base under a smooth coat, Oren–Nayar and EON bases under rough GGX coats and
   an EON base under a rough Beckmann coat; beside it, in the same run, the compiled Smith
   walk's segments per CPU second as the reference, and the ratio to it
   (``--walk-only``: this part alone).
2. ``Coated`` over Lambert with a rough GGX and a rough Beckmann coat: the default call
   ``model.brdf(wi, wo)`` (compiled fast path) against the C loop of the same formula
   (``rd_coated_lambert_*`` of ``c/kernels.c``, the same node rules and fitted multiple
   scattering, compiled as :func:`.run.build_c` compiles it), interleaved, on float64 (N, 3)
   arrays; the ratio default/C is what counts on a shared machine (``--coated-only``: this
   part alone).

Prints Markdown for ``RESULTS.md``; ``--write RESULTS.md`` replaces each table's marked
section there. Usage::

    python -m roughdiffuse.bench.layered_bench [--rows-log2 20] [--repeat 5] [--write FILE]
    python bench/layered_bench.py --write   # from a checkout: bench/RESULTS.md
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

import roughdiffuse as rd
from roughdiffuse.simulate import layered, smith

from .run import C_KERNELS, build_c, c_brdf_caller
from .timing import write_section

WALK_CASES = (
    ("Lambert ρ = 0.8, smooth coat", rd.Lambert(0.8), 0.0, "ggx"),
    ("Oren–Nayar full ρ = 0.8, σ = 0.3, GGX α = 0.3 coat", rd.OrenNayar(0.8, 0.3, "full"), 0.3,
     "ggx"),
    ("EON ρ = 0.8, r = 0.5, GGX α = 0.3 coat", rd.EON(0.8, 0.5), 0.3, "ggx"),
    ("EON ρ = 0.8, r = 0.5, Beckmann α = 0.3 coat", rd.EON(0.8, 0.5), 0.3, "beckmann"),
)


INTERFACES = ("multiple", "single")
"""The rough interfaces timed: the exact multiple-scattering microsurface (the default) and
the single-scattering one (pbrt-v4's and Mitsuba's)."""
INTERFACE_LABELS = {"multiple": "multiple-scattering interface", "single": "single interface"}


def _walk_rate(engine: str, base, alpha: float, dist: str, samples: int,
               interface: str = "multiple") -> tuple[int, float]:
    """(segments, CPU seconds) of one call of the layered walk on 4 geometries."""
    g = np.radians([0.0, 30.0, 60.0, 80.0])
    kw = dict(roughness=alpha, distribution=dist, engine=engine, interface=interface)
    t0 = time.process_time()
    _, seg = layered.brdf(g, g[::-1], 1.0, base, samples=samples, return_segments=True, **kw)
    return seg, time.process_time() - t0


def _smith_rate(samples: int) -> tuple[int, float]:
    g = np.radians([0.0, 30.0, 60.0, 80.0])
    t0 = time.process_time()
    r = smith.random_walk(g, g[::-1], 1.0, 0.5, 1.0, samples=8 * samples)
    return r.segments, time.process_time() - t0


def walk_rates(samples: int, repeat: int = 3) -> list[str]:
    """Segments per CPU second of the layered walk, compiled and NumPy, and of the compiled
    Smith walk in the same run (the reference: the ratio is what a shared machine keeps).
    The compiled walks run ``repeat`` rounds, interleaved, each keeping its fastest round
    (the least disturbed by other jobs); the NumPy walk one round."""
    smith.random_walk(0.3, 0.3, 0.0, 0.5, 1.0, samples=2_000)  # compile / load
    for _, base, alpha, dist in WALK_CASES:
        for interface in INTERFACES:
            layered.brdf(0.3, 0.3, 0.0, base, samples=2_000, roughness=alpha,
                         distribution=dist, engine="compiled", interface=interface)
    best: dict[str, tuple[int, float]] = {}

    def keep(key: str, seg_cpu: tuple[int, float]) -> None:
        old = best.get(key)
        if old is None or seg_cpu[0] / seg_cpu[1] > old[0] / old[1]:
            best[key] = seg_cpu

    for _ in range(repeat):
        keep("smith", _smith_rate(samples))
        for label, base, alpha, dist in WALK_CASES:
            for interface in INTERFACES if alpha > 0 else ("multiple",):
                keep(f"{label} {interface}",
                     _walk_rate("compiled", base, alpha, dist, samples, interface))
    seg, cpu = best["smith"]
    smith_rate = seg / cpu
    lines = [f"| Smith walk (compiled, reference), α = 0.5 | {seg:,} | {cpu:.2f} | "
             f"{smith_rate / 1e6:.2f} | 1 |"]
    for label, base, alpha, dist in WALK_CASES:
        for interface in INTERFACES if alpha > 0 else ("multiple",):
            seg, cpu = best[f"{label} {interface}"]
            kind = INTERFACE_LABELS[interface] if alpha > 0 else "smooth"
            lines.append(f"| layered walk (compiled, {kind}), {label} | {seg:,} | {cpu:.2f} | "
                         f"{seg / cpu / 1e6:.2f} | {seg / cpu / smith_rate:.2f} |")
        n = max(samples // 5, 2_000)
        layered.brdf(0.3, 0.3, 0.0, base, samples=200, roughness=alpha, distribution=dist,
                     engine="numpy", interface="single")
        seg, cpu = _walk_rate("numpy", base, alpha, dist, n, "single")
        lines.append(f"| layered walk (numpy, single interface), {label} | {seg:,} | "
                     f"{cpu:.2f} | {seg / cpu / 1e6:.2f} | {seg / cpu / smith_rate:.2f} |")
    return lines


BEGIN = "<!-- layered_bench walk: begin -->"
END = "<!-- layered_bench walk: end -->"


def _run_line(command: str) -> str:
    """``command`` with the date, the machine and its load, NumPy's and Numba's versions: the
    opening of each table's paragraph."""
    import os
    import platform
    from datetime import UTC, datetime

    import numba

    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    return (
        f"`{command}` on {datetime.now(UTC):%Y-%m-%d %H:%M} UTC, {os.cpu_count()} cores "
        f"({platform.processor() or platform.machine()}, load average {load:.1f} at the end: "
        f"shared), NumPy {np.__version__}, Numba {numba.__version__}."
    )


def walk_markdown(samples: int, repeat: int) -> str:
    """The walk table with its command, date and machine, between :data:`BEGIN` and
    :data:`END` (the part of bench/RESULTS.md that ``--write`` replaces)."""
    import numba

    rows = walk_rates(samples, repeat)
    threads = numba.get_num_threads()
    command = (f"python -m roughdiffuse.bench.layered_bench --walk-only --samples {samples} "
               f"--repeat {repeat} --threads {threads}")
    return "\n".join([
        BEGIN,
        _run_line(command) + " Path segments (arrivals on the base, and each facet event of "
        f"the multiple-scattering interface) per CPU second on {threads} Numba thread(s), "
        "every thread counted "
        "(`time.process_time`), 4 "
        f"geometries × {samples:,} paths; the compiled walks interleaved over {repeat} rounds, "
        "each its fastest round; the NumPy walk one round of a fifth of the paths; the last "
        "column is the ratio to the compiled Smith walk measured in the same run:",
        "",
        "| walk | segments | CPU s | M segments / CPU s | / Smith walk |",
        "| --- | ---: | ---: | ---: | ---: |",
        *rows,
        END,
    ])


def coated_vs_c(rows_log2: int, repeat: int) -> list[str]:
    """``Coated(Lambert(0.8), 1.5, 0.3, dist)``'s default call against the C loop, for GGX
    and Beckmann, interleaved: one Markdown row each (the medians' ratio default/C)."""
    lib, note = build_c(Path(tempfile.mkdtemp()))
    if lib is None:
        return [note]
    n = 1 << rows_log2
    rng = np.random.default_rng(3)
    wi = rng.normal(size=(n, 3))
    wo = rng.normal(size=(n, 3))
    wi[:, 2], wo[:, 2] = np.abs(wi[:, 2]), np.abs(wo[:, 2])
    out = np.empty(n)
    lines = []
    for dist in ("ggx", "beckmann"):
        model = rd.Coated(rd.Lambert(0.8), 1.5, 0.3, dist)
        c_call = c_brdf_caller(lib, *C_KERNELS["coated"](model), np.float64)

        def run_c(c_call=c_call) -> None:
            c_call(wi, wo, out)

        for _ in range(3):
            f = np.asarray(model.brdf(wi, wo))  # builds the compiled kernel
        run_c()
        err = float(np.max(np.abs(out - f) / np.maximum(np.abs(f), 1e-12)))
        times: dict[str, list[float]] = {"default": [], "c": []}
        for _ in range(repeat):
            for key, fn in (("default", lambda m=model: m.brdf(wi, wo)), ("c", run_c)):
                t0 = time.perf_counter()
                fn()
                times[key].append(time.perf_counter() - t0)
        med = {key: float(np.median(v)) for key, v in times.items()}
        lines.append(
            f"| 2^{rows_log2} | float64 | Coated(Lambert 0.8, η = 1.5, {dist_label(dist)} "
            f"α = 0.3) | {n / med['default'] / 1e6:.1f} | {n / med['c'] / 1e6:.1f} | "
            f"{med['c'] / med['default']:.2f} | {err:.1e} |")
    return lines


def dist_label(dist: str) -> str:
    return {"ggx": "GGX", "beckmann": "Beckmann"}[dist]


C_BEGIN = "<!-- layered_bench coated: begin -->"
C_END = "<!-- layered_bench coated: end -->"


def coated_markdown(rows_log2: int, repeat: int) -> str:
    """The closed form's table against C with its command, date and machine, between
    :data:`C_BEGIN` and :data:`C_END` (the part of bench/RESULTS.md that ``--write``
    replaces)."""
    import numba

    rows = coated_vs_c(rows_log2, repeat)
    command = (f"python -m roughdiffuse.bench.layered_bench --coated-only --rows-log2 "
               f"{rows_log2} --repeat {repeat}")
    return "\n".join([
        C_BEGIN,
        _run_line(command) + " `Coated` over Lambert "
        "with a rough coat: the default call `model.brdf(wi, wo)` (the compiled fast path, "
        f"{numba.config.NUMBA_NUM_THREADS} threads) against a C loop of the same formula "
        "(`rd_coated_lambert_*` of roughdiffuse/bench/c/kernels.c, the same node rules and "
        "fitted multiple scattering (its directional ratio and its lobes), "
        "gcc -O3 -march=native -fopenmp -ffast-math, every core), interleaved, "
        f"the median of {repeat} calls each on float64 (N, 3) arrays (wall time: both use "
        "every core); default/C is the ratio of the rates:",
        "",
        "| N | dtype | model | default M/s | C M/s | default/C | max rel. diff |",
        "| --- | --- | --- | ---: | ---: | ---: | ---: |",
        *rows,
        C_END,
    ])


HEADING = "## The layered walk and `Coated`\n"
"""Where a table goes the first time ``--write`` puts it in a file."""


def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    ap = argparse.ArgumentParser(prog=prog, description=__doc__.splitlines()[0])
    ap.add_argument("--rows-log2", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--samples", type=int, default=50_000)
    ap.add_argument("--walk-only", action="store_true", help="only the walks' speed")
    ap.add_argument("--coated-only", action="store_true",
                    help="only the closed form against C")
    ap.add_argument("--threads", type=int, default=1,
                    help="Numba threads of the walks (default 1: no idle thread's CPU time)")
    ap.add_argument("--write", metavar="RESULTS.md", help="replace the tables' sections there")
    args = ap.parse_args(argv)
    import numba

    if not args.coated_only:
        numba.set_num_threads(args.threads)
        text = walk_markdown(args.samples, args.repeat)
        print(text, flush=True)
        if args.write:
            write_section(Path(args.write), text, BEGIN, END, HEADING)
    if args.walk_only:
        return
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)  # the fast path uses every core
    text = coated_markdown(args.rows_log2, args.repeat)
    print(text, flush=True)
    if args.write:
        write_section(Path(args.write), text, C_BEGIN, C_END, HEADING)


if __name__ == "__main__":
    main()
