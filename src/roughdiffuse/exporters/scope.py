"""Which models an export target can represent.

Mitsuba and GLSL write the model itself. MaterialX, Blender and glTF hold one rough-diffuse
lobe (MaterialX's ``oren_nayar_diffuse_bsdf``, Blender's Diffuse BSDF, glTF's
``KHR_materials_diffuse_roughness``): a rough-diffuse BRDF is converted to it
(:func:`roughdiffuse.fit.between_models.convert`) with the error stated. Two kinds of model
are not rough-diffuse BRDFs and are refused, since a fit of that lobe to them is not the
model under another name:

* the planetary photometric functions (:data:`roughdiffuse.planetary.disk.PHOTOMETRIC_MODELS`
  but Lambert): Hapke's opposition surges and single-particle phase functions, the
  Lommel–Seeliger and Minnaert laws and Lunar-Lambert's limb darkening;
* glossy models (the registry's ``lobe`` ``"glossy"``: Torrance–Sparrow) and the coated
  model, whose specular coat a diffuse lobe cannot hold (fitted to ``coated``, EON's albedo
  is off by more than 200 %).
"""

from __future__ import annotations

from .. import registry
from .._validate import ParameterError
from ..models.base import Model
from .targets import TARGETS

__all__ = ["check_model", "converts"]

COATED = "coated"
"""The coated model's id: only the GLSL target writes it as it is (a Mitsuba scene cannot
hold its base's parameters)."""


def converts(target: str) -> bool:
    """Whether ``target`` holds a rough-diffuse lobe that other models are converted to."""
    return bool(TARGETS[target][1])


def _not_rough_diffuse(model_id: str) -> str | None:
    from ..planetary.disk import PHOTOMETRIC_MODELS

    if model_id in PHOTOMETRIC_MODELS and model_id != "lambert":
        return "a planetary photometric function"
    if registry.get(model_id).lobe == "glossy":
        return "a glossy model"
    if model_id == COATED:
        return "a specular coat over a base"
    return None


def _check_colour(model: Model) -> None:
    """Every target writes a colour as RGB (GLSL a ``vec3``): a model with other than 1 or 3
    channels is refused (GLSL kept the first three of four, silently)."""
    n = model.channels
    if n not in (0, 1, 3):
        names = "/".join(type(model).channel_fields) or "the colour"
        raise ParameterError(f"{names} has {n} channels; an RGB colour takes 1 or 3")


def check_model(model: Model, target: str) -> None:
    """Refuse ``model`` for ``target`` where the target cannot represent it.

    Raises
    ------
    ValueError
        Naming the model, what it is, what the target takes and the targets that write the
        model as it is.
    """
    _check_colour(model)
    model_id = registry.id_of(model)
    if not converts(target) or model_id is None:
        return
    kind = _not_rough_diffuse(model_id)
    if kind is None:
        return
    exact = [t for t, (_, computes) in TARGETS.items() if not computes]
    if model_id == COATED:
        exact = ["glsl"]
    raise ParameterError(
        f"cannot represent {model_id}, {kind}: {target} takes rough-diffuse BRDFs such as "
        f"eon, oren-nayar and burley (converted to {TARGETS[target][1]}); "
        f"{' and '.join(exact)} {'writes' if len(exact) == 1 else 'write'} {model_id} as it is"
    )
