"""A model that is another model after a change of parameters, declared once.

Other renderers often ship a formula roughdiffuse already has, under another parameter
convention (pbrt-v3's σ in degrees, Mitsuba 0.6's α = √2 σ, Filament's perceptual roughness).
Such a variant is an :class:`Alias`: it declares its own parameters (the other project's
names, units and ranges), the model it equals (``base`` with the categorical values in
``base_fixed``) and the conversion (:meth:`Alias.to_base`, elementwise, so the fast path,
JAX and Dr.Jit run it); the formula stays the base model's.
"""

from __future__ import annotations

from typing import Any, ClassVar

from .._array import Array
from .base import Model
from .conversion import Tree, recorded_conversion

__all__ = ["Alias"]


class Alias(Model):
    """A registry model defined as ``base(**base_fixed, **to_base(params))``.

    Subclasses (frozen dataclasses) declare ``params``, ``ids``, ``labels``, ``reference`` (the
    other project's file and function), ``base``, ``base_fixed`` and implement
    :meth:`to_base`. Sampling is the class's ``sampling`` (cosine by default: the
    strategies read the base model's parameter names).
    """

    base: ClassVar[type[Model]]
    base_fixed: ClassVar[dict[str, Any]] = {}

    @staticmethod
    def to_base(**params: Any) -> dict[str, Any]:
        """The base model's numeric parameters from this model's (elementwise arithmetic)."""
        raise NotImplementedError

    @classmethod
    def conversion(cls) -> dict[str, Tree]:
        """:meth:`to_base` recorded as one expression tree per base parameter
        (:mod:`~roughdiffuse.models.conversion`), checked against the numeric
        :meth:`to_base` over each parameter's range: what the explorer evaluates before the
        base model's GLSL, so the conversion stays declared once.

        Raises
        ------
        NotRecordable
            If :meth:`to_base` is more than arithmetic on its parameters.

        Examples
        --------
        >>> from roughdiffuse.models.renderers import Pbrt3OrenNayar
        >>> Pbrt3OrenNayar.conversion()["sigma"]
        ['*', 'sigma_deg', 0.017453292519943295]
        """
        ranges = {}
        for p in cls.params:
            if p.name in cls.array_fields:
                lo, hi = p.bounds or (p.min or 0.0, (p.min or 0.0) + 1.0)
                ranges[p.name] = (lo, hi)
        return recorded_conversion(cls.to_base, ranges)

    def base_model(self) -> Model:
        """The equal model of the base class (its parameters converted)."""
        values = {f: getattr(self, f) for f in self.array_fields}
        return self.base(**self.base_fixed, **self.to_base(**values))

    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, **p: Array) -> Array:
        shape = self.base(**self.base_fixed)  # categorical values only; numbers come from p
        return shape._kernel(xp, mu_i, mu_o, cos_io, **self.to_base(**p))

    def directional_albedo(self, wo: Array) -> Array:
        """The base model's (closed form where it has one)."""
        return self.base_model().directional_albedo(wo)
