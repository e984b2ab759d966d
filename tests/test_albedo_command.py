"""``roughdiffuse albedo``: the white-furnace plot, its table and the variance report.

Reference values are closed forms written here: Lambert and EON reflect everything at ρ = 1
(albedo 1); at normal view Fujii's albedo is A_F = 1/(1 + K1 r) (G(1) = 0, EON paper Eq. 8)
and the qualitative Oren–Nayar albedo is A = 1 − 0.5 σ²/(σ² + 0.33) (s = 0 when θo = 0).
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from roughdiffuse.cli import main

K1 = 0.5 - 2.0 / (3.0 * math.pi)


def _table(path):
    with open(path, newline="", encoding="utf-8") as fh:
        rows = list(csv.reader(fh))
    head, body = rows[0], np.array(rows[1:], dtype=float)
    return head, body


def test_plot_and_table(tmp_path, capsys):
    png, table = tmp_path / "albedo.png", tmp_path / "albedo.csv"
    args = ["albedo", "--model", "lambert,oren-nayar,fujii,eon", "--sigma", "0,30"]
    status = main([*args, "--roughness", "0,1", "-o", str(png), "--table", str(table)])
    assert status == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    head, body = _table(table)
    assert head[0] == "theta_r_deg"
    col = {name: body[:, i] for i, name in enumerate(head)}
    assert np.allclose(col["theta_r_deg"][:3], [0.0, 0.5, 1.0])
    assert col["theta_r_deg"].max() < 90.0
    np.testing.assert_allclose(col["Lambert, ρ = 1"], 1.0, atol=1e-7)
    np.testing.assert_allclose(col["EON, r = 1"], 1.0, atol=1e-6)  # white furnace
    assert col["Fujii (FON), r = 1"][0] == pytest.approx(1.0 / (1.0 + K1), abs=1e-6)
    s2 = math.radians(30.0) ** 2
    a = 1.0 - 0.5 * s2 / (s2 + 0.33)
    assert col["Oren–Nayar qualitative, σ = 30°"][0] == pytest.approx(a, abs=1e-5)
    # the qualitative model loses energy at high roughness, EON does not
    assert col["Oren–Nayar qualitative, σ = 30°"].max() < 0.99
    assert "EON: albedo between 1.0000 and 1.0000" in capsys.readouterr().out


def test_variance_report(capsys):
    assert main(["albedo", "--variance", "--model", "eon", "--roughness", "1"]) == 0
    out = capsys.readouterr().out
    row = next(line for line in out.splitlines() if line.startswith("| EON, r = 1"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    assert cells[1] == "cltc"
    own, cosine = (float(x) for x in cells[-1].replace("(", " ").replace(")", " ").split()[:2])
    assert own < cosine  # θo = 80°: the clipped LTC beats cosine sampling
    assert "differ" not in out


@pytest.mark.parametrize(
    "argv",
    [
        ["--sigma", "120"],
        ["--roughness", "2"],
        ["--model", "phong"],
        ["--albedo", "1.5"],
        ["-o", "x.jpg"],
        ["-o", "/no/such/folder/a.png"],
    ],
)
def test_bad_input_is_one_line_and_exit_2(argv, capsys):
    assert main(["albedo", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("roughdiffuse albedo: error:") and "\n" not in err


def test_plot_albedo_kind(tmp_path):
    out = tmp_path / "furnace.png"
    assert (
        main(["plot", "albedo", "--model", "eon,oren-nayar", "--sigma", "0,40", "-o", str(out)])
        == 0
    )
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_existing_output_needs_force(tmp_path, capsys):
    out = tmp_path / "a.png"
    out.write_bytes(b"keep")
    assert main(["albedo", "--model", "lambert", "-o", str(out)]) == 2
    assert "--force" in capsys.readouterr().err and out.read_bytes() == b"keep"
    assert main(["albedo", "--model", "lambert", "-o", str(out), "--force"]) == 0
    assert out.read_bytes()[:4] == b"\x89PNG"


def test_any_registry_model_sweeps_its_declared_roughness(tmp_path):
    """Registry ids beyond the first round's eight: the exact V-cavity surface at ρ = 1 keeps
    all its energy (white furnace: 1 within the solver's 1e-4 tolerance, the accuracy
    models/vcavity.py states for its table), and
    Hammon's α sweep comes from --alpha."""
    png, table = tmp_path / "a.png", tmp_path / "a.csv"
    argv = ["albedo", "--model", "v-cavity,hammon", "--sigma", "30", "--alpha", "0.2,0.6"]
    assert main([*argv, "-o", str(png), "--table", str(table)]) == 0
    head, body = _table(table)
    col = {name: body[:, i] for i, name in enumerate(head)}
    assert {"Hammon (GGX diffuse), α = 0.2", "Hammon (GGX diffuse), α = 0.6"} <= set(col)
    upto80 = col["theta_r_deg"] <= 80.0
    np.testing.assert_allclose(col["V-cavity surface (exact), σ = 30°"][upto80], 1.0, atol=1e-4)


def test_alpha_outside_a_models_range_is_refused(capsys):
    assert main(["albedo", "--model", "hammon", "--alpha", "1.5"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--alpha 1.5 for hammon" in err and "[0, 1]" in err and "\n" not in err
