"""Fitting images: a sphere with exact normals, the renderer's sphere and vase, PNG input."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.fit import fit, image_measurements, read_image, shape_normals
from roughdiffuse.fit.report import residual_image


def _sphere_normals(size: int) -> np.ndarray:
    """Orthographic view of the unit sphere along −z: n = (x, y, √(1 − x² − y²))."""
    c = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(c, -c)
    r2 = x * x + y * y
    n = np.stack([x, y, np.sqrt(np.clip(1 - r2, 0, 1))], axis=-1)
    return np.where((r2 < 1)[..., None], n, 0.0)


@pytest.mark.parametrize("sigma", [0.0, 0.35, 0.7])
@pytest.mark.parametrize("albedo", [0.4, 0.85])
def test_sphere_parameters_within_three_sigma(sigma: float, albedo: float) -> None:
    n = _sphere_normals(96)
    light = rd.spherical_to_vector(math.radians(35.0), 0.5)
    view = np.array([0.0, 0.0, 1.0])
    inside = np.linalg.norm(n, axis=-1) > 0
    img = np.zeros(n.shape[:2])
    img[inside] = np.asarray(rd.OrenNayar(albedo, sigma).radiance(n[inside], light, view))
    rng = np.random.default_rng(int(100 * sigma + 10 * albedo))
    img *= 1 + 0.01 * rng.standard_normal(img.shape)
    data = image_measurements(img, n, light, view)
    r = fit(rd.OrenNayar, data, noise="relative")
    truth = np.array([albedo, sigma])
    assert np.all(np.abs(r.values - truth) <= 3 * r.errors), (r.values, r.errors)
    assert r.errors[0] < 0.005
    if sigma > 0:
        assert r.errors[1] < 0.01
    else:
        assert r.values[1] < 0.05
    res = residual_image(data, r)
    assert res.shape == img.shape
    assert np.isnan(res[0, 0])  # background: no sample
    assert 0.008 < np.nanstd(res) < 0.012  # the 1% noise put in


@pytest.mark.parametrize("shape_name", ["sphere", "vase"])
def test_renderer_images_fit_back(shape_name: str) -> None:
    from roughdiffuse.render import DistantLight, Sphere, SurfaceOfRevolution, render

    shape = Sphere() if shape_name == "sphere" else SurfaceOfRevolution()
    light = DistantLight(math.radians(50.0), 0.3)
    model = rd.OrenNayar(0.6, 0.5, "full")
    img, coverage = render(model, shape, light, size=120, samples_per_pixel=1)
    normals, mask = shape_normals(shape, 120, light)
    # the normals computed here cover exactly the pixels the renderer drew
    np.testing.assert_array_equal(coverage > 0, np.linalg.norm(normals, axis=-1) > 0)
    rng = np.random.default_rng(7)
    noisy = img * (1 + 0.01 * rng.standard_normal(img.shape))
    data = image_measurements(noisy, normals, light, mask=mask)
    r = fit(rd.OrenNayar, data, fixed={"variant": "full"}, noise="relative")
    assert np.all(np.abs(r.values - [0.6, 0.5]) <= 3 * r.errors), (r.values, r.errors)
    assert r.errors[1] < 0.01


def test_png_with_stated_exposure(tmp_path) -> None:  # noqa: ANN001
    from roughdiffuse.io.images import write_png

    rng = np.random.default_rng(0)
    img = rng.uniform(0.0, 0.3, (20, 30))
    img[0, 0] = 5.0  # saturates at exposure 1 stop
    path = tmp_path / "x.png"
    write_png(path, img, exposure=1.0, bits=16)
    back, mask = read_image(path)  # exposure from the file's own statement
    assert not mask[0, 0]
    # sRGB 16-bit: quantisation step ≤ 1/65535 of the display value
    np.testing.assert_allclose(back[mask], img[mask], atol=2e-4)
    back2, _ = read_image(path, exposure=2.0)  # a stated exposure wins
    np.testing.assert_allclose(back2[mask], img[mask] / 2, atol=2e-4)


def test_png_of_a_12_bit_camera_saturates_at_its_own_full_scale(tmp_path) -> None:  # noqa: ANN001
    """12-bit codes shifted up into a 16-bit PNG saturate at 4095 · 16 = 65520."""
    from PIL import Image

    rng = np.random.default_rng(1)
    code = rng.integers(0, 4095, (16, 16))
    code[3, 4] = code[9, 1] = 4095
    path = tmp_path / "cam12.png"
    Image.fromarray((code << 4).astype(np.uint16)).save(path)
    img, mask = read_image(path, exposure=0.0, encoding="linear")
    np.testing.assert_array_equal(mask, code < 4095)
    np.testing.assert_allclose(img, (code << 4) / 65535)
    # samples that fill the low bits: 65520 is an ordinary value, 65535 the full scale
    full = rng.integers(0, 65535, (16, 16)) | 1
    full[0, 0], full[1, 1] = 65520, 65535
    path = tmp_path / "cam16.png"
    Image.fromarray(full.astype(np.uint16)).save(path)
    _, mask = read_image(path, exposure=0.0, encoding="linear")
    np.testing.assert_array_equal(mask, full < 65535)


def test_diligent_folder_marks_its_clipped_values_invalid(tmp_path) -> None:  # noqa: ANN001
    """write_diligent clips the brightest values at the 12-bit full scale; read_diligent
    marks exactly those (the codes 4095 · 16 read back by Pillow) invalid."""
    from PIL import Image

    from roughdiffuse import stereo
    from roughdiffuse.stereo.diligent import write_diligent
    from roughdiffuse.stereo.inputs import StereoInput

    rng = np.random.default_rng(2)
    images = rng.uniform(0.05, 0.3, (6, 20, 20, 1))
    # highlights: 0.3 % of the values, above the full scale (the 99.5th percentile / 0.9)
    images[[0, 1, 3, 3, 5, 2, 4], [2, 7, 7, 8, 19, 0, 11], [5, 5, 1, 1, 3, 19, 12]] = 2.0
    dirs = np.array([[0.3, 0.1, 1.0], [-0.3, 0.2, 1.0], [0.0, -0.4, 1.0], [0.5, 0.5, 1.0],
                     [-0.5, -0.2, 1.0], [0.1, 0.6, 1.0]])
    dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
    data = StereoInput.from_arrays(images, dirs, np.ones((6, 1)), mask=np.ones((20, 20), bool))
    normals = np.broadcast_to([0.0, 0.0, 1.0], (20, 20, 3))
    folder = write_diligent(tmp_path / "flatPNG", data, normals, seed=3)
    back = stereo.read_diligent(folder)
    codes = np.stack([np.asarray(Image.open(folder / f"{k + 1:03d}.png")) for k in range(6)])
    clipped = codes == 4095 << 4
    assert clipped.sum() > 0
    np.testing.assert_array_equal(~back.valid, clipped)


def test_png_without_exposure_is_an_error(tmp_path) -> None:  # noqa: ANN001
    from PIL import Image

    path = tmp_path / "plain.png"
    Image.fromarray(np.full((4, 4), 1000, np.uint16)).save(path)
    with pytest.raises(ValueError, match="state its exposure"):
        read_image(path)
    img, _ = read_image(path, exposure=0.0, encoding="linear")
    np.testing.assert_allclose(img, 1000 / 65535)


def test_image_input_errors() -> None:
    n = _sphere_normals(8)
    with pytest.raises(ValueError, match="normals must have shape"):
        image_measurements(np.zeros((9, 8)), n, (0.0, 0.0, 1.0))
    with pytest.raises(ValueError, match="light must be a unit 3-vector"):
        image_measurements(np.zeros((8, 8)), n, (0.0, 0.0, 2.0))
    with pytest.raises(ValueError, match="no pixel"):
        image_measurements(np.zeros((8, 8)), n, (0.0, 0.0, -1.0))


def test_exr_and_npy_read_back(tmp_path) -> None:  # noqa: ANN001
    from roughdiffuse.io.images import write_exr, write_npy

    rng = np.random.default_rng(1)
    img = rng.uniform(0.0, 2.0, (6, 5, 3)).astype(np.float32)
    write_exr(tmp_path / "a.exr", img)
    write_npy(tmp_path / "a.npy", img[..., 0])
    back, mask = read_image(tmp_path / "a.exr")
    np.testing.assert_array_equal(back, img)
    assert mask.all()
    grey, _ = read_image(tmp_path / "a.npy")
    np.testing.assert_array_equal(grey, img[..., 0])


def test_supersampled_render_fits_after_eroding_edges() -> None:
    """With 4 samples per pixel, pixels on the terminator and shadow edges average lit and
    unlit parts; dropping one pixel along every edge removes them from the fit."""
    from roughdiffuse.render import DistantLight, SurfaceOfRevolution, render

    shape, light = SurfaceOfRevolution(), DistantLight(math.radians(50.0), 0.35)
    img, _ = render(rd.OrenNayar(0.7, 0.44, "full"), shape, light, size=128, samples_per_pixel=4)
    normals, mask = shape_normals(shape, 128, light)
    data = image_measurements(img, normals, light, mask=mask, erode=1)
    r = fit(rd.OrenNayar, data, fixed={"variant": "full"}, noise="relative")
    assert abs(r.values[0] - 0.7) < 0.002 and abs(r.values[1] - 0.44) < 0.01, r.values
    assert r.rms_relative < 0.005


def test_flat_patch_is_degenerate() -> None:
    """A plane under a distant light, seen by an orthographic camera: every pixel has the
    same geometry, so ρ and σ cannot be told apart."""
    from roughdiffuse.fit import DegenerateDataWarning

    n = np.zeros((16, 16, 3))
    n[..., 2] = 1.0
    light = rd.spherical_to_vector(math.radians(40.0), 0.0)
    img = np.full((16, 16), float(rd.OrenNayar(0.5, 0.3).radiance(n[0, 0], light, n[0, 0])))
    img *= 1 + 0.01 * np.random.default_rng(0).standard_normal(img.shape)
    with pytest.warns(DegenerateDataWarning):
        r = fit(rd.OrenNayar, image_measurements(img, n, light, (0.0, 0.0, 1.0)))
    assert np.isinf(r.errors).any()
