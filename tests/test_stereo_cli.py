"""``roughdiffuse stereo``: files written, truth recovered, bad input refused on one line."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import stereo
from roughdiffuse.cli import main
from roughdiffuse.render import Sphere


def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "stereo", *args],
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """Eight .npy images of a full Oren–Nayar sphere (σ = 0.4), lights.json and a mask."""
    d = tmp_path_factory.mktemp("stereo")
    lights = stereo.default_lights(8)
    data, normals = stereo.render_stereo(rd.OrenNayar(0.6, 0.4, "full"), Sphere(), lights, 32)
    names = []
    for k in range(8):
        np.save(d / f"img{k}.npy", data.images[k, :, :, 0])
        names.append(str(d / f"img{k}.npy"))
    spec = {"directions": (lights * 2.0).tolist(), "intensities": [1.0] * 8}
    (d / "lights.json").write_text(json.dumps(spec))
    np.save(d / "mask.npy", data.mask)
    return d, names, normals, data.mask


def test_images_and_lights_give_the_outputs(scene, tmp_path):
    d, names, normals, mask = scene
    out = tmp_path / "out"
    code = main(
        [
            "stereo",
            *names,
            "--lights",
            str(d / "lights.json"),
            "--mask",
            str(d / "mask.npy"),
            "-o",
            str(out),
        ]
    )
    assert code == 0
    n = np.load(out / "normals.npy")
    assert n.shape == (*mask.shape, 3)
    assert np.all(np.isnan(n[~mask]))
    err = stereo.angular_error(n[mask], normals[mask])
    assert np.max(err) < 0.05  # noise-free: the float32 fit's convergence
    params = json.loads((out / "params.json").read_text())
    assert params["model"] == "oren-nayar-full"
    assert params["roughness"]["name"] == "sigma"
    assert params["roughness"]["value"] == pytest.approx(0.4, abs=1e-3)
    for name in (
        "albedo.npy",
        "depth.npy",
        "depth.ply",
        "normals.png",
        "normals.exr",
        "albedo.png",
        "residual.exr",
        "report.html",
    ):
        assert (out / name).stat().st_size > 0, name
    depth = np.load(out / "depth.npy")
    assert np.all(np.isfinite(depth[mask])) and np.all(np.isnan(depth[~mask]))
    html = (out / "report.html").read_text()
    assert html.count("data:image/png;base64,") >= 4 and "Lambertian" in html
    # a second run into the same folder needs --force
    code = main(["stereo", *names, "--lights", str(d / "lights.json"), "-o", str(out)])
    assert code == 2


def test_demo_recovers_its_sigma(tmp_path):
    r = _cli("--demo", "-o", str(tmp_path / "demo"))
    assert r.returncode == 0, r.stderr
    params = json.loads((tmp_path / "demo" / "params.json").read_text())
    rough = params["roughness"]
    from roughdiffuse.commands.stereo import DEMO_SIGMA

    assert abs(rough["value"] - DEMO_SIGMA) < 4 * rough["standard_error"] + 1e-4
    assert params["truth"]["sigma"] == DEMO_SIGMA  # the report states it beside the fit
    report = (tmp_path / "demo" / "report.html").read_text()
    assert f"the true sigma of the rendered object is {DEMO_SIGMA:.4g}" in report
    assert (
        params["rough"]["angular_error_deg"]["mean"]
        < params["lambertian"]["angular_error_deg"]["mean"] / 3
    )


@pytest.mark.parametrize(
    "case, message",
    [
        ("two images", "at least 3 images"),
        ("lights mismatch", "8 images but 3 lights"),
        ("sizes", "differ in size"),
        ("horizon", "below the horizon"),
        ("model", "unknown model"),
    ],
)
def test_bad_input_is_one_line_and_status_2(scene, tmp_path, case, message):
    d, names, _, _ = scene
    args = [*names, "--lights", str(d / "lights.json"), "-o", str(tmp_path / "o")]
    if case == "two images":
        args = [*names[:2], *args[8:]]
    elif case == "lights mismatch":
        (tmp_path / "l.json").write_text(json.dumps({"directions": [[0, 0, 1]] * 3}))
        args[9] = str(tmp_path / "l.json")
    elif case == "sizes":
        np.save(tmp_path / "small.npy", np.ones((5, 5)))
        args[3] = str(tmp_path / "small.npy")
    elif case == "horizon":
        spec = json.loads((d / "lights.json").read_text())
        spec["directions"][2] = [1.0, 0.0, -0.1]
        (tmp_path / "l.json").write_text(json.dumps(spec))
        args[9] = str(tmp_path / "l.json")
    elif case == "model":
        args += ["--model", "no-such-model"]
    r = _cli(*args)
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], r.stderr
    assert "Traceback" not in r.stderr
