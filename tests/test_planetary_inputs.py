"""The planetary readers and writer under the package's input rules: ``correct_file`` refuses
an output that is one of its inputs (the check the command line uses), and ``.npy`` and FITS
planes are read by the one shape and value rule of every image reader (bands first or last,
refusals that say how to give the image)."""

from __future__ import annotations

import numpy as np
import pytest
from astropy.io import fits

import roughdiffuse as rd
from roughdiffuse.planetary.chunked import (
    Correction,
    EllipsoidGeometry,
    FileGeometry,
    ParameterMaps,
    correct_file,
)
from roughdiffuse.planetary.correct import read_plane
from roughdiffuse.planetary.rasters import open_plane

SHAPE = (24, 20)


def _planes(tmp_path):
    rng = np.random.default_rng(3)
    paths = {}
    for name, lo, hi in (("img", 0.05, 0.3), ("i", 10.0, 60.0), ("e", 0.0, 30.0)):
        paths[name] = tmp_path / f"{name}.npy"
        np.save(paths[name], rng.uniform(lo, hi, SHAPE).astype(np.float32))
    i, e = np.load(paths["i"]), np.load(paths["e"])
    paths["g"] = tmp_path / "g.npy"
    np.save(paths["g"], np.maximum(i, e))  # inside [|i − e|, i + e]
    return paths


@pytest.mark.parametrize("which", ["img", "i", "e", "g"])
def test_correct_file_refuses_an_output_that_is_an_input(tmp_path, which):
    paths = _planes(tmp_path)
    before = {k: p.read_bytes() for k, p in paths.items()}
    geometry = FileGeometry(*(open_plane(paths[k]) for k in "ieg"))
    with pytest.raises(ValueError, match="is one of the inputs"):
        correct_file(open_plane(paths["img"]), geometry, Correction(rd.Lambert(1.0)), paths[which])
    assert {k: p.read_bytes() for k, p in paths.items()} == before


def test_correct_file_refuses_its_parameter_map_as_output(tmp_path):
    paths = _planes(tmp_path)
    maps = ParameterMaps((("albedo", open_plane(paths["e"]), False),))
    correction = Correction(rd.Lambert(1.0), maps=maps)
    geometry = EllipsoidGeometry(SHAPE, (5.0, -40.0), (0.0, 0.0))
    with pytest.raises(ValueError, match="is one of the inputs"):
        correct_file(open_plane(paths["img"]), geometry, correction, paths["e"])


def test_correct_file_writes_another_output(tmp_path):
    paths = _planes(tmp_path)
    geometry = FileGeometry(*(open_plane(paths[k]) for k in "ieg"))
    out, n = correct_file(
        open_plane(paths["img"]), geometry, Correction(rd.Lambert(1.0)), tmp_path / "out.npy"
    )
    assert out.exists() and n > 0


# a FITS cube is stored bands first (NAXIS3 the slowest axis); a .npy either way
@pytest.mark.parametrize(
    ("suffix", "layout"),
    [(".npy", "bands first"), (".npy", "bands last")]
    + [(s, "bands first") for s in (".fit", ".fts", ".fits")],
)
def test_cubes_are_read_band_by_band_by_every_array_format(tmp_path, suffix, layout):
    cube = np.random.default_rng(5).random((3, *SHAPE)).astype(np.float32)
    stored = cube if layout == "bands first" else cube.transpose(1, 2, 0)
    path = tmp_path / f"cube{suffix}"
    if suffix == ".npy":
        np.save(path, stored)
    else:
        fits.writeto(path, stored)
    for band in (1, 2, 3):
        plane = open_plane(path, band=band)
        assert plane.shape == SHAPE
        np.testing.assert_array_equal(plane.read_all(), cube[band - 1])
        np.testing.assert_array_equal(
            plane.read(slice(3, 9), slice(4, 17))[0], cube[band - 1, 3:9, 4:17]
        )
    np.testing.assert_array_equal(read_plane(path), cube[0])
    with pytest.raises(ValueError, match="3 bands .* no band 4"):
        open_plane(path, band=4)


@pytest.mark.parametrize(
    ("array", "words"),
    [
        (np.zeros((4, 4), dtype=[("a", "f8")]), "holds a structured array"),
        (np.zeros((4, 4), dtype=complex), "holds complex numbers"),
        (np.zeros((4, 4), dtype=bool), "holds booleans"),
        (np.zeros((4, 4), dtype="datetime64[s]"), "give real numbers"),
        (np.zeros((2, 3, 4, 4)), "4 axes; give (H, W)"),
        (np.zeros((1, 8)), "one row"),
        (np.zeros((5, 6, 7)), "no axis of 1, 3 channels"),
    ],
)
def test_arrays_the_shape_rule_refuses(tmp_path, array, words):
    path = tmp_path / "bad.npy"
    np.save(path, array)
    with pytest.raises(ValueError) as info:
        read_plane(path)
    assert str(info.value).startswith("bad.npy") and words in str(info.value), info.value


def test_a_fits_cube_of_five_bands_is_refused_by_the_same_rule(tmp_path):
    path = tmp_path / "five.fit"
    fits.writeto(path, np.zeros((5, *SHAPE), dtype=np.float32))
    with pytest.raises(ValueError, match="no axis of 1, 3 channels"):
        read_plane(path)


@pytest.mark.parametrize("param", ["L=1e308", "limb_darkening=1e308", "L=inf", "L=1001"])
def test_a_huge_parameter_is_one_line_before_any_output(tmp_path, capsys, param):
    """ISIS accepts any L; the declared ceiling (1000) refuses what would overflow to ∞ (an
    all-zero image, exit 0, before the ceiling)."""
    from roughdiffuse.cli import main

    paths = _planes(tmp_path)
    out = tmp_path / "out.npy"
    argv = ["photometry", "correct", str(paths["img"]), "--incidence", str(paths["i"]),
            "--emission", str(paths["e"]), "--phase", str(paths["g"]),
            "--model", "lunar-lambert", "--param", param, "-o", str(out)]  # fmt: skip
    status = main(argv)
    err = capsys.readouterr().err
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert "limb_darkening must be" in err and "1000" in err
    assert not out.exists()
