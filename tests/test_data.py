"""The sample files of ``roughdiffuse.data``: present, readable, and what they say they are.

Expected values are the generating models stated in the module's docstring (Oren–Nayar full,
given ρ and σ), evaluated here; the files are read by the package's readers.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from roughdiffuse import OrenNayar, data
from roughdiffuse.fit import fit, read_csv, read_image, read_merl, read_normals


def test_names_and_paths() -> None:
    names = data.names()
    assert {"samples.csv", "sphere.npy", "sphere_normals.npy", "sphere.json",
            "oren-nayar.binary"} <= set(names)
    for name in names:
        if name.endswith(".binary"):
            continue
        assert data.path(name).is_file(), name


def test_unknown_name_is_a_value_error_listing_the_names() -> None:
    with pytest.raises(ValueError, match="name must be one of .*samples.csv"):
        data.path("red-fabric.binary")


def test_csv_holds_the_stated_model_with_one_percent_noise() -> None:
    rows = np.loadtxt(data.path("samples.csv"), delimiter=",", comments="#", skiprows=3)
    ti, tr, dphi = (np.radians(rows[:, k]) for k in range(3))
    wi = np.stack([np.sin(ti), np.zeros_like(ti), np.cos(ti)], axis=-1)
    wo = np.stack([np.sin(tr) * np.cos(dphi), np.sin(tr) * np.sin(dphi), np.cos(tr)], axis=-1)
    truth = OrenNayar(albedo=0.7, sigma=0.35, variant="full")
    rel = rows[:, 3] / np.asarray(truth.brdf(wi, wo), dtype=np.float64) - 1.0
    # 1 % Gaussian noise: sample standard deviation of 243 draws within 20 % of 0.01
    assert rows.shape == (243, 4)
    assert 0.008 < float(np.std(rel)) < 0.012
    samples = read_csv(data.path("samples.csv"))
    assert np.asarray(samples.value).size == 243
    result = fit(OrenNayar, samples, fixed={"variant": "full"})
    # fitted to 1 % noise: within a few standard errors of the truth
    assert abs(result.values[0] - 0.7) < 5 * result.errors[0] + 1e-3
    assert abs(result.values[1] - 0.35) < 5 * result.errors[1] + 1e-3


def test_sphere_image_fits_back_to_its_model() -> None:
    meta = json.loads(data.path("sphere.json").read_text(encoding="utf-8"))
    assert meta["model"] == "OrenNayar(albedo=0.6, sigma=0.5, variant='full')"
    image, usable = read_image(data.path("sphere.npy"))
    normals = read_normals(data.path("sphere_normals.npy"))
    assert image.shape == normals.shape[:2] == (64, 64)
    from roughdiffuse.fit import image_measurements

    light = np.array(meta["light"]["direction"])
    t = math.radians(meta["light"]["theta_deg"])
    np.testing.assert_allclose(light, [math.sin(t), 0.0, math.cos(t)], atol=1e-12)
    samples = image_measurements(image, normals, light, mask=usable)
    result = fit(OrenNayar, samples, fixed={"variant": "full"})
    # the image is float32 radiance of that model: parameters back to float32 precision
    np.testing.assert_allclose(result.values, [0.6, 0.5], atol=1e-4)


def test_merl_file_is_generated_on_demand(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("ROUGHDIFFUSE_DATA_DIR", str(tmp_path))
    p = data.path("oren-nayar.binary")
    assert p.parent == tmp_path and p.stat().st_size == 12 + 3 * 90 * 90 * 180 * 8
    brdf = read_merl(p)
    wi = np.array([math.sin(0.5), 0.0, math.cos(0.5)])
    wo = np.array([-math.sin(0.3), 0.0, math.cos(0.3)])
    truth = OrenNayar(albedo=(0.6, 0.45, 0.3), sigma=0.3, variant="full").brdf(wi, wo)
    # nearest-cell lookup: the BRDF varies by well under 10 % across one cell here
    np.testing.assert_allclose(brdf.lookup(wi, wo), np.asarray(truth), rtol=0.1)
    assert data.path("oren-nayar.binary") == p  # the second call reuses the file
