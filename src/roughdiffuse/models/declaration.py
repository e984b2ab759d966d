"""How a model declares its parameters, once; validation, the CLI, fits and the explorer read it.

A model class lists its parameters as :class:`Param` records in its ``params`` class attribute
(see :class:`roughdiffuse.models.base.Model` and :mod:`roughdiffuse.registry`)::

    params = (
        Param("albedo", "facet albedo ρ", min=0.0, max=1.0, default=1.0, channels=True),
        Param("sigma", "slope-angle standard deviation σ", unit="radians",
              min=0.0, max=math.pi / 2, default=0.0),
    )

From this the constructor's checks (a ``ValueError`` naming the parameter, its unit and its
range), the pytree leaves (numeric parameters), the colour-channel parameters, the command
line's ``--param NAME=VALUE`` (degrees for radians), fit bounds and ``roughdiffuse models``
are derived. This module is a leaf: it imports NumPy only.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Param", "Unit", "UNITS", "format_interval"]

Unit = str
UNITS: tuple[str, ...] = ("dimensionless", "radians")
"""The units a parameter may have; the command line accepts degrees for ``"radians"``."""


def _fmt(x: float) -> str:
    if x == math.pi / 2:
        return "π/2"
    if x == math.pi:
        return "π"
    return f"{x:g}"


def format_interval(lo: float | None, hi: float | None, lo_open: bool = False) -> str:
    """``[0, 1]``, ``(0, 1000]``, ``[0, ∞)``: an interval as messages and tables show it.

    An infinite end is always open (∞ is not a value a parameter can take).

    >>> format_interval(0.0, None)
    '[0, ∞)'
    >>> format_interval(0.0, 1e3, lo_open=True)
    '(0, 1000]'
    """
    left = "(-∞" if lo is None else f"{'(' if lo_open else '['}{_fmt(lo)}"
    right = "∞)" if hi is None else f"{_fmt(hi)}]"
    return f"{left}, {right}"


def _describe(value: Any) -> str:
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


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
        Value when the parameter is not given (the dataclass field's default agrees; a test
        checks it).
    channels : bool
        The value may be a 1-D array with one value per colour channel (albedo).
    choices : tuple of str or None
        The values of a categorical parameter (e.g. the Oren–Nayar variant); ``None`` for a
        numeric one.
    min_open : bool
        Exclude ``min`` (η > 0).
    when : mapping or None
        The parameter exists only for these values of categorical parameters, e.g.
        ``{"distribution": "gaussian"}``; otherwise it must be left unset (``None``).
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
    when: Mapping[str, str] | None = field(default=None, hash=False)
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
        """Whether the parameter exists for these categorical values (see ``when``)."""
        return not self.when or all(values.get(k) == v for k, v in self.when.items())

    def range_text(self) -> str:
        """``in [0, π/2] radians``: the range and unit as the error messages say it."""
        unit = "" if self.unit == "dimensionless" else f" {self.unit}"
        return f"in {self.interval}{unit}"

    # ------------------------------------------------------------------ checking
    def check(self, value: Any) -> Any:
        """Return ``value`` checked (and lists turned into arrays); raise ``ValueError`` if bad.

        Refused: ``None``, booleans, strings and other non-numbers, NaN and ±∞, values out of
        the range, arrays with more than one axis (more than zero unless ``channels``). Values
        with no concrete value (JAX tracers inside ``jit``) pass unchecked.

        >>> Param("k", "exponent", min=0.0, max=2.0, default=1.0).check(0.5)
        0.5
        >>> Param("k", "exponent", min=0.0, max=2.0, default=1.0).check(True)
        Traceback (most recent call last):
        ...
        ValueError: k must be a real number in [0, 2] (got True)
        """
        if self.choices is not None:
            if not isinstance(value, str) or value not in self.choices:
                raise ValueError(
                    f"{self.name} must be one of {', '.join(map(repr, self.choices))} "
                    f"(got {_describe(value)})"
                )
            return value
        bad = f"{self.name} must be a real number {self.range_text()}"
        if self.channels:
            bad = f"{self.name} must be a real number or one per channel, {self.range_text()}"
        if value is None or isinstance(value, bool | np.bool_ | str | bytes):
            raise ValueError(f"{bad} (got {_describe(value)})")
        if isinstance(value, list | tuple):
            if not self.channels:
                raise ValueError(f"{self.name} must be a scalar (got a {type(value).__name__})")
            if any(v is None or isinstance(v, bool | np.bool_ | str | bytes) for v in value):
                raise ValueError(f"{bad} (got {_describe(value)})")
            try:
                value = np.asarray(value, dtype=np.float64)
            except (TypeError, ValueError):
                raise ValueError(f"{bad} (got {_describe(value)})") from None
        arr = _concrete(value)
        if arr is None:
            return value
        if arr.dtype.kind not in "iuf":
            raise ValueError(f"{bad} (got {_describe(value)})")
        if self.channels:
            if arr.ndim > 1:
                raise ValueError(
                    f"{self.name} must be a scalar or a 1-D array of channel values "
                    f"(got shape {arr.shape})"
                )
            if arr.ndim == 1 and arr.shape[0] == 0:
                raise ValueError(f"{self.name} must hold at least one channel value")
        elif arr.ndim != 0:
            raise ValueError(f"{self.name} must be a scalar (got shape {arr.shape})")
        a = arr.astype(np.float64)
        out = ~np.isfinite(a)
        if self.min is not None:
            out |= (a <= self.min) if self.min_open else (a < self.min)
        if self.max is not None:
            out |= a > self.max
        if np.any(out):
            shown = a[out].flat[0] if a.ndim else float(a)
            per = " (per channel)" if self.channels and a.ndim else ""
            raise ValueError(f"{self.name} must be {self.range_text()}{per} (got {shown:g})")
        return value

    # ------------------------------------------------------------------ export
    def to_json(self) -> dict[str, Any]:
        """The JSON record of ``roughdiffuse models --json`` and the explorer's ``/api/models``.

        Infinite or absent bounds are ``null``; ``choices`` is ``null`` for a numeric
        parameter, ``min``/``max`` are ``null`` for a categorical one.
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
        }


def _concrete(x: Any) -> np.ndarray | None:
    """``x`` as a NumPy array when its value is known now, else ``None`` (a JAX tracer or
    another array-API object with no value yet). Non-numbers come out with dtype object."""
    module = type(x).__module__
    if module.startswith("jax"):
        import jax

        return None if isinstance(x, jax.core.Tracer) else np.asarray(x)
    if module.startswith("torch"):
        return x.detach().cpu().numpy()
    if hasattr(x, "__array_namespace__") and not isinstance(x, np.ndarray | np.generic):
        return None  # another array-API object (the fast path's symbolic values)
    try:
        return np.asarray(x)
    except Exception:  # noqa: BLE001 - a value NumPy cannot read is not a number
        return np.asarray(None)
