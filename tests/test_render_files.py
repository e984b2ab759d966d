"""Image files: PNG values against the sRGB standard (read back by Pillow), .npy, OpenEXR,
atomic writes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from roughdiffuse.io.atomic import atomic_write
from roughdiffuse.io.images import (
    exposure_scale,
    linear_to_srgb,
    write_exr,
    write_image,
    write_npy,
    write_png,
)

# IEC 61966-2-1 values: sRGB(0.5) = 1.055 * 0.5^(1/2.4) - 0.055 = 0.735357; the linear
# segment 12.92 x below 0.0031308; sRGB(0.18) = 0.461356 ("18% grey" encodes to ~118/255).
LINEAR = np.array([[0.0, 0.002, 0.18, 0.5, 1.0, 3.0]])
SRGB = np.array([[0.0, 0.02584, 0.461356, 0.735357, 1.0, 1.0]])


def test_srgb_curve_matches_the_standard():
    np.testing.assert_allclose(linear_to_srgb(LINEAR), SRGB, atol=1e-5)


def test_png_8bit_grey_holds_srgb_values_and_metadata(tmp_path):
    path = write_png(tmp_path / "g.png", LINEAR, exposure=0.0, metadata={"note": "x"})
    im = Image.open(path)
    assert im.mode == "L" and im.size == (6, 1)
    np.testing.assert_array_equal(np.asarray(im), np.rint(SRGB * 255))
    assert "sRGB" in im.info["roughdiffuse:encoding"]
    assert float(im.info["roughdiffuse:scale"]) == 1.0
    assert im.info["note"] == "x"


def test_png_16bit_grey(tmp_path):
    path = write_png(tmp_path / "g16.png", LINEAR, exposure=0.0, bits=16)
    im = Image.open(path)
    assert im.mode.startswith("I")
    np.testing.assert_array_equal(np.asarray(im).astype(int), np.rint(SRGB * 65535))


def test_png_exposure_in_stops(tmp_path):
    # one stop up: 0.25 -> 0.5 -> sRGB 0.735357
    path = write_png(tmp_path / "e.png", np.full((2, 2), 0.25), exposure=1.0)
    assert np.all(np.asarray(Image.open(path)) == round(0.735357 * 255))


def test_png_rgb_with_alpha(tmp_path):
    img = np.zeros((2, 3, 3))
    img[..., 0] = 0.5
    img[:, 2, 2] = 0.25  # premultiplied by coverage 0.5 below: straight value 0.5
    mask = np.ones((2, 3))
    mask[:, 2] = 0.5
    path = write_png(tmp_path / "c.png", img, exposure=0.0, mask=mask)
    im = Image.open(path)
    assert im.mode == "RGBA"
    px = np.asarray(im)
    assert px[0, 0].tolist() == [188, 0, 0, 255]
    assert px[0, 2, 3] == 128
    assert px[0, 2, 0] == 255 and px[0, 2, 2] == 188  # 0.5/0.5 = 1 and 0.25/0.5 = 0.5


def test_png_16bit_rgb_reads_back(tmp_path):
    img = np.full((4, 5, 3), 0.5)
    path = write_png(tmp_path / "c16.png", img, exposure=0.0, bits=16)
    raw = path.read_bytes()
    assert raw[24] == 16 and raw[25] == 2  # IHDR bit depth 16, colour type RGB
    im = Image.open(path)
    assert im.size == (5, 4)
    assert np.all(np.abs(np.asarray(im.convert("RGB")).astype(int) - 188) <= 1)


def test_auto_exposure_maps_the_top_to_white():
    img = np.linspace(0, 2.0, 10001)
    assert exposure_scale(img, "auto") == pytest.approx(1 / np.percentile(img, 99.9))
    assert exposure_scale(np.zeros(4), "auto") == 1.0
    with pytest.raises(ValueError, match="exposure"):
        exposure_scale(img, "bright")


def test_npy_round_trip(tmp_path):
    img = np.random.default_rng(0).random((7, 9, 3)).astype(np.float32)
    path = write_npy(tmp_path / "a.npy", img)
    np.testing.assert_array_equal(np.load(path), img)


def test_exr_round_trip(tmp_path):
    import OpenEXR

    img = np.random.default_rng(1).random((6, 8)).astype(np.float32) * 10
    path = write_exr(tmp_path / "a.exr", img, metadata={"roughdiffuse:model": "Lambert"})
    with OpenEXR.File(str(path)) as f:
        y = f.channels()["Y"].pixels
        assert f.header()["roughdiffuse:model"] == "Lambert"
    np.testing.assert_array_equal(y, img)
    rgb = np.random.default_rng(2).random((3, 4, 3)).astype(np.float32)
    with OpenEXR.File(str(write_exr(tmp_path / "c.exr", rgb))) as f:
        np.testing.assert_array_equal(f.channels()["RGB"].pixels, rgb)


def test_write_image_dispatches_on_suffix(tmp_path):
    img = np.ones((3, 3), np.float32)
    for suffix in (".png", ".npy", ".exr"):
        assert write_image(tmp_path / f"x{suffix}", img).exists()
    with pytest.raises(ValueError, match="must end in"):
        write_image(tmp_path / "x.jpg", img)


def test_atomic_write_leaves_nothing_on_failure(tmp_path):
    target = tmp_path / "keep.png"
    target.write_bytes(b"old")

    def boom(tmp: Path) -> None:
        tmp.write_bytes(b"half")
        raise RuntimeError("interrupted")

    with pytest.raises(RuntimeError):
        atomic_write(target, boom)
    assert target.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["keep.png"]


def test_missing_folder_is_a_value_error(tmp_path):
    with pytest.raises(ValueError, match="does not exist"):
        write_npy(tmp_path / "nope" / "a.npy", np.zeros(2))


def test_read_png_agrees_with_pillow(tmp_path):
    """Our PNG decoder against Pillow on 8-bit RGB and 16-bit grey (both filters paths)."""
    from roughdiffuse.io.images import read_png

    rng = np.random.default_rng(0)
    rgb = rng.integers(0, 256, size=(37, 23, 3), dtype=np.uint8)
    rgb[:, :5] = 200  # flat areas make the encoder pick other filters
    Image.fromarray(rgb).save(tmp_path / "a.png")
    pix, bits, _ = read_png(tmp_path / "a.png")
    assert bits == 8 and np.array_equal(pix, rgb)
    grey = rng.integers(0, 65536, size=(19, 31), dtype=np.uint16)
    Image.fromarray(grey).save(tmp_path / "b.png")
    pix, bits, _ = read_png(tmp_path / "b.png")
    assert bits == 16 and np.array_equal(pix[..., 0], np.asarray(Image.open(tmp_path / "b.png")))


def test_read_png_with_a_bad_header_is_a_value_error_naming_the_file(tmp_path):
    from roughdiffuse.io.images import read_png

    good = write_png(tmp_path / "g.png", np.zeros((2, 2))).read_bytes()
    # shorten the IHDR chunk's declared length from 13 to 5 bytes
    bad = good[:8] + (5).to_bytes(4, "big") + good[12:]
    (tmp_path / "bad.png").write_bytes(bad)
    with pytest.raises(ValueError, match="bad.png: corrupt PNG header"):
        read_png(tmp_path / "bad.png")
