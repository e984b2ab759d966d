"""``roughdiffuse simulate``: the exact V-cavity BRDF, ground-truth tables, the accuracy report."""

from __future__ import annotations

import argparse
import math
import os
from typing import Any

from .._version import version
from ..progress import progress_enabled
from . import UsageError
from ._checks import finite_float, fits_in_memory, output_file, output_folder, require_finite
from ._inputs import GEOMETRY_HELP, angle, angle_list, geometry_arguments, geometry_used

MAX_BOUNCES = 100
"""Largest finite --bounces. N bounces cost N − 1 products of the element matrices per slope
node (``simulate.cavity.radiosity_operator``), so the time grows linearly with N and 100
bounces already cost more than the all-bounce limit ('all', one matrix inverse), which is
what many bounces approach."""

MAX_ELEMENTS = 128
"""Largest --elements K (default 16): the solver's time grows fast with K (its matrices are
2K × 2K per slope node); see :func:`_solver_bytes` for its memory."""

EXAMPLES = (
    """\
examples:
  roughdiffuse simulate --theta-i 40 --theta-r 60 --delta-phi 0 --sigma 20 --bounces all
  roughdiffuse simulate --theta-i 0.7rad --sigma 0.35rad --bounces 1
  roughdiffuse simulate --table gt.npz --step 45 --delta-phi-step 90 --sigma 10,20
  roughdiffuse simulate --report --quick -o report/

A table run writes finished chunks to FILE.chunks/; run the same command again to resume
(--workers N for a local Dask cluster, --scheduler tcp://HOST:PORT for a distributed one).
A finished FILE is kept: the same command returns it at once; other settings need --force.
"""
    + GEOMETRY_HELP
    + """
Defaults: θi = 30, θr = 30, Δφ = 0, σ = 20, ρ = 0.8; the values used are printed.
"""
)


def _bounces(text: str) -> int | str:
    if text == "all":
        return text
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"bounces must be an integer in [1, {MAX_BOUNCES}] or 'all' (got {text!r})"
        ) from None


def _solver_bytes(elements: int) -> float:
    """Memory of the radiosity solver for K elements per facet: deep cavities take 4K
    (``simulate.cavity.elements_for_slope``), Richardson extrapolation doubles that, two
    facets double it again: float64 matrices of (16 K)² entries, about 20 of them at once
    (measured: K = 64 added 150 MB to the process)."""
    return 20 * 8 * float(16 * elements) ** 2


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "simulate",
        help="exact V-cavity ground truth: one BRDF value, a table, or the accuracy report",
        description="The exact BRDF of Oren and Nayar's V-cavity surface (shadowing, masking, "
        "interreflection). Angles in degrees.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    geometry_arguments(p, 30.0, 30.0, 0.0)
    p.add_argument(
        "--sigma",
        type=angle_list,
        default=[20.0],
        help="roughness σ in DEGREES or with a unit, 0.35rad (list for tables; default 20)",
    )
    p.add_argument(
        "--albedo", type=finite_float, default=0.8, help="facet albedo ρ in [0, 1] (default 0.8)"
    )
    p.add_argument(
        "--bounces",
        type=_bounces,
        default="all",
        help=f"1, 2, ... {MAX_BOUNCES} or all (default all)",
    )
    p.add_argument(
        "--measure",
        default="solid-angle",
        choices=["angle", "solid-angle"],
        help="slope-distribution measure: density in dθa, or per solid angle of facet normals "
        "(default; the reading the Oren-Nayar coefficients fit, docs/accuracy.md)",
    )
    p.add_argument(
        "--elements",
        type=int,
        default=16,
        help=f"radiosity elements per facet K, 1 to {MAX_ELEMENTS} (default 16)",
    )
    p.add_argument("--table", metavar="FILE", help="compute a ground-truth table into FILE (.npz)")
    p.add_argument(
        "--force",
        action="store_true",
        help="replace a finished --table FILE (or chunks of other settings) by a new run",
    )
    p.add_argument(
        "--step", type=angle, default=10.0, help="table step of θi and θr, degrees (default 10)"
    )
    p.add_argument(
        "--delta-phi-step", type=angle, default=30.0, help="table step of Δφ, degrees (default 30)"
    )
    p.add_argument("--workers", type=int, default=1, help="processes (local Dask cluster if > 1)")
    p.add_argument(
        "--backend",
        choices=("auto", "jax", "numpy"),
        default="auto",
        help="array namespace of the table's solver: compiled JAX or NumPy (default auto: "
        "JAX in one process, NumPy with --workers or --scheduler)",
    )
    p.add_argument("--scheduler", metavar="ADDRESS", help="Dask distributed scheduler address")
    p.add_argument("--report", action="store_true", help="write the accuracy report")
    p.add_argument("-o", "--output", default="report", help="report folder (default report/)")
    p.add_argument("--quick", action="store_true", help="report on a coarse grid (for testing)")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def _grid(step: float, lo: float, hi: float, name: str):
    import numpy as np

    if not 0.0 < step <= hi - lo:
        raise UsageError(f"--{name} must be in (0, {hi - lo:g}] degrees (got {step:g})")
    n = int(round((hi - lo) / step))
    return np.radians(np.linspace(lo, lo + n * step, n + 1))


def run(args: argparse.Namespace) -> int:
    from ..simulate import Settings

    _check(args)
    settings = Settings(measure=args.measure, elements=args.elements)
    if args.report:
        from ..accuracy.report import write_report

        output_folder(args.output, option="-o")
        out = write_report(
            args.output,
            quick=args.quick,
            progress=progress_enabled() and not args.no_progress,
            workers=args.workers,
            scheduler=args.scheduler,
        )
        print(f"report written to {out}")
        return 0
    if args.table:
        return _run_table(args, settings)
    return _run_single(args, settings)


def _check(args: argparse.Namespace) -> None:
    """Refuse options out of range before any work (and jobs too large for memory)."""
    if not 0.0 <= args.albedo <= 1.0:
        raise UsageError(f"--albedo must be in [0, 1] (got {args.albedo:g})")
    for s in args.sigma:
        if not 0.0 <= s <= 90.0:
            raise UsageError(f"--sigma must be in [0, 90] degrees (got {s:.15g})")
    if len(set(args.sigma)) != len(args.sigma):
        twice = next(s for s in args.sigma if args.sigma.count(s) > 1)
        raise UsageError(f"--sigma gives {twice:g} more than once; give each value once")
    if args.bounces != "all" and not 1 <= args.bounces <= MAX_BOUNCES:
        raise UsageError(
            f"--bounces must be an integer in [1, {MAX_BOUNCES}] or 'all' (got {args.bounces})"
        )
    if not 1 <= args.elements <= MAX_ELEMENTS:
        raise UsageError(f"--elements must be in [1, {MAX_ELEMENTS}] (got {args.elements})")
    fits_in_memory(
        _solver_bytes(args.elements) * args.workers,
        f"--elements {args.elements} --workers {args.workers}",
    )
    if args.workers < 1:
        raise UsageError(f"--workers must be >= 1 (got {args.workers})")


def _run_table(args: argparse.Namespace, settings: Any) -> int:
    """``--table``: compute (or resume, or reuse) a ground-truth table."""
    import numpy as np

    from ..simulate import compute_table

    ang = _grid(args.step, 0.0, 90.0, "step")
    delta_phi = _grid(args.delta_phi_step, 0.0, 180.0, "delta-phi-step")
    cells = float(ang.size) ** 2 * delta_phi.size * len(args.sigma)
    fits_in_memory(  # the values and their K-differences, float64, assembled at the end
        16.0 * cells,
        f"--step {args.step:g} --delta-phi-step {args.delta_phi_step:g} with "
        f"{len(args.sigma)} σ ({cells:.3g} table values, 16 bytes each)",
    )
    # checked before any chunk is computed; an existing table is resumed or reused
    output_file(args.table, option="--table", overwrite=True)
    if not args.table.lower().endswith(".npz"):  # an .npz archive under another name
        raise UsageError(f"--table must name an .npz file (got {args.table!r})")
    chunks = f"{args.table}.chunks"
    if os.path.exists(chunks) and not os.path.isdir(chunks):
        raise UsageError(f"--table: {chunks!r} (the chunk folder) is not a folder")
    table = compute_table(
        args.table,
        ang,
        ang,
        delta_phi,
        np.radians(args.sigma),
        args.albedo,
        args.bounces,
        settings,
        workers=args.workers,
        scheduler=args.scheduler,
        progress=progress_enabled() and not args.no_progress,
        backend=args.backend,
        force=args.force,
        package_version=version(),
    )
    if table.meta.get("reused"):
        print(
            f"kept {args.table}: a finished table of these settings, "
            f"{table.values.shape} values (θi, θr, Δφ, σ); --force recomputes it"
        )
        return 0
    print(
        f"wrote {args.table}: {table.values.shape} values (θi, θr, Δφ, σ), "
        f"max |f(K) - f(2K)| / f = {np.max(np.abs(table.k_difference) / table.values):.2e} "
        "(before Richardson extrapolation, which the values have)"
    )
    return 0


def _run_single(args: argparse.Namespace, settings: Any) -> int:
    """One BRDF value at the angles given, with its element-refinement change."""
    from ..simulate import brdf

    geometry = geometry_used(args)
    for name in ("theta_i", "theta_r"):
        val = getattr(args, name)
        if not 0.0 <= val <= 90.0:
            flag = "--" + name.replace("_", "-")
            raise UsageError(f"{flag} must be in [0, 90] degrees (got {val:.15g})")
    if len(args.sigma) != 1:
        raise UsageError("give one --sigma for a single value (a list is for --table)")
    f, d = brdf(
        math.radians(args.theta_i),
        math.radians(args.theta_r),
        math.radians(args.delta_phi),
        math.radians(args.sigma[0]),
        args.albedo,
        args.bounces,
        settings,
        return_difference=True,
    )
    require_finite([f, d], "the BRDF", f"--sigma {args.sigma[0]:g} --albedo {args.albedo:g}")
    print(f"geometry: {geometry}")
    print(
        f"surface: σ = {args.sigma[0]:g}°, facet albedo ρ = {args.albedo:g}, "
        f"bounces: {args.bounces}, measure: {args.measure}"
    )
    print(f"brdf (1/sr): {float(f):.8g}")
    print(f"f * pi / albedo: {float(f) * math.pi / max(args.albedo, 1e-300):.8g}")
    print(f"element change f(K) - f(2K): {float(d):.2e} (K = {args.elements}, extrapolated)")
    print(f"settings: {settings}")
    return 0
