"""roughdiffuse: how rough matte surfaces reflect light.

Models (Lambert, Oren–Nayar, Fujii, EON, Torrance–Sparrow, lunar models, mixes) written once
against the array API standard, so they run on NumPy, JAX and PyTorch arrays.

>>> import numpy as np, roughdiffuse as rd
>>> m = rd.OrenNayar(albedo=0.8, sigma=0.3)
>>> wi = rd.spherical_to_vector(np.radians(30.0))
>>> f = m.brdf(wi, np.array([0.0, 0.0, 1.0]))
"""

from typing import Any

from . import _lazy
from . import roughness as roughness
from .engine.dispatch import fastpath_enabled as fastpath_enabled
from .engine.dispatch import use_fastpath as use_fastpath
from .frames import spherical_to_vector as spherical_to_vector
from .frames import vector_to_spherical as vector_to_spherical
from .registry import register_model as register_model

SUBMODULES = (
    "accuracy",
    "bench",
    "energy",
    "engine",
    "explorer",
    "figures",
    "fit",
    "integrations",
    "planetary",
    "plots",
    "render",
    "simulate",
)
"""Submodules imported on first access (``rd.fastpath``, ``rd.plots``...): ``import
roughdiffuse`` stays light (NumPy and the models), JAX, SciPy, matplotlib, Numba and Mitsuba
are imported by the code that needs them."""

_submodule, _dir = _lazy.attach(__name__, SUBMODULES)


def _models() -> Any:
    from . import models

    return models


def _from_models() -> list[str]:
    """The names of :mod:`roughdiffuse.models` served here: its models, ``Model``, ``Param``,
    ``BSDFSample`` and helper functions (not its declaration plumbing)."""
    plumbing = ("builtin_classes", "param", "register_pytree")
    return [n for n in _models().__all__ if n not in plumbing]


def __getattr__(name: str) -> Any:
    if name == "__version__":  # importlib.metadata is imported on first use
        from ._version import version

        globals()["__version__"] = version()
        return globals()["__version__"]
    if name == "__all__":
        return sorted(_OWN + _from_models())
    if name in SUBMODULES:
        return _submodule(name)
    if name in _FUNCTIONS:  # rd.convert, rd.export: a function of a submodule
        from importlib import import_module

        value = getattr(import_module(f"{__name__}.{_FUNCTIONS[name]}"), name)
        globals()[name] = value
        return value
    if name == "fastpath":  # the compiled engine's public face
        from .engine import fastpath

        return fastpath
    if name in _from_models():
        value = getattr(_models(), name)
        globals()[name] = value
        return value
    return _submodule(name)


def __dir__() -> list[str]:
    return sorted(set(_dir()) | set(__getattr__("__all__")) | {"fastpath"})


_FUNCTIONS = {"convert": "fit.between_models", "export": "exporters"}
"""Functions served here from the submodule that holds them (imported on first use)."""

_OWN = [
    "__version__",
    "convert",
    "export",
    "fastpath_enabled",
    "register_model",
    "roughness",
    "spherical_to_vector",
    "use_fastpath",
    "vector_to_spherical",
]
"""Names defined here; the models (``rd.OrenNayar``...), ``Model``, ``Param``, ``BSDFSample``
and the helper functions of :mod:`roughdiffuse.models` are served from it on first use."""
