"""Parameters valid one by one but not together: each model's combination rules.

A model's declared box (:class:`~roughdiffuse.models.declaration.Param`) checks each
parameter alone. Where a combination inside the box is meaningless, the class lists a
:class:`Constraint` in its ``constraints``, which :meth:`Model._validate
<roughdiffuse.models.base.Model._validate>` checks after every parameter: a refusal names the
parameters together, their values and what goes wrong.

* :data:`LEGENDRE_PHASE_NON_NEGATIVE` (``hapke-legendre``): ISIS's Legendre phase function
  p(g) = 1 + b cos g + c P2(cos g) must not be negative at any phase. With x = cos g in
  [−1, 1], p is a parabola in x: its least value is at x = ±1 (1 ± b + c) or, for c > 0, at
  its vertex x = −b/(3c) inside [−1, 1] (1 − b²/(6c) − c/2). b = c = −1, each in its range,
  gives p(0) = −1 and a negative BRDF.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import ParameterError

__all__ = ["LEGENDRE_PHASE_NON_NEGATIVE", "Constraint", "check_constraints", "legendre_minimum"]


@dataclass(frozen=True)
class Constraint:
    """A rule on several parameters together.

    Attributes
    ----------
    names : tuple of str
        The declared parameters it joins (named in the refusal).
    holds : callable
        ``holds(**values)``: true (for every channel) where the combination is accepted.
    what : str
        What goes wrong otherwise, for the message.
    """

    names: tuple[str, ...]
    holds: Callable[..., Any]
    what: str

    def check(self, model: Any) -> None:
        """Refuse ``model`` if its values of :attr:`names` break the rule (``ValueError``);
        a parameter left ``None`` (not applicable), or with no concrete value, skips it."""
        raw = {n: getattr(model, n, None) for n in self.names}
        if any(v is None for v in raw.values()):
            return
        try:
            values = {n: np.asarray(v, dtype=float) for n, v in raw.items()}
        except Exception:  # noqa: BLE001 - no concrete value (a JAX tracer inside jit, a
            return  # tensor with a gradient): unchecked, as Param.check leaves it
        if not bool(np.all(self.holds(**values))):
            given = ", ".join(f"{n}={_shown(v)}" for n, v in values.items())
            raise ParameterError(
                f"{' and '.join(self.names)} together: {self.what} (got {given})"
            )


def _shown(value: Any) -> str:
    arr = np.asarray(value, dtype=float)
    return f"{float(arr):g}" if arr.ndim == 0 else "[" + ", ".join(f"{v:g}" for v in arr) + "]"


def check_constraints(model: Any) -> None:
    """Check every :class:`Constraint` of ``type(model).constraints``."""
    for constraint in getattr(type(model), "constraints", ()):
        constraint.check(model)


def legendre_minimum(b: Any, c: Any) -> Any:
    """The least value of 1 + b x + c (3x² − 1)/2 over x in [−1, 1] (see the module)."""
    b, c = np.asarray(b, dtype=float), np.asarray(c, dtype=float)
    ends = np.minimum(1.0 + b + c, 1.0 - b + c)
    safe_c = np.where(c > 0, c, 1.0)
    vertex_inside = (c > 0) & (np.abs(b) <= 3.0 * safe_c)
    vertex = 1.0 - b * b / (6.0 * safe_c) - 0.5 * c
    return np.where(vertex_inside, np.minimum(ends, vertex), ends)


LEGENDRE_PHASE_NON_NEGATIVE = Constraint(
    ("bh", "ch"),
    lambda bh, ch: legendre_minimum(bh, ch) >= 0.0,
    "the Legendre phase function 1 + b cos g + c P2(cos g) is negative at some phase "
    "(its least value 1 ± b + c, or 1 − b²/(6c) − c/2 for c > 0, must be ≥ 0)",
)
