"""Weighted sums of models: rough surfaces with diffuse and surface reflection.

The lecture's summary ("many surfaces may be rough and show both diffuse and surface
reflection"): for example ``Mix([(0.9, OrenNayar(0.8, 0.3)), (0.1, TorranceSparrow())])``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array
from .._validate import check_range
from .base import Model, register_pytree
from .declaration import Param
from .oren_nayar import SIGMA_MAX, OrenNayar
from .torrance_sparrow import ETA_MAX, TorranceSparrow

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

    components: Sequence[tuple[float | Array, Model]] = ()

    array_fields: ClassVar[tuple[str, ...]] = ("components",)
    channel_fields: ClassVar[tuple[str, ...]] = ()
    # The registry's "mix" is the lecture's rough surface with diffuse and surface reflection,
    # (1 − w) Oren–Nayar full + w Torrance–Sparrow with one σ (see from_params); these are its
    # parameters, not fields of the class.
    params: ClassVar[tuple[Param, ...]] = (
        Param("albedo", "facet albedo ρ of the diffuse part", min=0.0, max=1.0, default=1.0,
              channels=True, example=0.8),
        Param("sigma", "σ, slope-angle standard deviation of both parts", unit="radians",
              min=0.0, max=SIGMA_MAX, default=0.2, example=math.radians(20.0)),
        Param("weight", "w, weight of the specular part", min=0.0, max=1.0, default=0.1),
        Param("eta", "relative refractive index η of the specular part", min=0.0, max=ETA_MAX,
              min_open=True, default=1.5, fit_range=(1.0, 3.0)),
        Param("distribution", "facet distribution of the specular part (Beckmann: α = √2 σ)",
              choices=("gaussian", "beckmann"), default="gaussian"),
    )
    ids: ClassVar[dict[str, dict[str, Any]]] = {"mix": {}}
    labels: ClassVar[dict[str, str]] = {"mix": "Mix: Oren–Nayar full + Torrance–Sparrow"}
    reference: ClassVar[str] = "weighted sum of models (Mitsuba 3 blendbsdf)"
    glsl: ClassVar[bool] = True

    @classmethod
    def from_params(
        cls,
        albedo: float | Array = 1.0,
        sigma: float | Array = 0.2,
        weight: float | Array = 0.1,
        eta: float | Array = 1.5,
        distribution: str = "gaussian",
    ) -> Mix:
        """The registry's ``mix``: (1 − w) OrenNayar(ρ, σ, "full") + w TorranceSparrow(η, σ).

        With ``distribution="beckmann"`` the specular part has α = √2 σ (the explorer's
        reading: the same small-slope width as the Gaussian).

        >>> m = Mix.from_params(albedo=0.5, sigma=0.3, weight=0.25)
        >>> [round(float(w), 2) for w, _ in m.components]
        [0.75, 0.25]
        """
        checked = {p.name: p for p in cls.params}
        w = checked["weight"].check(weight)
        checked["distribution"].check(distribution)
        diffuse = OrenNayar(albedo, sigma, "full")
        if distribution == "beckmann":
            sigma = checked["sigma"].check(sigma)
            specular = TorranceSparrow(eta, None, "beckmann", alpha=math.sqrt(2.0) * sigma)
        else:
            specular = TorranceSparrow(eta, sigma)
        return cls([(1.0 - w, diffuse), (w, specular)])

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
