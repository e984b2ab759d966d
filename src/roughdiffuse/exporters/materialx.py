"""A MaterialX document of a model: ``oren_nayar_diffuse_bsdf`` or ``open_pbr_surface``.

MaterialX evaluates both through its node ``oren_nayar_diffuse_bsdf``
(``libraries/pbrlib/genglsl/mx_oren_nayar_diffuse_bsdf.glsl``): the qualitative Oren–Nayar
model with ``energy_compensation`` false (roughdiffuse's ``materialx-oren-nayar``: exact for
``oren-nayar`` and its aliases, roughness = σ in radians), else EON with its L·V clamp
(``materialx-eon``; ``open_pbr_surface`` sets ``energy_compensation`` true in
``libraries/bxdf/open_pbr_surface.mtlx``). Any other model is converted to ``materialx-eon``.

That holds for MaterialX's GLSL, ESSL and MSL outputs. Its other backends render the node
otherwise, and the export says so (:data:`BACKEND_WARNINGS`, a
:class:`~roughdiffuse.exporters.common.BackendWarning`): the OSL generator
(``libraries/pbrlib/genosl/pbrlib_genosl_impl.mtlx``) writes
``oren_nayar_diffuse_bsdf(normal, color, roughness)`` without ``energy_compensation``, so OSL
renders qualitative Oren–Nayar (``materialx-eon-genosl``) and Cycles' OSL closure, which has
no switch, its own EON with the ρ³ lobe (``cycles-osl``); MDL 1.9 and earlier mark the option
unused (``libraries/mdl/materialx/pbrlib_1_6.mdl``) and MDL 1.10 maps it to
``multiscatter_tint`` (``pbrlib_1_10.mdl``), which is not EON's formula.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .. import registry
from .._validate import ParameterError
from ..models.base import Model
from .common import (
    Export,
    error_lines,
    material_for,
    rgb_of,
    warn_backends,
    write_files,
    xml_comment_text,
)

__all__ = ["BACKEND_WARNINGS", "document", "write"]

VERSION = "1.39"

BACKEND_WARNINGS: dict[str, str] = {
    "materialx-eon": (
        "EON renders as written only in MaterialX's GLSL, ESSL and MSL; genosl drops "
        "energy_compensation (OSL renders materialx-eon-genosl, qualitative Oren-Nayar; Cycles' "
        "OSL renders cycles-osl), MDL 1.9 and earlier ignore it, MDL 1.10 maps it to "
        "multiscatter_tint (not EON)"
    ),
    "materialx-oren-nayar": (
        "Cycles' OSL closure has no energy_compensation switch: through genosl in Cycles this "
        "renders cycles-osl (Fujii's model and the rho^3 lobe), not the qualitative model"
    ),
}
"""The one-line warning of each MaterialX export target: what its other backends render."""


def _is_qualitative_oren_nayar(model: Model) -> bool:
    base = getattr(model, "base_model", None)
    model = base() if base is not None else model
    return registry.id_of(model) == "oren-nayar"


def _colour(albedo: Any) -> str:
    return ", ".join(f"{x:.9g}" for x in rgb_of(albedo))


def document(
    params: dict[str, Any], compensated: bool, comments: list[str], openpbr: bool = False
) -> str:
    """The ``.mtlx`` text of a material with these ``materialx-*`` parameters."""
    notes = "\n".join(f"  {xml_comment_text(line)}" for c in comments for line in c.splitlines())
    colour, rough = _colour(params.get("albedo", 1.0)), f"{float(params['roughness']):.9g}"
    if openpbr:
        shader = f"""  <open_pbr_surface name="surface" type="surfaceshader">
    <input name="base_weight" type="float" value="1" />
    <input name="base_color" type="color3" value="{colour}" />
    <input name="base_diffuse_roughness" type="float" value="{rough}" />
    <input name="specular_weight" type="float" value="0" />
  </open_pbr_surface>"""
    else:
        flag = "true" if compensated else "false"
        shader = f"""  <oren_nayar_diffuse_bsdf name="diffuse_bsdf" type="BSDF">
    <input name="color" type="color3" value="{colour}" />
    <input name="roughness" type="float" value="{rough}" />
    <input name="energy_compensation" type="boolean" value="{flag}" />
  </oren_nayar_diffuse_bsdf>
  <surface name="surface" type="surfaceshader">
    <input name="bsdf" type="BSDF" nodename="diffuse_bsdf" />
  </surface>"""
    return f"""<?xml version="1.0"?>
<materialx version="{VERSION}">
  <!-- written by roughdiffuse export
{notes}
  -->
{shader}
  <surfacematerial name="roughdiffuse_material" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="surface" />
  </surfacematerial>
</materialx>
"""


def write(model: Model, path: Path, openpbr: bool = False) -> Export:
    """Write the ``.mtlx`` document of ``model`` (converted where MaterialX cannot hold it)."""
    if _is_qualitative_oren_nayar(model) and not openpbr:
        target = "materialx-oren-nayar"
    else:
        target = "materialx-eon"
    params, conversion = material_for(model, target)
    backend = BACKEND_WARNINGS["materialx-eon" if openpbr else target]
    comments = [
        f"MaterialX's GLSL, ESSL and MSL evaluate this as roughdiffuse's {target!r}.",
        f"Other backends: {backend}.",
        *error_lines(conversion),
    ]
    text = document(params, target == "materialx-eon", comments, openpbr)
    note = check_document(text)
    notes = (note,) if note else ()
    paths = write_files({path: text})
    return warn_backends(Export("materialx", paths, target, params, conversion, notes, (backend,)))


def check_document(text: str) -> str | None:
    """Validate the ``.mtlx`` text with MaterialX (its standard data libraries attached),
    before it is written: an invalid document is a ``ValueError`` with MaterialX's message.
    Returns a note when it could not be checked (MaterialX not installed), else ``None``."""
    try:
        import MaterialX as mx
    except ImportError:
        return "not validated here: MaterialX is not installed (pip install materialx)"
    doc = mx.createDocument()
    try:
        mx.readFromXmlString(doc, text)
    except Exception as exc:  # noqa: BLE001 - MaterialX's parser refusal, in one line
        raise ParameterError(f"the MaterialX document does not parse: {exc}") from None
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    doc.setDataLibrary(lib)
    valid, message = doc.validate()
    if not valid:
        first = (message.strip().splitlines() or ["invalid"])[0]
        raise ParameterError(f"the MaterialX document is not valid: {first}")
    return None
