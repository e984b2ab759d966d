"""``roughdiffuse eval``: one BRDF value at one geometry."""

from __future__ import annotations

import argparse
import math

from . import UsageError
from ._checks import finite_float, require_finite
from ._common import add_model_arguments, model_from_args

EXAMPLES = """\
examples:
  roughdiffuse eval --model oren-nayar --sigma 20 --theta-i 30 --theta-r 60 --delta-phi 0
  roughdiffuse eval --model eon --roughness 1 --albedo 0.9,0.5,0.2 --theta-i 80
  roughdiffuse eval --model torrance-sparrow-beckmann --param alpha=0.3 --theta-i 20
  roughdiffuse eval --model mix --param weight=0.3 --param sigma=15

`roughdiffuse models` lists the model ids and their parameters.
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "eval",
        help="evaluate a model's BRDF and directional albedo at one geometry",
        description="Print f_r (1/sr) and the directional albedo at one geometry. "
        "Angles in degrees.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_arguments(p)
    p.add_argument(
        "--theta-i", type=finite_float, default=0.0, help="incidence angle θi, degrees [0, 90]"
    )
    p.add_argument(
        "--theta-r", type=finite_float, default=0.0, help="viewing angle θr, degrees [0, 90]"
    )
    p.add_argument("--delta-phi", type=finite_float, default=0.0, help="azimuth φr − φi, degrees")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..frames import spherical_to_vector

    for name in ("theta_i", "theta_r"):
        val = getattr(args, name)
        if not 0.0 <= val <= 90.0:
            raise UsageError(f"--{name.replace('_', '-')} must be in [0, 90] degrees (got {val:g})")
    model = model_from_args(args)
    wi = spherical_to_vector(math.radians(args.theta_i), 0.0)
    wo = spherical_to_vector(math.radians(args.theta_r), math.radians(args.delta_phi))
    f = np.asarray(model.brdf(wi, wo))
    a = np.asarray(model.directional_albedo(wo))
    inputs = (
        f"{model!r} at θi = {args.theta_i:g}°, θr = {args.theta_r:g}°, Δφ = {args.delta_phi:g}°"
    )
    require_finite(f, "the BRDF", inputs)
    require_finite(a, "the directional albedo", inputs)
    print(f"model: {model!r}")
    print(f"brdf (1/sr): {np.array2string(f, precision=6)}")
    print(f"directional albedo at wo: {np.array2string(a, precision=6)}")
    return 0
