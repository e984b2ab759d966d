"""The command line reads the registry: --model ID, --param NAME=VALUE, `roughdiffuse models`."""

from __future__ import annotations

import json
import math

import pytest

import roughdiffuse as rd
from roughdiffuse import registry
from roughdiffuse.cli import main


def status(argv: list[str]) -> int:
    """main's exit status (argparse's own errors raise SystemExit)."""
    try:
        return main(argv)
    except SystemExit as exc:
        return int(exc.code)


def brdf_line(out: str) -> float:
    return float(next(x for x in out.splitlines() if x.startswith("brdf")).split(":")[1])


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--model", "eon", "--sigma", "30"], "--sigma: model 'eon' has no parameter 'sigma'"),
        (["--model", "lambert", "--roughness", "0.5"], "has no parameter 'roughness'"),
        (["--model", "torrance-sparrow", "--albedo", "0.5"], "has no parameter 'albedo'"),
        (["--model", "oren-nayar", "--param", "variant=full"], "has no parameter 'variant'"),
        (["--model", "torrance-sparrow-beckmann", "--sigma", "10"], "no parameter 'sigma'"),
        (["--model", "eon", "--param", "roughness"], "--param takes NAME=VALUE"),
        (["--model", "eon", "--param", "roughness=abc"], "--param roughness must be a number"),
        (["--model", "oren-nayar", "--param", "sigma=100"], "--param sigma must be in [0, 90]"),
        (["--model", "torrance-sparrow", "--eta", "1e300"], "eta must be in (0, 1000]"),
        (["--model", "nope"], "unknown model 'nope'"),
    ],
)
def test_a_parameter_the_model_does_not_take_is_a_usage_error(capsys, args, message):
    assert status(["eval", *args]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_flags_left_at_their_defaults_do_not_count(capsys):
    """eval --model eon takes no σ, and says nothing about the σ nobody typed."""
    assert main(["eval", "--model", "eon"]) == 0
    out = capsys.readouterr().out
    assert "EON(albedo=0.8, roughness=0.5)" in out


def test_param_sets_any_parameter_degrees_for_angles(capsys):
    """--param sigma=30 is 30°; head-on Oren–Nayar f = ρ A/π, A = 1 − 0.5 σ²/(σ² + 0.33)."""
    assert main(["eval", "--model", "oren-nayar", "--param", "sigma=30", "--albedo", "0.6"]) == 0
    s2 = math.radians(30) ** 2
    expected = 0.6 * (1 - 0.5 * s2 / (s2 + 0.33)) / math.pi
    assert brdf_line(capsys.readouterr().out) == pytest.approx(expected, abs=1e-6)
    assert main(["eval", "--model", "oren-nayar", "--param", "sigma=0.5rad"]) == 0
    assert "sigma=0.5," in capsys.readouterr().out


def test_beckmann_alpha_from_the_command_line(capsys):
    """Normal incidence and view: f = F/(4π α²), F = ((η − 1)/(η + 1))² (G = 1, D = 1/(πα²))."""
    args = ["eval", "--model", "torrance-sparrow-beckmann", "--param", "alpha=0.5", "--eta", "2"]
    assert main(args) == 0
    assert brdf_line(capsys.readouterr().out) == pytest.approx(
        (1 / 3) ** 2 / (4 * math.pi * 0.25), rel=1e-5
    )


def test_models_table_lists_every_id(capsys):
    assert main(["models"]) == 0
    out = capsys.readouterr().out
    for model_id in registry.ids():
        assert f"\n{model_id}  " in f"\n{out}"
    assert "limb_darkening  [0, 1000]; default 0.5" in out


def test_models_json_agrees_with_the_python_defaults(capsys):
    """`models --json` = registry.to_json() with the GLSL printer's glsl_id and glsl_keys,
    and each default builds the class's default."""
    assert main(["models", "--json"]) == 0
    records = json.loads(capsys.readouterr().out)
    printer = ("glsl_id", "glsl_keys")
    assert [{k: v for k, v in r.items() if k not in printer} for r in records] == json.loads(
        json.dumps(registry.to_json())
    )
    by_id = {r["id"]: r for r in records}
    assert by_id["lunar-lambert"]["parameters"][1]["default"] == rd.LunarLambert().limb_darkening
    assert by_id["eon"]["parameters"][1]["default"] == rd.EON().roughness
    ts = {p["name"]: p["default"] for p in by_id["torrance-sparrow"]["parameters"]}
    assert ts == {"eta": rd.TorranceSparrow().eta, "sigma": rd.TorranceSparrow().sigma}
