"""``roughdiffuse albedo``: white-furnace plots and tables, sampling variance report."""

from __future__ import annotations

import argparse
import math
from pathlib import Path

from . import UsageError
from ._checks import finite_float
from ._common import float_list

EXAMPLES = """\
examples:
  roughdiffuse albedo -o albedo.png
  roughdiffuse albedo --model oren-nayar,eon --sigma 0,20,40,60 --roughness 0,0.5,1 \\
      -o albedo.svg --table albedo.csv
  roughdiffuse albedo --variance

σ (for oren-nayar, oren-nayar-full, torrance-sparrow) is in DEGREES; r (fujii, eon) is in
[0, 1]; lunar-lambert is drawn for limb darkening L = 0, 0.5, 1. The white-furnace test
uses albedo ρ = 1 (change it with --albedo).
"""

FAMILIES = {
    "lambert": "Lambert",
    "oren-nayar": "Oren–Nayar (qualitative)",
    "oren-nayar-full": "Oren–Nayar (full)",
    "fujii": "Fujii (FON)",
    "eon": "EON",
    "torrance-sparrow": "Torrance–Sparrow (η = 1.5)",
    "lommel-seeliger": "Lommel–Seeliger",
    "lunar-lambert": "Lunar–Lambert",
}
USES_SIGMA = ("oren-nayar", "oren-nayar-full", "torrance-sparrow")
USES_R = ("fujii", "eon")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "albedo",
        help="white-furnace plots and tables (albedo vs θr), sampling variance report",
        description="Plot the directional albedo of each model against the viewing angle θr "
        "for several roughnesses at ρ = 1 (the white-furnace test), or print the variance of "
        "each model's sample weights against cosine sampling (--variance).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "--model",
        default="oren-nayar,oren-nayar-full,fujii,eon",
        help=f"comma-separated names from: {', '.join(FAMILIES)} "
        "(default: oren-nayar,oren-nayar-full,fujii,eon)",
    )
    p.add_argument(
        "--sigma",
        type=float_list,
        default=[0.0, 15.0, 30.0, 45.0, 60.0],
        help="roughness σ in DEGREES, 0 to 90, comma-separated (default: 0,15,30,45,60)",
    )
    p.add_argument(
        "--roughness",
        type=float_list,
        default=[0.0, 0.25, 0.5, 0.75, 1.0],
        help="Fujii/EON roughness r in [0, 1], comma-separated (default: 0,0.25,0.5,0.75,1)",
    )
    p.add_argument(
        "--albedo", type=finite_float, default=1.0, help="albedo ρ in [0, 1] (default: 1)"
    )
    p.add_argument("-o", "--output", default="albedo.png", help="plot file: .png, .svg or .pdf")
    p.add_argument("--table", metavar="CSV", help="also write the albedo table (CSV) here")
    p.add_argument("--force", action="store_true", help="overwrite existing output files")
    p.add_argument(
        "--variance",
        action="store_true",
        help="print the sample-weight variance table (markdown) instead of plotting",
    )
    p.set_defaults(func=run)


def _groups(args: argparse.Namespace) -> dict[str, dict[str, object]]:
    from ..models import (
        EON,
        Fujii,
        Lambert,
        LommelSeeliger,
        LunarLambert,
        OrenNayar,
        TorranceSparrow,
    )

    names = [n.strip() for n in args.model.split(",") if n.strip()]
    if not names:
        raise UsageError("--model must name at least one model")
    for n in names:
        if n not in FAMILIES:
            raise UsageError(f"unknown model {n!r}; choose from: {', '.join(FAMILIES)}")
    for s in args.sigma:
        if not 0.0 <= s <= 90.0:
            raise UsageError(f"--sigma must be in [0, 90] degrees (got {s:g})")
    for r in args.roughness:
        if not 0.0 <= r <= 1.0:
            raise UsageError(f"--roughness must be in [0, 1] (got {r:g})")
    if not 0.0 <= args.albedo <= 1.0:
        raise UsageError(f"--albedo must be in [0, 1] (got {args.albedo:g})")
    rho = args.albedo
    groups: dict[str, dict[str, object]] = {}
    for n in names:
        if n == "lambert":
            curves = {f"ρ = {rho:g}": Lambert(rho)}
        elif n == "lommel-seeliger":
            curves = {f"ρ = {rho:g}": LommelSeeliger(rho)}
        elif n == "lunar-lambert":
            curves = {f"L = {x:g}": LunarLambert(rho, x) for x in (0.0, 0.5, 1.0)}
        elif n in USES_SIGMA:
            curves = {}
            for s in args.sigma:
                sig = math.radians(s)
                if n == "torrance-sparrow":
                    curves[f"σ = {s:g}°"] = TorranceSparrow(1.5, sig)
                else:
                    variant = "full" if n == "oren-nayar-full" else "qualitative"
                    curves[f"σ = {s:g}°"] = OrenNayar(rho, sig, variant)
        else:
            cls = EON if n == "eon" else Fujii
            curves = {f"r = {r:g}": cls(rho, r) for r in args.roughness}
        groups[FAMILIES[n]] = curves
    return groups


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import energy

    groups = _groups(args)
    if args.variance:
        flat = {f"{g}, {k}": m for g, curves in groups.items() for k, m in curves.items()}
        print(energy.variance_table(flat))
        return 0
    from ._checks import output_file

    # every output checked before anything is computed or written
    out = output_file(args.output, (".png", ".svg", ".pdf"), force=args.force, option="-o")
    if args.table:
        output_file(args.table, (".csv",), force=args.force, option="--table")

    from ..io.atomic import atomic_write

    th = np.radians(np.arange(0.0, 89.75, 0.5))
    fig = energy.plot_albedo(groups, th)
    atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=110))
    print(f"wrote {out}")
    if args.table:
        curves = {
            f"{g}, {k}": v
            for g, models in groups.items()
            for k, v in energy.albedo_curves(models, th).items()
        }
        energy.write_albedo_csv(args.table, th, curves)
        print(f"wrote {args.table}")
    for g, models in groups.items():
        curves = energy.albedo_curves(models, th)
        lo = min(float(a.min()) for a in curves.values())
        hi = max(float(a.max()) for a in curves.values())
        print(f"{g}: albedo between {lo:.4f} and {hi:.4f} over θr in [0°, 89.5°]")
    return 0


def plot_kind(args: argparse.Namespace, out: Path) -> int:
    """``roughdiffuse plot albedo``: the white-furnace plot for ``plot``'s --model and --sigma.

    ρ = 1; Fujii and EON get r = 0, 0.25, 0.5, 0.75, 1 (``plot`` has a single --roughness);
    ``roughdiffuse albedo`` takes lists of both and writes tables.
    """
    forwarded = argparse.Namespace(
        model=args.model,
        sigma=list(args.sigma),
        roughness=[0.0, 0.25, 0.5, 0.75, 1.0],
        albedo=1.0,
        output=str(out),
        table=None,
        variance=False,
        force=True,  # `plot` has checked the output already
    )
    return run(forwarded)
