"""How the command line reads names and angles: one resolver for each.

* :func:`data_file` -- a file argument, where ``data:NAME`` is a file shipped with the
  package (:mod:`roughdiffuse.data`), e.g. ``roughdiffuse fit data:samples.csv``;
* :func:`known_id` -- a model id (or any name from a list), refusing a misspelt one with the
  closest names (:func:`difflib.get_close_matches`: "did you mean oren-nayar-full?");
* :func:`angle` -- an argparse type for every angle option: degrees, or a number with a
  ``deg`` or ``rad`` suffix (``20``, ``20deg``, ``0.35rad``), returned in degrees;
  :func:`angle_pair` does the same for ``THETA,PHI``.
"""

from __future__ import annotations

import argparse
import difflib
import math
import os
from collections.abc import Iterable

from .._validate import ParameterError
from . import UsageError

__all__ = [
    "DATA_PREFIX",
    "GEOMETRY_HELP",
    "angle",
    "angle_list",
    "angle_pair",
    "geometry_arguments",
    "geometry_used",
    "data_file",
    "input_file",
    "known_id",
    "suggest",
]

DATA_PREFIX = "data:"
"""A file argument starting with this names a file shipped with the package."""


def data_file(text: str, what: str = "data file") -> str:
    """The path a file argument names: ``data:NAME`` is the shipped sample ``NAME`` (see
    ``roughdiffuse data``); anything else is returned as given.

    Raises
    ------
    UsageError
        For ``data:`` followed by a name that is not shipped, with the closest names.
    """
    if not text.startswith(DATA_PREFIX):
        return text
    from .. import data

    name = text[len(DATA_PREFIX) :]
    if name not in data.names():
        raise UsageError(
            f"{what} {text!r}: no shipped file {name!r}{suggest(name, data.names())}; "
            f"shipped: {', '.join(DATA_PREFIX + n for n in data.names())}"
        )
    return os.fspath(data.path(name))


def input_file(text: str) -> str:
    """argparse type of every option naming a file to read: :func:`data_file`."""
    try:
        return data_file(text)
    except UsageError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def suggest(name: str, choices: Iterable[str]) -> str:
    """``" (did you mean a?)"`` or ``" (did you mean a or b?)"`` with the closest of
    ``choices`` to ``name``, or ``""`` when none is close."""
    close = difflib.get_close_matches(name, list(choices), n=3, cutoff=0.6)
    if not close:
        return ""
    return f" (did you mean {' or '.join(close)}?)"


def known_id(name: str, choices: Iterable[str], option: str = "--model") -> str:
    """``name`` if it is one of ``choices``; otherwise a UsageError naming the closest ones
    and every accepted name."""
    choices = list(choices)
    if name in choices:
        return name
    from ..io.reading import short

    raise UsageError(
        f"{option}: unknown model {short(name)}{suggest(name, choices)}; "
        f"choose one of: {', '.join(choices)}"
    )


def _number_with_unit(text: str) -> float:
    """Degrees from ``"20"``, ``"20deg"``, ``"20°"`` or ``"0.35rad"``."""
    t = text.strip().lower()
    radians = t.endswith("rad")
    if radians:
        t = t[: -len("rad")]
    else:
        t = t.removesuffix("deg").removesuffix("°")
    value = float(t)  # ValueError for anything else
    degrees = math.degrees(value) if radians else value
    if not math.isfinite(degrees):  # 1e308rad is ∞ degrees
        raise ParameterError(text)
    return degrees


def angle(text: str) -> float:
    """argparse type of an angle option: a number of degrees, or with a ``deg`` or ``rad``
    suffix (``30``, ``30deg``, ``0.52rad``); returns degrees."""
    try:
        return _number_with_unit(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"expected an angle in degrees, or with a unit: 30, 30deg, 0.52rad (got {text!r})"
        ) from None


def angle_list(text: str) -> list[float]:
    """argparse type of a list of angles: ``10,20,30`` or ``0.1rad,0.2rad`` (degrees)."""
    parts = [p for p in text.replace(",", " ").split() if p]
    try:
        vals = [_number_with_unit(p) for p in parts]
    except ValueError:
        vals = []
    if not vals:
        raise argparse.ArgumentTypeError(
            f"expected comma-separated angles in degrees, or with a unit: 10,20 or 0.2rad "
            f"(got {text!r})"
        )
    return vals


GEOMETRY_HELP = (
    "Angles in DEGREES, or with a unit (30deg, 0.52rad); Δφ = 0 puts the viewer on the "
    "light's side of the plane of incidence, 180 opposite it."
)


def geometry_arguments(
    parser: argparse.ArgumentParser, theta_i: float, theta_r: float, delta_phi: float = 0.0
) -> None:
    """--theta-i, --theta-r and --delta-phi (angles, :func:`angle`), their defaults in the
    help; the parsed values are ``None`` when not given (see :func:`geometry_used`)."""
    g = parser.add_argument_group("geometry", GEOMETRY_HELP)
    for flag, what, default, rng in (
        ("--theta-i", "incidence angle θi", theta_i, "[0, 90]"),
        ("--theta-r", "viewing angle θr", theta_r, "[0, 90]"),
        ("--delta-phi", "azimuth Δφ = φr − φi", delta_phi, "(any)"),
    ):
        g.add_argument(
            flag,
            type=angle,
            default=None,
            metavar="ANGLE",
            help=f"{what}, degrees {rng} (default: {default:g})",
        )
    parser.set_defaults(_geometry_defaults=(theta_i, theta_r, delta_phi))


def geometry_used(args: argparse.Namespace) -> str:
    """Fill in the geometry defaults in ``args`` and describe what is used, e.g.
    ``"θi = 30°, θr = 0° (default), Δφ = 0° (default)"``."""
    parts = []
    for name, sym, default in zip(
        ("theta_i", "theta_r", "delta_phi"),
        ("θi", "θr", "Δφ"),
        args._geometry_defaults,
        strict=True,
    ):
        value = getattr(args, name)
        note = ""
        if value is None:
            value, note = default, " (default)"
        if name == "delta_phi" and not -360.0 < value < 360.0:
            # reduced exactly (fmod is exact) before radians: radians(1e308) keeps no phase
            note = f" (≡ {math.fmod(value, 360.0):g}° mod 360)"
            setattr(args, name, math.fmod(value, 360.0))
        else:
            setattr(args, name, value)
        parts.append(f"{sym} = {value:g}°{note}")
    return ", ".join(parts)


def angle_pair(text: str) -> tuple[float, float]:
    """argparse type of ``THETA,PHI``: two angles (degrees or with ``rad``/``deg``); PHI
    defaults to 0. Returns degrees."""
    parts = [p for p in text.replace(",", " ").split() if p]
    try:
        vals = [_number_with_unit(p) for p in parts]
    except ValueError:
        vals = []
    if len(vals) == 1:
        vals.append(0.0)
    if len(vals) != 2:
        raise argparse.ArgumentTypeError(
            f"expected THETA,PHI in degrees, or with a unit: 30,90 or 0.52rad,0 (got {text!r})"
        )
    return vals[0], vals[1]
