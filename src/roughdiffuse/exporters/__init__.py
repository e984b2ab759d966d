"""Write a model, or a fit result, as a material another renderer opens.

Targets (:data:`TARGETS`):

* ``mitsuba``: a Mitsuba 3 scene (XML, and the same scene as a Python dict in a ``.py``)
  with the model's roughdiffuse plugin (exact), a sphere under a directional light and an
  orthographic camera; Lambert also as Mitsuba's own ``diffuse``, Burley 2015 as its
  ``principled`` with ``specular`` 0;
* ``materialx``: a ``.mtlx`` document with an ``oren_nayar_diffuse_bsdf`` (or, with
  ``openpbr=True``, an ``open_pbr_surface`` with ``base_diffuse_roughness``);
* ``blender``: a ``.py`` that builds the node tree (Diffuse BSDF) when run by Blender or
  ``bpy``, and beside it a ``.blend`` saved by Blender where Blender's Python is found
  (:mod:`roughdiffuse.exporters.blender_run`);
* ``glsl``: a GLSL ES 3.00 function ``vec3 rd_brdf(vec3 wi, vec3 wo)`` for a WebGL 2,
  three.js or Godot shader, printed from the model's own code (exact; parameter values baked
  in, or uniforms with ``uniforms=True``; :mod:`roughdiffuse.exporters.glsl`);
* ``gltf``: a glTF 2.0 sphere (``.gltf`` with its buffer embedded, or ``.glb``) whose
  material carries EON's roughness in ``KHR_materials_diffuse_roughness``, the specular lobe
  off (:mod:`roughdiffuse.exporters.gltf`).

Where the target cannot hold the model exactly, the parameters are converted
(:func:`roughdiffuse.fit.between_models.convert`) and the conversion error is written into
the file's comments and returned. A model that is not a rough-diffuse BRDF (a planetary
photometric function, a glossy model) is refused by the targets that convert
(:mod:`roughdiffuse.exporters.scope`). A ``UsdPreviewSurface`` is not offered: its diffuse
lobe has no roughness, so any rough model would be exported wrong.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from .. import registry
from .._validate import ParameterError
from ..models.base import Model
from .common import Export, material_for, model_record
from .scope import check_model
from .targets import TARGETS, suffixes

__all__ = [
    "TARGETS",
    "Export",
    "export",
    "load_result",
    "material_for",
    "model_record",
    "planned_files",
    "suffixes",
]


def _from_fit_json(data: dict[str, Any]) -> dict[str, Any]:
    """``fit --json``'s best fit (``fits[0]``): its model id and ``names``/``values`` (per-channel
    ``albedo[k]`` gathered into a list)."""
    best = data["fits"][0]
    params: dict[str, Any] = {}
    for name, value in zip(best["names"], best["values"], strict=True):
        base, _, index = name.partition("[")
        if index:
            params.setdefault(base, []).append(value)
        else:
            params[base] = value
    return {"model": best["model"], "params": params}


def load_result(path: str | Path) -> Model:
    """The model of a fit result: the output of ``fit --json`` (its best fit), a record
    ``{"model": id, "params": {...}}`` (:func:`model_record`), or a photometric-stereo
    ``params.json`` (``model`` and ``roughness``; the albedo is the median of ``albedo.npy``
    beside it).

    Raises
    ------
    ValueError
        If the file cannot be read or parsed, or names no model.
    """
    path = Path(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ParameterError(f"{path}: not a readable fit result ({exc})") from None
    if not isinstance(data, dict):
        raise ParameterError(f"{path}: not a fit result (expected a JSON object)")
    if isinstance(data.get("fits"), list) and data["fits"]:
        try:
            data = _from_fit_json(data)
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            raise ParameterError(f"{path}: not a readable fit --json output ({exc})") from None
    model_id = data.get("model", data.get("target"))
    if not isinstance(model_id, str):
        raise ParameterError(f"{path}: names no model (expected a 'model' entry)")
    entry = registry.get(model_id)
    params = data.get("params")
    if isinstance(params, dict):
        return entry.create(**params)
    rough = data.get("roughness")
    if isinstance(rough, dict) and "name" in rough:
        value = rough.get("value", rough.get("median"))
        albedo = _stereo_albedo(path.parent)
        return entry.create(**{rough["name"]: value, **albedo})
    raise ParameterError(f"{path}: no parameters found (expected 'params' or 'roughness')")


def _stereo_albedo(folder: Path) -> dict[str, Any]:
    f = folder / "albedo.npy"
    if not f.exists():
        return {}
    a = np.load(f, allow_pickle=False)
    a = a.reshape(-1, a.shape[-1]) if a.ndim == 3 else a.reshape(-1, 1)
    med = np.nanmedian(a, axis=0)
    vals = [float(np.clip(x, 0.0, 1.0)) for x in med]
    return {"albedo": vals if len(vals) > 1 else vals[0]}


def export(
    model: Model,
    target: str,
    path: str | Path,
    *,
    openpbr: bool = False,
    blend: bool | None = None,
    uniforms: bool = False,
    name: str = "rd_brdf",
) -> Export:
    """Write ``model`` as a ``target`` material to ``path`` (files written whole or not at all).

    Parameters
    ----------
    model : Model
        The model (from the registry, a fit, or :func:`load_result`).
    target : {"mitsuba", "materialx", "blender", "glsl", "gltf"}
    path : path
        The file to write (Mitsuba also writes the scene dict beside it, ``.py``; glTF: a
        ``.glb`` is binary, a ``.gltf`` JSON with the buffer embedded).
    openpbr : bool
        MaterialX: an ``open_pbr_surface`` instead of an ``oren_nayar_diffuse_bsdf``.
    blend : bool or None
        Blender: also the ``.blend`` beside the script (same name), saved by Blender's own
        Python: ``None`` where it is found, ``True`` always, ``False`` never.
    uniforms : bool
        GLSL: the model's numeric parameters as ``uniform`` declarations (named after the
        parameters, angles in radians) instead of constants.
    name : str
        GLSL: the function's name, ``vec3 NAME(vec3 wi, vec3 wo)``.

    Raises
    ------
    ValueError
        For an unknown target or a model the target cannot hold (with the reason).
    OSError
        If the file cannot be written.
    BlenderError
        If Blender's process fails while writing the ``.blend``.

    Warns
    -----
    BackendWarning
        Where a backend of the target renders the material as another model (MaterialX's
        OSL and MDL outputs, Cycles' OSL), one line naming what it renders
        (:class:`roughdiffuse.exporters.common.BackendWarning`; also in ``Export.warnings``).
    """
    _check_target(target)
    check_model(model, target)
    path = Path(path)
    if target == "mitsuba":
        from .mitsuba import write

        return write(model, path)
    if target == "materialx":
        from .materialx import write as write_mtlx

        return write_mtlx(model, path, openpbr=openpbr)
    if target == "glsl":
        from .glsl import write as write_glsl

        return write_glsl(model, path, uniforms=uniforms, name=name)
    if target == "gltf":
        from .gltf import write as write_gltf

        return write_gltf(model, path)
    from .blender import write as write_blender

    return write_blender(model, path, blend=blend)


def _check_target(target: str) -> None:
    if target not in TARGETS:
        raise ParameterError(
            f"unknown export target {target!r}; choose one of: {', '.join(TARGETS)}"
        )


def planned_files(
    model: Model | None, target: str, path: str | Path, *, blend: bool | None = None
) -> tuple[Path, ...]:
    """Every file :func:`export` will write for these arguments, ``path`` first: Mitsuba's
    ``.xml``, its ``.py`` and (Lambert, Burley 2015) its ``_builtin.xml``; MaterialX's
    ``.mtlx``; Blender's ``.py`` and (``blend``, see :func:`export`) its ``.blend``; glTF's
    ``.gltf`` or ``.glb``. A command checks each of them before any work (and keeps each
    existing one unless ``--force``).
    ``model`` ``None`` (not known yet: before a fit) gives every file the target may write.

    Raises
    ------
    ValueError
        For an unknown target, or a ``path`` whose suffix is not the target's (``.xml``,
        ``.mtlx``, ``.py``, ``.glsl``, ``.gltf`` or ``.glb``): two of the files would have the
        same name.
    """
    _check_target(target)
    path = Path(path)
    if path.suffix.lower() not in suffixes(target):
        raise ParameterError(
            f"the {target} target writes a {' or '.join(suffixes(target))} file (got {str(path)!r})"
        )
    if target == "mitsuba":
        from .mitsuba import files_for

        return files_for(model, path)
    if target == "blender":
        from .blender import files_for as blender_files

        return blender_files(path, blend)
    return (path,)
