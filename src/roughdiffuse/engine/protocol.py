"""What the compiled engine needs of a model (a leaf module: the standard library only).

:mod:`.fastpath` and :mod:`.dispatch` compile and run any object that looks like a
reflectance model: a dataclass instance with the class attributes ``closed_form`` and
``array_fields`` and the methods ``radiance``, ``brdf`` and ``brdf_cosines``
(:class:`roughdiffuse.models.base.Model` is one). The engine does not import the models,
so the models may import the engine.
"""

from __future__ import annotations

import dataclasses
from typing import Any, Protocol, runtime_checkable

__all__ = ["CompilableModel", "is_model"]


@runtime_checkable
class CompilableModel(Protocol):
    """A model the fast path can trace: its fields are its parameters (a dataclass), the
    numeric ones listed in ``array_fields``; ``closed_form`` says whether its methods are
    elementwise formulas of the inputs."""

    closed_form: bool
    array_fields: tuple[str, ...]

    def radiance(self, n: Any, l: Any, v: Any, irradiance: Any = 1.0) -> Any: ...  # noqa: E741

    def brdf(self, wi: Any, wo: Any) -> Any: ...

    def brdf_cosines(self, mu_i: Any, mu_o: Any, cos_io: Any) -> Any: ...


def is_model(x: Any) -> bool:
    """Whether ``x`` is a model instance (:class:`CompilableModel` and a dataclass instance)."""
    return (
        not isinstance(x, type) and dataclasses.is_dataclass(x) and isinstance(x, CompilableModel)
    )
