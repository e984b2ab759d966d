"""The GLSL printer (roughdiffuse.engine.glsl): what it prints compiles and says what it takes.

The values the printed code computes are checked in Chromium against the Python models
(tests/test_explorer_glsl.py); here, without a browser: every closed-form model's exported
function compiles as a GLSL ES 3.00 fragment shader (glslang, the Khronos reference
compiler), baked and with uniforms, and the refusals name the reason.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from roughdiffuse import Lambert, registry
from roughdiffuse._validate import ParameterError
from roughdiffuse.engine.glsl import glsl_source, glsl_uniforms
from roughdiffuse.models.mix import Mix

GLSLANG = shutil.which("glslangValidator")
CLOSED_FORMS = [e.id for e in registry.entries() if e.cls.closed_form]


def _compile(tmp_path, source: str, name: str) -> None:
    if GLSLANG is None:
        pytest.skip("glslangValidator is not installed (apt-get install glslang-tools)")
    frag = tmp_path / "shader.frag"
    frag.write_text(
        "#version 300 es\nprecision highp float;\nprecision highp int;\n" + source
        + f"\nout vec4 o;\nvoid main() {{ o = vec4({name}(vec3(0.1, 0.2, 1.0), "
        "vec3(0.3, -0.1, 0.9)), 1.0); }\n"
    )
    r = subprocess.run([GLSLANG, str(frag)], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout[-2000:]


@pytest.mark.parametrize("model_id", CLOSED_FORMS)
def test_every_closed_form_compiles_baked(tmp_path, model_id):
    entry = registry.get(model_id)
    source = glsl_source(entry.create(**entry.test_points()[0]), name="my_brdf")
    assert "vec3 my_brdf(vec3 wi, vec3 wo)" in source
    assert "uniform" not in source
    _compile(tmp_path, source, "my_brdf")


@pytest.mark.parametrize("model_id", [i for i in CLOSED_FORMS if i not in ("mix", "coated")])
def test_uniforms_are_the_declared_parameters(tmp_path, model_id):
    entry = registry.get(model_id)
    model = entry.create(**entry.test_points()[0])
    source = glsl_source(model, bake=False)
    declared = re.findall(r"^uniform (\w+) (\w+);$", source, flags=re.M)
    numeric = [p for p in entry.applicable(entry.test_points()[0]) if not p.categorical]
    assert dict((n, t) for t, n in declared) == {
        p.name: "vec3" if p.channels else "float" for p in numeric
    }
    assert glsl_uniforms(model) == {n: t for t, n in declared}
    _compile(tmp_path, source, "rd_brdf")


def test_two_exported_models_live_in_one_shader(tmp_path):
    a = glsl_source(registry.create("eon", roughness=0.5), name="brdf_a")
    b = glsl_source(registry.create("eon", roughness=0.2), name="brdf_b", bake=False)
    if GLSLANG is None:
        pytest.skip("glslangValidator is not installed")
    frag = tmp_path / "two.frag"
    frag.write_text("#version 300 es\nprecision highp float;\n" + a + b
                    + "out vec4 o;\nvoid main() { o = vec4(brdf_a(vec3(0, 0, 1), vec3(0, 0, 1))"
                    " + brdf_b(vec3(0, 0, 1), vec3(0, 0, 1)), 1.0); }\n")
    r = subprocess.run([GLSLANG, str(frag)], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stdout[-2000:]


def test_refusals_name_the_reason():
    with pytest.raises(ParameterError, match="bake=True"):
        glsl_source(Mix([(0.5, Lambert(0.5)), (0.5, Lambert(0.2))]), bake=False)
    with pytest.raises(ParameterError, match="cannot be uniforms|bake=True"):
        glsl_source(registry.create("coated"), bake=False)
    with pytest.raises(ParameterError, match="not a closed form"):
        glsl_source(registry.create("smith-diffuse-ggx"))
    with pytest.raises(ParameterError, match="GLSL identifier"):
        glsl_source(Lambert(0.5), name="2bad")
