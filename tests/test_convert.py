"""rd.convert (roughdiffuse.fit.between_models): the parameters of one model that best
reproduce another.

References independent of the code under test: a model converted to itself returns its own
parameters; pbrt-v3's σ in degrees is Oren–Nayar's σ in radians times 180/π and Mitsuba 0.6's
α is √2 σ (exact identities: the residual is 0); the MaterialX node differs from EON only
where L·V < 0 (so the conversion finds r and ρ close to EON's, with a small residual); a
target whose albedo cannot reach the source's is refused.
"""

from __future__ import annotations

import math
import subprocess
import sys

import pytest

import roughdiffuse as rd
from roughdiffuse import convert


@pytest.mark.parametrize(
    "model, target",
    [(rd.EON(0.8, 0.5), "eon"), (rd.OrenNayar(0.6, 0.4, "full"), "oren-nayar-full")],
)
def test_a_model_converted_to_itself_keeps_its_parameters(model, target):
    r = convert(model, target=target)
    assert r.params["albedo"] == pytest.approx(model.albedo, abs=1e-7)
    name = "roughness" if target == "eon" else "sigma"
    assert r.params[name] == pytest.approx(getattr(model, name), abs=1e-7)
    assert r.rms_f < 1e-7 and r.max_f < 1e-6 and r.max_albedo < 1e-7


def test_pbrt3_degrees_and_mitsuba06_alpha_are_exact_identities():
    sigma = math.radians(25.0)
    r = convert(rd.OrenNayar(0.7, sigma), target="pbrt3-oren-nayar")
    assert r.params["sigma_deg"] == pytest.approx(25.0, abs=1e-5)
    assert r.max_f < 1e-7
    r = convert(rd.OrenNayar(0.7, sigma, "full"), target="mitsuba06-roughdiffuse")
    assert r.params["alpha"] == pytest.approx(math.sqrt(2.0) * sigma, abs=1e-6)
    assert r.max_f < 1e-6


def test_eon_to_the_materialx_node_stays_close():
    """The node differs from EON only where L·V < 0 (its clamp), where it is brighter."""
    r = convert(rd.EON(0.8, 0.5), target="materialx-eon")
    assert 0.0 < r.rms_f < 0.1
    assert r.params["roughness"] == pytest.approx(0.5, abs=0.2)


def test_a_target_that_cannot_reach_the_source_albedo_is_refused():
    # Burley at roughness 1 and ρ = 1 reflects more than it receives at grazing: EON cannot
    with pytest.raises(ValueError, match="cannot represent the source's albedo"):
        convert(rd.Burley(1.0, 1.0), target="eon")


def test_rgb_albedo_is_converted_per_channel():
    r = convert(rd.EON([0.8, 0.5, 0.2], 0.5), target="openpbr-diffuse")
    assert r.params["albedo"] == pytest.approx([0.8, 0.5, 0.2], abs=1e-6)
    assert r.params["roughness"] == pytest.approx(0.5, abs=1e-5)


def test_cli_prints_parameters_differences_and_snippet():
    run = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "convert", "--model", "oren-nayar",
         "--param", "sigma=20", "--to", "pbrt3-oren-nayar"],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    assert "sigma_deg = 20" in run.stdout
    assert 'rd.registry.create("pbrt3-oren-nayar"' in run.stdout
    bad = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "convert", "--model", "eon", "--to", "nope"],
        capture_output=True, text=True,
    )  # fmt: skip
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize(
    "name, default",
    [("unity", "unity-disney-diffuse"), ("Filament", "filament-lambert"),
     ("blender", "cycles-diffuse"), ("materialx", "materialx-oren-nayar")],
)  # fmt: skip
def test_an_engine_name_picks_what_the_engine_renders_by_default(name, default):
    """HDRP's Lit calls DisneyDiffuse (Lit.hlsl); Filament defines BRDF_DIFFUSE as
    DIFFUSE_LAMBERT (surface_brdf.fs); Cycles' Diffuse BSDF; MaterialX's node defaults to
    energy_compensation = false (pbrlib_defs.mtlx)."""
    assert convert(rd.EON(0.8, 0.5), target=name).target == default


def test_an_opt_in_variant_is_named_by_its_id():
    r = convert(rd.Burley(0.8, 0.5), target="filament-burley")
    assert r.target == "filament-burley"
    # Filament's Fd_Burley at perceptual roughness √0.5 is Burley at r = 0.5: exact
    assert r.params["roughness"] == pytest.approx(math.sqrt(0.5), abs=1e-5) and r.max_f < 1e-6


def test_unity_default_reproduces_burley_with_its_colour_scale():
    """DisneyDiffuse is Burley at the perceptual roughness divided by 1.03571 (BSDF.hlsl):
    the conversion of Burley is exact, with the colour 1.03571 times larger."""
    r = convert(rd.Burley(0.5, 0.6), target="unity")
    assert r.params["albedo"] == pytest.approx(0.5 * 1.03571, abs=1e-6)
    assert r.params["roughness"] == pytest.approx(0.6, abs=1e-5) and r.max_f < 1e-6


def test_cli_engine_name_says_which_variant_and_a_misspelt_one_gets_did_you_mean(capsys):
    from roughdiffuse.cli import main

    assert main(["convert", "--model", "eon", "--to", "unity"]) == 0
    first = capsys.readouterr().out.splitlines()[0]
    assert first.startswith("unity: its default diffuse, unity-disney-diffuse")
    assert "unity-diffuse-ggx" in first
    assert main(["convert", "--model", "eon", "--to", "untiy"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1 and "did you mean unity?" in err


def test_progress_bar_counts_the_starts_and_is_off_when_asked(capsys):
    """A bar on standard error (a conversion to a coat takes minutes): one step per start of
    the search; none without ``progress`` (the command's default off a terminal)."""
    convert(rd.EON(0.8, 0.5), target="eon", progress=True)
    err = capsys.readouterr().err
    assert "convert to eon" in err and "start" in err and "evaluations" in err
    convert(rd.EON(0.8, 0.5), target="eon")
    assert capsys.readouterr().err == ""
