"""`roughdiffuse render`, `plot` and `figures` through a subprocess: exit codes, messages,
files."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from PIL import Image


def run(*args: str, cwd=None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "roughdiffuse", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=300,
    )


def test_render_writes_a_png_and_refuses_to_overwrite(tmp_path):
    out = tmp_path / "s.png"
    args = [
        "render",
        "--model",
        "oren-nayar",
        "--sigma",
        "17",
        "--albedo",
        "0.8",
        "--shape",
        "sphere",
        "--light-theta",
        "30",
        "--size",
        "48",
        "-o",
        str(out),
    ]
    r = run(*args)
    assert r.returncode == 0, r.stderr
    im = Image.open(out)
    assert im.size == (48, 48) and im.mode == "L"
    px = np.asarray(im)
    assert px[24, 24] > 100 and px[0, 0] == 0  # lit sphere on black
    r = run(*args)
    assert r.returncode == 2
    assert "exists" in r.stderr and "--force" in r.stderr and "Traceback" not in r.stderr
    assert run(*args, "--force").returncode == 0


def test_render_npy_holds_linear_radiance(tmp_path):
    out = tmp_path / "m.npy"
    r = run(
        "render",
        "--model",
        "lambert",
        "--albedo",
        "0.5",
        "--shape",
        "plane",
        "--light-theta",
        "60",
        "--size",
        "8",
        "-o",
        str(out),
    )
    assert r.returncode == 0, r.stderr
    img = np.load(out)
    np.testing.assert_allclose(img, 0.5 / np.pi * 0.5, rtol=1e-5)  # ρ/π E0 cos 60°


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--model", "phong"], "unknown model"),
        (["--shape", "cube"], "unknown shape"),
        (["--sigma", "95"], "--sigma must be in [0, 90]"),
        (["--spp", "5"], "--spp"),
        (["--light-theta", "-5"], "--light-theta"),
        (["--size", "big"], "size"),
    ],
)
def test_render_bad_arguments_exit_2_with_one_line(tmp_path, args, message):
    r = run("render", *args, "-o", str(tmp_path / "x.png"))
    assert r.returncode == 2
    assert message in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x.png").exists()


def test_output_folder_must_exist(tmp_path):
    r = run("render", "-o", str(tmp_path / "missing" / "x.png"))
    assert r.returncode == 2 and "does not exist" in r.stderr


def test_help_texts_have_examples():
    for cmd in ("render", "plot", "figures"):
        r = run(cmd, "--help")
        assert r.returncode == 0 and "examples:" in r.stdout
    assert "roughdiffuse" in run("--version").stdout


def test_plot_and_figures(tmp_path):
    r = run(
        "plot",
        "plane",
        "--model",
        "lambert,oren-nayar",
        "--sigma",
        "10,30",
        "--theta-i",
        "45",
        "-o",
        str(tmp_path / "p.png"),
    )
    assert r.returncode == 0, r.stderr
    assert Image.open(tmp_path / "p.png").size[0] > 300
    r = run("plot", "wiggle", "-o", str(tmp_path / "q.png"))
    assert r.returncode == 2 and "unknown plot" in r.stderr
    r = run("figures", "-o", str(tmp_path / "figs"), "--only", "1", "5", "--no-progress")
    assert r.returncode == 0, r.stderr
    names = sorted(p.name for p in (tmp_path / "figs").iterdir())
    assert names == ["1-lambert-sphere.png", "5-view-dependence.png", "index.html"]
    page = (tmp_path / "figs" / "index.html").read_text()
    assert page.count("<figcaption>") == 2 and "1-lambert-sphere.png" in page
