"""roughdiffuse export: Mitsuba 3 scenes, MaterialX documents, Blender scripts.

Checks by the target programs themselves: Mitsuba loads the XML (``mi.load_file``) and the
dict and renders the same sphere as roughdiffuse's own renderer (an independent ray tracer;
bounds as in test_mitsuba_render.py); MaterialX reads and validates the .mtlx and generates
GLSL and OSL from it, and glslangValidator compiles the GLSL. Blender's script is checked here
as Python and for the values it sets, and rendered by Blender in test_export_blender.py.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import numpy as np
import pytest

import roughdiffuse as rd
from materialx_setup import load_document
from roughdiffuse import registry
from roughdiffuse.exporters import export, load_result
from roughdiffuse.exporters.mitsuba import LIGHT, MARGIN, SIZE, load_dict, scene_dict

ALBEDO = [0.8, 0.6, 0.4]


def _render(mi, scene, seed=7):
    return np.array(mi.render(scene, seed=seed))


def _ours(model):
    from roughdiffuse.render import DistantLight, OrthographicCamera, Sphere, render

    image, mask = render(
        model,
        Sphere(),
        DistantLight(*np.radians(LIGHT)),
        OrthographicCamera(0.0, 0.0, margin=MARGIN),
        size=SIZE,
        samples_per_pixel=16,
    )
    return image, mask


def _compare(ours, mask, theirs):
    ours, theirs = ours[..., 0], theirs[..., 0]
    keep = (mask == 1) & (ours > 0.02 * ours.max())
    assert keep.sum() > 0.3 * SIZE * SIZE / 4
    scale = float(np.mean(ours[keep]))
    return float(np.mean(np.abs(theirs - ours)[keep])) / scale


@pytest.fixture(scope="module")
def mi():
    from mitsuba_setup import mitsuba_variant

    return mitsuba_variant("llvm_ad_rgb")


@pytest.mark.slow
def test_mitsuba_xml_renders_as_the_dict_and_as_roughdiffuse(mi, tmp_path):
    model = registry.create("cycles-diffuse", albedo=ALBEDO, roughness=0.7)
    result = export(model, "mitsuba", tmp_path / "scene.xml")
    assert result.conversion is None
    from_xml = _render(mi, mi.load_file(str(tmp_path / "scene.xml")))
    from roughdiffuse.exporters.mitsuba import bsdf_dict

    from_dict = _render(mi, load_dict(mi, scene_dict(bsdf_dict(model))))
    np.testing.assert_allclose(from_xml, from_dict, rtol=1e-5, atol=1e-7)
    ours, mask = _ours(model)
    assert _compare(ours, mask, from_xml) < 0.01
    # negative control: another roughness is told apart
    other, _ = _ours(registry.create("cycles-diffuse", albedo=ALBEDO, roughness=0.0))
    assert _compare(other, mask, from_xml) > 0.01


@pytest.mark.slow
def test_mitsuba_builtin_counterparts(mi, tmp_path):
    """Lambert as Mitsuba's diffuse, Burley 2015 as its principled with specular 0."""
    for model in (rd.Lambert(np.array(ALBEDO)), rd.Burley2015(np.array(ALBEDO), 0.6)):
        paths = export(model, "mitsuba", tmp_path / "s.xml").paths
        builtin = [p for p in paths if p.name.endswith("_builtin.xml")]
        assert builtin
        plugin = _render(mi, mi.load_file(str(tmp_path / "s.xml")))
        theirs = _render(mi, mi.load_file(str(builtin[0])))
        lit = theirs[..., 0] > 0.02 * theirs[..., 0].max()
        assert np.abs(plugin - theirs)[lit].mean() / theirs[lit].mean() < 0.01


def _generate(path):
    _, doc, search = load_document(path)
    import MaterialX.PyMaterialXGenGlsl as mgl
    import MaterialX.PyMaterialXGenOsl as mgo
    import MaterialX.PyMaterialXGenShader as mgs

    (elem,) = mgs.findRenderableElements(doc)
    out = {}
    for name, gen in (
        ("glsl", mgl.GlslShaderGenerator.create()),
        ("osl", mgo.OslShaderGenerator.create()),
    ):
        ctx = mgs.GenContext(gen)
        ctx.registerSourceCodeSearchPath(search)
        shader = gen.generate("roughdiffuse", elem, ctx)
        vertex = shader.getSourceCode(mgs.VERTEX_STAGE) if name == "glsl" else ""
        out[name] = (shader.getSourceCode(mgs.PIXEL_STAGE), vertex)
    return out


@pytest.mark.filterwarnings("ignore::roughdiffuse.exporters.common.BackendWarning")  # GLSL here
@pytest.mark.parametrize(
    "model, openpbr, node",
    [
        (rd.OrenNayar(0.8, 0.35), False, "mx_oren_nayar_diffuse"),
        (rd.EON(ALBEDO, 0.5), False, "mx_oren_nayar_compensated_diffuse"),
        (rd.EON(ALBEDO, 0.5), True, "mx_oren_nayar_compensated_diffuse"),
    ],
)
def test_materialx_document_validates_and_generates_glsl_that_compiles(
    tmp_path, model, openpbr, node
):
    path = tmp_path / "m.mtlx"
    result = export(model, "materialx", path, openpbr=openpbr)
    assert ("converted" in path.read_text()) == (result.conversion is not None)
    code = _generate(path)
    assert node in code["glsl"][0]
    assert "surface" in code["osl"][0]
    if shutil.which("glslangValidator") is None:
        pytest.skip("glslangValidator is not installed (apt-get install glslang-tools)")
    frag, vert = tmp_path / "s.frag", tmp_path / "s.vert"
    frag.write_text(code["glsl"][0])
    vert.write_text(code["glsl"][1])
    run = subprocess.run(["glslangValidator", str(frag), str(vert)], capture_output=True, text=True)
    assert run.returncode == 0, run.stdout[-2000:]
    frag.write_text(
        code["glsl"][0].replace("void main()", "void main() { undefined_name; }\nvoid x()")
    )
    assert subprocess.run(["glslangValidator", str(frag)], capture_output=True).returncode != 0


@pytest.mark.filterwarnings("ignore::roughdiffuse.exporters.common.BackendWarning")
def test_materialx_qualitative_oren_nayar_is_exact(tmp_path):
    result = export(rd.OrenNayar(0.8, 0.35), "materialx", tmp_path / "m.mtlx")
    assert result.model_id == "materialx-oren-nayar"
    assert result.params["roughness"] == pytest.approx(0.35, abs=1e-6)
    assert (
        'name="energy_compensation" type="boolean" value="false"'
        in (tmp_path / "m.mtlx").read_text()
    )


def test_blender_script_sets_the_converted_values(tmp_path):
    path = tmp_path / "mat.py"
    result = export(rd.OrenNayar(0.8, 0.35, "full"), "blender", path, blend=False)
    text = path.read_text()
    compile(text, str(path), "exec")
    assert result.model_id == "cycles-diffuse" and result.conversion is not None
    assert f"{result.params['roughness']:.9g}" in text
    assert "differs by" in text  # the conversion error in the comments
    exact = export(
        registry.create("cycles-diffuse", albedo=0.5, roughness=0.3), "blender", path, blend=False
    )
    assert exact.conversion is None and "exact" in path.read_text()


def test_fit_results_are_read(tmp_path):
    f = tmp_path / "fit.json"
    f.write_text(json.dumps({"model": "eon", "params": {"albedo": 0.7, "roughness": 0.4}}))
    assert load_result(f) == rd.EON(0.7, 0.4)
    stereo = tmp_path / "params.json"
    stereo.write_text(
        json.dumps({"model": "oren-nayar", "roughness": {"name": "sigma", "value": 0.3}})
    )
    np.save(tmp_path / "albedo.npy", np.full((4, 4, 3), 0.6))
    m = load_result(stereo)
    assert m.sigma == pytest.approx(0.3) and list(m.albedo) == pytest.approx([0.6] * 3)
    (tmp_path / "bad.json").write_text("{")
    with pytest.raises(ValueError, match="not a readable fit result"):
        load_result(tmp_path / "bad.json")


def _cli(*args):
    return subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "export", *args], capture_output=True, text=True
    )


def test_cli_bad_input_is_one_line_and_status_2(tmp_path):
    (tmp_path / "bad.json").write_text("not json")
    (tmp_path / "file").write_text("")
    cases = [
        ["--model", "eon", "--to", "usd", "-o", str(tmp_path / "a")],
        ["--from", str(tmp_path / "bad.json"), "--to", "mitsuba", "-o", str(tmp_path / "a.xml")],
        ["--model", "burley", "--param", "albedo=1", "--param", "roughness=1", "--to", "materialx",
         "-o", str(tmp_path / "a.mtlx")],
        ["--model", "eon", "--to", "mitsuba", "-o", str(tmp_path / "file" / "a.xml")],
    ]  # fmt: skip
    for args in cases:
        run = _cli(*args)
        assert run.returncode == 2, (args, run.stderr)
        assert len(run.stderr.strip().splitlines()) == 1, run.stderr
    ok = _cli("--model", "eon", "--to", "mitsuba", "-o", str(tmp_path / "s.xml"))
    assert ok.returncode == 0 and "exact" in ok.stdout


def test_fit_json_feeds_export(tmp_path):
    """fit --json prints the fit; export --from reads it and converts it for Blender. The
    same fit's --export writes each target's file (Mitsuba's plugin with the fitted values
    themselves; the summaries on stderr, stdout stays the JSON)."""
    import xml.etree.ElementTree as ET

    from roughdiffuse.data import path

    out = tmp_path / "fit.json"
    run = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "fit", str(path("samples.csv")),
         "--model", "oren-nayar-full", "--json", "--export", "mitsuba,materialx",
         "--export-prefix", str(tmp_path / "mat")],
        capture_output=True, text=True,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    out.write_text(run.stdout)
    best = json.loads(run.stdout)["fits"][0]
    fitted = dict(zip(best["names"], best["values"], strict=True))
    xml = ET.parse(tmp_path / "mat_mitsuba.xml").getroot()
    values = {e.get("name"): e.get("value") for e in xml.iter() if e.get("name")}
    assert float(values["sigma"]) == pytest.approx(fitted["sigma"], rel=1e-12)
    assert (tmp_path / "mat_materialx.mtlx").is_file()
    assert "mitsuba: " in run.stderr and "converted from" in run.stderr
    model = load_result(out)
    assert model.variant == "full" and 0.0 < float(model.sigma) < 1.0
    done = _cli("--from", str(out), "--to", "blender", "-o", str(tmp_path / "m.py"), "--no-blend")
    assert done.returncode == 0 and "cycles-diffuse" in done.stdout


def test_fit_export_refuses_an_unknown_target_before_fitting(tmp_path, capsys):
    from roughdiffuse.cli import main

    missing = tmp_path / "never-read.csv"
    missing.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n30,30,0,0.2\n")
    assert main(["fit", str(missing), "--export", "blender,usd"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'usd'" in err[0] and "blender" in err[0]
    assert main(["fit", str(missing), "--export", "mitsuba",
                 "--export-prefix", str(tmp_path / "no" / "m")]) == 2  # fmt: skip
    assert "does not exist" in capsys.readouterr().err
