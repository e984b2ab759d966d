"""roughdiffuse: how rough matte surfaces reflect light.

Models (Lambert, Oren–Nayar, Fujii, EON, Torrance–Sparrow, lunar models, mixes) written once
against the array API standard, so they run on NumPy, JAX and PyTorch arrays.

>>> import numpy as np, roughdiffuse as rd
>>> m = rd.OrenNayar(albedo=0.8, sigma=0.3)
>>> wi = rd.spherical_to_vector(np.radians(30.0))
>>> f = m.brdf(wi, np.array([0.0, 0.0, 1.0]))
"""

from typing import Any

from . import _lazy, roughness
from ._dispatch import fastpath_enabled, use_fastpath
from .frames import spherical_to_vector, vector_to_spherical
from .models import (
    EON,
    BSDFSample,
    Burley,
    Burley2015,
    BurleyRenormalized,
    Chan,
    Coated,
    Fujii,
    Hammon,
    Hapke,
    Lambert,
    LambertSphere,
    LommelSeeliger,
    LunarLambert,
    Minnaert,
    Mix,
    Model,
    OrenNayar,
    SmithDiffuse,
    TorranceSparrow,
    VCavity,
    oren_nayar,
)
from .models.declaration import Param
from .registry import register_model

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

_submodule, __dir__ = _lazy.attach(__name__, SUBMODULES)


def __getattr__(name: str) -> Any:
    if name == "__version__":  # importlib.metadata costs about 0.1 s: read on first use
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("roughdiffuse")
        except PackageNotFoundError:  # pragma: no cover - running from a source tree
            value = "0.0.0+unknown"
        globals()["__version__"] = value
        return value
    return _submodule(name)


__all__ = [
    "EON",
    "BSDFSample",
    "Burley",
    "Burley2015",
    "BurleyRenormalized",
    "Chan",
    "Fujii",
    "Hammon",
    "Hapke",
    "Lambert",
    "LambertSphere",
    "LommelSeeliger",
    "LunarLambert",
    "Minnaert",
    "Mix",
    "Coated",
    "Model",
    "OrenNayar",
    "Param",
    "SmithDiffuse",
    "TorranceSparrow",
    "VCavity",
    "__version__",
    "fastpath_enabled",
    "oren_nayar",
    "register_model",
    "roughness",
    "spherical_to_vector",
    "use_fastpath",
    "vector_to_spherical",
]
