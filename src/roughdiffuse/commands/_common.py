"""Arguments shared by several subcommands: choosing and parametrising a model."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

from ..models import (
    EON,
    Fujii,
    Lambert,
    LommelSeeliger,
    LunarLambert,
    Model,
    OrenNayar,
    TorranceSparrow,
)
from . import UsageError

MODEL_NAMES: dict[str, Callable[[argparse.Namespace], Model]] = {
    "lambert": lambda a: Lambert(a.albedo),
    "oren-nayar": lambda a: OrenNayar(a.albedo, math.radians(a.sigma), "qualitative"),
    "oren-nayar-full": lambda a: OrenNayar(a.albedo, math.radians(a.sigma), "full"),
    "fujii": lambda a: Fujii(a.albedo, a.roughness),
    "eon": lambda a: EON(a.albedo, a.roughness),
    "torrance-sparrow": lambda a: TorranceSparrow(a.eta, math.radians(a.sigma)),
    "lommel-seeliger": lambda a: LommelSeeliger(a.albedo),
    "lunar-lambert": lambda a: LunarLambert(a.albedo, a.limb_darkening),
}


def float_list(text: str) -> list[float]:
    """argparse type: "1, 2,3" or "1 2 3" -> [1.0, 2.0, 3.0] (at least one number)."""
    try:
        vals = [float(p) for p in text.replace(",", " ").split()]
    except ValueError:
        vals = []
    if not vals:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers (got {text!r})")
    return vals


def _albedo(text: str) -> float | list[float]:
    parts = [p for p in text.replace(",", " ").split() if p]
    try:
        vals = [float(p) for p in parts]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"albedo must be a number or three comma-separated numbers (got {text!r})"
        ) from None
    if len(vals) not in (1, 3):
        raise argparse.ArgumentTypeError(f"albedo must have 1 or 3 values (got {len(vals)})")
    return vals[0] if len(vals) == 1 else vals


def add_model_arguments(parser: argparse.ArgumentParser, default: str = "oren-nayar") -> None:
    """--model, --albedo, --sigma (degrees), --roughness, --eta, --limb-darkening."""
    g = parser.add_argument_group("model")
    g.add_argument(
        "--model",
        default=default,
        metavar="NAME",
        help=f"one of: {', '.join(MODEL_NAMES)} (default: {default})",
    )
    g.add_argument(
        "--albedo", type=_albedo, default=0.8, help="albedo ρ in [0, 1], or R,G,B (default: 0.8)"
    )
    g.add_argument(
        "--sigma", type=float, default=20.0, help="roughness σ in DEGREES, 0 to 90 (default: 20)"
    )
    g.add_argument(
        "--roughness",
        type=float,
        default=0.5,
        help="Fujii/EON roughness r in [0, 1] (default: 0.5)",
    )
    g.add_argument(
        "--eta",
        type=float,
        default=1.5,
        help="Torrance-Sparrow refractive index, > 0 (default: 1.5)",
    )
    g.add_argument(
        "--limb-darkening",
        type=float,
        default=0.5,
        help="Lunar-Lambert weight L in [0, 1] (default: 0.5)",
    )


def model_from_args(args: argparse.Namespace) -> Model:
    """Build the model the arguments describe (UsageError / ValueError on bad values)."""
    if args.model not in MODEL_NAMES:
        raise UsageError(f"unknown model {args.model!r}; choose one of: {', '.join(MODEL_NAMES)}")
    if not 0.0 <= args.sigma <= 90.0:
        raise UsageError(f"--sigma must be in [0, 90] degrees (got {args.sigma:g})")
    return MODEL_NAMES[args.model](args)
