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
  roughdiffuse convert --model eon --roughness 0.5 --to unity

An engine's name (blender, cycles, filament, materialx, mitsuba06, openpbr, osl, pbrt3, unity)
picks what that engine renders by default (unity: unity-disney-diffuse, filament:
filament-lambert); an opt-in variant is named by its id (unity-diffuse-ggx, filament-burley).
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
    p.add_argument(
        "--to",
        required=True,
        metavar="ID",
        help="target model id (e.g. eon), or an engine's name for its default (e.g. unity)",
    )
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def target_id(name: str) -> tuple[str, str | None]:
    """The registry id ``--to`` names and the line that says which engine default it is
    (``None`` for an id); a misspelt name is a ``UsageError`` with the closest names."""
    from .. import registry
    from ..models.renderers import ENGINES, engine_variant
    from ._inputs import known_id

    model_id = engine_variant(name)
    if model_id == name:
        known_id(name, [*registry.ids(), *ENGINES], option="--to")
        return name, None
    engine = name.strip().lower()
    others = ENGINES[engine][1:]
    note = f"{engine}: its default diffuse, {model_id}"
    return model_id, note + (f" (opt-in, by id: {', '.join(others)})" if others else "")


def run(args: argparse.Namespace) -> int:
    from ..fit.between_models import convert
    from ..progress import progress_enabled

    target, note = target_id(args.to)
    model = model_from_args(args)
    try:  # the bar on standard error, on a terminal (a coat's conversion takes minutes)
        result = convert(model, target=target,
                         progress=progress_enabled() and not args.no_progress)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    if args.json:
        print(json.dumps(result.to_json(), indent=2, ensure_ascii=False))
        return 0
    if note:
        print(note)
    print(result.summary())
    print("\nPython:\n" + result.snippet())
    print("\nCommand line:\n" + result.command())
    return 0
