"""Reflectance models: one module per family, one interface (see :mod:`.base`).

The package lists no model by hand. :func:`builtin_classes` imports every public module of
this package once and keeps each public :class:`~.base.Model` subclass that declares ``ids``;
their names (``OrenNayar``, ``Fujii``...) become attributes of this package and of
``roughdiffuse``, and :mod:`roughdiffuse.registry` registers them. The order is stated by
each class's ``order`` (then module name, then definition order in the module): it is the
order of ``roughdiffuse models``.
"""

from __future__ import annotations

import importlib
import pkgutil

from .base import BSDFSample as BSDFSample
from .base import Model
from .base import register_pytree as register_pytree
from .declaration import Param as Param
from .declaration import param as param

HELPERS: dict[str, str] = {
    "fon_albedo": "fujii",
    "fon_average_albedo": "fujii",
    "fresnel_dielectric": "torrance_sparrow",
    "oren_nayar": "oren_nayar",
    "slope_distribution": "torrance_sparrow",
}
"""Public functions that are not models, by the module defining them."""


def builtin_classes() -> list[type[Model]]:
    """Every public model class of this package, in the registry's order.

    A class counts when it is defined in a public module of ``roughdiffuse.models`` (name not
    starting with ``_``), its name does not start with ``_``, it subclasses
    :class:`~.base.Model` and it declares ``ids`` itself. Sorted by its ``order`` class
    attribute, then by module name, then by definition order in the module.
    """
    found: list[tuple[int, str, int, type[Model]]] = []
    for info in pkgutil.iter_modules(__path__):
        if info.name.startswith("_"):
            continue
        module = importlib.import_module(f"{__name__}.{info.name}")
        for k, obj in enumerate(vars(module).values()):
            if (
                isinstance(obj, type)
                and issubclass(obj, Model)
                and obj.__module__ == module.__name__
                and not obj.__name__.startswith("_")
                and obj.__dict__.get("ids")
            ):
                found.append((obj.order, info.name, k, obj))
    return [cls for *_, cls in sorted(found, key=lambda t: t[:3])]


_CLASSES = builtin_classes()
globals().update({cls.__name__: cls for cls in _CLASSES})
for _name, _module in HELPERS.items():
    globals()[_name] = getattr(importlib.import_module(f"{__name__}.{_module}"), _name)

__all__ = sorted(
    ["BSDFSample", "Model", "Param", "builtin_classes", "param", "register_pytree", *HELPERS]
    + [cls.__name__ for cls in _CLASSES]
)
