"""The exported Blender script rendered by Cycles (the optional ``bpy`` wheel, extra
``blender``): a flat plane under a sun, an orthographic camera, direct light only
(``max_bounces`` 0), Standard view transform, written to EXR. Every pixel sees the same
geometry, so each render is one value of f(wi, wo) E cos θi; it must equal roughdiffuse's
``cycles-diffuse`` at that geometry to float32 precision. Skipped without ``bpy``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.materials import export

ALBEDO = [0.8, 0.5, 0.2]
ROUGHNESS = 0.6
GEOMETRIES = [(50.0, 0.0, 0.0), (50.0, 60.0, 0.0), (60.0, 45.0, 180.0), (30.0, 70.0, 90.0)]


def _direction(theta_deg: float, phi_deg: float) -> np.ndarray:
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def _render(bpy, script: str, tmp_path, theta_i: float, theta_o: float, dphi: float) -> np.ndarray:
    from mathutils import Vector

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    exec(compile(script, "material.py", "exec"), {"__name__": "__main__"})  # noqa: S102
    sun = bpy.data.lights.new("sun", type="SUN")
    sun.energy = 1.0  # irradiance 1 W/m² perpendicular to the sun
    sun.angle = 0.0
    sun_obj = bpy.data.objects.new("sun", sun)
    scene.collection.objects.link(sun_obj)
    l_dir = _direction(theta_i, 0.0)
    sun_obj.rotation_euler = Vector(-l_dir).to_track_quat("-Z", "Y").to_euler()
    cam = bpy.data.cameras.new("cam")
    cam.type = "ORTHO"
    cam.ortho_scale = 1.0
    cam_obj = bpy.data.objects.new("cam", cam)
    scene.collection.objects.link(cam_obj)
    v_dir = _direction(theta_o, dphi)
    cam_obj.location = Vector(5.0 * v_dir)
    cam_obj.rotation_euler = Vector(-v_dir).to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam_obj
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 4
    scene.cycles.max_bounces = 0
    scene.cycles.use_denoising = False
    scene.render.resolution_x = scene.render.resolution_y = 8
    scene.view_settings.view_transform = "Standard"
    scene.world = None
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    out = tmp_path / f"r_{theta_i}_{theta_o}_{dphi}.exr"
    scene.render.filepath = str(out)
    bpy.ops.render.render(write_still=True)
    img = bpy.data.images.load(str(out))
    pixels = np.array(img.pixels[:], dtype=np.float64).reshape(8, 8, 4)[..., :3]
    return pixels.reshape(-1, 3).mean(axis=0)


def test_cycles_renders_the_exported_material_as_the_cycles_variant(tmp_path):
    bpy = pytest.importorskip("bpy", reason="bpy (Blender as a module) is not installed")
    model = registry.create("cycles-diffuse", albedo=ALBEDO, roughness=ROUGHNESS)
    export(model, "blender", tmp_path / "material.py")
    script = (tmp_path / "material.py").read_text()
    for ti, to, dp in GEOMETRIES:
        got = _render(bpy, script, tmp_path, ti, to, dp)
        wi, wo = _direction(ti, 0.0), _direction(to, dp)
        expected = np.asarray(model.brdf(wi, wo)) * math.cos(math.radians(ti))
        np.testing.assert_allclose(got, expected, rtol=2e-5, err_msg=str((ti, to, dp)))
