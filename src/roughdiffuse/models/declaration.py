"""How a model declares its parameters, once; validation, the CLI, fits and the explorer read it.

A model class declares each parameter once, as a field whose default is :func:`param` (as
astropy.modeling's ``Parameter``; see :class:`roughdiffuse.models.base.Model` and
:mod:`roughdiffuse.registry`)::

    albedo: float | Array = param("facet albedo ρ", min=0.0, max=1.0, default=1.0,
                                  channels=True)
    sigma: float | Array = param("slope-angle standard deviation σ", unit="radians",
                                 min=0.0, max=math.pi / 2, default=0.0)

The class's ``params`` (a tuple of :class:`Param` records, in field order) is derived from
these fields. The arguments of a ``from_params`` factory that are not fields
(:class:`~roughdiffuse.models.mix.Mix`) are :class:`Param` records in the class's
``factory_params``, first in ``params``. From this the constructor's checks (a
:class:`~roughdiffuse._validate.ParameterError`, a ``ValueError``, naming the parameter, its
unit and its range), the pytree leaves (numeric parameters), the colour-channel parameters,
the command line's options (``--NAME`` and ``--param NAME=VALUE``, degrees for radians), fit
bounds and ``roughdiffuse models`` are derived. This module is a leaf: it imports
:mod:`roughdiffuse._validate` only.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import MISSING, dataclass, field
from typing import Any

from .._validate import ParameterError, check_real, describe_value, format_interval

__all__ = ["Param", "Unit", "UNITS", "albedo_param", "param", "declared_params"]

_SPEC = "roughdiffuse.param"
"""The key of a field's metadata holding its declaration (the keywords of :class:`Param`)."""

Unit = str
UNITS: tuple[str, ...] = ("dimensionless", "radians")
"""The units a parameter may have; the command line accepts degrees for ``"radians"``."""


@dataclass(frozen=True)
class Param:
    """One parameter of a model: its name, meaning, unit, accepted range and default.

    Parameters
    ----------
    name : str
        The dataclass field (and keyword argument) it is stored in.
    description : str
        What it means, with its symbol (shown by ``roughdiffuse models`` and ``--help``).
    unit : {"dimensionless", "radians"}
        Radians parameters take degrees on the command line.
    min, max : float or None
        Accepted interval, ends included (``min`` excluded when ``min_open``); ``None`` for an
        unbounded end. ``None`` for both in a categorical parameter.
    default : float or str
        Value when the parameter is not given (the dataclass field's default, declared by
        :func:`param`).
    channels : bool
        The value may be a 1-D array with one value per colour channel (albedo).
    choices : tuple of str or None
        The values of a categorical parameter (e.g. the Oren–Nayar variant); ``None`` for a
        numeric one.
    min_open : bool
        Exclude ``min`` (η > 0).
    when : mapping or None
        The parameter exists only for these values of categorical parameters, e.g.
        ``{"distribution": "gaussian"}``, or for any of several values, e.g.
        ``{"base": ("fujii", "eon")}``; otherwise it must be left unset (``None``).
    fit_range : (float, float) or None
        The box a fit searches by default (finite); ``None``: ``[min, max]``. Narrower where
        the accepted range is unbounded (η) or has a degenerate end (σ = 0 is a mirror).
    example : float or None
        A typical value, where the command line and the explorer start when the user gives
        none (σ = 20° shows roughness where the default σ = 0 is Lambert); ``None``: the
        default.
    """

    name: str
    description: str
    unit: Unit = "dimensionless"
    min: float | None = None
    max: float | None = None
    default: float | str | None = None
    channels: bool = False
    choices: tuple[str, ...] | None = None
    min_open: bool = False
    when: Mapping[str, str | tuple[str, ...]] | None = field(default=None, hash=False)
    example: float | None = None
    fit_range: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        if self.unit not in UNITS:
            raise ValueError(f"Param {self.name}: unit must be one of {UNITS} (got {self.unit!r})")
        if self.choices is not None and self.default not in self.choices:
            raise ValueError(f"Param {self.name}: default {self.default!r} is not a choice")
        if self.choices is None:
            for value in (self.default, self.example):
                if value is not None:
                    self.check(value)  # a declaration error shows at import

    # ------------------------------------------------------------------ properties
    @property
    def categorical(self) -> bool:
        """True for a parameter with named choices (a static field, not a pytree leaf)."""
        return self.choices is not None

    @property
    def bounds(self) -> tuple[float, float] | None:
        """The default fit box: ``fit_range``, else ``(min, max)`` if both are finite."""
        if self.fit_range is not None:
            return (float(self.fit_range[0]), float(self.fit_range[1]))
        if self.choices is None and self.min is not None and self.max is not None:
            return (float(self.min), float(self.max))
        return None

    @property
    def interval(self) -> str:
        """The accepted interval as text, e.g. ``[0, π/2]`` (choices for a categorical one)."""
        if self.choices is not None:
            return "{" + ", ".join(repr(c) for c in self.choices) + "}"
        return format_interval(self.min, self.max, self.min_open)

    def applies(self, values: Mapping[str, Any]) -> bool:
        """Whether the parameter exists for these categorical values (see ``when``).

        >>> p = Param("r", "roughness", min=0.0, max=1.0, default=0.5, when={"base": ("a", "b")})
        >>> p.applies({"base": "b"}), p.applies({"base": "c"})
        (True, False)
        """
        return not self.when or all(
            values.get(k) in (v if isinstance(v, tuple) else (v,)) for k, v in self.when.items()
        )

    def when_text(self) -> str:
        """``base='eon'`` or ``base in {'fujii', 'eon'}``: where the parameter exists, as the
        error messages say it (empty without ``when``)."""
        return ", ".join(
            f"{k} in {{{', '.join(map(repr, v))}}}" if isinstance(v, tuple) else f"{k}={v!r}"
            for k, v in (self.when or {}).items()
        )

    def range_text(self) -> str:
        """``in [0, π/2] radians``: the range and unit as the error messages say it."""
        unit = "" if self.unit == "dimensionless" else f" {self.unit}"
        return f"in {self.interval}{unit}"

    # ------------------------------------------------------------------ checking
    def check(self, value: Any) -> Any:
        """Return ``value`` checked (and lists turned into arrays); raise
        :class:`~roughdiffuse._validate.ParameterError` (a ``ValueError``) if bad.

        Refused: ``None``, booleans, strings and other non-numbers, NaN and ±∞, values out of
        the range, arrays with more than one axis (more than zero unless ``channels``). Values
        with no concrete value (JAX tracers inside ``jit``) pass unchecked. The numeric check
        is :func:`roughdiffuse._validate.check_real`, the one :func:`check_range
        <roughdiffuse._validate.check_range>` makes too.

        >>> Param("k", "exponent", min=0.0, max=2.0, default=1.0).check(0.5)
        0.5
        >>> Param("k", "exponent", min=0.0, max=2.0, default=1.0).check(True)
        Traceback (most recent call last):
        ...
        roughdiffuse._validate.ParameterError: k must be a real number in [0, 2] (got True)
        """
        if self.choices is not None:
            if not isinstance(value, str) or value not in self.choices:
                raise ParameterError(
                    f"{self.name} must be one of {', '.join(map(repr, self.choices))} "
                    f"(got {describe_value(value)})"
                )
            return value
        return check_real(
            self.name,
            value,
            self.min,
            self.max,
            lo_open=self.min_open,
            unit=self.unit,
            channels=self.channels,
        )

    # ------------------------------------------------------------------ export
    def to_json(self) -> dict[str, Any]:
        """The JSON record of ``roughdiffuse models --json`` and the explorer's ``/api/models``.

        Infinite or absent bounds are ``null``; ``choices`` is ``null`` for a numeric
        parameter, ``min``/``max`` are ``null`` for a categorical one; ``when`` maps each
        categorical parameter the parameter depends on to the list of values it exists for
        (``null``: always).
        """
        return {
            "name": self.name,
            "description": self.description,
            "unit": self.unit,
            "min": self.min,
            "max": self.max,
            "min_open": self.min_open,
            "default": self.default,
            "example": self.default if self.example is None else self.example,
            "channels": self.channels,
            "choices": list(self.choices) if self.choices is not None else None,
            "fit_range": list(self.fit_range) if self.fit_range is not None else None,
            "when": {
                k: list(v) if isinstance(v, tuple) else [v] for k, v in self.when.items()
            } if self.when else None,
        }


def param(
    description: str,
    *,
    default: float | str | None,
    unit: Unit = "dimensionless",
    min: float | None = None,  # noqa: A002 - Param's own names
    max: float | None = None,  # noqa: A002
    channels: bool = False,
    choices: tuple[str, ...] | None = None,
    min_open: bool = False,
    when: Mapping[str, str | tuple[str, ...]] | None = None,
    example: float | None = None,
    fit_range: tuple[float, float] | None = None,
    unset: Any = MISSING,
) -> Any:
    """A model's parameter, declared once: the dataclass field and its :class:`Param`.

    Returns a :func:`dataclasses.field` whose default is ``default`` (``unset`` instead,
    where given) and whose metadata holds the declaration; the class's ``params`` is built
    from these fields (:func:`declared_params`), the field's name being the parameter's.
    The keywords are those of :class:`Param`.

    ``unset``: the field's default when it differs from the declared default, for a
    parameter that exists only for some choices (``when``) and that ``__post_init__`` fills
    in (Torrance–Sparrow's ``alpha`` is ``None`` until derived from σ).

    >>> import dataclasses
    >>> f = param("exponent k", default=1.0, min=0.0, max=2.0)
    >>> f.default
    1.0
    """
    if unset is not MISSING and when is None:
        raise TypeError("param(unset=...) is for a parameter that exists only for some choices "
                        "(when=...); the field's default is otherwise the declared default")
    spec = {
        "description": description,
        "unit": unit,
        "min": min,
        "max": max,
        "default": default,
        "channels": channels,
        "choices": choices,
        "min_open": min_open,
        "when": when,
        "example": example,
        "fit_range": fit_range,
    }
    return field(default=default if unset is MISSING else unset, metadata={_SPEC: spec})


def albedo_param(description: str, *, default: float = 1.0, example: float | None = 0.8) -> Any:
    """The albedo most models take: a :func:`param` in [0, 1], one value per colour channel
    allowed (``albedo: float | Array = albedo_param("facet albedo ρ")``).

    >>> import dataclasses
    >>> albedo_param("albedo ρ").metadata["roughdiffuse.param"]["channels"]
    True
    """
    return param(description, min=0.0, max=1.0, default=default, channels=True, example=example)


def declared_params(fields: Any) -> tuple[Param, ...]:
    """The :class:`Param` of each field declared by :func:`param`, in field order.

    ``fields``: the class's :func:`dataclasses.fields`. A declaration error (a default out
    of its range, a unit not in :data:`UNITS`) raises here, when the class is defined.
    """
    return tuple(Param(f.name, **f.metadata[_SPEC]) for f in fields if _SPEC in f.metadata)
