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
from ._dispatch import fastpath_enabled as fastpath_enabled
from ._dispatch import use_fastpath as use_fastpath
from .frames import spherical_to_vector as spherical_to_vector
from .frames import vector_to_spherical as vector_to_spherical
from .registry import register_model as register_model

SUBMODULES = (
    "bench",
    "energy",
    "explorer",
    "fastpath",
    "figures",
    "fit",
    "integrations",
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


def __getattr__(name: str) -> Any:
    if name == "__version__":  # importlib.metadata costs about 0.1 s: read on first use
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("roughdiffuse")
        except PackageNotFoundError:  # pragma: no cover - running from a source tree
            value = "0.0.0+unknown"
        globals()["__version__"] = value
        return value
    if name == "__all__":
        return sorted(_OWN + _models().__all__)
    if name in SUBMODULES:
        return _submodule(name)
    models = _models()
    if name in models.__all__ and name not in ("builtin_classes", "register_pytree"):
        value = getattr(models, name)
        globals()[name] = value
        return value
    return _submodule(name)


def __dir__() -> list[str]:
    return sorted(set(_dir()) | set(__getattr__("__all__")))


_OWN = [
    "__version__",
    "fastpath_enabled",
    "register_model",
    "roughness",
    "spherical_to_vector",
    "use_fastpath",
    "vector_to_spherical",
]
"""Names defined here; the models (``rd.OrenNayar``...), ``Model``, ``Param``, ``BSDFSample``
and the helper functions of :mod:`roughdiffuse.models` are served from it on first use."""
