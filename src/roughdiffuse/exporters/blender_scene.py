"""Run by Blender's own Python (``bpy``), not by roughdiffuse: the scenes of the Blender check.

``python blender_scene.py REQUEST.json`` (the interpreter of the ``bpy`` wheel, or
``blender --background --python blender_scene.py -- REQUEST.json``). The request holds the
exported material script and a list of jobs (each may name its own ``"material"`` script):

* ``{"kind": "render", "shape": "plane" | "sphere", "light": [x, y, z], "view": [x, y, z],
  "size": N, "scale": S, "samples": K, "output": "out.npy"}`` (and ``"pixel_filter": "box"``
  to average over each pixel's area instead of its centre; ``"osl": true`` to shade through
  Cycles' OSL, ``scene.cycles.shading_system``, instead of its SVM): renders the shape made of
  the material in Cycles and saves the linear RGB image (float32, row 0 at the top) as ``.npy``;
* ``{"kind": "blend", "output": "material.blend"}``: saves the sphere scene with the material
  as a ``.blend`` file.

The scene: a sun of strength 1 (irradiance 1 W/m² on a plane facing it, ``angle`` 0: parallel
rays) towards ``light``, no world light, direct light only (``max_bounces`` 0), an orthographic
camera towards ``view`` whose frame is ``scale`` wide, and a pixel filter 0.01 pixel wide, so
each pixel sees its centre. The plane is 40 units wide through the origin (normal +z); the
sphere has radius 1 at the origin and is a point of a point cloud, which Cycles intersects as
an exact sphere (no tessellation). This module imports only ``bpy``, ``mathutils``, ``json``
and ``numpy`` (from Blender's environment): it must not import roughdiffuse.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

__all__ = ["main"]


def _look(obj: Any, towards: list[float]) -> None:
    """Place ``obj`` so that its local −Z points along −``towards`` (it looks at the origin
    from that side); straight down the z axis the rotation is the identity (image x = world x)."""
    from mathutils import Vector

    d = Vector(towards).normalized()
    if abs(d.z - 1.0) < 1e-12:
        obj.rotation_euler = (0.0, 0.0, 0.0)
    else:
        obj.rotation_euler = (-d).to_track_quat("-Z", "Y").to_euler()


def _sphere(bpy: Any, material: Any) -> Any:
    """A unit sphere at the origin: one point of radius 1 made by geometry nodes."""
    tree = bpy.data.node_groups.new("sphere", "GeometryNodeTree")
    tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    points = tree.nodes.new("GeometryNodePoints")
    points.inputs["Count"].default_value = 1
    points.inputs["Radius"].default_value = 1.0
    setmat = tree.nodes.new("GeometryNodeSetMaterial")
    setmat.inputs["Material"].default_value = material
    out = tree.nodes.new("NodeGroupOutput")
    tree.links.new(points.outputs["Points"], setmat.inputs["Geometry"])
    tree.links.new(setmat.outputs["Geometry"], out.inputs["Geometry"])
    obj = bpy.data.objects.new("sphere", bpy.data.meshes.new("sphere"))
    bpy.context.scene.collection.objects.link(obj)
    obj.modifiers.new("sphere", "NODES").node_group = tree
    obj.data.materials.append(material)
    return obj


def _plane(bpy: Any, material: Any) -> Any:
    bpy.ops.mesh.primitive_plane_add(size=40.0)
    obj = bpy.context.active_object
    obj.data.materials.clear()
    obj.data.materials.append(material)
    return obj


def _scene(bpy: Any, material_script: str, job: dict[str, Any]) -> Any:
    """Build the scene of ``job`` from factory settings; returns the scene."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    exec(compile(material_script, "material.py", "exec"), {"__name__": "__main__"})  # noqa: S102
    material = bpy.data.materials["roughdiffuse"]
    material.use_fake_user = True
    (_plane if job.get("shape") == "plane" else _sphere)(bpy, material)
    sun = bpy.data.lights.new("sun", type="SUN")
    sun.energy = 1.0
    sun.angle = 0.0
    sun_obj = bpy.data.objects.new("sun", sun)
    scene.collection.objects.link(sun_obj)
    _look(sun_obj, job.get("light", [0.0, 0.0, 1.0]))
    cam = bpy.data.cameras.new("camera")
    cam.type = "ORTHO"
    cam.ortho_scale = float(job.get("scale", 2.2))
    cam.clip_end = 100.0
    cam_obj = bpy.data.objects.new("camera", cam)
    scene.collection.objects.link(cam_obj)
    view = job.get("view", [0.0, 0.0, 1.0])
    cam_obj.location = [10.0 * float(x) for x in view]
    _look(cam_obj, view)
    scene.camera = cam_obj
    _settings(scene, int(job.get("size", 64)), int(job.get("samples", 16)))
    scene.cycles.shading_system = bool(job.get("osl", False))  # True: OSL (CPU only)
    if job.get("pixel_filter") == "box":  # the pixel's area, as roughdiffuse's k × k samples
        scene.cycles.pixel_filter_type = "BOX"
        scene.render.filter_size = scene.cycles.filter_width = 1.0
    return scene


def _settings(scene: Any, size: int, samples: int) -> None:
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.seed = 0
    scene.cycles.max_bounces = 0
    scene.cycles.use_denoising = False
    scene.cycles.pixel_filter_type = "GAUSSIAN"
    scene.cycles.filter_width = 0.01
    scene.render.filter_size = 0.01  # the film's filter width, which Cycles reads in Blender 5
    scene.render.resolution_x = scene.render.resolution_y = size
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.world = None
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "ZIP"


def _render(bpy: Any, scene: Any, output: Path) -> None:
    import numpy as np

    exr = output.with_suffix(".exr")
    scene.render.filepath = str(exr)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(exr))
    w, h = img.size
    pixels = np.array(img.pixels[:], dtype=np.float32).reshape(h, w, 4)[::-1, :, :3]
    np.save(output, np.ascontiguousarray(pixels))
    exr.unlink()


def main(argv: list[str]) -> int:
    """Run the jobs of the request file ``argv[-1]``."""
    import bpy

    request = json.loads(Path(argv[-1]).read_text(encoding="utf-8"))
    for job in request["jobs"]:
        material = job.get("material", request["material"])
        scene = _scene(bpy, Path(material).read_text(encoding="utf-8"), job)
        output = Path(job["output"])
        if job["kind"] == "blend":
            bpy.ops.wm.save_as_mainfile(filepath=str(output), compress=True)
        else:
            _render(bpy, scene, output)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
