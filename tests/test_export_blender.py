"""The exported Blender material rendered by Cycles, through Blender's own Python.

Blender (the ``bpy`` wheel, ``make install-blender``) runs in a virtual environment of its own
(``.venv-blender``, or ``ROUGHDIFFUSE_BLENDER_PYTHON``), as a subprocess on
:mod:`roughdiffuse.exporters.blender_scene`; without it these tests skip. The scenes: a sun of
irradiance 1 with parallel rays, an orthographic camera, direct light only, a pixel filter
0.01 pixel wide (each pixel sees its centre).

* A flat plane: every pixel sees one geometry, so each render is one value of
  f(wi, wo) cos θi, which must equal roughdiffuse's ``cycles-diffuse`` there to float32,
  rendered through Cycles' SVM and through its OSL (``scene.cycles.shading_system``, whose
  Diffuse BSDF is ``node_diffuse_bsdf.osl``: the ``oren_nayar_diffuse_bsdf`` closure,
  ``cycles-osl``).
* A unit sphere (a point of a point cloud, which Cycles intersects exactly) lit from the side,
  against roughdiffuse's own ray tracer (:func:`roughdiffuse.render.render`, one sample at each
  pixel centre). Inside the disc, the median relative difference is at float32 level; the
  largest comes from the samples' jitter within the filter (16 samples per pixel).
* Oren–Nayar (σ = 20°) exported to Blender is converted; the sphere Cycles renders from it
  differs from roughdiffuse's render of Oren–Nayar by no more than the conversion's stated
  largest difference of f cos θi.
"""

from __future__ import annotations

import json
import math
import subprocess

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.exporters import export
from roughdiffuse.exporters.blender import write
from roughdiffuse.exporters.blender_run import blender_command, run_scene

ALBEDO = [0.8, 0.5, 0.2]
ROUGHNESS = 0.6
PLANE = [(50.0, 0.0, 0.0), (50.0, 60.0, 0.0), (60.0, 45.0, 180.0), (30.0, 70.0, 90.0)]
SIZE = 48  # sphere image, pixels
MARGIN = 0.04  # roughdiffuse's default camera margin: the frame is 2 (1 + 2 margin) wide
LIGHT = (math.radians(40.0), math.radians(35.0))  # towards the sun: θ, φ


def _direction(theta: float, phi: float) -> list[float]:
    return [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]


def _deg(theta: float, phi: float) -> list[float]:
    return _direction(math.radians(theta), math.radians(phi))


@pytest.fixture(scope="module")
def blender():
    command = blender_command()
    if command is None:
        pytest.skip("no Blender interpreter (make install-blender, or ROUGHDIFFUSE_BLENDER_PYTHON)")
    return command


def _sphere_job(output) -> dict:
    return {"kind": "render", "shape": "sphere", "light": _direction(*LIGHT),
            "view": [0.0, 0.0, 1.0], "size": SIZE, "scale": 2.0 * (1.0 + 2.0 * MARGIN),
            "samples": 16, "output": str(output)}  # fmt: skip


@pytest.fixture(scope="module")
def cycles():
    return registry.create("cycles-diffuse", albedo=ALBEDO, roughness=ROUGHNESS)


SHADING = {"svm": ("cycles-diffuse", False), "osl": ("cycles-osl", True)}
"""Cycles' shading systems: the variant each renders, and ``scene.cycles.shading_system``."""


@pytest.fixture(scope="module")
def plane(blender, tmp_path_factory):
    """One Blender process: the plane at each geometry, made of the exported Cycles variant as
    a Diffuse BSDF and as a Principled BSDF (its "Diffuse Roughness", specular off), each
    shaded by Cycles' SVM and by its OSL."""
    tmp = tmp_path_factory.mktemp("blender_plane")
    cycles = registry.create("cycles-diffuse", albedo=ALBEDO, roughness=ROUGHNESS)
    exported = write(cycles, tmp / "cycles.py", blend=False)
    write(cycles, tmp / "principled.py", principled=True, blend=False)
    jobs = [
        {"kind": "render", "shape": "plane", "light": _deg(ti, 0.0), "view": _deg(to, dp),
         "size": 8, "scale": 1.0, "samples": 4, "material": str(tmp / f"{node}.py"),
         "osl": osl, "output": str(tmp / f"{node}_{shading}{k}.npy")}
        for node in ("cycles", "principled") for shading, (_, osl) in SHADING.items()
        for k, (ti, to, dp) in enumerate(PLANE)
    ]  # fmt: skip
    run_scene(tmp / "cycles.py", jobs)
    images = {
        (n, s): [np.load(tmp / f"{n}_{s}{k}.npy") for k in range(len(PLANE))]
        for n in ("cycles", "principled") for s in SHADING
    }  # fmt: skip
    return exported, images


@pytest.fixture(scope="module")
def spheres(blender, cycles, tmp_path_factory):
    """The sphere rendered by Cycles from the Cycles variant (exported exactly) and from
    Oren–Nayar (exported converted)."""
    tmp = tmp_path_factory.mktemp("blender_sphere")
    source = registry.create("oren-nayar-full", albedo=ALBEDO, sigma=math.radians(20.0))
    converted = write(source, tmp / "oren_nayar.py", blend=False)
    write(cycles, tmp / "cycles.py", blend=False)
    run_scene(tmp / "cycles.py", [_sphere_job(tmp / "sphere.npy")])
    run_scene(tmp / "oren_nayar.py", [_sphere_job(tmp / "sphere_on.npy")])
    return {
        "cycles": np.load(tmp / "sphere.npy"),
        "source": source,
        "converted": converted,
        "oren_nayar": np.load(tmp / "sphere_on.npy"),
    }


def _ours(model) -> tuple[np.ndarray, np.ndarray]:
    from roughdiffuse.render import DistantLight, OrthographicCamera, Sphere, render

    image, mask = render(
        model, Sphere(), DistantLight(*LIGHT), OrthographicCamera(0.0, 0.0, margin=MARGIN),
        size=SIZE, samples_per_pixel=1,
    )  # fmt: skip
    return image, mask


def _interior(image: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Pixels whose 3 × 3 neighbourhood lies on the sphere, lit above 1 % of the brightest."""
    from scipy.ndimage import binary_erosion

    lum = image.mean(axis=-1)
    return binary_erosion(mask == 1) & (lum > 0.01 * lum.max())


@pytest.mark.slow
@pytest.mark.parametrize("shading", list(SHADING))
@pytest.mark.parametrize("node", ["cycles", "principled"])
def test_cycles_renders_the_plane_as_the_cycles_variant(plane, node, shading):
    """SVM and OSL each render their variant (cycles-diffuse, cycles-osl) to float32."""
    exported, images = plane
    assert exported.conversion is None
    model = registry.create(SHADING[shading][0], albedo=ALBEDO, roughness=ROUGHNESS)
    for (ti, to, dp), image in zip(PLANE, images[node, shading], strict=True):
        got = image.reshape(-1, 3).mean(axis=0)
        wi, wo = np.array(_deg(ti, 0.0)), np.array(_deg(to, dp))
        expected = np.asarray(model.brdf(wi, wo)) * wi[2]
        # float32: Cycles' own arithmetic (measured ≤ 1e-6 relative, both nodes)
        np.testing.assert_allclose(got, expected, rtol=5e-6, err_msg=str((ti, to, dp)))
        spread = np.ptp(image.reshape(-1, 3), axis=0)  # one geometry, one value
        np.testing.assert_array_less(spread, 5e-6 * expected)


@pytest.mark.slow
def test_cycles_renders_the_sphere_as_roughdiffuse(spheres, cycles):
    ours, mask = _ours(cycles)
    theirs = spheres["cycles"]
    keep = _interior(ours, mask)
    assert keep.sum() > 0.4 * SIZE * SIZE  # the lit part of the disc
    rel = np.abs(theirs - ours)[keep] / ours[keep]
    assert float(np.median(rel)) < 1e-5  # float32 (measured 4e-6)
    assert float(np.percentile(rel, 99)) < 1e-3  # sub-pixel jitter (measured 1e-4 near the limb)
    assert float(np.max(np.abs(theirs - ours)[keep])) < 2e-3 * float(ours.max())
    # the lit part of the disc is the same set of pixels, up to those its edges cross
    lit_ours, lit_theirs = ours.mean(-1) > 0, theirs.mean(-1) > 0
    assert float((lit_ours != lit_theirs).sum()) < 0.02 * float(lit_ours.sum())


def _rms_f_cos(model, n: int = 24) -> float:
    """Root mean square of f cos θi over both hemispheres in solid angle (midpoint rule in μi,
    μo and Δφ on [0, π]): the normalisation of :func:`roughdiffuse.convert`'s differences."""
    mu = (np.arange(n) + 0.5) / n
    phi = (np.arange(n) + 0.5) / n * math.pi
    mi, mo, ph = (g.ravel() for g in np.meshgrid(mu, mu, phi, indexing="ij"))
    si, so = np.sqrt(1 - mi**2), np.sqrt(1 - mo**2)
    wi = np.stack([si, np.zeros_like(si), mi], -1)
    wo = np.stack([so * np.cos(ph), so * np.sin(ph), mo], -1)
    value = np.asarray(model.brdf(wi, wo)) * mi[:, None]
    return float(np.sqrt(np.mean(value**2)))


@pytest.mark.slow
def test_cycles_renders_the_converted_material_within_the_stated_error(spheres):
    conversion = spheres["converted"].conversion
    assert conversion is not None and conversion.target == "cycles-diffuse"
    source = spheres["source"]
    ours, mask = _ours(source)
    theirs = spheres["oren_nayar"]
    keep = _interior(ours, mask)
    diff = np.abs(theirs - ours)[keep]
    # the conversion's largest difference of f cos θi, relative to the source's RMS f cos θi
    # (stated over its quadrature nodes; the sphere's pixels are other geometries: 10 % margin)
    assert float(diff.max()) <= 1.1 * conversion.max_f * _rms_f_cos(source)
    # and it is a real difference, larger than Cycles' own error
    assert float(np.median(diff / ours[keep])) > 1e-3


BLEND_CHECK = """
import bpy, json, sys
bpy.ops.wm.open_mainfile(filepath=sys.argv[-1])
node = [n for n in bpy.data.materials["roughdiffuse"].node_tree.nodes
        if n.bl_idname == "ShaderNodeBsdfDiffuse"][0]
print("VALUES" + json.dumps([list(node.inputs["Color"].default_value),
                            node.inputs["Roughness"].default_value,
                            bpy.context.scene.render.engine]))
"""


@pytest.mark.slow
def test_the_blend_file_holds_the_material(blender, cycles, tmp_path):
    result = export(cycles, "blender", tmp_path / "material.py")
    blend = tmp_path / "material.blend"
    assert result.paths == (tmp_path / "material.py", blend)
    assert blend.read_bytes()[:4] in (b"BLEN", b"\x28\xb5\x2f\xfd")  # plain or zstd-compressed
    args = [*blender, "-c", BLEND_CHECK, str(blend)] if len(blender) == 1 else None
    if args is None:
        pytest.skip("the .blend check runs through a Python with bpy")
    out = subprocess.run(args, capture_output=True, text=True, timeout=300, check=True).stdout
    colour, rough, engine = json.loads(out.split("VALUES", 1)[1].splitlines()[0])
    np.testing.assert_allclose(colour, [*ALBEDO, 1.0], rtol=1e-7)  # float32 sockets
    assert rough == pytest.approx(ROUGHNESS, rel=1e-7)
    assert engine == "CYCLES"


def test_the_blender_interpreter_is_found_or_refused(monkeypatch, tmp_path):
    """Without Blender: a named interpreter that is not there is refused, one that has no bpy
    fails with Blender's own last lines, and a .blend given as the script's name is refused."""
    import sys

    from roughdiffuse.exporters.blender_run import ENV, BlenderError

    monkeypatch.setenv(ENV, str(tmp_path / "no-such-python"))
    with pytest.raises(ValueError, match=ENV):
        blender_command()
    monkeypatch.setenv(ENV, sys.executable)  # a Python without bpy
    assert blender_command() == [sys.executable]
    script = tmp_path / "m.py"
    script.write_text("")
    with pytest.raises(BlenderError, match="bpy"):
        run_scene(script, [])
    with pytest.raises(ValueError, match=r"\.py"):
        write(registry.create("eon"), tmp_path / "m.blend")
