"""``roughdiffuse fit``: the table, the HTML report, one-line errors with exit status 2."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.cli import main


@pytest.fixture
def samples_csv(tmp_path):  # noqa: ANN201, ANN001
    rng = np.random.default_rng(0)
    n = 200
    ti, tr, dp = rng.uniform(0, 80, n), rng.uniform(0, 80, n), rng.uniform(0, 180, n)
    f = np.asarray(rd.oren_nayar(np.radians(ti), np.radians(tr), np.radians(dp), 0.35, 0.6))
    path = tmp_path / "s.csv"
    rows = "".join(f"{a},{b},{c},{v}\n" for a, b, c, v in zip(ti, tr, dp, f, strict=True))
    path.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n" + rows)
    return path


def test_fit_csv_prints_table_and_writes_report(samples_csv, tmp_path, capsys) -> None:  # noqa: ANN001
    report = tmp_path / "r.html"
    assert main(["fit", str(samples_csv), "--model", "oren-nayar", "--report", str(report)]) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.strip().startswith("sigma"))
    assert float(line.split()[1]) == pytest.approx(0.35, abs=1e-6)
    assert f"({math.degrees(0.35):.2f}°)" in line
    html = report.read_text()
    assert "data:image/png;base64," in html and "albedo" in html


@pytest.mark.slow
def test_fit_compare(samples_csv, capsys) -> None:  # noqa: ANN001
    assert main(["fit", str(samples_csv), "--compare"]) == 0
    out = capsys.readouterr().out
    first = next(x for x in out.splitlines() if x.strip().startswith("1 "))
    assert "oren-nayar " in first  # the qualitative model made the data


def test_fit_image_with_shape(tmp_path, capsys) -> None:  # noqa: ANN001
    from roughdiffuse.render import DistantLight, Sphere, render

    img, _ = render(
        rd.OrenNayar(0.5, 0.3),
        Sphere(),
        DistantLight(math.radians(30), 0.0),
        size=64,
        samples_per_pixel=1,
    )
    path = tmp_path / "sphere.npy"
    np.save(path, img)
    report = tmp_path / "img.html"
    args = ["fit", str(path), "--shape", "sphere", "--light", "30,0", "--report", str(report)]
    assert main(args) == 0
    out = capsys.readouterr().out
    line = next(x for x in out.splitlines() if x.strip().startswith("albedo"))
    assert float(line.split()[1]) == pytest.approx(0.5, abs=1e-4)  # float32 image
    assert "residual image" not in out and report.exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["fit", "missing.csv"], "does not exist"),
        (["fit", "{csv}", "--model", "phong"], "unknown model 'phong'"),
        (["fit", "{npy}"], "needs --light"),
        (["fit", "{npy}", "--light", "30,0"], "exactly one of --normals"),
        (["fit", "{csv}", "--report", "out.pdf"], "must name an .html file"),
        (["fit", "{bad}"], "line 2, column 'brdf': negative value"),
    ],
)
def test_bad_input_one_line_exit_2(tmp_path, samples_csv, capsys, args, message) -> None:  # noqa: ANN001
    npy = tmp_path / "x.npy"
    np.save(npy, np.zeros((4, 4)))
    bad = tmp_path / "bad.csv"
    bad.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,10,0,-1\n")
    args = [a.format(csv=samples_csv, npy=npy, bad=bad) for a in args]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1
