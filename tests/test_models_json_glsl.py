"""``roughdiffuse models --json``'s ``glsl_id`` and ``glsl_keys`` say what the GLSL printer
prints: the function of each model in the explorer's generated ``models.glsl`` and the
parameters it takes, in order."""

from __future__ import annotations

import json
import re

import pytest

from roughdiffuse import registry
from roughdiffuse.cli import main
from roughdiffuse.engine.glsl import glsl_source, glsl_uniforms
from roughdiffuse.explorer.shaders import models_glsl, shader_records


@pytest.fixture(scope="module")
def records():
    import contextlib
    import io

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["models", "--json"]) == 0
    return {r["id"]: r for r in json.loads(out.getvalue())}


def test_every_printed_model_names_its_function(records):
    glsl = models_glsl()
    defined = set(re.findall(r"^vec3 (rd_m\d+)\(float mu_i, float mu_o, float cos_io", glsl, re.M))
    for model_id, rec in records.items():
        entry = registry.get(model_id)
        printed = entry.cls.closed_form and "variants" in shader_records()[model_id]
        if not printed:  # a simulation, a table, or a shader printed on the server (coated)
            assert rec["glsl_id"] is None and rec["glsl_keys"] == [], model_id
            continue
        assert rec["glsl_id"] in defined, model_id
        # dispatched under the id's own macro (the default choices' variant)
        macro = re.search(rf"if \(p\.model == (RD_\w+)\) return {rec['glsl_id']}\(", glsl)
        assert macro and macro.group(1).startswith("RD_" + model_id.upper().replace("-", "_"))


def test_glsl_keys_are_the_printed_uniforms_in_order(records):
    """Against the user's shader printed with uniforms (``export --to glsl --uniforms``):
    its ``uniform`` declarations, in order, are ``glsl_keys``."""
    checked = 0
    for model_id, rec in records.items():
        if rec["glsl_id"] is None:
            continue
        model = registry.create(model_id)
        try:
            source = glsl_source(model, bake=False)
        except ValueError:  # a Mix: its parameters are not its fields
            continue
        declared = re.findall(r"^uniform (?:float|vec3) (\w+);", source, re.M)
        assert rec["glsl_keys"] == declared == list(glsl_uniforms(model)), model_id
        checked += 1
    assert checked >= 30


def test_glsl_keys_are_what_the_prepass_reads(records):
    """The page computes the function's arguments from these parameters (its prepass)."""
    for model_id, rec in records.items():
        if rec["glsl_id"] is None:
            continue
        variant = next(
            v
            for v in shader_records()[model_id]["variants"]
            if v["function"] == rec["glsl_id"]
        )
        read = set(re.findall(r"p\['(\w+)'\]", variant["prepass"]))
        assert read <= set(rec["glsl_keys"]), model_id
        assert rec["glsl"] is True


def test_the_json_field_order_puts_them_beside_glsl(records):
    keys = list(records["oren-nayar"])
    assert keys[keys.index("glsl") + 1 : keys.index("glsl") + 3] == ["glsl_id", "glsl_keys"]
    assert records["oren-nayar"]["glsl_keys"] == ["albedo", "sigma"]
