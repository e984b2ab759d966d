"""Weighted sums of models: rough surfaces with diffuse and surface reflection.

The lecture's summary ("many surfaces may be rough and show both diffuse and surface
reflection"): for example ``Mix([(0.9, OrenNayar(0.8, 0.3)), (0.1, TorranceSparrow())])``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array
from .._validate import check_range
from .base import Model, register_pytree

__all__ = ["Mix"]


@register_pytree
@dataclass(frozen=True)
class Mix(Model):
    """f = Σ_k w_k f_k.

    Parameters
    ----------
    components : sequence of (weight, model)
        Non-negative weights (they need not sum to 1) and models.

    Examples
    --------
    >>> from roughdiffuse import Lambert
    >>> import numpy as np
    >>> m = Mix([(0.5, Lambert(1.0)), (0.5, Lambert(0.0))])
    >>> w = np.array([0.0, 0.0, 1.0])
    >>> round(float(m.brdf(w, w)) * np.pi, 12)
    0.5
    """

    components: Sequence[tuple[Any, Model]] = ()

    array_fields: ClassVar[tuple[str, ...]] = ("components",)

    def __post_init__(self) -> None:
        comps = tuple((w, m) for w, m in self.components)
        if not comps:
            raise ValueError("components must hold at least one (weight, model) pair")
        for k, (w, m) in enumerate(comps):
            check_range(f"components[{k}] weight", w, 0.0, float("inf"))
            if not isinstance(m, Model):
                raise ValueError(f"components[{k}] must be a (weight, Model) pair (got {m!r})")
        object.__setattr__(self, "components", comps)

    def _param_values(self) -> list[Any]:
        vals: list[Any] = []
        for w, m in self.components:
            vals.append(w)
            vals.extend(m._param_values())
        return vals

    def _params(self, xp: Any, dtype: Any) -> dict[str, Array]:
        return {}  # the parameters live in the components

    @property
    def channels(self) -> int:
        return max(m.channels for _, m in self.components)

    def _eval(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, dtype: Any) -> Array:
        total = None
        ch = self.channels
        for w, m in self.components:
            f = m._eval(xp, mu_i, mu_o, cos_io, dtype)
            if ch and not m.channels:
                f = f[..., None]
            term = f * w
            total = term if total is None else total + term
        return total
