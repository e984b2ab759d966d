"""Every image reader honours NoData and refuses what it cannot read: one shape rule for
every file type, real numbers only."""

from __future__ import annotations

import numpy as np
import pytest

from roughdiffuse.fit.images import read_image, read_normals
from roughdiffuse.io.images import write_exr
from roughdiffuse.io.reading import check_real, image_array, load_npy
from roughdiffuse.stereo.inputs import read_mask


@pytest.mark.parametrize(
    ("array", "held"),
    [
        (np.zeros((4, 4), dtype=[("a", "f8"), ("b", "f8")]), "structured"),
        (np.zeros((4, 4), dtype=complex), "complex"),
        (np.zeros((4, 4), dtype=bool), "booleans"),
        (np.zeros((4, 4), dtype="datetime64[s]"), "dates"),
        (np.zeros((4, 4), dtype="timedelta64[s]"), "time spans"),
        (np.full((4, 4), "a"), "text"),
    ],
)
def test_npy_of_other_than_real_numbers_is_refused_by_name(tmp_path, array, held):
    path = tmp_path / "img.npy"
    np.save(path, array)
    with pytest.raises(ValueError, match=held) as info:
        read_image(path)
    assert "img.npy" in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(ValueError, match=held):
        load_npy(path)


def test_a_boolean_mask_is_still_read(tmp_path):
    path = tmp_path / "mask.npy"
    mask = np.zeros((4, 5), dtype=bool)
    mask[1:3, 2:4] = True
    np.save(path, mask)
    np.testing.assert_array_equal(read_mask(path), mask)
    assert check_real(mask, "m", bool_ok=True) is mask


def test_band_first_and_channels_last_cubes_read_the_same(tmp_path):
    rng = np.random.default_rng(1)
    rgb = rng.uniform(0.1, 1.0, (8, 24, 3))
    np.save(tmp_path / "last.npy", rgb)
    np.save(tmp_path / "first.npy", np.moveaxis(rgb, -1, 0))  # (3, 8, 24)
    last, _ = read_image(tmp_path / "last.npy")
    first, mask = read_image(tmp_path / "first.npy")
    np.testing.assert_array_equal(first, rgb)
    np.testing.assert_array_equal(last, rgb)
    assert mask.shape == (8, 24) and mask.all()
    one_band = rgb[..., :1].transpose(2, 0, 1)  # (1, 8, 24): a one-band cube
    np.testing.assert_array_equal(image_array(one_band, "x"), rgb[..., 0])


@pytest.mark.parametrize(
    ("shape", "says"),
    [
        ((2, 3, 8, 8), "4 axes"),
        ((1, 16), "(1, 16): one row"),
        ((16, 1), "(16, 1): one column"),
        ((1, 16, 1), "cannot be told"),
        ((3, 16, 3), "cannot be told"),
        ((8, 8, 4), "no axis of 1, 3 channels"),
        ((16,), "(16,): 1 axis"),
        ((0, 8), "(0, 8): no rows"),  # an empty image is not "one row"
        ((8, 0), "(8, 0): no columns"),
        ((1, 0), "(1, 0): no columns"),
    ],
)
def test_shapes_no_rule_understands_are_refused_with_the_shape_given(tmp_path, shape, says):
    path = tmp_path / "img.npy"
    np.save(path, np.ones(shape))
    with pytest.raises(ValueError, match="give|at least 2") as info:
        read_image(path)
    assert says in str(info.value)
    assert str(shape) in str(info.value)


def test_band_first_normals_are_understood(tmp_path):
    n = np.zeros((6, 7, 3))
    n[..., 2] = 1.0
    np.save(tmp_path / "n.npy", np.moveaxis(n, -1, 0))
    np.testing.assert_array_equal(read_normals(tmp_path / "n.npy"), n)


def test_exr_nan_pixels_are_nodata_not_zero(tmp_path):
    """The same data as EXR and as NPY: half the pixels NaN; both readers mark the same
    2048 of 4096 pixels as data."""
    pytest.importorskip("OpenEXR")
    img = np.full((64, 64), 0.5, dtype=np.float32)
    img[:, :32] = np.nan
    write_exr(tmp_path / "a.exr", img)
    np.save(tmp_path / "a.npy", img)
    for name in ("a.exr", "a.npy"):
        _, mask = read_image(tmp_path / name)
        assert int(mask.sum()) == 2048
        assert not mask[:, :32].any()
