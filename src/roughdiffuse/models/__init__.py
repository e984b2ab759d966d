"""Reflectance models: one module per family, one interface (see :mod:`.base`)."""

from .base import MODEL_CLASSES, BSDFSample, Model, register_pytree
from .burley import Burley, Burley2015, BurleyRenormalized
from .chan import Chan
from .coated import Coated
from .declaration import Param
from .eon import EON
from .fujii import Fujii, fon_albedo, fon_average_albedo
from .hammon import Hammon
from .hapke import Hapke
from .lambert import Lambert
from .lambert_sphere import LambertSphere
from .lunar import LommelSeeliger, LunarLambert
from .minnaert import Minnaert
from .mix import Mix
from .oren_nayar import OrenNayar, oren_nayar
from .smith_diffuse import SmithDiffuse
from .torrance_sparrow import TorranceSparrow, fresnel_dielectric, slope_distribution
from .vcavity import VCavity

__all__ = [
    "EON",
    "MODEL_CLASSES",
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
    "Coated",
    "Mix",
    "Model",
    "OrenNayar",
    "Param",
    "SmithDiffuse",
    "TorranceSparrow",
    "VCavity",
    "fon_albedo",
    "fon_average_albedo",
    "fresnel_dielectric",
    "oren_nayar",
    "register_pytree",
    "slope_distribution",
]
