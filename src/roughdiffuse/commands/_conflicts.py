"""Nothing the user typed is silently ignored: flags that conflict, or that do not apply to
the chosen output, are declared here, in one table, and checked once after parsing.

:data:`RULES` maps a command to its declarations:

* :class:`Conflict` -- two flags that cannot be given together (one would be ignored);
* :class:`AppliesOnly` -- flags that only mean something when a condition holds (``--bits``
  with a PNG output); given otherwise they are an error naming the flag and the condition.

Besides the table, every command with model arguments refuses a parameter set twice: by
``--param NAME=…`` twice, or by a named flag and ``--param`` (``--sigma 30 --param
sigma=10``).

Only flags the user typed count: :func:`given_options` parses the command line a second time
with every default suppressed, so a flag left at its default is never "given", and a flag
typed with its default value is. :func:`check_options` (called by :func:`roughdiffuse.cli.main`)
raises a :class:`~roughdiffuse.commands.UsageError`, exit status 2. A command added later
adds its row to :data:`RULES`.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from . import UsageError

__all__ = ["RULES", "AppliesOnly", "Conflict", "check_options", "given", "given_options"]


@dataclass(frozen=True)
class Conflict:
    """Two flags that cannot be given together; ``why`` says which one would be ignored."""

    first: str
    second: str
    why: str = ""


@dataclass(frozen=True)
class AppliesOnly:
    """``flags`` apply only when ``when(args)`` holds, which ``what`` describes."""

    flags: tuple[str, ...]
    when: Callable[[argparse.Namespace], bool]
    what: str


def _suffix(dest: str, *suffixes: str) -> Callable[[argparse.Namespace], bool]:
    def check(args: argparse.Namespace) -> bool:
        value = getattr(args, dest, None)
        return value is not None and os.path.splitext(str(value))[1].lower() in suffixes

    return check


def _set(dest: str) -> Callable[[argparse.Namespace], bool]:
    return lambda args: bool(getattr(args, dest, None))


def _to(target: str) -> Callable[[argparse.Namespace], bool]:
    return lambda args: getattr(args, "to", None) == target


def _kind(*kinds: str) -> Callable[[argparse.Namespace], bool]:
    return lambda args: getattr(args, "kind", None) in kinds


_IMAGE = (".npy", ".exr", ".png")
_SCENE_FLAGS = (
    "--shape", "--size", "--spp", "--no-shadows", "--light", "--light-theta", "--light-phi",
    "--irradiance", "--view-theta", "--view-phi",
)  # fmt: skip
"""The flags of a rendered scene (render.add_scene_arguments)."""
_SCENE = (
    Conflict("--light", "--light-theta", "--light replaces --light-theta/--light-phi"),
    Conflict("--light", "--light-phi", "--light replaces --light-theta/--light-phi"),
    Conflict("--light", "--irradiance", "--light THETA,PHI,E0 gives each light's E0"),
)

RULES: dict[str, tuple[Conflict | AppliesOnly, ...]] = {
    "render": (
        *_SCENE,
        AppliesOnly(
            ("--bits", "--alpha", "--exposure"),
            _suffix("output", ".png"),
            "a .png output (-o FILE.png)",
        ),
    ),
    "plot": (
        *_SCENE,
        AppliesOnly(
            _SCENE_FLAGS,
            _kind("cross-section", "roughness-series"),
            "plot cross-section or roughness-series (a rendered scene)",
        ),
        AppliesOnly(("--theta-i",), _kind("plane", "polar"), "plot plane or polar"),
    ),
    "fit": (
        Conflict("--compare", "--model", "--compare fits every model"),
        AppliesOnly(
            ("--normals", "--shape", "--light", "--view", "--margin", "--erode"),
            _suffix("data", *_IMAGE),
            "an image DATA (.npy, .exr, .png)",
        ),
        AppliesOnly(("--exposure", "--encoding"), _suffix("data", ".png"), "a .png DATA"),
        AppliesOnly(("--max-samples",), _suffix("data", ".binary"), "a MERL .binary DATA"),
        AppliesOnly(("--margin",), _set("shape"), "--shape"),
        AppliesOnly(("--force",), _set("report"), "--report"),
        AppliesOnly(("--export-prefix", "--blender-python"), _set("export"), "--export"),
    ),
    "export": (
        AppliesOnly(
            ("--principled", "--no-blend", "--blender-python"), _to("blender"), "--to blender"
        ),
        AppliesOnly(("--openpbr",), _to("materialx"), "--to materialx"),
        AppliesOnly(("--uniforms", "--name"), _to("glsl"), "--to glsl"),
    ),
    "albedo": (
        Conflict("--variance", "--output", "--variance prints a table and writes no plot"),
        Conflict("--variance", "--table", "--variance prints a table and writes no file"),
        Conflict("--variance", "--force", "--variance writes no file"),
    ),
    "simulate": (
        *(
            Conflict("--table", flag, "--table computes a whole grid")
            for flag in ("--theta-i", "--theta-r", "--delta-phi", "--report")
        ),
        *(
            Conflict("--report", flag, "--report uses its own grid and settings")
            for flag in (
                *("--theta-i", "--theta-r", "--delta-phi", "--sigma", "--albedo"),
                *("--bounces", "--measure", "--elements"),
            )
        ),
        AppliesOnly(
            ("--step", "--delta-phi-step", "--force", "--backend"), _set("table"), "--table"
        ),
        AppliesOnly(("--output", "--quick"), _set("report"), "--report"),
        AppliesOnly(
            ("--workers", "--scheduler", "--no-progress"),
            lambda a: bool(a.table or a.report),
            "--table or --report",
        ),
    ),
    "stereo": (
        Conflict("--diligent", "--lights", "a DiLiGenT folder holds its own lights"),
        Conflict("--diligent", "--mask", "a DiLiGenT folder holds its own mask"),
        Conflict("--demo", "--lights", "--demo renders its own lights"),
        Conflict("--demo", "--mask", "--demo renders its own mask"),
        AppliesOnly(("--exposure",), lambda a: bool(a.images), "IMAGE files"),
        Conflict("--benchmark", "--lights", "a DiLiGenT folder holds its own lights"),
        Conflict("--benchmark", "--mask", "a DiLiGenT folder holds its own masks"),
        Conflict("--benchmark", "--method", "--benchmark runs every method"),
        Conflict("--benchmark", "--model", "--benchmark runs every method"),
        AppliesOnly(
            ("--per-pixel",),
            lambda a: a.method in (None, "rough", "coated"),
            "--method rough or coated",
        ),
    ),
    "figures": (),
}
"""Per command: the flags that conflict and the flags that apply only in some cases."""


def _subparser(parser: argparse.ArgumentParser, name: str) -> argparse.ArgumentParser | None:
    for action in parser._actions:  # argparse keeps its subparsers only here
        if isinstance(action, argparse._SubParsersAction):
            return action.choices.get(name)
    return None


def given_options(
    parser: argparse.ArgumentParser, argv: Sequence[str] | None, command: str
) -> frozenset[str]:
    """The ``dest`` of every option of ``command`` that the user typed in ``argv``."""
    sub = _subparser(parser, command)
    if sub is None:
        return frozenset()
    optional = [a for a in sub._actions if a.option_strings]
    saved = [(a, a.default) for a in optional]
    try:
        for a in optional:
            a.default = argparse.SUPPRESS
        ns = parser.parse_args(argv)
    finally:
        for a, default in saved:
            a.default = default
    dests = {a.dest for a in optional}
    return frozenset(k for k in vars(ns) if k in dests)


def given(args: argparse.Namespace) -> frozenset[str]:
    """The options the user typed (``dest`` names), as :func:`check_options` recorded them."""
    return getattr(args, "_given", frozenset())


def _dest(sub: argparse.ArgumentParser, flag: str) -> str:
    action = sub._option_string_actions.get(flag)
    if action is None:  # a declaration naming a flag the command does not have
        raise KeyError(f"{sub.prog}: the conflict table names {flag}, which it does not take")
    return action.dest


def _check_params(args: argparse.Namespace, typed: frozenset[str]) -> None:
    seen: dict[str, str] = {}
    for name in getattr(args, "shorthand_params", ()):  # the named options of the model
        if name in typed and getattr(args, name, None) is not None:
            seen[name] = "--" + name.replace("_", "-")
    for name, _ in getattr(args, "param", None) or []:
        flag = f"--param {name}"
        if name in seen:
            raise UsageError(f"{seen[name]} and {flag} both set {name}; give it once")
        seen[name] = flag


def check_options(
    parser: argparse.ArgumentParser, args: argparse.Namespace, argv: Sequence[str] | None
) -> None:
    """Refuse conflicting or inapplicable flags of ``args.command`` (see :data:`RULES`);
    record the typed options on ``args`` for :func:`given`."""
    command = getattr(args, "command", None)
    if not command:
        return
    typed = given_options(parser, argv, command)
    args._given = typed
    _check_params(args, typed)
    sub = _subparser(parser, command)
    for rule in RULES.get(command, ()):
        if isinstance(rule, Conflict):
            if _dest(sub, rule.first) in typed and _dest(sub, rule.second) in typed:
                why = f" ({rule.why})" if rule.why else ""
                raise UsageError(f"{rule.first} and {rule.second} cannot be used together{why}")
        elif not rule.when(args):
            for flag in rule.flags:
                if _dest(sub, flag) in typed:
                    raise UsageError(f"{flag} applies only to {rule.what}; leave it out")
