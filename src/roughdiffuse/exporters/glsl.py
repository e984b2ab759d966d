"""A model as a GLSL ES 3.00 function for the user's own shader (WebGL 2, three.js, Godot).

The file holds the code :func:`roughdiffuse.engine.glsl.glsl_source` prints from the model's
own array-API code (no formula is written by hand): ``vec3 NAME(vec3 wi, vec3 wo)``, the BRDF
in 1/sr without the cosine, in the surface's frame (z the normal; ``wi`` towards the light,
``wo`` towards the viewer), 0 below the horizon, one value per RGB channel. Radiance under a
light of irradiance E0 is ``NAME(wi, wo) * E0 * max(wi.z, 0.0)``.

The parameter values are constants of the code (the default), or, with ``uniforms=True``,
``uniform`` declarations named after the model's parameters (angles in radians) that the
user's program sets, so that one compiled shader serves every value. The function is exact:
nothing is converted. Models that are not closed forms (simulations, tables) have no GLSL
code and are refused.
"""

from __future__ import annotations

from pathlib import Path

from .. import registry
from .._validate import ParameterError
from ..models.base import Model
from .common import Export, params_of, write_files

__all__ = ["write"]


def write(model: Model, path: Path, *, uniforms: bool = False, name: str = "rd_brdf") -> Export:
    """Write the GLSL function of ``model`` to ``path`` (whole or not at all).

    Parameters
    ----------
    model : Model
        A registry model with a closed form.
    path : path
        The ``.glsl`` file to write.
    uniforms : bool
        Declare the model's numeric parameters as uniforms instead of baking their values in.
    name : str
        The function's name (a GLSL identifier); its helpers' names start with it.

    Raises
    ------
    ValueError
        For a model that has no GLSL code (not a closed form, or, with ``uniforms``, whose
        parameters are not its own fields), or a bad ``name``.
    """
    from ..engine.glsl import glsl_source, glsl_uniforms

    model_id = registry.id_of(model)
    if model_id is None:
        raise ParameterError(f"{type(model).__name__} is not a registry model")
    try:
        source = glsl_source(model, name=name, bake=not uniforms)
    except ParameterError as exc:
        reason = str(exc).removesuffix("; use bake=True")
        if reason != str(exc):  # the printer's advice, in this function's terms
            reason += "; export it with the values baked in (uniforms=False, no --uniforms)"
        raise ParameterError(reason) from None
    if uniforms:
        declared = ", ".join(f"{kind} {p}" for p, kind in glsl_uniforms(model).items())
        notes = (f"uniforms to set: {declared or 'none'} (angles in radians)",)
    else:
        notes = ("parameter values baked in (export --uniforms: set them from your program)",)
    values, complete = _fields(model, model_id)
    if not complete:
        notes += (
            f"{type(model).__name__} holds some parameters in its parts: all are in the "
            "file's header",
        )
    usage = f"radiance = {name}(wi, wo) * E0 * max(wi.z, 0.0) (wi, wo in the surface's frame)"
    return Export(
        "glsl",
        write_files({Path(path): source}),
        model_id,
        values,
        None,
        (*notes, usage),
    )


def _fields(model: Model, model_id: str) -> tuple[dict, bool]:
    """The model's parameter values for the summary, and whether they are all there: a
    model may hold some in its parts (a Coated its base's, a Mix its components')."""
    declared = [p for p in registry.get(model_id).parameters if not p.categorical]
    if all(hasattr(model, p.name) for p in declared):
        return params_of(model, model_id), True
    held = {p.name: float(getattr(model, p.name)) for p in declared if hasattr(model, p.name)}
    return held, False
