"""Input checks that name the parameter and the accepted range: the one validation path.

:meth:`roughdiffuse.models.declaration.Param.check` (a model's declared parameters) and
:func:`check_range` (the solvers', renderers' and simulations' own arguments) both refuse a
value here, with :class:`ParameterError` and the same wording. This module is a leaf (NumPy
and :mod:`roughdiffuse._array` only), so every floor of the package may use it.

Every check runs on concrete values only (see :func:`roughdiffuse._array.concrete`): inside
``jax.jit`` the values are not known and the checks are skipped, so validate before tracing.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._array import concrete

__all__ = [
    "ParameterError",
    "check_range",
    "check_real",
    "describe_value",
    "format_interval",
    "format_number",
]


class ParameterError(ValueError):
    """A value given to roughdiffuse that it refuses: a parameter outside its accepted range,
    an option or a file's contents that cannot be used.

    A ``ValueError``, so callers that catch ``ValueError`` keep working. The command line
    reports it as bad input (one line, exit status 2); any other exception, including a
    ``ValueError`` raised inside NumPy or SciPy, is a bug (exit status 1).
    """


def format_number(x: float) -> str:
    """A range end as messages and tables show it: ``π/2``, ``π``, ``∞``, ``-∞``, or ``%g``."""
    if x == math.pi / 2:
        return "π/2"
    if x == math.pi:
        return "π"
    if math.isinf(x):
        return "∞" if x > 0 else "-∞"
    return f"{x:g}"


def format_interval(lo: float | None, hi: float | None, lo_open: bool = False) -> str:
    """``[0, 1]``, ``(0, 1000]``, ``[0, ∞)``: an interval as messages and tables show it.

    An infinite or absent (``None``) end is always open (∞ is not a value a parameter can take).

    >>> format_interval(0.0, None)
    '[0, ∞)'
    >>> format_interval(0.0, 1e3, lo_open=True)
    '(0, 1000]'
    """
    if lo is None or lo == -math.inf:
        left = "(-∞"
    else:
        left = f"{'(' if lo_open else '['}{format_number(lo)}"
    right = "∞)" if hi is None or hi == math.inf else f"{format_number(hi)}]"
    return f"{left}, {right}"


def describe_value(value: Any) -> str:
    """``repr(value)`` cut to 60 characters, for the ``(got ...)`` of a message."""
    text = repr(value)
    return text if len(text) <= 60 else text[:57] + "..."


def _not_a_number(value: Any) -> bool:
    return value is None or isinstance(value, bool | np.bool_ | str | bytes)


def check_real(
    name: str,
    value: Any,
    lo: float | None,
    hi: float | None,
    *,
    lo_open: bool = False,
    unit: str = "",
    channels: bool = False,
    any_shape: bool = False,
) -> Any:
    """Return ``value`` checked (lists turned into arrays); raise :class:`ParameterError`
    unless it is real, finite and in the interval.

    Refused: ``None``, booleans, strings and other non-numbers, NaN and ±∞, values out of the
    range, arrays with more than one axis (more than zero unless ``channels``, any number
    with ``any_shape``). Values with no concrete value (JAX tracers inside ``jit``) pass
    unchecked.

    Parameters
    ----------
    name : str
        Parameter name used in the message.
    value : scalar or array
        The value to check.
    lo, hi : float or None
        Interval ends, included (``lo`` excluded when ``lo_open``); ``None`` or ±∞ for an
        unbounded end.
    unit : str
        Unit named in the message (``"radians"``); ``""`` or ``"dimensionless"`` for none.
    channels : bool
        Allow a 1-D array (one value per colour channel) as well as a scalar.
    any_shape : bool
        Allow an array of any shape (every entry is checked).
    """
    where = "" if unit in ("", "dimensionless") else f" {unit}"
    range_text = f"in {format_interval(lo, hi, lo_open)}{where}"
    bad = f"{name} must be a real number {range_text}"
    if channels:
        bad = f"{name} must be a real number or one per channel, {range_text}"
    if _not_a_number(value):
        raise ParameterError(f"{bad} (got {describe_value(value)})")
    if isinstance(value, list | tuple):
        if not (channels or any_shape):
            raise ParameterError(f"{name} must be a scalar (got a {type(value).__name__})")
        if any(_not_a_number(v) for v in value):
            raise ParameterError(f"{bad} (got {describe_value(value)})")
        try:
            value = np.asarray(value, dtype=np.float64)
        except (TypeError, ValueError):
            raise ParameterError(f"{bad} (got {describe_value(value)})") from None
    arr = concrete(value, non_numbers=True)
    if arr is None:
        return value
    if arr.dtype.kind not in "iuf":
        raise ParameterError(f"{bad} (got {describe_value(value)})")
    if channels and not any_shape:
        if arr.ndim > 1:
            raise ParameterError(
                f"{name} must be a scalar or a 1-D array of channel values (got shape {arr.shape})"
            )
        if arr.ndim == 1 and arr.shape[0] == 0:
            raise ParameterError(f"{name} must hold at least one channel value")
    elif not any_shape and arr.ndim != 0:
        raise ParameterError(f"{name} must be a scalar (got shape {arr.shape})")
    a = arr.astype(np.float64)
    out = ~np.isfinite(a)
    if lo is not None:
        out |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        out |= a > hi
    if np.any(out):
        shown = a[out].flat[0] if a.ndim else float(a)
        per = " (per channel)" if channels and a.ndim else ""
        raise ParameterError(f"{name} must be {range_text}{per} (got {shown:g})")
    return value


def check_range(
    name: str,
    value: object,
    lo: float,
    hi: float,
    *,
    lo_open: bool = False,
    unit: str = "",
    scalar: bool = True,
    channels: bool = False,
) -> None:
    """Raise :class:`ParameterError` (a ``ValueError``) unless every entry of ``value`` lies in
    the interval: :func:`check_real`, the check of :meth:`Param.check
    <roughdiffuse.models.declaration.Param.check>`, for an argument that is not a model
    parameter.

    Parameters
    ----------
    name : str
        Parameter name used in the message.
    value : scalar or array
        Value to check; skipped when it has no concrete value (JAX tracer).
    lo, hi : float
        Interval ends; ``hi`` is included unless infinite, ``lo`` unless ``lo_open``.
    unit : str
        Unit named in the message (e.g. ``"radians"``).
    scalar : bool
        Require a scalar (0-d) value; ``False`` accepts an array of any shape.
    channels : bool
        Allow a 1-D array (one value per colour channel) as well as a scalar.
    """
    check_real(
        name,
        value,
        lo,
        hi,
        lo_open=lo_open,
        unit=unit,
        channels=channels,
        any_shape=not (scalar or channels),
    )
