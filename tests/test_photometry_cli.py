"""``roughdiffuse photometry fit`` and ``correct`` on the command line: results, and bad input
(one line on stderr, exit status 2)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import cli
from roughdiffuse.models.photometry import radiance_factor
from roughdiffuse.planetary.backplanes import ellipsoid_backplanes
from roughdiffuse.planetary.correct import read_plane, write_plane


def error_line(capsys, argv, *words):
    status = cli.main(argv)
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


def photometry_csv(path: Path, rows: list[tuple], band: bool = False) -> Path:
    head = "I/F,i,e,g" + (",band" if band else "")
    path.write_text(head + "\n" + "\n".join(",".join(map(str, r)) for r in rows) + "\n")
    return path


def lunar_rows(n=24):
    rng = np.random.default_rng(1)
    i = rng.uniform(5, 70, n)
    e = rng.uniform(5, 70, n)
    g = np.clip(np.abs(i - e) + rng.uniform(0, 1, n) * (i + e - np.abs(i - e)), 0, 180)
    iof = radiance_factor(rd.LunarLambert(0.1, 0.6), *np.radians([i, e, g]))
    return [
        (f"{v:.9g}", f"{a:.9g}", f"{b:.9g}", f"{c:.9g}")
        for v, a, b, c in zip(iof, i, e, g, strict=True)
    ]


@pytest.mark.parametrize(
    ("rows", "band", "words"),
    [
        ([(0.1, 30, 20, 200)], False, ["g must be in [0, 180]"]),
        ([(0.1, -3, 20, 20)], False, ["i must be in [0, 180]"]),
        (
            [
                (0.1, 30, 20, 40),
                (0.1, 40, 20, 50),
                (
                    0.2,
                    30,
                    30,
                    10,
                ),
            ],
            False,
            [],
        ),
        (
            [(0.1, 30, 20, 40, "v"), (0.1, 40, 20, 50, "v"), (0.2, 30, 30, 10, "u")],
            True,
            ["band 'u' has a single row"],
        ),
    ],
)
def test_fit_bad_data(tmp_path, capsys, rows, band, words):
    if not words:  # three rows is too few for two parameters plus one: the fit says so
        words = ["need more than"]
        rows = rows[:2]
    path = photometry_csv(tmp_path / "d.csv", rows, band)
    error_line(capsys, ["photometry", "fit", str(path), "--model", "lunar-lambert"], *words)


def test_fit_model_without_radiance_factor(tmp_path, capsys):
    path = photometry_csv(tmp_path / "d.csv", lunar_rows())
    error_line(
        capsys, ["photometry", "fit", str(path), "--model", "oren-nayar"], "no radiance factor"
    )


@pytest.mark.slow
def test_fit_lunar_lambert_per_band(tmp_path, capsys):
    rows = lunar_rows()
    path = photometry_csv(
        tmp_path / "d.csv", [(*r, "b1") for r in rows] + [(*r, "b2") for r in rows], band=True
    )
    report = tmp_path / "fit.html"
    assert (
        cli.main(
            [
                "photometry",
                "fit",
                str(path),
                "--model",
                "lunar-lambert",
                "--noise",
                "absolute",
                "--report",
                str(report),
            ]
        )
        == 0
    )
    out = capsys.readouterr().out
    assert out.count("band b") == 2 and "limb_darkening" in out and "0.6" in out
    assert report.stat().st_size > 10_000


def _scene(tmp_path, size=24):
    bp = ellipsoid_backplanes((size, size), (0.0, 30.0), (0.0, 0.0))
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    iof = np.full((size, size), np.nan)
    iof[lit] = radiance_factor(
        rd.LunarLambert(0.12, 0.6), bp.incidence[lit], bp.emission[lit], bp.phase[lit]
    )
    files = {}
    for name, a in (
        ("image", iof),
        ("i", np.degrees(bp.incidence)),
        ("e", np.degrees(bp.emission)),
        ("g", np.degrees(bp.phase)),
    ):
        files[name] = tmp_path / f"{name}.fits"
        write_plane(files[name], a)
    return files, bp


def test_correct_fits_end_to_end(tmp_path, capsys):
    pytest.importorskip("astropy")
    files, bp = _scene(tmp_path)
    out = tmp_path / "corrected.fits"
    argv = [
        "photometry",
        "correct",
        str(files["image"]),
        "--incidence",
        str(files["i"]),
        "--emission",
        str(files["e"]),
        "--phase",
        str(files["g"]),
        "--model",
        "lunar-lambert",
        "--param",
        "L=0.6",
        "-o",
        str(out),
    ]
    assert cli.main(argv) == 0
    got = read_plane(out)
    keep = bp.on_body & (bp.incidence < math.radians(80)) & (bp.emission < math.radians(80))
    # Lunar-Lambert is linear in its albedo: normalised to i = e = g = 0 it is ρ = 0.12
    np.testing.assert_allclose(got[keep], 0.12, rtol=1e-6)
    assert np.all(np.isnan(got[~bp.on_body]))
    # the same from a sphere's backplanes, written as .npy
    out2 = tmp_path / "c.npy"
    assert (
        cli.main(
            [
                "photometry",
                "correct",
                str(files["image"]),
                "--subsolar",
                "0,30",
                "--subobserver",
                "0,0",
                "--model",
                "lunar-lambert",
                "--param",
                "L=0.6",
                "-o",
                str(out2),
            ]
        )
        == 0
    )
    np.testing.assert_allclose(np.load(out2)[keep], 0.12, rtol=1e-6)


def test_correct_bad_input(tmp_path, capsys):
    pytest.importorskip("astropy")
    files, _ = _scene(tmp_path)
    small = tmp_path / "small.npy"
    np.save(small, np.zeros((5, 5)))
    base = ["photometry", "correct", str(files["image"]), "-o", str(tmp_path / "o.fits")]
    planes = ["--incidence", str(files["i"]), "--emission", str(files["e"])]
    error_line(capsys, [*base, *planes, "--phase", str(small)], "--phase", "5 x 5", "24 x 24")
    big = tmp_path / "big.npy"
    np.save(big, np.full((24, 24), 200.0))
    error_line(capsys, [*base, *planes, "--phase", str(big)], "[0, 180]")
    error_line(
        capsys,
        [*base, "--subsolar", "0,30", "--subobserver", "0,0", "--model", "torrance-sparrow"],
        "no radiance factor",
    )
    error_line(
        capsys,
        [*base, "--subsolar", "0,30", "--subobserver", "0,0", "--param", "Q=1"],
        "no parameter 'Q'",
    )
