"""``roughdiffuse eval``: one BRDF value at one geometry."""

from __future__ import annotations

import argparse
import math

from . import UsageError
from ._checks import require_finite
from ._common import add_model_arguments, given_names, model_from_args
from ._inputs import geometry_arguments, geometry_used

EXAMPLES = """\
examples:
  roughdiffuse eval --model oren-nayar --sigma 20 --theta-i 30 --theta-r 60 --delta-phi 0
  roughdiffuse eval --model oren-nayar-full --sigma 0.35rad --theta-i 0.5rad --theta-r 40
  roughdiffuse eval --model eon --roughness 1 --albedo 0.9,0.5,0.2 --theta-i 80
  roughdiffuse eval --model torrance-sparrow-beckmann --param alpha=0.3 --theta-i 20
  roughdiffuse eval --model mix --param weight=0.3 --param sigma=15

`roughdiffuse models` lists the model ids and their parameters.
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "eval",
        help="evaluate a model's BRDF and directional albedo at one geometry",
        description="Print f_r (1/sr) and the directional albedo at one geometry, with the "
        "geometry and model parameters used (defaults marked). Angles in degrees "
        "(default θi = 0, θr = 0, Δφ = 0), or with a unit: 0.5rad.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_arguments(p)
    geometry_arguments(p, 0.0, 0.0, 0.0)
    p.set_defaults(func=run)


def parameters_defaulted(args: argparse.Namespace) -> list[str]:
    """The parameters of ``args.model`` the user did not give (they start from the
    declaration's example or default), for the echo of ``eval``."""
    from .. import registry

    given = given_names(args)
    entry = registry.get(args.model)
    chosen = dict(getattr(args, "param", None) or [])  # categorical values given (base=eon)
    return [p.name for p in entry.applicable(chosen) if p.name not in given]


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..frames import spherical_to_vector

    geometry = geometry_used(args)
    for name in ("theta_i", "theta_r"):
        val = getattr(args, name)
        if not 0.0 <= val <= 90.0:
            flag = "--" + name.replace("_", "-")
            raise UsageError(f"{flag} must be in [0, 90] degrees (got {val:.15g})")
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
    print(f"geometry: {geometry}")
    defaulted = parameters_defaulted(args)
    if defaulted:
        print(f"defaults used for: {', '.join(defaulted)} (see `roughdiffuse models`)")
    print(f"brdf (1/sr): {np.array2string(f, precision=6)}")
    print(f"directional albedo at wo: {np.array2string(a, precision=6)}")
    return 0
