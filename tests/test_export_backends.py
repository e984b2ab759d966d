"""Exports say what each backend of the target renders.

The evidence is MaterialX's own shader generators run on the exported document: its OSL
generator (``pbrlib_genosl_impl.mtlx``) writes the node's closure call without
``energy_compensation`` (so OSL renders the qualitative model, ``materialx-eon-genosl``), its
GLSL generator passes the switch on. The export warns once, in one line, through Python's
warnings for the API and in the summary for the command line.
"""

from __future__ import annotations

import warnings

import pytest

import roughdiffuse as rd
from roughdiffuse.exporters.common import BackendWarning

mx = pytest.importorskip("MaterialX")


def _closure_lines(path, generator: str) -> list[str]:
    """The lines of the generated pixel shader that call the Oren–Nayar node."""
    import MaterialX.PyMaterialXGenShader as gen_shader

    if generator == "osl":
        import MaterialX.PyMaterialXGenOsl as gen_module

        gen = gen_module.OslShaderGenerator.create()
    else:
        import MaterialX.PyMaterialXGenGlsl as gen_module

        gen = gen_module.GlslShaderGenerator.create()
    doc = mx.createDocument()
    mx.readFromXmlFile(doc, str(path))
    lib = mx.createDocument()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), mx.getDefaultDataSearchPath(), lib)
    doc.importLibrary(lib)
    context = gen_shader.GenContext(gen)
    context.registerSourceCodeSearchPath(mx.getDefaultDataSearchPath())
    shader = gen.generate("s", doc.getNode("roughdiffuse_material"), context)
    code = shader.getSourceCode(gen_shader.PIXEL_STAGE)
    return [line.strip() for line in code.splitlines() if "oren_nayar_diffuse_bsdf(" in line]


def test_eon_through_materialx_warns_and_genosl_drops_the_switch(tmp_path):
    path = tmp_path / "eon.mtlx"
    with pytest.warns(BackendWarning, match="genosl drops energy_compensation") as caught:
        result = rd.export(rd.EON(0.8, 0.5), "materialx", path)
    assert len(caught) == 1 and "\n" not in str(caught[0].message)
    assert result.model_id == "materialx-eon" and len(result.warnings) == 1
    assert "materialx-eon-genosl" in result.warnings[0] and "MDL 1.10" in result.warnings[0]
    osl = _closure_lines(path, "osl")
    assert len(osl) == 1 and "energy_compensation" not in osl[0]
    assert osl[0].count(",") == 2  # (normal, color, roughness): the switch is not passed
    glsl = " ".join(_closure_lines(path, "glsl"))
    assert "energy_compensation" in glsl  # the GLSL node receives it


def test_openpbr_surface_gets_the_same_warning(tmp_path):
    with pytest.warns(BackendWarning, match="GLSL, ESSL and MSL"):
        rd.export(rd.EON(0.8, 0.5), "materialx", tmp_path / "o.mtlx", openpbr=True)


def test_qualitative_oren_nayar_warns_about_cycles_osl(tmp_path):
    with pytest.warns(BackendWarning, match="cycles-osl"):
        result = rd.export(rd.OrenNayar(0.8, 0.3), "materialx", tmp_path / "on.mtlx")
    assert result.model_id == "materialx-oren-nayar"


@pytest.mark.parametrize("target, name", [("mitsuba", "m.xml"), ("glsl", "m.glsl")])
def test_an_exact_target_does_not_warn(tmp_path, target, name):
    with warnings.catch_warnings():
        warnings.simplefilter("error", BackendWarning)
        result = rd.export(rd.EON(0.8, 0.5), target, tmp_path / name)
    assert result.warnings == ()


def test_the_command_prints_the_warning_once_in_one_line(tmp_path, capsys):
    from roughdiffuse.cli import main

    out = tmp_path / "eon.mtlx"
    assert main(["export", "--model", "eon", "--roughness", "0.5", "--to", "materialx",
                 "-o", str(out)]) == 0  # fmt: skip
    captured = capsys.readouterr()
    lines = [line for line in captured.out.splitlines() if "warning:" in line]
    assert len(lines) == 1 and "materialx-eon-genosl" in lines[0]
    assert "BackendWarning" not in captured.err
    assert "genosl drops energy_compensation" in out.read_text(encoding="utf-8")
