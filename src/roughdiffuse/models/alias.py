"""A model that is another model after a change of parameters, declared once.

Other renderers often ship a formula roughdiffuse already has, under another parameter
convention (pbrt-v3's σ in degrees, Mitsuba 0.6's α = √2 σ, Filament's perceptual roughness).
Such a variant is an :class:`Alias`: it declares its own parameters (the other project's
names, units and ranges), the model it equals (``base`` with the categorical values in
``base_fixed``) and the conversion (:meth:`Alias.to_base`, elementwise, so the fast path,
JAX and Dr.Jit run it); the formula stays the base model's. The explorer traces an alias
like any model (:mod:`roughdiffuse.engine.glsl`); :meth:`Alias.conversion` traces
:meth:`~Alias.to_base` alone, to show it and to convert the page's values for the base model
(its ground truth).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

from .._array import Array
from .base import Model, register_pytree
from .declaration import Param

__all__ = ["Alias", "alias"]


class Alias(Model):
    """A registry model defined as ``base(**base_fixed, **to_base(params))``.

    Subclasses (frozen dataclasses) declare ``params``, ``ids``, ``labels``, ``reference`` (the
    other project's file and function), ``base``, ``base_fixed`` and implement
    :meth:`to_base`. Sampling is the class's ``sampling`` (cosine by default: the
    strategies read the base model's parameter names).
    """

    base: ClassVar[type[Model]]
    base_fixed: ClassVar[dict[str, Any]] = {}
    base_choices: ClassVar[dict[str, dict[str, dict[str, Any]]]] = {}
    """For a categorical parameter of the alias: each of its values -> the base's categorical
    values it selects (Mitsuba 0.6's ``variant`` "fast" is Oren–Nayar's "qualitative")."""

    @staticmethod
    def to_base(**params: Any) -> dict[str, Any]:
        """The base model's numeric parameters from this model's (elementwise arithmetic)."""
        raise NotImplementedError

    @classmethod
    def conversion(cls) -> dict[str, Any]:
        """:meth:`to_base` traced on symbols (:mod:`roughdiffuse.engine.trace`):
        ``{"text": {name: expression}, "tree": {name: tree}, "javascript": body}``, each base
        parameter as an expression to show and as a JSON expression tree
        (:func:`~roughdiffuse.engine.glsl.expression_tree`), and the body of a JavaScript
        function ``(p) => ({...})`` that computes them from this model's values
        (``p.sigma_deg``; a colour channel by channel).

        Raises
        ------
        TraceError
            If :meth:`to_base` does what a trace cannot follow (a Python branch on a value).

        Examples
        --------
        >>> from roughdiffuse.models.renderers import Pbrt3OrenNayar
        >>> Pbrt3OrenNayar.conversion()["text"]["sigma"]
        'sigma_deg * 0.0174533'
        """
        import numpy as np

        from ..engine.glsl import expression_text, expression_tree, javascript_values
        from ..engine.trace import Graph

        graph = Graph(np.dtype(np.float64))
        names = [p.name for p in cls.params if p.name in cls.array_fields]
        out = cls.to_base(**{n: graph.input(n) for n in names})
        return {
            "text": {k: expression_text(graph, v) for k, v in out.items()},
            "tree": {k: expression_tree(graph, v) for k, v in out.items()},
            "javascript": javascript_values(graph, out),
        }

    def base_categories(self) -> dict[str, Any]:
        """The base's categorical values: ``base_fixed``, and those this instance's own
        categorical values select (``base_choices``)."""
        chosen = dict(self.base_fixed)
        for name, by_value in self.base_choices.items():
            chosen.update(by_value[getattr(self, name)])
        return chosen

    def base_model(self) -> Model:
        """The equal model of the base class (its parameters converted)."""
        values = {f: getattr(self, f) for f in self.array_fields}
        return self.base(**self.base_categories(), **self.to_base(**values))

    def _kernel(self, xp: Any, mu_i: Array, mu_o: Array, cos_io: Array, **p: Array) -> Array:
        shape = self.base(**self.base_categories())  # categorical only; numbers come from p
        return shape._kernel(xp, mu_i, mu_o, cos_io, **self.to_base(**p))

    def directional_albedo(self, wo: Array) -> Array:
        """The base model's (closed form where it has one)."""
        return self.base_model().directional_albedo(wo)


def alias(
    name: str,
    module: str,
    *,
    base: type[Model],
    params: tuple[Param, ...],
    to_base: Callable[..., dict[str, Any]],
    rule: str,
    reference: str,
    formula: str,
    doc: str,
    order: int,
    model_id: str | None = None,
    label: str | None = None,
    ids: dict[str, dict[str, Any]] | None = None,
    labels: dict[str, str] | None = None,
    base_fixed: dict[str, Any] | None = None,
    base_choices: dict[str, dict[str, dict[str, Any]]] | None = None,
    symbols: dict[str, str] | None = None,
) -> type[Alias]:
    """An :class:`Alias` class from one row of a table (``models/renderers.py``).

    The class is a frozen dataclass (a JAX pytree) whose fields are ``params`` with their
    declared defaults, in order; ``to_base`` its conversion, whose docstring becomes ``rule``
    (the rule docs/implementations.md shows); the other arguments are the class attributes
    of :class:`~roughdiffuse.models.base.Model` and :class:`Alias` (``model_id`` and
    ``label`` its one id and label, or ``ids`` and ``labels`` for several ids, each fixing a
    categorical parameter whose values select the base's through ``base_choices``;
    ``symbols`` defaults to ρ for albedo and r for roughness).
    """
    if (model_id is None) == (ids is None) or (label is None) == (labels is None):
        raise TypeError(f"alias {name}: give model_id and label, or ids and labels")
    if model_id is not None:
        ids, labels = {model_id: {}}, {model_id: str(label)}
    for choice, by_value in (base_choices or {}).items():
        declared = next((p for p in params if p.name == choice), None)
        if declared is None or set(declared.choices or ()) != set(by_value):
            raise TypeError(
                f"alias {name}: base_choices[{choice!r}] must map each choice of a "
                "categorical parameter of params"
            )
    convert = staticmethod(to_base)
    to_base.__doc__ = rule + "."
    attributes: dict[str, Any] = {
        "__module__": module,
        "__qualname__": name,
        "__doc__": doc,
        "__annotations__": {p.name: Any for p in params},
        **{p.name: p.default for p in params},
        "params": params,
        "ids": dict(ids or {}),
        "labels": dict(labels or {}),
        "reference": reference,
        "formula": formula,
        "symbols": symbols or {"albedo": r"\rho", "roughness": r"r"},
        "order": order,
        "base": base,
        "base_fixed": dict(base_fixed or {}),
        "base_choices": dict(base_choices or {}),
        "to_base": convert,
    }
    return register_pytree(dataclass(frozen=True)(type(name, (Alias,), attributes)))
