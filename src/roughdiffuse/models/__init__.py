"""Reflectance models: one module per family, one interface (see :mod:`.base`)."""

from .base import MODEL_CLASSES, BSDFSample, Model, register_pytree
from .declaration import Param
from .eon import EON
from .fujii import Fujii, fon_albedo, fon_average_albedo
from .lambert import Lambert
from .lunar import LommelSeeliger, LunarLambert
from .mix import Mix
from .oren_nayar import OrenNayar, oren_nayar
from .torrance_sparrow import TorranceSparrow, fresnel_dielectric, slope_distribution
from .vcavity import VCavity

__all__ = [
    "EON",
    "MODEL_CLASSES",
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
    "fon_albedo",
    "fon_average_albedo",
    "fresnel_dielectric",
    "oren_nayar",
    "register_pytree",
    "slope_distribution",
]
