"""``roughdiffuse convert``: the parameters of another model that best reproduce a model."""

from __future__ import annotations

import argparse
import json

from . import UsageError
from ._common import add_model_arguments, model_from_args

EXAMPLES = """\
examples:
  roughdiffuse convert --model oren-nayar-full --param sigma=20 --to cycles-diffuse
  roughdiffuse convert --model eon --roughness 0.5 --to materialx-eon --json
  roughdiffuse convert --model oren-nayar --param sigma=20 --to pbrt3-oren-nayar

The differences are those of f cos θi over both hemispheres (relative to the source's RMS)
and of the directional albedo; `roughdiffuse models` lists the targets.
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "convert",
        help="find another model's parameters that best reproduce a model",
        description="Least-squares conversion of a model's parameters into another model's "
        "(f cos θi over the hemisphere and the directional albedo); prints the parameters, "
        "the differences left, and the snippet that builds the target.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_arguments(p)
    p.add_argument("--to", required=True, metavar="ID", help="target model id (e.g. eon)")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from .. import registry
    from ..fit.between_models import convert

    try:
        registry.get(args.to)
    except ValueError as exc:
        raise UsageError(f"--to: {exc}") from None
    model = model_from_args(args)
    try:
        result = convert(model, target=args.to)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps(result.to_json(), indent=2, ensure_ascii=False))
        return 0
    print(result.summary())
    print("\nPython:\n" + result.snippet())
    print("\nCommand line:\n" + result.command())
    return 0
