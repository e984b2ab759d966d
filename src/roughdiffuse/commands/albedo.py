"""``roughdiffuse albedo``: white-furnace plots and tables, sampling variance report."""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import Any

from . import UsageError
from ._checks import finite_float
from ._common import float_list, parameter_help
from ._inputs import angle_list

EXAMPLES = """\
examples:
  roughdiffuse albedo -o albedo.png
  roughdiffuse albedo --model oren-nayar,eon --sigma 0,20,40,60 --roughness 0,0.5,1 \\
      -o albedo.svg --table albedo.csv
  roughdiffuse albedo --model hammon,v-cavity --alpha 0.1,0.5 --sigma 10,30 -o ggx.png
  roughdiffuse albedo --variance

Any model of `roughdiffuse models` is accepted. Each panel sweeps the model's roughness:
σ (a parameter named sigma, e.g. oren-nayar, torrance-sparrow, v-cavity) in DEGREES from
--sigma; r (named roughness: fujii, eon, burley) in [0, 1] from --roughness; α (named alpha:
hammon, chan, smith-diffuse-*) from --alpha. Models with none of these are drawn once, at
their defaults. The white-furnace test uses albedo ρ = 1 (change it with --albedo).
"""

#: The roughness parameter a panel sweeps: declared name -> (option, unit shown, in degrees)
SWEEPS = {
    "sigma": ("sigma", "σ", True),
    "roughness": ("roughness", "r", False),
    "alpha": ("alpha", "α", False),
}
DEFAULT_MODELS = "oren-nayar,oren-nayar-full,fujii,eon"


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
        default=DEFAULT_MODELS,
        help="comma-separated model ids, any of `roughdiffuse models` "
        f"(default: {DEFAULT_MODELS})",
    )
    p.add_argument(
        "--sigma",
        type=angle_list,
        default=[0.0, 15.0, 30.0, 45.0, 60.0],
        help=f"{parameter_help('sigma')}; comma-separated, or 0.2rad (default: 0,15,30,45,60)",
    )
    p.add_argument(
        "--roughness",
        type=float_list,
        default=[0.0, 0.25, 0.5, 0.75, 1.0],
        help=f"{parameter_help('roughness')}; comma-separated (default: 0,0.25,0.5,0.75,1)",
    )
    p.add_argument(
        "--alpha",
        type=float_list,
        default=[0.1, 0.3, 0.5, 0.8],
        help=f"{parameter_help('alpha')}; comma-separated (default: 0.1,0.3,0.5,0.8)",
    )
    p.add_argument(
        "--albedo",
        type=finite_float,
        default=1.0,
        help=f"{parameter_help('albedo', channels=False)} (default: 1)",
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


def _sweep(
    entry: Any, args: argparse.Namespace, only: str | None = None
) -> tuple[str, str, list[Any]] | None:
    """The declared roughness parameter of ``entry`` that a panel sweeps: its name, the
    symbol for the curve labels and the values (``None`` when the model has none, or when it
    is not ``only``)."""
    names = {p.name for p in entry.parameters}
    for name, (option, symbol, degrees) in SWEEPS.items():
        if name in names:
            if only is not None and name != only:
                return None
            values = getattr(args, option)
            return name, symbol, [(v, math.radians(v) if degrees else v) for v in values]
    return None


def _typed_sweeps_apply(args: argparse.Namespace, names: list[str]) -> None:
    """Refuse a typed --sigma, --roughness or --alpha that none of the models sweeps (it
    would be ignored, its values unchecked)."""
    from .. import registry
    from ._conflicts import given

    typed = given(args)
    for name, (option, symbol, _) in SWEEPS.items():
        if option not in typed:
            continue
        if not any(_sweep(registry.get(n), args, only=name) for n in names):
            raise UsageError(
                f"--{option} applies only to models with a roughness {symbol} named {name!r}; "
                f"--model {','.join(names)} has none (see `roughdiffuse models`)"
            )


def _groups(args: argparse.Namespace) -> dict[str, dict[str, object]]:
    from .. import registry
    from ._inputs import known_id

    names = [n.strip() for n in args.model.split(",") if n.strip()]
    if not names:
        raise UsageError("--model must name at least one model")
    for n in names:
        known_id(n, registry.ids())
    for s in args.sigma:
        if not 0.0 <= s <= 90.0:
            raise UsageError(f"--sigma must be in [0, 90] degrees (got {s:.15g})")
    if not 0.0 <= args.albedo <= 1.0:
        raise UsageError(f"--albedo must be in [0, 1] (got {args.albedo:g})")
    _typed_sweeps_apply(args, names)
    rho = args.albedo
    groups: dict[str, dict[str, object]] = {}
    for n in names:
        entry = registry.get(n)
        base = {"albedo": rho} if "albedo" in {p.name for p in entry.parameters} else {}
        sweep = _sweep(entry, args)
        if sweep is None:
            groups[entry.label] = {f"ρ = {rho:g}": entry.create(**base)}
            continue
        name, symbol, values = sweep
        param = entry.param(name)
        curves = {}
        for shown, value in values:
            try:
                param.check(value)
            except ValueError as exc:
                option = SWEEPS[name][0]
                raise UsageError(f"--{option} {shown:g} for {n}: {exc}") from None
            unit = "°" if SWEEPS[name][2] else ""
            curves[f"{symbol} = {shown:g}{unit}"] = entry.create(**base, **{name: value})
        groups[entry.label] = curves
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
    flat = {f"{g}\0{k}": m for g, models in groups.items() for k, m in models.items()}
    computed = energy.albedo_curves(flat, th, progress=True)  # once, with a progress bar
    per_group = {
        g: {k: computed[f"{g}\0{k}"] for k in models} for g, models in groups.items()
    }
    fig = energy.plot_albedo(groups, th, curves=per_group)
    atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=110))
    print(f"wrote {out}")
    if args.table:
        table = {f"{g}, {k}": v for g, curves in per_group.items() for k, v in curves.items()}
        energy.write_albedo_csv(args.table, th, table)
        print(f"wrote {args.table}")
    for g, curves in per_group.items():
        lo = min(float(a.min()) for a in curves.values())
        hi = max(float(a.max()) for a in curves.values())
        print(f"{g}: albedo between {lo:.4f} and {hi:.4f} over θr in [0°, 89.5°]")
    return 0


def plot_kind(args: argparse.Namespace, out: Path) -> int:
    """``roughdiffuse plot albedo``: the white-furnace plot for ``plot``'s --model and --sigma.

    ρ = 1; models with a roughness r get r = 0, 0.25, 0.5, 0.75, 1 and those with α get
    α = 0.1, 0.3, 0.5, 0.8 (``plot`` has a single --roughness); ``roughdiffuse albedo`` takes
    lists of each and writes tables.
    """
    forwarded = argparse.Namespace(
        model=args.model,
        sigma=list(args.sigma),
        roughness=[0.0, 0.25, 0.5, 0.75, 1.0],
        alpha=[0.1, 0.3, 0.5, 0.8],
        albedo=1.0,
        output=str(out),
        table=None,
        variance=False,
        force=True,  # `plot` has checked the output already
    )
    return run(forwarded)
