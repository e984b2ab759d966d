"""`photometry fit` never prints nonsense: I/F that no relative residual can be computed on
is refused by its line, a fit with no finite or meaningful residual is refused as `fit`'s
are, and the report shows any band or file name as text."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import cli
from roughdiffuse.models.photometry import radiance_factor


def run(argv: list[str]) -> int:
    try:
        return cli.main(argv)
    except SystemExit as exc:
        return int(exc.code)


def rows(n: int = 24, scale: float = 1.0) -> list[tuple]:
    rng = np.random.default_rng(2)
    i, e = rng.uniform(5, 70, n), rng.uniform(5, 70, n)
    g = np.abs(i - e) + rng.uniform(0, 1, n) * (i + e - np.abs(i - e))
    iof = scale * radiance_factor(rd.LunarLambert(0.1, 0.6), *np.radians([i, e, g]))
    table = zip(iof, i, e, g, strict=True)
    return [(f"{v:.9g}", f"{a:.9g}", f"{b:.9g}", f"{c:.9g}") for v, a, b, c in table]


def write_csv(path: Path, data: list[tuple], band: str | None = None) -> Path:
    head = "I/F,i,e,g" + (",band" if band is not None else "")
    body = [",".join(r) + (f",{band}" if band is not None else "") for r in data]
    path.write_text(head + "\n" + "\n".join(body) + "\n")
    return path


@pytest.mark.parametrize("bad", ["-0.05", "0", "nan", "inf"])
def test_iof_that_is_not_positive_and_finite_is_refused_by_its_line(tmp_path, capsys, bad):
    data = rows()
    data[3] = (bad, *data[3][1:])
    path = write_csv(tmp_path / "d.csv", data)
    assert run(["photometry", "fit", str(path), "--model", "lunar-lambert"]) == 2
    err = capsys.readouterr().err
    assert "line 5" in err and "positive finite" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("i", "e", "g"), [("30", "20", "170"), ("30", "20", "5"), ("60", "10", "71")]
)
def test_an_impossible_geometry_is_refused_as_correct_refuses_it(tmp_path, capsys, i, e, g):
    """g outside [|i − e|, i + e]: the one geometry check of `photometry fit` and `correct`
    (correct clipped it silently); the message gives the three angles."""
    data = rows()
    data[3] = (data[3][0], i, e, g)
    path = write_csv(tmp_path / "d.csv", data)
    assert run(["photometry", "fit", str(path), "--model", "lunar-lambert"]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1, err
    assert "phase must be in [|incidence − emission|, incidence + emission]" in err
    assert f"got phase {g}° with incidence {i}°, emission {e}°" in err


def test_a_fit_with_no_finite_residual_is_refused_not_printed(tmp_path, capsys):
    """I/F of 1e300: the model cannot reach it; no 'RMS inf' or 'nan%' is printed."""
    path = write_csv(tmp_path / "d.csv", rows(scale=1e300))
    assert run(["photometry", "fit", str(path), "--model", "lunar-lambert"]) == 2
    captured = capsys.readouterr()
    assert "nan%" not in captured.out and "inf" not in captured.out.lower().replace("info", "")
    assert "fit" in captured.err and len(captured.err.strip().splitlines()) == 1


@pytest.mark.parametrize("band", ["$x^{", "a$b$c", "$\\frac{1}$"])
def test_the_report_shows_a_mathtext_band_name_as_text(tmp_path, capsys, band):
    path = write_csv(tmp_path / "d.csv", rows(), band=band)
    report = tmp_path / "r.html"
    argv = ["photometry", "fit", str(path), "--model", "lunar-lambert", "--noise", "absolute",
            "--report", str(report)]  # fmt: skip
    assert run(argv) == 0, capsys.readouterr().err
    assert report.stat().st_size > 10_000


def test_the_report_of_a_non_utf8_file_name_is_written(tmp_path, capsys):
    name = os.fsdecode(b"flyby-\xe9.csv")  # a Latin-1 name on a UTF-8 system
    path = write_csv(tmp_path / name, rows())
    report = tmp_path / "r.html"
    argv = ["photometry", "fit", str(path), "--model", "lunar-lambert", "--noise", "absolute",
            "--report", str(report)]  # fmt: skip
    assert run(argv) == 0, capsys.readouterr().err
    assert "flyby-\ufffd.csv" in report.read_text("utf-8")
