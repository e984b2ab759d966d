"""Photometric stereo (roughdiffuse.stereo): truth known from the renderer, closed forms."""

from __future__ import annotations

import json

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import stereo
from roughdiffuse._validate import ParameterError
from roughdiffuse.render import Sphere


@pytest.fixture(scope="module")
def rough_sphere():
    """Full Oren–Nayar sphere (ρ = 0.7, σ = 0.6) under 8 lights, noise-free, and its normals."""
    model = rd.OrenNayar(0.7, 0.6, "full")
    return stereo.render_stereo(model, Sphere(), stereo.default_lights(8), 40)


def test_lambertian_recovers_a_lambertian_sphere_exactly():
    data, normals = stereo.render_stereo(rd.Lambert(0.6), Sphere(), stereo.default_lights(6), 32)
    res = stereo.lambertian(data)
    err = stereo.angular_error(res.normals, normals[data.mask])
    assert np.nanmax(err) < 1e-3  # float32 images: ~1e-7 relative
    np.testing.assert_allclose(res.albedo[:, 0], 0.6, rtol=1e-5)


def test_lambertian_is_biased_on_a_rough_sphere_and_the_rough_fit_is_not(rough_sphere):
    data, normals = rough_sphere
    truth = normals[data.mask]
    lam = stereo.lambertian(data)
    lam_err = np.nanmean(stereo.angular_error(lam.normals, truth))
    assert lam_err > 3.0  # the lecture's claim: n·l is the wrong law for a rough object
    # noise-free images of the same model: exact up to the precision of the fit, √eps rad
    for precision, bound in (("double", 1e-3), ("single", 0.05)):
        res = stereo.rough(data, rd.OrenNayar(variant="full"), precision=precision)
        err = stereo.angular_error(res.normals, truth)
        assert np.nanmax(err) < bound, precision
        assert res.roughness == pytest.approx(0.6, abs=1e-4)
        np.testing.assert_allclose(np.nanmedian(res.albedo), 0.7, rtol=1e-4)
        assert np.all(np.isfinite(res.normals))


def test_rough_fit_with_noise_is_within_its_standard_errors(rough_sphere):
    clean, normals = rough_sphere
    truth = normals[clean.mask]
    rng = np.random.default_rng(7)
    noisy = clean.images * (1.0 + rng.normal(0.0, 0.01, clean.images.shape))  # 1% noise
    data = stereo.StereoInput.from_arrays(np.abs(noisy), clean.directions, mask=clean.mask)
    res = stereo.rough(data, rd.OrenNayar(variant="full"))
    err = np.nanmean(stereo.angular_error(res.normals, truth))
    assert err < 0.5  # degrees: the target with 1% noise on each value
    # the reported angular standard errors describe the actual errors (within 30%)
    se = np.degrees(np.nanmean(res.normal_se))
    assert 0.7 * se < err < 1.3 * se
    assert abs(res.roughness - 0.6) < 4 * res.roughness_se
    assert 0 < res.roughness_se < 0.02


def test_rough_fit_in_many_chunks_on_threads_with_a_subset_start(rough_sphere, monkeypatch):
    """The path of large objects, on a small one: the pixels in 8 chunks (run on a thread per
    core when there are several) and σ started from a random subset of 128 pixels. Noise-free
    images: the truth, to the float32 fit's precision as in the single-chunk test above."""
    import importlib

    module = importlib.import_module("roughdiffuse.stereo.rough")
    data, normals = rough_sphere
    assert data.mask.sum() > 4 * 128  # the subset start applies
    monkeypatch.setattr(module, "CHUNK", 128)
    monkeypatch.setattr(module, "SUBSET", 128)
    res = stereo.rough(data, rd.OrenNayar(variant="full"))
    err = stereo.angular_error(res.normals, normals[data.mask])
    assert np.nanmax(err) < 0.05
    assert res.roughness == pytest.approx(0.6, abs=1e-4)
    np.testing.assert_allclose(np.nanmedian(res.albedo), 0.7, rtol=1e-4)
    assert np.all(np.isfinite(res.normal_se)) and np.all(res.normal_se > 0)


def test_per_pixel_roughness_noise_free(rough_sphere):
    data, _ = rough_sphere
    res = stereo.rough(data, rd.OrenNayar(variant="full"), per_pixel=True)
    sig = res.roughness[np.isfinite(res.roughness)]
    # pixels whose observations constrain σ (enough lights away from the normal) recover it
    assert np.median(np.abs(sig - 0.6)) < 1e-3
    assert res.roughness.shape == (int(data.mask.sum()),)


def test_depth_of_a_sphere_from_its_normals():
    h = w = 64
    y, x = np.mgrid[0:h, 0:w]
    u = (x + 0.5 - w / 2) / (w / 2)
    v = (h / 2 - y - 0.5) / (h / 2)
    r2 = u * u + v * v
    mask = r2 < 0.8**2
    z = np.sqrt(np.maximum(1 - r2, 0))
    n = np.stack([u, v, z], axis=-1)
    truth = z * (w / 2)  # in pixel units
    truth = np.where(mask, truth - truth[mask].mean(), np.nan)
    for method in ("poisson", "frankot-chellappa"):
        d = stereo.integrate(n, mask, method)
        err = np.nanmax(np.abs(d - truth)) / (w / 2)
        # Poisson on the mask: second-order differences, O(h²); FC assumes periodicity
        assert err < (0.01 if method == "poisson" else 0.08), method
    assert np.all(np.isnan(d[~mask]))


def test_poisson_depth_of_two_separate_planes_and_its_kept_factorisation():
    """Two pieces of the mask, each a plane of its own slope: each is recovered exactly up to
    its own constant (each piece has mean 0), with the factorisation made for the first
    normal map or kept for the second on the same mask."""
    mask = np.zeros((6, 11), bool)
    mask[:, :4] = True
    mask[1:5, 6:] = True
    cols = np.arange(11)[None, :] * np.ones((6, 1))
    for slope_a, slope_b in ((0.5, -0.25), (-1.0, 2.0)):
        p = np.where(cols < 5, slope_a, slope_b)
        n = np.stack([-p, np.zeros_like(p), np.ones_like(p)], axis=-1)
        n /= np.linalg.norm(n, axis=-1, keepdims=True)
        d = stereo.integrate(n, mask)
        for piece, slope in ((mask & (cols < 5), slope_a), (mask & (cols > 5), slope_b)):
            truth = slope * cols[piece]
            assert np.allclose(d[piece], truth - truth.mean(), atol=1e-9)


def test_poisson_depth_from_a_factorisation_made_in_the_background():
    """prefactor() starts the factorisation of a mask in a thread; integrate() on that mask
    uses it, and on another mask factorises afresh: two planes recovered exactly either way
    (closed form: z = slope · x up to each piece's constant)."""
    from roughdiffuse.stereo.depth import clear_cache, prefactor

    mask = np.zeros((6, 11), bool)
    mask[:, :4] = True
    mask[1:5, 6:] = True
    cols = np.arange(11)[None, :] * np.ones((6, 1))
    p = np.where(cols < 5, 0.5, -0.25)
    n = np.stack([-p, np.zeros_like(p), np.ones_like(p)], axis=-1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    other = mask.copy()
    other[0, 0] = False
    try:
        for used, pre in ((mask, mask), (other, mask)):
            prefactor(pre)
            d = stereo.integrate(n, used)
            for piece, slope in ((used & (cols < 5), 0.5), (used & (cols > 5), -0.25)):
                truth = slope * cols[piece]
                assert np.allclose(d[piece], truth - truth.mean(), atol=1e-9)
            assert np.all(np.isnan(d[~used]))
    finally:
        clear_cache()


def test_lambertian_with_given_weights_uses_them_and_refuses_another_shape():
    """Given weights replace the threshold's: leaving out every observation of one light
    changes nothing for exact Lambertian data (closed form: any three lights determine b),
    and weights of another shape are refused with the expected one."""
    data = stereo.synthetic_sphere(rd.Lambert(0.5), size=12, lights=6, noise=0.0)
    full = stereo.lambertian(data, shadow=0.0)
    w = np.asarray(full.weights).copy()
    w[0] = 0.0
    part = stereo.lambertian(data, weights=w)
    good = w.sum(axis=0) >= 3
    assert np.allclose(part.normals[good], full.normals[good], atol=1e-9)
    assert np.array_equal(part.weights, w)
    with pytest.raises(ParameterError, match=r"weights must have shape \(6, \d+\)"):
        stereo.lambertian(data, weights=w[:, :-1])


def test_ply_mesh_header_and_counts(tmp_path):
    depth = np.full((3, 4), np.nan)
    depth[:2, :3] = 1.0  # 6 vertices, a 2 × 3 block: 2 quads, 4 triangles
    stereo.write_ply(tmp_path / "d.ply", depth)
    data = (tmp_path / "d.ply").read_bytes()
    head = data[: data.index(b"end_header\n") + 11].decode()
    assert "element vertex 6" in head and "element face 4" in head
    assert len(data) - len(head) == 6 * 12 + 4 * 13


@pytest.mark.parametrize(
    "case, message",
    [
        ("two images", "at least 3 images"),
        ("lights mismatch", "lights do not match"),
        ("below horizon", "below the horizon"),
        ("no mask", "selects no pixel"),
    ],
)
def test_bad_input_is_refused_by_name(case, message):
    imgs = np.ones((4, 5, 6))
    dirs = stereo.default_lights(4)
    kwargs = {}
    if case == "two images":
        imgs, dirs = imgs[:2], dirs[:2]
    elif case == "lights mismatch":
        dirs = dirs[:3]
    elif case == "below horizon":
        dirs = dirs.copy()
        dirs[1, 2] = -0.2
    elif case == "no mask":
        kwargs["mask"] = np.zeros((5, 6), bool)
    with pytest.raises(ValueError, match=message):
        stereo.StereoInput.from_arrays(imgs, dirs, **kwargs)


def test_images_of_different_sizes_are_refused(tmp_path):
    for k, shape in enumerate([(4, 4), (4, 4), (5, 4)]):
        np.save(tmp_path / f"i{k}.npy", np.ones(shape))
    with pytest.raises(ValueError, match="differ in size"):
        stereo.load_images([tmp_path / f"i{k}.npy" for k in range(3)])


def test_read_lights_json(tmp_path):
    p = tmp_path / "lights.json"
    p.write_text(
        json.dumps(
            {"directions": [[0, 0, 2], [1, 0, 1], [0, 1, 1]], "intensities": [1, 2, [1, 2, 3]]}
        )
    )
    with pytest.raises(ValueError, match="must be numbers"):
        stereo.read_lights(p)  # a ragged list of scalars and triples
    p.write_text(
        json.dumps({"directions": [[0, 0, 2], [1, 0, 1], [0, 1, 1]], "intensities": [1, 2, 3]})
    )
    d, e = stereo.read_lights(p)
    np.testing.assert_allclose(d[0], [0, 0, 1])
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1)
    assert e.tolist() == [1, 2, 3]
    p.write_text("{not json")
    with pytest.raises(ValueError, match="lights.json"):
        stereo.read_lights(p)


def test_read_diligent_layout(tmp_path):
    from PIL import Image

    dirs = stereo.default_lights(3)
    ints = np.array([[1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [0.5, 0.5, 0.5]])
    names = []
    for k in range(3):
        vals = np.full((4, 5), 1000 * (k + 1), dtype=np.uint16)
        Image.fromarray(vals).save(tmp_path / f"{k:03d}.png")
        names.append(f"{k:03d}.png")
    (tmp_path / "filenames.txt").write_text("\n".join(names) + "\n")
    np.savetxt(tmp_path / "light_directions.txt", dirs)
    np.savetxt(tmp_path / "light_intensities.txt", ints)
    mask = np.zeros((4, 5), np.uint8)
    mask[1:3, 1:4] = 255
    Image.fromarray(mask).save(tmp_path / "mask.png")
    data = stereo.read_diligent(tmp_path)
    assert data.images.shape == (3, 4, 5, 1)
    np.testing.assert_allclose(data.images[2, 0, 0, 0], 3000 / 65535)
    np.testing.assert_allclose(data.intensities[:, 0], [1.0, 2.0, 0.5])
    assert data.mask.sum() == 6
    (tmp_path / "mask.png").unlink()
    with pytest.raises(ValueError, match="missing mask.png"):
        stereo.read_diligent(tmp_path)
