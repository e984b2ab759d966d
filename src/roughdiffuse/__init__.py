"""roughdiffuse: how rough matte surfaces reflect light.

Models (Lambert, Oren–Nayar, Fujii, EON, Torrance–Sparrow, lunar models, mixes) written once
against the array API standard, so they run on NumPy, JAX and PyTorch arrays.

>>> import numpy as np, roughdiffuse as rd
>>> m = rd.OrenNayar(albedo=0.8, sigma=0.3)
>>> wi = rd.spherical_to_vector(np.radians(30.0))
>>> f = m.brdf(wi, np.array([0.0, 0.0, 1.0]))
"""

from importlib.metadata import PackageNotFoundError, version

from . import roughness
from .frames import spherical_to_vector, vector_to_spherical
from .models import (
    EON,
    BSDFSample,
    Fujii,
    Lambert,
    LommelSeeliger,
    LunarLambert,
    Mix,
    Model,
    OrenNayar,
    TorranceSparrow,
    VCavity,
    oren_nayar,
)
from .models.declaration import Param
from .registry import register_model

try:
    __version__ = version("roughdiffuse")
except PackageNotFoundError:  # pragma: no cover - running from a source tree
    __version__ = "0.0.0+unknown"

__all__ = [
    "EON",
    "BSDFSample",
    "Fujii",
    "Lambert",
    "LommelSeeliger",
    "LunarLambert",
    "Mix",
    "Model",
    "OrenNayar",
    "Param",
    "TorranceSparrow",
    "VCavity",
    "__version__",
    "oren_nayar",
    "register_model",
    "roughness",
    "spherical_to_vector",
    "vector_to_spherical",
]
