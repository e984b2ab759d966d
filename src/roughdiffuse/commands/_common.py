"""Arguments shared by several subcommands: choosing and parametrising a model.

The models, their parameters, units, ranges and defaults come from the registry
(:mod:`roughdiffuse.registry`); nothing about a particular model is written here. The named
flags (``--albedo``, ``--sigma``, ``--alpha``, ...) are shorthands for ``--param NAME=VALUE``,
one for every numeric parameter some model declares (:func:`shorthands`), with help text
written from the declarations.
"""

from __future__ import annotations

import argparse
import math
from typing import Any

from .._validate import format_interval
from ..models import Model
from ..models.declaration import Param
from . import UsageError
from ._inputs import angle

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


def shorthands() -> dict[str, list[Param]]:
    """Parameter name -> its declarations, for every numeric parameter a model declares whose
    name is longer than one letter (``--param h=0.1`` sets the others), in registry order.
    """
    from .. import registry

    found: dict[str, list[Param]] = {}
    for entry in registry.entries():
        for p in entry.parameters:
            if not p.categorical and len(p.name) > 1:
                found.setdefault(p.name, []).append(p)
    return found


def _channel_values(name: str) -> Any:
    """argparse type of a colour parameter: one number or R,G,B."""

    def parse(text: str) -> float | list[float]:
        parts = [t for t in text.replace(",", " ").split() if t]
        try:
            vals = [float(t) for t in parts]
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{name} must be a number or three comma-separated numbers (got {text!r})"
            ) from None
        if len(vals) not in (1, 3):
            raise argparse.ArgumentTypeError(f"{name} must have 1 or 3 values (got {len(vals)})")
        return vals[0] if len(vals) == 1 else vals

    parse.__name__ = name  # argparse names the type in its own messages
    return parse


def _option_type(name: str, declared: Param) -> Any:
    """argparse type of a named model option: an angle (degrees, or with a unit), a colour
    (one number or R,G,B), or a number."""
    if declared.unit == "radians":
        return angle
    return _channel_values(name) if declared.channels else float


def _range_on_command_line(p: Param) -> str:
    """``[0, 1]``, or for an angle its range in degrees, ``[0, 90] degrees``."""
    if p.unit != "radians":
        return p.interval
    lo = None if p.min is None else math.degrees(p.min)
    hi = None if p.max is None else math.degrees(p.max)
    return f"{format_interval(lo, hi, p.min_open)} DEGREES"


def parameter_help(name: str, *, channels: bool = True) -> str:
    """What a parameter is, from its declarations: meaning, range (degrees for an angle) and
    which models take it, e.g. ``the model's roughness, in [0, 1]; 5 models``.
    ``channels``: mention that a colour parameter takes R,G,B."""
    from .. import registry

    declared = shorthands()[name]
    models = [e.id for e in registry.entries() if any(p.name == name for p in e.parameters)]
    first = declared[0]
    meanings = {p.description for p in declared}
    what = first.description if len(meanings) == 1 else f"the model's {name}"
    ranges = list(dict.fromkeys(_range_on_command_line(p) for p in declared))
    where = "in " + (ranges[0] if len(ranges) == 1 else " or ".join(ranges) + " by model")
    colour = ", or R,G,B" if first.channels and channels else ""
    if len(models) <= 3:
        taken = "model " + ", ".join(models) if len(models) == 1 else "models " + ", ".join(models)
    else:
        taken = f"{len(models)} models"
    return f"{what}, {where}{colour}; {taken}"


def add_model_arguments(
    parser: argparse.ArgumentParser,
    default: str = "oren-nayar",
    skip: tuple[str, ...] = (),
) -> None:
    """--model ID, --param NAME=VALUE and the shorthands --albedo, --sigma (degrees), ...

    The shorthands (:func:`shorthands`) default to ``None``: only a flag the user typed is
    applied (and refused when the model does not take that parameter). ``skip`` names
    parameters that get no shorthand because the command uses that flag for something else.
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
    added = []
    for name, declared in shorthands().items():
        if name in skip:
            continue
        g.add_argument(
            _flag(name),
            dest=name,
            type=_option_type(name, declared[0]),
            default=None,
            metavar=name.upper(),
            help=f"{parameter_help(name)} (default: {_start(name)})",
        )
        added.append(name)
    parser.set_defaults(shorthand_params=tuple(added))


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


def current_name(model: Any, name: str, flag: str) -> str:
    """``name``, or the current name of a renamed parameter of ``model`` (a model class), with
    a ``DeprecationWarning`` naming ``flag`` (:mod:`roughdiffuse.deprecation`)."""
    from ..deprecation import rename_keywords

    return next(iter(rename_keywords(model, {name: None}, flag)))


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
    from ._inputs import known_id

    entry = registry.get(known_id(args.model, registry.ids()))
    taken = {p.name: p for p in entry.parameters}
    values: dict[str, Any] = {
        p.name: p.example for p in entry.parameters if p.example is not None
    }
    for name in getattr(args, "shorthand_params", ()):
        value = getattr(args, name, None)
        if value is None:
            continue
        flag = _flag(name)
        if name not in taken:
            if strict:
                raise UsageError(
                    f"{flag}: model {entry.id!r} has no parameter {name!r}; its parameters: "
                    f"{', '.join(taken) or 'none'}"
                )
            continue
        p = taken[name]
        values[name] = _degrees(p, value, flag) if p.unit == "radians" else value
    typed = {n for n in getattr(args, "shorthand_params", ()) if getattr(args, n, None) is not None}
    for given_name, text in getattr(args, "param", None) or []:
        flag = f"--param {given_name}"
        name = current_name(entry.cls, given_name, flag)
        if name not in taken:
            raise UsageError(
                f"{flag}: model {entry.id!r} has no parameter {name!r}; its parameters: "
                f"{', '.join(taken) or 'none'}"
            )
        if name != given_name and name in typed | {n for n, _ in args.param}:
            raise UsageError(f"{flag} is the former name of {name}, also given; give {name} once")
        values[name] = parse_value(taken[name], text, flag)
    # starting values of parameters the chosen categorical values leave out (σ of an
    # Oren–Nayar base when --param base=eon) are dropped; those the user gave are refused by
    # the model, by name
    given = given_names(args)
    kept = {p.name for p in entry.applicable(values)}
    return {k: v for k, v in values.items() if k in kept or k in given}


def given_names(args: argparse.Namespace) -> set[str]:
    """The model parameters the user gave (``--param`` or a shorthand flag)."""
    from .. import registry
    from ..deprecation import renamed_keywords

    known = getattr(args, "model", None) in registry.ids()
    renamed = renamed_keywords(registry.get(args.model).cls) if known else {}  # old -> new
    given = {renamed.get(n, n) for n, _ in getattr(args, "param", None) or []}
    shorthand = getattr(args, "shorthand_params", ())
    return given | {n for n in shorthand if getattr(args, n, None) is not None}


def model_from_args(args: argparse.Namespace, strict: bool = True) -> Model:
    """Build the model the arguments describe (UsageError / ValueError on bad values)."""
    from .. import registry

    params = model_params_from_args(args, strict)
    return registry.get(args.model).create(**params)
