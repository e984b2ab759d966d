"""A Blender script that builds a model's material: Diffuse BSDF (or Principled BSDF).

Cycles computes roughdiffuse's ``cycles-diffuse`` (Fujii's single scattering plus ρ times
EON's multiple-scattering lobe, ``intern/cycles/kernel/closure/bsdf_oren_nayar.h``); the
Principled BSDF's "Diffuse Roughness" builds the same closure (``cycles-principled``). Any
other model is converted to it (:func:`roughdiffuse.fit.between_models.convert`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from .._validate import ParameterError
from ..models.base import Model
from .common import Export, error_lines, material_for, python_comment_lines, rgb_of, write_files

__all__ = ["script", "write"]


def script(params: dict[str, Any], comments: list[str], principled: bool = False) -> str:
    """Python for Blender (``bpy``): a material ``roughdiffuse`` with these parameters,
    assigned to the active object if there is one."""
    rgb = rgb_of(params.get("albedo", 1.0))
    colour = "(" + ", ".join(f"{x:.9g}" for x in rgb) + ", 1.0)"
    rough = f"{float(params['roughness']):.9g}"
    notes = "\n".join(line for c in comments for line in python_comment_lines(c))
    if principled:
        node = f"""bsdf = nodes.new("ShaderNodeBsdfPrincipled")
bsdf.inputs["Base Color"].default_value = {colour}
bsdf.inputs["Diffuse Roughness"].default_value = {rough}
bsdf.inputs["Specular IOR Level"].default_value = 0.0  # no specular: the diffuse alone"""
    else:
        node = f"""bsdf = nodes.new("ShaderNodeBsdfDiffuse")
bsdf.inputs["Color"].default_value = {colour}
bsdf.inputs["Roughness"].default_value = {rough}"""
    return f'''"""Material written by roughdiffuse export: run in Blender (or with the bpy module).

Colours are linear (scene-referred) RGB.
"""
{notes}
import bpy

material = bpy.data.materials.new("roughdiffuse")
material.use_nodes = True
nodes = material.node_tree.nodes
nodes.clear()
output = nodes.new("ShaderNodeOutputMaterial")
{node}
material.node_tree.links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
obj = bpy.context.active_object
if obj is not None and obj.type == "MESH":
    obj.data.materials.clear()
    obj.data.materials.append(material)
'''


def files_for(path: Path, blend: bool | None = None) -> tuple[Path, ...]:
    """The files :func:`write` writes: the script ``path`` and, where ``blend`` says so
    (``None``: where a Blender interpreter is found), the ``.blend`` beside it."""
    from .blender_run import blender_command

    if blend is None:
        blend = blender_command() is not None
    return (path, path.with_suffix(".blend")) if blend else (path,)


def write(model: Model, path: Path, principled: bool = False, blend: bool | None = None) -> Export:
    """Write the Blender script of ``model`` (converted to ``cycles-diffuse`` if needed), and
    the ``.blend`` file beside it (same name, suffix ``.blend``) made by running the script in
    Blender's Python (:mod:`roughdiffuse.exporters.blender_run`).

    Parameters
    ----------
    blend : bool or None
        Write the ``.blend``: ``None`` (default) where a Blender interpreter is found,
        ``True`` always (``BlenderError`` without one), ``False`` never.

    Raises
    ------
    BlenderError
        If Blender's process fails (or, with ``blend=True``, none is found).
    """
    from .blender_run import blender_command, write_blend

    if path.suffix == ".blend":
        raise ParameterError(f"{path}: give the script's name (.py); the .blend goes beside it")
    target = "cycles-principled" if principled else "cycles-diffuse"
    params, conversion = material_for(model, target)
    comments = [f"Cycles computes this as roughdiffuse's {target!r}."] + error_lines(conversion)
    text = script(params, comments, principled)
    try:  # the script Blender will run is Python: check it parses before writing it
        compile(text, str(path), "exec")
    except SyntaxError as exc:
        raise ParameterError(f"the Blender script does not parse: {exc.msg}") from None
    paths = write_files({path: text})
    notes: tuple[str, ...] = ()
    if blend is None:
        blend = blender_command() is not None
        if not blend:
            notes = ("no .blend: no Blender interpreter (make install-blender, or set "
                     "ROUGHDIFFUSE_BLENDER_PYTHON)",)  # fmt: skip
    if blend:
        paths = (*paths, write_blend(path, path.with_suffix(".blend")))
    return Export("blender", paths, target, params, conversion, notes)
