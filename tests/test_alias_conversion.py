"""An Alias's ``to_base`` traced (roughdiffuse.engine.trace) for the explorer: the text it
shows, the JSON expression trees (``to_base``) and the JavaScript that converts the page's
values (``javascript``), in the ``alias`` record of ``roughdiffuse models --json`` /
``/api/models``.

Reference values are the conversions as the other projects state them (pbrt-v3's σ in
degrees, Mitsuba 0.6's α = √2 σ, Filament's and Unreal's α = roughness²), not the code under
test."""

from __future__ import annotations

import math
import shutil
import subprocess

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.models.alias import Alias
from roughdiffuse.models.renderers import Pbrt3OrenNayar

ALIASES = [e.id for e in registry.entries() if issubclass(e.cls, Alias)]
NODE = shutil.which("node") or shutil.which("nodejs")


def _run_javascript(body: str, values: dict) -> dict:
    """The traced conversion run by Node.js (the page runs it in the browser)."""
    import json

    if NODE is None:
        pytest.skip("Node.js is not installed")
    code = (f"const f = new Function('p', {json.dumps(body)});"
            f"console.log(JSON.stringify(f({json.dumps(values)})));")
    out = subprocess.run([NODE, "-e", code], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def test_conversion_text():
    assert Pbrt3OrenNayar.conversion()["text"] == {"albedo": "albedo",
                                                   "sigma": "sigma_deg * 0.0174533"}


@pytest.mark.parametrize(
    ("model_id", "base", "name", "own", "value", "want"),
    [
        ("pbrt3-oren-nayar", "oren-nayar", "sigma", "sigma_deg", 90.0, math.pi / 2),
        ("mitsuba06-roughdiffuse", "oren-nayar-full", "sigma", "alpha", math.sqrt(2.0), 1.0),
        ("mitsuba06-roughdiffuse-fast", "oren-nayar", "sigma", "alpha", math.sqrt(2.0), 1.0),
        ("filament-burley", "burley", "roughness", "roughness", 0.5, 0.25),
        ("unreal-chan", "chan", "alpha", "roughness", 0.5, 0.25),
        ("unreal-burley", "burley", "roughness", "roughness", 0.5, 0.5),
        ("unity-diffuse-ggx", "hammon", "alpha", "roughness", 0.3, 0.3),
        ("materialx-oren-nayar", "oren-nayar", "sigma", "roughness", 0.7, 0.7),
        ("openpbr-diffuse", "eon", "roughness", "roughness", 0.7, 0.7),
        ("materialx-eon-genosl", "oren-nayar", "sigma", "roughness", 0.7, 0.7),
    ],
    ids=lambda v: v if isinstance(v, str) else None,
)
def test_each_alias_record(model_id, base, name, own, value, want):
    """The published base id and the traced conversion (run as the page runs it), as the
    other project defines it; colour passes unchanged."""
    rec = {r["id"]: r for r in registry.to_json()}[model_id]["alias"]
    assert rec["base"] == base and rec["fixed"] == {} and rec["why"] is None
    got = _run_javascript(rec["javascript"], {own: value, "albedo": 0.4})
    assert got[name] == pytest.approx(want, rel=1e-15) and got["albedo"] == 0.4
    trees = rec["to_base"]  # the JSON expression trees, evaluated here by their definition
    assert set(trees) == set(got)
    assert _evaluate_tree(trees[name], {own: value, "albedo": 0.4}) == pytest.approx(
        want, rel=1e-15
    )
    assert _evaluate_tree(trees["albedo"], {own: value, "albedo": 0.4}) == 0.4


_TREE_OPS = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "**": lambda a, b: a**b,
    "neg": lambda a: -a,
    "sqrt": math.sqrt,
}


def _evaluate_tree(tree, values):
    """A name, a number, or [op, operand, ...] (the documented form of ``to_base``)."""
    if isinstance(tree, str):
        return values[tree]
    if isinstance(tree, int | float):
        return float(tree)
    op, *args = tree
    return _TREE_OPS[op](*(_evaluate_tree(a, values) for a in args))


def test_to_base_trees_are_json_of_names_numbers_and_operators():
    """pbrt-v3: σ = sigma · π/180, the tree ["*", "sigma_deg", π/180] (its source's rule)."""
    rec = {r["id"]: r for r in registry.to_json()}["pbrt3-oren-nayar"]["alias"]
    assert rec["to_base"]["albedo"] == "albedo"
    op, name, factor = rec["to_base"]["sigma"]
    assert (op, name) == ("*", "sigma_deg") and factor == pytest.approx(math.pi / 180, rel=1e-15)


def test_unity_disney_diffuse_record_scales_the_colour():
    """HDRP's ``DisneyDiffuseNoPI`` divides by 1.03571 (BSDF.hlsl); perceptual roughness is
    Burley's r as it is."""
    rec = {r["id"]: r for r in registry.to_json()}["unity-disney-diffuse"]["alias"]
    assert rec["base"] == "burley"
    got = _run_javascript(rec["javascript"], {"roughness": 0.6, "albedo": 0.4})
    assert got["roughness"] == pytest.approx(0.6, rel=1e-15)
    assert got["albedo"] == pytest.approx(0.4 / 1.03571, rel=1e-15)


def test_filament_lambert_record_is_lambert():
    rec = {r["id"]: r for r in registry.to_json()}["filament-lambert"]["alias"]
    assert rec["base"] == "lambert"
    assert _run_javascript(rec["javascript"], {"albedo": 0.4}) == {"albedo": 0.4}


def test_every_alias_has_a_record_and_nothing_else_does():
    assert len(ALIASES) == 12
    for r in registry.to_json():
        assert (r["alias"] is not None) == (r["id"] in ALIASES), r["id"]


def test_the_vase_query_carries_an_alias_s_own_numbers():
    """The vase request (``/api/vase.png``'s query) for pbrt-v3 at sigma_deg = 30 is the
    qualitative Oren–Nayar model at σ = π/6 rad (pbrt-v3's constructor converts degrees)."""
    from roughdiffuse.explorer import model_from_params
    from roughdiffuse.explorer.backend import params_from_query

    model = model_from_params(
        params_from_query({"model": "pbrt3-oren-nayar", "sigma_deg": "30", "albedo": "0.5"})
    )
    ref = registry.create("oren-nayar", albedo=[0.5] * 3, sigma=math.pi / 6)
    mu_i, mu_o = np.array([0.9, 0.3, 0.5]), np.array([0.4, 0.8, 0.1])
    cos_io = mu_i * mu_o + np.array([0.9, 0.5, -0.7]) * np.sqrt((1 - mu_i**2) * (1 - mu_o**2))
    want = ref.brdf_cosines(mu_i, mu_o, cos_io)
    assert np.ptp(want) > 0.01  # forward geometries: σ matters
    np.testing.assert_allclose(model.brdf_cosines(mu_i, mu_o, cos_io), want, rtol=1e-14)
