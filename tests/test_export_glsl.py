"""roughdiffuse export --to glsl: the function a user pastes into a shader, run in three.js.

The exported file goes into a ``THREE.ShaderMaterial`` on a sphere under a distant light,
seen by an orthographic camera (tests/js/sphere.html, three.js from npm; headless Chromium,
WebGL 2 through SwiftShader, float32), and the radiance read back from a float render target
is compared with roughdiffuse's own ray tracer (:func:`roughdiffuse.render.render`, one
sample at each pixel's centre) for the same sphere, light and camera. The shader finds the
normal where each pixel centre's ray meets the sphere, as the ray tracer does; the material
the documentation shows (tests/js/material.js, the mesh's interpolated normals) is checked
too, within the error of those normals.

Tolerance: |three.js − roughdiffuse| ≤ 1e-4 · |roughdiffuse| + 4e-6 · max(roughdiffuse), per
channel: float32 arithmetic in both renderers (the ray tracer runs the model's array code in
JAX float32; the printed GLSL uses the trace's float32 polynomials, about 1e-7 relative, and
the GPU's sqrt, atan, ...). Measured: 5e-6 relative where n·l > 0.05. The absolute part is
for the terminator, where the radiance is n·l itself rounded: a dot product of unit vectors
carries a few float32 steps of 1 (1.2e-7 each) in each renderer; measured 9e-7 of the
brightest pixel.

Only pixels away from the silhouette are compared (n·v ≥ 0.1): there the normal changes with
image position by a factor 1 / (n·v), so the float32 rounding of each pixel's position, done
differently in the two renderers (three.js un-projects ``gl_FragCoord`` through its camera
matrices, the ray tracer adds offsets to the image centre), grows without bound, and a pixel
whose centre lies within rounding of the rim is on the sphere in one image and not in the
other.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.engine.glsl import glsl_uniforms
from roughdiffuse.exporters import TARGETS, export
from roughdiffuse.render import DistantLight, OrthographicCamera, Sphere, pixel_coordinates, render
from threejs_sphere import open_sphere_page, threejs_sphere

RTOL = 1e-4
ATOL = 4e-6  # of the brightest pixel
MIN_COS_VIEW = 0.1
SIZE = 64
LIGHT = DistantLight(math.radians(50.0), math.radians(30.0), (1.0, 0.9, 0.8))
CAMERA = OrthographicCamera(math.radians(20.0), math.radians(100.0))


@pytest.fixture(scope="module")
def page(browser):
    log = open_sphere_page(browser)
    yield log
    log.page.close()


def _interior(camera: OrthographicCamera) -> np.ndarray:
    """Pixels whose centre sees the unit sphere with n·v ≥ MIN_COS_VIEW."""
    x, y = pixel_coordinates(Sphere(), camera, SIZE)
    r2 = x[None, :] ** 2 + y[:, None] ** 2
    return np.sqrt(np.clip(1.0 - r2, 0.0, None)) >= MIN_COS_VIEW


def _compare(page, model, path, uniforms=None):
    """three.js's render of the exported file and roughdiffuse's; the largest difference in
    units of the tolerance."""
    ours, mask = render(model, Sphere(), LIGHT, CAMERA, size=SIZE, samples_per_pixel=1)
    ours = np.broadcast_to(ours[..., None] if ours.ndim == 2 else ours, (SIZE, SIZE, 3))
    theirs, covered = threejs_sphere(
        page, path.read_text(), uniforms=uniforms, light=LIGHT, camera=CAMERA, size=SIZE
    )
    assert not page.errors, page.errors
    inside = _interior(CAMERA)
    assert np.array_equal(covered[inside], mask[inside] == 1) and covered[inside].all()
    lit = inside & (ours.max(axis=-1) > 0)
    assert lit.sum() > 0.3 * inside.sum()
    bound = RTOL * np.abs(ours) + ATOL * float(ours.max())
    return float(np.max((np.abs(theirs - ours) / bound)[inside])), theirs, ours


def test_baked_function_renders_in_threejs_as_roughdiffuse(page, tmp_path):
    model = registry.create("oren-nayar-full", albedo=[0.8, 0.5, 0.2], sigma=math.radians(30))
    result = export(model, "glsl", tmp_path / "brdf.glsl")
    assert result.paths == (tmp_path / "brdf.glsl",) and result.conversion is None
    worst, _, _ = _compare(page, model, tmp_path / "brdf.glsl")
    assert worst <= 1.0, f"largest difference {worst:.3g} × the tolerance"


def test_comparison_tells_a_roughness_one_degree_away_apart(page, tmp_path):
    """σ 29° rendered by three.js against roughdiffuse's render of σ 30°: far outside the
    tolerance."""
    model = registry.create("oren-nayar-full", albedo=[0.8, 0.5, 0.2], sigma=math.radians(30))
    other = registry.create("oren-nayar-full", albedo=[0.8, 0.5, 0.2], sigma=math.radians(29))
    export(other, "glsl", tmp_path / "other.glsl")
    worst, _, _ = _compare(page, model, tmp_path / "other.glsl")
    assert worst > 10.0


@pytest.mark.parametrize("model_id", ["eon", "hapke-2012"])
def test_function_with_uniforms_renders_in_threejs_as_roughdiffuse(page, tmp_path, model_id):
    """The parameters as uniforms: three.js sets them from the model's values."""
    model = registry.get(model_id).create(albedo=[0.7, 0.45, 0.3])
    path = tmp_path / "brdf.glsl"
    export(model, "glsl", path, uniforms=True)
    values = {}
    for name, kind in glsl_uniforms(model).items():
        value = np.asarray(getattr(model, name), dtype=np.float64)
        values[name] = np.broadcast_to(value, (3,)).tolist() if kind == "vec3" else float(value)
    assert values and all(f"uniform {k} {n};" in path.read_text() for n, k in
                          glsl_uniforms(model).items())  # fmt: skip
    worst, _, _ = _compare(page, model, path, uniforms=values)
    assert worst <= 1.0, f"largest difference {worst:.3g} × the tolerance"


CLOSED_FORMS = [e.id for e in registry.entries() if e.cls.closed_form]


@pytest.mark.slow
@pytest.mark.parametrize("model_id", CLOSED_FORMS)
def test_every_closed_form_renders_in_threejs_as_roughdiffuse(page, tmp_path, model_id):
    """Each closed-form registry model at its command-line starting values (the declared
    ``example``, else the default), baked, in the same scene."""
    entry = registry.get(model_id)
    start = {p.name: p.default if p.example is None else p.example for p in entry.parameters}
    model = entry.create(**{p.name: start[p.name] for p in entry.applicable(start)})
    export(model, "glsl", tmp_path / "brdf.glsl")
    worst, _, _ = _compare(page, model, tmp_path / "brdf.glsl")
    assert worst <= 1.0, f"largest difference {worst:.3g} × the tolerance"


def test_documented_material_renders_in_threejs_near_roughdiffuse(page, tmp_path):
    """The material of the documentation (tests/js/material.js): the mesh's normals, the
    view direction from three.js's own camera uniforms. Its normals are interpolated across
    the triangles of a 256 × 128 SphereGeometry, whose corners the rasterizer snaps to a
    sub-pixel grid, so they are off by up to about 1e-3: bound 1 % of the brightest pixel
    (measured 0.53 %)."""
    model = registry.create("oren-nayar-full", albedo=[0.8, 0.5, 0.2], sigma=math.radians(30))
    glsl = export(model, "glsl", tmp_path / "brdf.glsl").paths[0].read_text()
    theirs, covered = threejs_sphere(
        page, glsl, light=LIGHT, camera=CAMERA, size=SIZE, normals="mesh"
    )
    assert not page.errors, page.errors
    ours, _ = render(model, Sphere(), LIGHT, CAMERA, size=SIZE, samples_per_pixel=1)
    inside = _interior(CAMERA)
    assert covered[inside].all()
    worst = float(np.max(np.abs(theirs - ours)[inside])) / float(ours.max())
    assert worst <= 0.01, f"largest difference {worst:.3g} of the brightest pixel"


def test_cli_writes_the_function_and_names_the_file(tmp_path, capsys):
    """Run as a user runs it (a process of its own); the summary names the file."""
    out = tmp_path / "brdf.glsl"
    run = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "export", "--model", "oren-nayar-full",
         "--param", "sigma=20", "--to", "glsl", "-o", str(out), "--name", "rough"],
        capture_output=True, text=True,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith(f"glsl: {out}\n") and "exact" in run.stdout
    text = out.read_text()
    assert "vec3 rough(vec3 wi, vec3 wo)" in text
    assert "#version" not in text and "uniform" not in text  # pasted below the shader's own
    assert "glsl" in TARGETS and TARGETS["glsl"][0] == ".glsl"
    from roughdiffuse.cli import main

    assert main(["export", "--model", "eon", "--to", "glsl", "--uniforms",
                 "-o", str(tmp_path / "u.glsl")]) == 0  # fmt: skip
    assert "uniform float roughness;" in (tmp_path / "u.glsl").read_text()
    assert "uniforms to set: vec3 albedo, float roughness" in capsys.readouterr().out


@pytest.mark.parametrize(
    "args, says",
    [
        (["--model", "v-cavity", "--to", "glsl"], "not a closed form"),
        (["--model", "smith-diffuse-ggx", "--to", "glsl"], "not a closed form"),
        (["--model", "coated", "--to", "glsl", "--uniforms"], "baked in"),
        (["--model", "eon", "--to", "glsl", "--name", "gl_brdf"], "GLSL identifier"),
        (["--model", "eon", "--to", "glsl", "--name", "2x"], "GLSL identifier"),
        (["--model", "eon", "--to", "gls"], "unknown target 'gls'"),
        (["--model", "eon", "--to", "mitsuba", "--uniforms"], "--uniforms applies only"),
    ],
    ids=["v-cavity", "smith", "coated-uniforms", "gl-prefix", "digit", "target", "uniforms"],
)
def test_cli_refuses_on_one_line_and_writes_nothing(tmp_path, capsys, args, says):
    from roughdiffuse.cli import main

    assert main(["export", *args, "-o", str(tmp_path / "out.glsl")]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and says in err, err
    assert list(tmp_path.iterdir()) == []


def test_fit_export_writes_a_glsl_file_beside_the_others(tmp_path):
    from roughdiffuse.commands._export_targets import export_paths, parse_targets

    paths = export_paths(str(tmp_path / "m"), parse_targets("glsl,mitsuba"))
    assert paths == {"glsl": tmp_path / "m_glsl.glsl", "mitsuba": tmp_path / "m_mitsuba.xml"}


def test_a_coated_model_is_exported_baked_with_its_base_in_the_header(tmp_path):
    """A Coated holds its base's parameters in the base: the summary lists its own, and the
    file's header names the base with its values."""
    model = registry.create("coated", base="eon", albedo=0.6, base_roughness=0.3, eta=1.4)
    result = export(model, "glsl", tmp_path / "coated.glsl")
    assert result.params["eta"] == pytest.approx(1.4) and "albedo" not in result.params
    assert any("holds some parameters in its parts" in n for n in result.notes)
    header = (tmp_path / "coated.glsl").read_text().split("\n", 6)[:6]
    assert any("EON(albedo=0.6, roughness=0.3)" in line for line in header), header
