"""Mitsuba 3 scenes of a model: XML and a Python dict, with roughdiffuse's plugin.

The scene: a unit sphere, a directional light of irradiance 1 from (θ, φ) = (50°, 0°), an
orthographic camera on the normal framing the sphere with a 4 % margin (as
:class:`roughdiffuse.render.OrthographicCamera`), the ``path`` integrator with ``max_depth`` 2
(direct light only, as roughdiffuse's renderer). Loading either needs the plugins registered
first (``roughdiffuse.integrations.mitsuba.register()``). Lambert is also written with
Mitsuba's own ``diffuse``, Burley 2015 with its ``principled`` (``specular`` 0), both exact.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any
from xml.sax.saxutils import quoteattr

from .. import registry
from .._mitsuba_scene import orthographic_sensor
from .._validate import ParameterError
from ..integrations.mitsuba import plugin_name
from ..models.base import Model
from .common import Export, error_lines, params_of, rgb_of, write_files, xml_comment_text

__all__ = [
    "LIGHT",
    "MARGIN",
    "SIZE",
    "bsdf_dict",
    "scene_dict",
    "scene_xml",
    "write",
]

LIGHT = (50.0, 0.0)
"""Direction towards the light, (θ, φ) in degrees."""
MARGIN = 0.04
SIZE = 64

_BUILTIN = {"lambert": "diffuse", "burley-2015": "principled"}


def bsdf_dict(model: Model, builtin: bool = False) -> dict[str, Any]:
    """The BSDF: the model's roughdiffuse plugin, or (``builtin``) Mitsuba's own counterpart."""
    model_id = registry.id_of(model)
    if model_id is None:
        raise ParameterError(
            f"{type(model).__name__} is not a registry model; Mitsuba cannot hold it"
        )
    entry = registry.get(model_id)
    if not builtin and not entry.cls.mitsuba:
        raise ParameterError(
            f"{model_id} has no Mitsuba plugin (a Monte Carlo simulation); export a closed-form "
            "model (roughdiffuse convert)"
        )
    params = params_of(model, model_id)
    albedo = params.get("albedo", 1.0)
    colour = {"type": "rgb", "value": rgb_of(albedo)}
    if builtin:
        kind = _BUILTIN.get(model_id)
        if kind == "diffuse":
            return {"type": "diffuse", "reflectance": colour}
        if kind == "principled":
            return {
                "type": "principled",
                "base_color": colour,
                "roughness": params["roughness"],
                "specular": 0.0,
            }
        raise ParameterError(f"Mitsuba has no built-in BSDF equal to {model_id!r}")
    out: dict[str, Any] = {"type": plugin_name(model_id)}
    declared = {p.name: p for p in entry.parameters}
    for name, value in params.items():
        if declared[name].channels:  # a colour texture
            out[name] = {"type": "rgb", "value": rgb_of(value)}
        elif isinstance(value, list):  # the plugin takes a float
            raise ParameterError(f"{name} has {len(value)} values; Mitsuba's {name} takes one")
        else:
            out[name] = value
    out.update(_categorical(model, entry))
    return out


def _categorical(model: Model, entry: registry.Entry) -> dict[str, str]:
    """The model's categorical values (``bounces``, ``measure``, ``variant``...), as the
    plugin's strings: every one, so the scene is the model and not the plugin's defaults."""
    choices: dict[str, str] = {}
    for p in entry.parameters:
        if not p.categorical:
            continue
        value = getattr(model, p.name, entry.fixed.get(p.name))
        if value is None:
            raise ParameterError(
                f"{entry.id}: its {p.name} cannot be read from the model; Mitsuba cannot hold it"
            )
        choices[p.name] = str(value)
    return choices


def _direction(theta_deg: float, phi_deg: float) -> list[float]:
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return [math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)]


def scene_dict(bsdf: dict[str, Any], size: int = SIZE, spp: int = 256) -> dict[str, Any]:
    """The scene as a dict of plain values (``to_world`` as a 4×4 list), for ``mi.load_dict``
    after ``to_world`` is wrapped: :func:`load_dict` does it."""
    l = _direction(*LIGHT)
    half = 1.0 + 2.0 * MARGIN
    # look_at from (0, 0, 10) to the origin, up (0, 1, 0), times scale(half, half, 1):
    # camera x = -world x, camera z = -world z (Mitsuba's look_at: x = up × dir)
    to_world = [[-half, 0, 0, 0], [0, half, 0, 0], [0, 0, -1, 10], [0, 0, 0, 1]]
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 2},
        "sensor": orthographic_sensor(to_world, size, spp),
        "light": {"type": "directional", "direction": [-x for x in l], "irradiance": 1.0},
        "sphere": {"type": "sphere", "bsdf": bsdf},
    }


def load_dict(mi: Any, scene: dict[str, Any]) -> Any:
    """``mi.load_dict`` of :func:`scene_dict` (its ``to_world`` made a transform)."""
    s = {**scene, "sensor": {**scene["sensor"]}}
    s["sensor"]["to_world"] = mi.ScalarTransform4f(s["sensor"]["to_world"])
    return mi.load_dict(s)


def _xml_value(name: str, value: Any) -> str:
    if isinstance(value, dict) and value.get("type") == "rgb":
        v = ", ".join(f"{x:.17g}" for x in value["value"])
        return f'<rgb name="{name}" value="{v}"/>'
    if isinstance(value, str):
        return f'<string name="{name}" value={quoteattr(value)}/>'
    return f'<float name="{name}" value="{float(value):.17g}"/>'


def scene_xml(bsdf: dict[str, Any], comments: list[str], size: int = SIZE, spp: int = 256) -> str:
    """The scene of :func:`scene_dict` as Mitsuba 3 XML."""
    scene = scene_dict(bsdf, size, spp)
    m = scene["sensor"]["to_world"]
    matrix = " ".join(f"{x:g}" for row in m for x in row)
    d = ", ".join(f"{x:.17g}" for x in scene["light"]["direction"])
    inner = "\n".join(f"        {_xml_value(k, v)}" for k, v in bsdf.items() if k != "type")
    notes = "\n".join(f"     {xml_comment_text(line)}" for c in comments for line in c.splitlines())
    return f"""<?xml version="1.0" encoding="utf-8"?>
<!-- written by roughdiffuse export
{notes}
     Load after roughdiffuse.integrations.mitsuba.register() (the roughdiffuse_* plugins). -->
<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <sensor type="orthographic">
        <transform name="to_world"><matrix value="{matrix}"/></transform>
        <film type="hdrfilm">
            <integer name="width" value="{size}"/>
            <integer name="height" value="{size}"/>
            <rfilter type="box"/>
            <string name="pixel_format" value="rgb"/>
        </film>
        <sampler type="independent"><integer name="sample_count" value="{spp}"/></sampler>
    </sensor>
    <emitter type="directional">
        <vector name="direction" value="{d}"/>
        <float name="irradiance" value="1"/>
    </emitter>
    <shape type="sphere">
        <bsdf type="{bsdf["type"]}">
{inner}
        </bsdf>
    </shape>
</scene>
"""


def files_for(model: Model | None, path: Path) -> tuple[Path, ...]:
    """The files :func:`write` writes: the XML scene ``path``, the dict beside it (suffix
    ``.py``) and, for a model Mitsuba has built in, ``STEM_builtin.xml`` (for ``model``
    ``None``, not yet known, every file it may write)."""
    files = [path, path.with_suffix(".py")]
    if model is None or (registry.id_of(model) or "") in _BUILTIN:
        files.append(path.with_name(path.stem + "_builtin.xml"))
    return tuple(files)


def write(model: Model, path: Path) -> Export:
    """Write the XML scene to ``path`` and the dict to ``path`` with suffix ``.py``."""
    bsdf = bsdf_dict(model)
    comments = error_lines(None)
    xml, py, *builtin = files_for(model, path)
    files = {xml: scene_xml(bsdf, comments)}
    files[py] = (
        "# Mitsuba 3 scene written by roughdiffuse export (exact: roughdiffuse's plugin)\n"
        "import mitsuba as mi\n\n"
        "from roughdiffuse.exporters.mitsuba import load_dict\n"
        "from roughdiffuse.integrations.mitsuba import register\n\n"
        "mi.set_variant('scalar_rgb')\nregister()\n"
        f"SCENE = {scene_dict(bsdf)!r}\nscene = load_dict(mi, SCENE)\n"
    )
    mid = registry.id_of(model) or bsdf["type"]
    if builtin:
        files[builtin[0]] = scene_xml(bsdf_dict(model, builtin=True), comments)
    note = check_scenes([text for f, text in files.items() if f.suffix == ".xml"])
    notes = (note,) if note else ()
    params = {**params_of(model, mid), **_categorical(model, registry.get(mid))}
    return Export("mitsuba", write_files(files), mid, params, None, notes)


def check_scenes(xml_texts: list[str]) -> str | None:
    """Load each XML scene in Mitsuba (``scalar_rgb``, the plugins registered), before any
    file is written: a scene that does not load is a ``ValueError``. Returns a note when it
    could not be checked (Mitsuba not installed), else ``None``."""
    try:
        import mitsuba as mi
    except ImportError:
        return "not loaded in Mitsuba here: Mitsuba is not installed (pip install mitsuba)"
    from ..integrations.mitsuba import register

    previous = mi.variant()
    mi.set_variant("scalar_rgb")
    try:
        register()
        for text in xml_texts:
            try:
                mi.load_string(text)
            except Exception as exc:  # noqa: BLE001 - Mitsuba's own refusal, in one line
                lines = [ln.strip() for ln in str(exc).splitlines() if ln.strip()]
                raise ParameterError(
                    f"the Mitsuba scene does not load: {lines[-1] if lines else type(exc).__name__}"
                ) from None
    finally:
        if previous is not None:
            mi.set_variant(previous)
    return None
