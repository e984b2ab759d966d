"""Write a model, or a fit result, as a material another renderer opens.

Targets (:data:`TARGETS`):

* ``mitsuba``: a Mitsuba 3 scene (XML, and the same scene as a Python dict in a ``.py``)
  with the model's roughdiffuse plugin (exact), a sphere under a directional light and an
  orthographic camera; Lambert also as Mitsuba's own ``diffuse``, Burley 2015 as its
  ``principled`` with ``specular`` 0;
* ``materialx``: a ``.mtlx`` document with an ``oren_nayar_diffuse_bsdf`` (or, with
  ``openpbr=True``, an ``open_pbr_surface`` with ``base_diffuse_roughness``);
* ``blender``: a ``.py`` that builds the node tree (Diffuse BSDF) when run by Blender or
  ``bpy``.

Where the target cannot hold the model exactly, the parameters are converted
(:func:`roughdiffuse.conversion.convert`) and the conversion error is written into the file's
comments and returned. A ``UsdPreviewSurface`` is not offered: its diffuse lobe has no
roughness, so any rough model would be exported wrong.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import registry
from ..conversion import Conversion, convert
from ..io.atomic import write_text
from ..models.base import Model

__all__ = ["TARGETS", "Export", "export", "load_result", "material_for", "model_record"]

TARGETS: dict[str, tuple[str, str]] = {
    # target -> (file suffix, the registry id of what the renderer computes)
    "mitsuba": (".xml", ""),
    "materialx": (".mtlx", "materialx-eon"),
    "blender": (".py", "cycles-diffuse"),
}
"""Export targets: their file suffix and the registry model the renderer evaluates ('' for
Mitsuba: the plugin of the model itself)."""


@dataclass(frozen=True)
class Export:
    """What :func:`export` wrote: the files, the target model and the conversion (or None)."""

    target: str
    paths: tuple[Path, ...]
    model_id: str
    params: dict[str, Any]
    conversion: Conversion | None

    def summary(self) -> str:
        """The lines ``roughdiffuse export`` prints."""
        lines = [f"{self.target}: {', '.join(str(p) for p in self.paths)}"]
        lines.append(f"  as {self.model_id}: " + _params_text(self.params))
        lines.extend("  " + line for line in error_lines(self.conversion))
        return "\n".join(lines)


def _params_text(params: dict[str, Any]) -> str:
    return ", ".join(f"{k}={_num(v)}" for k, v in params.items())


def _num(v: Any) -> str:
    if isinstance(v, list | tuple):
        return "[" + ", ".join(f"{x:.6g}" for x in v) + "]"
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def error_lines(conversion: Conversion | None) -> list[str]:
    """The conversion error as comment lines ('exact' when nothing was converted)."""
    if conversion is None:
        return ["exact: the target computes this model (no conversion)"]
    return [
        f"converted from {conversion.source} by least squares (roughdiffuse.conversion):",
        f"f cos theta_i differs by {100 * conversion.rms_f:.3g} % RMS, "
        f"{100 * conversion.max_f:.3g} % at most (relative to the source's RMS);",
        f"directional albedo differs by {100 * conversion.rms_albedo:.3g} % RMS, "
        f"{100 * conversion.max_albedo:.3g} % at most",
    ]


def _params_of(model: Model, model_id: str) -> dict[str, Any]:
    entry = registry.get(model_id)
    out: dict[str, Any] = {}
    for p in entry.parameters:
        if p.categorical:
            continue
        value = getattr(model, p.name)
        if value is None:
            continue
        arr = [float(x) for x in np.ravel(value)]
        out[p.name] = arr if len(arr) > 1 else arr[0]
    return out


def model_record(model: Model) -> dict[str, Any]:
    """``{"model": id, "params": {...}}``, which :func:`load_result` reads (``ValueError``
    for a model the registry does not name)."""
    model_id = registry.id_of(model)
    if model_id is None:
        raise ValueError(f"{type(model).__name__} is not a registry model")
    return {"model": model_id, "params": _params_of(model, model_id)}


def material_for(model: Model, target_id: str) -> tuple[dict[str, Any], Conversion | None]:
    """The parameters of ``target_id`` for ``model``: its own if it is that model, else
    converted (``ValueError`` if the target cannot hold it)."""
    source_id = registry.id_of(model)
    if source_id == target_id or (
        source_id is not None and registry.get(source_id).cls is registry.get(target_id).cls
    ):
        return _params_of(model, target_id), None
    base = getattr(model, "base_model", None)
    if base is not None and registry.id_of(base()) == target_id:  # an alias of the target
        return _params_of(base(), target_id), None
    result = convert(model, target=target_id)
    return dict(result.params), result


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
        raise ValueError(f"{path}: not a readable fit result ({exc})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{path}: not a fit result (expected a JSON object)")
    if isinstance(data.get("fits"), list) and data["fits"]:
        try:
            data = _from_fit_json(data)
        except (KeyError, TypeError, ValueError, IndexError) as exc:
            raise ValueError(f"{path}: not a readable fit --json output ({exc})") from None
    model_id = data.get("model", data.get("target"))
    if not isinstance(model_id, str):
        raise ValueError(f"{path}: names no model (expected a 'model' entry)")
    entry = registry.get(model_id)
    params = data.get("params")
    if isinstance(params, dict):
        return entry.create(**params)
    rough = data.get("roughness")
    if isinstance(rough, dict) and "name" in rough:
        value = rough.get("value", rough.get("median"))
        albedo = _stereo_albedo(path.parent)
        return entry.create(**{rough["name"]: value, **albedo})
    raise ValueError(f"{path}: no parameters found (expected 'params' or 'roughness')")


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
) -> Export:
    """Write ``model`` as a ``target`` material to ``path`` (files written whole or not at all).

    Parameters
    ----------
    model : Model
        The model (from the registry, a fit, or :func:`load_result`).
    target : {"mitsuba", "materialx", "blender"}
    path : path
        The file to write (Mitsuba also writes the scene dict beside it, ``.py``).
    openpbr : bool
        MaterialX: an ``open_pbr_surface`` instead of an ``oren_nayar_diffuse_bsdf``.

    Raises
    ------
    ValueError
        For an unknown target or a model the target cannot hold (with the reason).
    OSError
        If the file cannot be written.
    """
    if target not in TARGETS:
        raise ValueError(f"unknown export target {target!r}; choose one of: {', '.join(TARGETS)}")
    path = Path(path)
    if target == "mitsuba":
        from .mitsuba import write

        return write(model, path)
    if target == "materialx":
        from .materialx import write as write_mtlx

        return write_mtlx(model, path, openpbr=openpbr)
    from .blender import write as write_blender

    return write_blender(model, path)


def write_files(files: dict[Path, str]) -> tuple[Path, ...]:
    """Write each text file whole (:mod:`roughdiffuse.io.atomic`)."""
    for p, text in files.items():
        write_text(p, text)
    return tuple(files)
