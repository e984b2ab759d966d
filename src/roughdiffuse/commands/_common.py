"""Arguments shared by several subcommands: choosing and parametrising a model.

The models, their parameters, units, ranges and defaults come from the registry
(:mod:`roughdiffuse.registry`); nothing about a particular model is written here. The named
flags (``--albedo``, ``--sigma``, ...) are shorthands for ``--param NAME=VALUE``.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from ..models import Model
from ..models.declaration import Param
from . import UsageError

SHORTHANDS: dict[str, str] = {
    "albedo": "albedo",
    "sigma": "sigma",
    "roughness": "roughness",
    "eta": "eta",
    "limb_darkening": "limb_darkening",
}
"""argparse dest of a named flag -> the model parameter it sets."""

PARAM_HELP = """\
model parameters: --param NAME=VALUE (repeatable) sets any parameter of the chosen model;
`roughdiffuse models` lists every model with its parameters, units, ranges and defaults.
Angles (unit radians) are given in DEGREES on the command line; append 'rad' for radians
(--param sigma=0.35rad). Colour parameters take R,G,B (--param albedo=0.9,0.5,0.2).
A parameter the chosen model does not take is an error.
"""


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


def _assignment(text: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise argparse.ArgumentTypeError(f"--param takes NAME=VALUE (got {text!r})")
    return name.strip().replace("-", "_"), value.strip()


def model_ids() -> list[str]:
    """The ids ``--model`` accepts (the registry's)."""
    from .. import registry

    return registry.ids()


def _start(name: str) -> str:
    """The value a parameter starts at on the command line (first model declaring it)."""
    from .. import registry

    for entry in registry.entries():
        for p in entry.parameters:
            if p.name == name:
                v = p.default if p.example is None else p.example
                return f"{math.degrees(v):g}" if p.unit == "radians" else f"{v:g}"
    return "none"


def add_model_arguments(parser: argparse.ArgumentParser, default: str = "oren-nayar") -> None:
    """--model ID, --param NAME=VALUE and the shorthands --albedo, --sigma (degrees), ...

    The shorthands default to ``None``: only a flag the user typed is applied (and refused
    when the model does not take that parameter).
    """
    g = parser.add_argument_group("model", PARAM_HELP)
    g.add_argument(
        "--model",
        default=default,
        metavar="ID",
        help=f"model id: {', '.join(model_ids())} (default: {default}; see `roughdiffuse models`)",
    )
    g.add_argument(
        "--param",
        type=_assignment,
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set a model parameter, e.g. --param sigma=20 (degrees) or --param alpha=0.3",
    )
    g.add_argument(
        "--albedo",
        type=_albedo,
        default=None,
        help=f"albedo ρ in [0, 1], or R,G,B (default: {_start('albedo')})",
    )
    g.add_argument(
        "--sigma",
        type=float,
        default=None,
        help=f"roughness σ in DEGREES, 0 to 90 (default: {_start('sigma')})",
    )
    g.add_argument(
        "--roughness",
        type=float,
        default=None,
        help=f"Fujii/EON roughness r in [0, 1] (default: {_start('roughness')})",
    )
    g.add_argument(
        "--eta",
        type=float,
        default=None,
        help=f"Torrance-Sparrow refractive index η in (0, 1000] (default: {_start('eta')})",
    )
    g.add_argument(
        "--limb-darkening",
        type=float,
        default=None,
        help=f"Lunar-Lambert weight L in [0, 1] (default: {_start('limb_darkening')})",
    )


def _flag(name: str) -> str:
    return "--" + name.replace("_", "-")


def _degrees(p: Param, value: float, flag: str) -> float:
    """Degrees -> radians, refusing values outside the parameter's range in degrees."""
    lo = math.degrees(p.min) if p.min is not None else -math.inf
    hi = math.degrees(p.max) if p.max is not None else math.inf
    # a bound typed as printed ("60" for π/3) is the bound itself: degrees(radians(x)) is
    # not always x, so values within rounding of a bound are snapped to it, not refused
    for bound, radians in ((lo, p.min), (hi, p.max)):
        if radians is not None and math.isclose(value, bound, rel_tol=1e-12, abs_tol=1e-12):
            return radians
    if not lo <= value <= hi:
        raise UsageError(f"{flag} must be in [{lo:g}, {hi:g}] degrees (got {value:g})")
    return math.radians(value)


def parse_value(p: Param, text: str, flag: str) -> Any:
    """A ``--param`` value for parameter ``p``: a choice, numbers, or degrees for an angle."""
    if p.categorical:
        return text  # the model names the choices if it is not one
    if p.unit == "radians":
        radians = text.endswith("rad")
        number = text[: -len("rad")] if radians else text.removesuffix("deg")
        try:
            value = float(number)
        except ValueError:
            raise UsageError(f"{flag} must be a number of degrees (got {text!r})") from None
        return value if radians else _degrees(p, value, flag)
    parts = [t for t in text.replace(",", " ").split() if t]
    try:
        vals = [float(t) for t in parts]
    except ValueError:
        raise UsageError(f"{flag} must be a number {p.range_text()} (got {text!r})") from None
    if len(vals) == 1:
        return vals[0]
    if p.channels and len(vals) == 3:
        return vals
    raise UsageError(f"{flag} takes one number{' or R,G,B' if p.channels else ''} (got {text!r})")


def model_params_from_args(args: argparse.Namespace, strict: bool = True) -> dict[str, Any]:
    """The parameters the user gave for the model ``args.model``, starting values filled in.

    Values the user did not give start from the declaration's ``example`` (a typical value:
    albedo 0.8, σ = 20°, r = 0.5), else its default.

    Parameters
    ----------
    strict : bool
        Refuse a typed shorthand flag the model does not take (commands that draw several
        models at once pass False: the flag applies to the models that take it).
    """
    from .. import registry

    try:
        entry = registry.get(args.model)
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    taken = {p.name: p for p in entry.parameters}
    values: dict[str, Any] = {
        p.name: p.example for p in entry.parameters if p.example is not None
    }
    for dest, name in SHORTHANDS.items():
        value = getattr(args, dest, None)
        if value is None:
            continue
        flag = _flag(dest)
        if name not in taken:
            if strict:
                raise UsageError(
                    f"{flag}: model {entry.id!r} has no parameter {name!r}; its parameters: "
                    f"{', '.join(taken) or 'none'}"
                )
            continue
        p = taken[name]
        values[name] = _degrees(p, value, flag) if p.unit == "radians" else value
    for name, text in getattr(args, "param", None) or []:
        if name not in taken:
            raise UsageError(
                f"--param {name}: model {entry.id!r} has no parameter {name!r}; its parameters: "
                f"{', '.join(taken) or 'none'}"
            )
        values[name] = parse_value(taken[name], text, f"--param {name}")
    return values


def model_from_args(args: argparse.Namespace, strict: bool = True) -> Model:
    """Build the model the arguments describe (UsageError / ValueError on bad values)."""
    from .. import registry

    params = model_params_from_args(args, strict)
    return registry.get(args.model).create(**params)
