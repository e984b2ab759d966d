"""Speed of the V-cavity solver (roughdiffuse.simulate): cavities per second, table times.

``roughdiffuse bench`` (:mod:`roughdiffuse.bench.run`) runs this module in a subprocess (BLAS
must be single-threaded, see below) and puts its rows in ``RESULTS.md``; on its own::

    python -m roughdiffuse.bench.simulate_bench                    # prints the table
    python -m roughdiffuse.bench.simulate_bench --cavities 2000 --geometries 2 --json /tmp/s.json
    python -m roughdiffuse.bench.simulate_bench --cases "closed form,bounces=1"  # those cases
    python -m roughdiffuse.bench.simulate_bench --versus --geometries 32  # old solver (git) vs new

Measured, each with the NumPy solver path (the baseline) and, next to it, the same call with
``jax.numpy`` arrays (the solver's JAX path, jitted; timed after a warm-up call, float64),
interleaved run by run:

* cavity evaluations per second (``cavity_radiance``), one bounce (closed form) and all
  bounces (radiosity, K = 16 and 32 elements per facet, Richardson-extrapolated from K and
  2K), for cavities that share one slope θa (as the surface quadrature calls them) and for
  cavities of all-different θa;
* surface BRDF evaluations per second (``brdf``) with the default settings (those that give
  1e-4, see docs/accuracy.md) for σ = 0.3 and 0.7, one bounce and all bounces, on random
  geometries;
* from those rates, the time of a 90 × 90 × 180 × 1 table (θi, θr, Δφ at 1°, one σ) on 2
  cores: for NumPy (one core per process here) two worker processes that scale linearly (the
  chunks are independent), for JAX the one process measured (its compiled code already uses
  every core).

If the call with JAX arrays raises, or returns a NumPy array (no JAX path), the row says "not
available" with the reason. BLAS runs single-threaded here (set before NumPy is imported): the
solver's matrices are small (2K ≤ 256), and BLAS threads per process compete with the
worker processes for the same cores (slower, see bench/RESULTS.md). Run as a script, this
file sets ``OPENBLAS_NUM_THREADS=1`` and ``OMP_NUM_THREADS=1`` (unless set); imported, it
changes nothing, so call :func:`bench_simulate` in a process started with them (as
:mod:`roughdiffuse.bench.run` does). Dask workers
(``--workers``) get one BLAS thread each by default; for a single process, set
``OPENBLAS_NUM_THREADS=1`` yourself.
"""

from __future__ import annotations

import os

from .._validate import ParameterError

if __name__ == "__main__":  # before NumPy is imported; run.py sets them for its subprocess
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
from collections.abc import Callable  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

from .timing import block, interleaved, rate_summary, rel_error  # noqa: E402

TABLE_SIZE = 90 * 90 * 180
CORES = 2
CAVITIES = 200_000
GEOMETRIES = 48


def _dirs(rng: np.random.Generator, n: int) -> np.ndarray:
    th = rng.uniform(0, 1.4, n)
    ph = rng.uniform(0, 2 * math.pi, n)
    return np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)


def _jax_numpy() -> Any:
    """``jax.numpy`` with float64 enabled (the solver's precision), or None without JAX."""
    try:
        import jax
    except ImportError:
        return None
    jax.config.update("jax_enable_x64", True)
    return jax.numpy


def _case(
    name: str,
    count: int,
    run: Callable[[Any], Any],
    args: tuple[np.ndarray, ...],
    repeat: int,
    jnp: Any,
) -> dict[str, Any]:
    """Time ``run(*args)`` on NumPy arrays and on JAX arrays; evaluations per second."""
    variants: dict[str, Callable[[], Any]] = {"numpy": lambda: run(*args)}
    ref = np.asarray(run(*args))  # warm-up
    row: dict[str, Any] = {"case": name, "evaluations": count}
    if jnp is None:
        row["jax_error"] = "not available: JAX is not installed"
    else:
        jargs = tuple(jnp.asarray(a) for a in args)
        try:
            got = block(run(*jargs))  # warm-up: tracing and compilation
            if isinstance(got, np.ndarray) or not hasattr(got, "block_until_ready"):
                raise TypeError(f"returned {type(got).__name__}, not a JAX array (no JAX path)")
            row["jax_max_rel_difference_vs_numpy"] = rel_error(got, ref)
            variants["jax"] = lambda: run(*jargs)
        except Exception as exc:  # the JAX path may not exist (yet): say so, go on
            msg = " ".join(f"{type(exc).__name__}: {exc}".split())
            row["jax_error"] = "not available: " + msg[:300]
    times = interleaved(variants, repeat)
    for k, t in times.items():
        row[k] = rate_summary(t, count, unit=1.0)
    if "jax" in row:
        row["jax_over_numpy"] = row["jax"]["median"] / row["numpy"]["median"]
    return row


def _cases(
    n_surface: int, n_cavities: int
) -> list[tuple[str, int, Callable[..., Any], tuple[np.ndarray, ...]]]:
    """The solver cases on seeded random inputs: (name, evaluations, function, its
    arguments)."""
    from roughdiffuse.simulate import Settings, brdf, cavity_radiance

    rng = np.random.default_rng(0)
    n = n_cavities
    ta = rng.uniform(0, 1.4, n)
    pa = rng.uniform(0, 2 * math.pi, n)
    wi, wo = _dirs(rng, n), _dirs(rng, n)
    n2, n3 = max(n // 4, 1), max(n // 100, 1)
    ti, tr = rng.uniform(0, 1.5, (2, n_surface))
    dp = rng.uniform(0, math.pi, n_surface)

    def cavities(bounces: Any, k: int = 32) -> Callable[..., Any]:
        return lambda t, p, i, o: cavity_radiance(t, p, i, o, 0.9, bounces, k)

    def surface(sigma: float, bounces: Any) -> Callable[..., Any]:
        return lambda a, b, c: brdf(a, b, c, sigma, 0.9, bounces, Settings())

    specs: list[tuple[str, int, Callable[..., Any], tuple[np.ndarray, ...]]] = [
        ("cavity, 1 bounce (closed form)", n, cavities(1), (ta, pa, wi, wo))
    ]
    shared = (np.full(n2, 0.8), pa[:n2], wi[:n2], wo[:n2])
    for k in (16, 32):
        specs.append(
            (f"cavity, all bounces, K={k} (+2K), shared θa", n2, cavities("all", k), shared)
        )
    specs.append(
        (
            "cavity, all bounces, K=16 (+2K), distinct θa",
            n3,
            cavities("all", 16),
            (ta[:n3], pa[:n3], wi[:n3], wo[:n3]),
        )
    )
    for sigma in (0.3, 0.7):
        for bounces in (1, "all"):
            specs.append(
                (
                    f"surface BRDF, σ={sigma}, bounces={bounces}",
                    n_surface,
                    surface(sigma, bounces),
                    (ti, tr, dp),
                )
            )
    return specs


def bench_simulate(
    repeat: int = 3,
    n_surface: int = GEOMETRIES,
    n_cavities: int = CAVITIES,
    only: list[str] | None = None,
) -> list[dict[str, Any]]:
    """Time the cases; one dict per case with evaluations per second (median, min, max).

    Parameters
    ----------
    repeat : int
        Timed runs per variant, after one warm-up call.
    n_surface : int
        Random geometries of the surface BRDF cases.
    n_cavities : int
        Cavities of the one-bounce case; a quarter of them for the all-bounce cases of one
        shared slope, a hundredth for all-different slopes.
    only : list of str, optional
        Run only the cases whose name contains one of these texts.
    """
    specs = _cases(n_surface, n_cavities)
    if only:
        specs = [s for s in specs if any(text in s[0] for text in only)]
        if not specs:
            raise ParameterError(f"no solver case matches {only!r}")
    jnp = _jax_numpy()
    rows = []
    for name, count, fn, args in specs:
        row = _case(name, count, fn, args, repeat, jnp)
        if name.startswith("surface"):
            # NumPy runs on one core here (one BLAS thread): CORES worker processes; the
            # JAX process already runs its compiled code on every core (XLA's thread pool)
            for k, procs in (("numpy", CORES), ("jax", 1)):
                if k in row:
                    row[f"table_90x90x180_hours_{CORES}_cores_{k}"] = (
                        TABLE_SIZE / row[k]["median"] / procs / 3600
                    )
        rows.append(row)
    return rows


BASELINE_REVISION = "1c092a6"
"""The solver before the tabulated V-cavity model (per-cavity element radiosity): the "old"
column of :func:`bench_versus`."""


def _baseline(revision: str) -> Any:
    """``roughdiffuse.simulate`` of git ``revision``, imported as ``roughdiffuse_baseline``.

    The package at that revision is extracted (``git archive``) into a temporary folder and
    imported under another name, so both solvers run in this process, interleaved.
    """
    import importlib
    import io
    import tarfile
    import tempfile

    root = Path(__file__).resolve().parent.parent
    from ..programs import find_program, run

    git = find_program("git")
    if git is None:
        raise ParameterError("--versus needs git (none on PATH)")
    data = run(
        [git, "-C", str(root), "archive", revision, "src/roughdiffuse"],
        check=True,
        capture_output=True,
    ).stdout
    tmp = Path(tempfile.mkdtemp(prefix="roughdiffuse_baseline_"))
    with tarfile.open(fileobj=io.BytesIO(data)) as tar:
        tar.extractall(tmp, filter="data")
    (tmp / "src" / "roughdiffuse").rename(tmp / "roughdiffuse_baseline")
    sys.path.insert(0, str(tmp))
    return importlib.import_module("roughdiffuse_baseline.simulate")


def bench_versus(
    repeat: int = 3,
    n_surface: int = 32,
    sigmas: tuple[float, ...] = (0.3, 0.7, 1.2),
    revision: str = BASELINE_REVISION,
) -> list[dict[str, Any]]:
    """Old solver (``revision``) against the new one, NumPy, surface BRDF, default settings.

    For each σ and bounces in (1, "all"): values per second of both (interleaved, same
    geometries, ρ = 0.9), their ratio, the largest relative difference, and the 90 × 90 ×
    180 table time on 2 cores (two single-core worker processes) from each rate. The
    geometries are random with θi, θr up to 89.9° and four of them grazing (90°).
    """
    from roughdiffuse.simulate import brdf

    old = _baseline(revision)
    rng = np.random.default_rng(0)
    ti, tr = rng.uniform(0, math.radians(89.9), (2, n_surface))
    dp = rng.uniform(0, math.pi, n_surface)
    ti[:2] = tr[2:4] = math.pi / 2
    rows = []
    for sigma in sigmas:
        for bounces in (1, "all"):
            variants = {
                "old": lambda s=sigma, b=bounces: old.brdf(ti, tr, dp, s, 0.9, b),
                "new": lambda s=sigma, b=bounces: brdf(ti, tr, dp, s, 0.9, b),
            }
            ref, got = (np.asarray(f()) for f in variants.values())  # warm-up, caches
            times = interleaved(variants, repeat)
            row: dict[str, Any] = {"sigma": sigma, "bounces": bounces, "evaluations": n_surface}
            for k, t in times.items():
                row[k] = rate_summary(t, n_surface, unit=1.0)
                row[f"table_90x90x180_hours_{CORES}_cores_{k}"] = (
                    TABLE_SIZE / row[k]["median"] / CORES / 3600
                )
            row["new_over_old"] = row["new"]["median"] / row["old"]["median"]
            row["max_rel_difference"] = rel_error(got, ref)
            rows.append(row)
    return rows


def markdown_versus(rows: list[dict[str, Any]], revision: str = BASELINE_REVISION) -> str:
    """Markdown table of :func:`bench_versus` rows."""
    lines = [
        f"| σ | bounces | old ({revision}), values / s | new, values / s | new / old "
        f"| max relative difference | 90×90×180 table on {CORES} cores, h (old; new) |",
        "| ---: | --- | --- | --- | ---: | ---: | --- |",
    ]
    for r in rows:
        cells = [
            f"{r[k]['median']:.4g} ({r[k]['min']:.4g}–{r[k]['max']:.4g})" for k in ("old", "new")
        ]
        hours = "; ".join(
            f"{r[f'table_90x90x180_hours_{CORES}_cores_{k}']:.3g}" for k in ("old", "new")
        )
        lines.append(
            f"| {r['sigma']} | {r['bounces']} | {cells[0]} | {cells[1]} "
            f"| {r['new_over_old']:.1f} | {r['max_rel_difference']:.1e} | {hours} |"
        )
    return "\n".join(lines)


def markdown(rows: list[dict[str, Any]]) -> str:
    """Markdown table of :func:`bench_simulate` rows."""
    lines = [
        "| case | N | NumPy, evaluations / s | JAX, evaluations / s | JAX / NumPy "
        f"| 90×90×180 table on {CORES} cores, h (NumPy; JAX) |",
        "| --- | ---: | --- | --- | ---: | --- |",
    ]
    for r in rows:
        num = r["numpy"]
        num_txt = f"{num['median']:.4g} ({num['min']:.4g}–{num['max']:.4g})"
        if "jax" in r:
            j = r["jax"]
            jax_txt = f"{j['median']:.4g} ({j['min']:.4g}–{j['max']:.4g})"
            ratio = f"{r['jax_over_numpy']:.2f}"
        else:
            jax_txt = r.get("jax_error", "–").replace("|", "\\|")
            ratio = "–"
        hours = [
            f"{r[key]:.3g}"
            for key in (f"table_90x90x180_hours_{CORES}_cores_{k}" for k in ("numpy", "jax"))
            if key in r
        ]
        lines.append(
            f"| {r['case']} | {r['evaluations']:,} | {num_txt} | {jax_txt} | {ratio} "
            f"| {'; '.join(hours)} |"
        )
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """``python bench/simulate_bench.py [--repeat N] [--cavities N] [--geometries N]``."""
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeat", type=int, default=3, help="timed runs per variant (default 3)")
    p.add_argument("--cavities", type=int, default=CAVITIES, help=f"cavities (default {CAVITIES})")
    p.add_argument(
        "--geometries",
        type=int,
        default=GEOMETRIES,
        help=f"surface BRDF geometries (default {GEOMETRIES})",
    )
    p.add_argument(
        "--cases",
        default="",
        help="only cases whose name contains one of these comma-separated texts",
    )
    p.add_argument("--json", type=Path, help="write the rows as JSON (- : standard output)")
    p.add_argument(
        "--versus",
        metavar="REV",
        nargs="?",
        const=BASELINE_REVISION,
        help="instead: the old solver of git revision REV (default "
        f"{BASELINE_REVISION}) against this one, surface BRDF, σ = 0.3, 0.7, 1.2",
    )
    args = p.parse_args(argv)
    if args.versus:
        rows = bench_versus(args.repeat, args.geometries, revision=args.versus)
        print(markdown_versus(rows, args.versus))
        if args.json:
            from timing import write_atomic

            write_atomic(args.json, json.dumps(rows, indent=1) + "\n")
        return 0
    if args.repeat < 1 or args.cavities < 100 or args.geometries < 1:
        p.error("--repeat and --geometries must be >= 1, --cavities >= 100")
    only = [t.strip() for t in args.cases.split(",") if t.strip()]
    try:
        rows = bench_simulate(args.repeat, args.geometries, args.cavities, only or None)
    except ValueError as exc:
        p.error(str(exc))
    if str(args.json) == "-":
        print(json.dumps(rows))
        return 0
    print(markdown(rows))
    if args.json:
        from timing import write_atomic

        write_atomic(args.json, json.dumps(rows, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
