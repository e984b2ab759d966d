"""Input checks that name the parameter and the accepted range.

Every check runs on concrete values only (see :func:`roughdiffuse._array.concrete`): inside
``jax.jit`` the values are not known and the checks are skipped, so validate before tracing.
"""

from __future__ import annotations

import math

import numpy as np

from ._array import concrete


class ParameterError(ValueError):
    """A parameter outside its accepted range (raised by the checks here).

    A ``ValueError``, so callers that catch ``ValueError`` keep working; the CLI tells it
    apart from a ``ValueError`` raised inside NumPy or SciPy, which would be a bug.
    """


def _fmt(x: float) -> str:
    if x == math.pi / 2:
        return "π/2"
    if x == math.inf:
        return "∞"
    return f"{x:g}"


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
    the interval.

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
        Require a scalar (0-d) value.
    channels : bool
        Allow a 1-D array (one value per colour channel) as well as a scalar.
    """
    arr = concrete(value)
    if arr is None:
        return
    right = "∞)" if hi == math.inf else f"{_fmt(hi)}]"  # ∞ is never a value: open
    interval = f"{'(' if lo_open else '['}{_fmt(lo)}, {right}"
    where = f" {unit}" if unit else ""
    if arr.dtype.kind not in "biuf":
        raise ParameterError(f"{name} must be a real number in {interval}{where} (got {value!r})")
    if channels:
        if arr.ndim > 1:
            raise ParameterError(
                f"{name} must be a scalar or a 1-D array of channel values (got shape {arr.shape})"
            )
    elif scalar and arr.ndim != 0:
        raise ParameterError(f"{name} must be a scalar (got shape {arr.shape})")
    a = arr.astype(np.float64)
    bad = ~np.isfinite(a) | (a > hi) | ((a <= lo) if lo_open else (a < lo))
    if np.any(bad):
        shown = a[bad].flat[0] if a.ndim else float(a)
        per = " (per channel)" if channels and a.ndim else ""
        raise ParameterError(f"{name} must be in {interval}{where}{per} (got {shown:g})")
