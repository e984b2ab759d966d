"""``roughdiffuse stereo --benchmark``: the DiLiGenT protocol on a tiny folder of that format.

The folder is written here as the data set ships it (16-bit PNGs listed in filenames.txt,
light_directions.txt, light_intensities.txt, mask.png, Normal_gt.mat saved by scipy), and the
table is checked against angular errors computed here from the same images.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image
from scipy.io import savemat

from roughdiffuse.cli import main
from roughdiffuse.stereo import StereoInput
from roughdiffuse.stereo.benchmark import run_benchmark, write_benchmark
from roughdiffuse.stereo.methods import METHODS

LIGHTS = np.array(
    [
        [0.3, 0.2, 0.93],
        [-0.4, 0.1, 0.91],
        [0.1, -0.5, 0.86],
        [0.0, 0.0, 1.0],
        [0.5, 0.4, 0.77],
        [-0.3, -0.4, 0.87],
    ]
)
LIGHTS = LIGHTS / np.linalg.norm(LIGHTS, axis=1, keepdims=True)
E0 = np.array([[1.0, 1.2, 0.9], [0.8, 0.8, 0.8], [1.5, 1.4, 1.6], [1.0, 1.0, 1.0],
               [0.7, 0.9, 1.1], [1.2, 1.0, 0.8]])


def _object(h: int, w: int, tilt: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A Lambertian bump of albedo 0.6 seen from +z (x right, y up, row 0 at the top):
    16-bit images (K, H, W, 3), mask, true normals."""
    x = (np.arange(w) + 0.5) / w * 2 - 1
    y = -((np.arange(h) + 0.5) / h * 2 - 1)
    xx, yy = np.meshgrid(x, y)
    mask = xx**2 + yy**2 < 0.85
    n = np.stack([xx * tilt, yy * tilt, np.ones_like(xx)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    shade = np.maximum(np.einsum("hwi,ki->khw", n, LIGHTS), 0.0)
    lin = 0.6 / np.pi * shade[..., None] * E0[:, None, None, :] * mask[None, ..., None]
    return np.round(lin * 65535).astype(np.uint16), mask, n


def _png16(path: Path, rgb: np.ndarray) -> None:
    """A 16-bit RGB PNG, written with its own chunk layout (PIL writes only 16-bit grey)."""
    import struct
    import zlib

    h, w, _ = rgb.shape
    raw = b"".join(b"\0" + rgb[i].astype(">u2").tobytes() for i in range(h))

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    path.write_bytes(
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 2, 0, 0, 0))
        + chunk(b"IDAT", zlib.compress(raw))
        + chunk(b"IEND", b"")
    )


def write_folder(root: Path, objects: dict[str, tuple[int, int, float]]) -> dict:
    """pmsData/<name>PNG/ for each object; returns name -> (images, mask, normals)."""
    made = {}
    for name, (h, w, tilt) in objects.items():
        d = root / "pmsData" / f"{name}PNG"
        d.mkdir(parents=True)
        imgs, mask, n = _object(h, w, tilt)
        names = []
        for k, img in enumerate(imgs):
            names.append(f"{k + 1:03d}.png")
            _png16(d / names[-1], img)
        (d / "filenames.txt").write_text("\n".join(names) + "\n")
        np.savetxt(d / "light_directions.txt", LIGHTS)
        np.savetxt(d / "light_intensities.txt", E0)
        Image.fromarray((mask * 255).astype(np.uint8)).save(d / "mask.png")
        savemat(d / "Normal_gt.mat", {"Normal_gt": np.where(mask[..., None], n, 0.0)})
        made[name] = (imgs, mask, n)
    return made


OBJECTS = {"pot1": (10, 12, 0.8), "bear": (12, 10, 0.6)}


FAST = ["lambertian", "l1", "sparse", "rpca"]
"""The methods of the fast tests (the rough fit compiles for half a minute: the slow set)."""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    root = tmp_path_factory.mktemp("diligent")
    return root, write_folder(root, OBJECTS)


def _independent_error(method: str, imgs: np.ndarray, mask: np.ndarray, n: np.ndarray) -> float:
    data = StereoInput.from_arrays(imgs / 65535.0, LIGHTS, E0, mask=mask)
    got = METHODS[method](data).normals
    cos = np.clip(np.sum(got * n[mask], axis=-1), -1.0, 1.0)
    return float(np.mean(np.degrees(np.arccos(cos))))


def _check_table(table: dict, made: dict, methods: list[str]) -> None:
    assert table["objects"] == ["pot1", "bear"]  # the order of Shi et al.'s table
    assert table["methods"] == methods
    for m in methods:
        for obj, (imgs, mask, n) in made.items():
            assert table["errors"][m][obj] == pytest.approx(
                _independent_error(m, imgs, mask, n), abs=1e-6
            )
        mean = np.mean([table["errors"][m][o] for o in made])
        assert table["average"][m] == pytest.approx(mean, abs=1e-12)
    # the frame: noise-free Lambertian images give their normals back (a flipped axis, a
    # missed light intensity or a transposed image would cost degrees)
    for obj in made:
        assert table["errors"]["lambertian"][obj] < 0.05


def _check_layout(out: Path, methods: list[str]) -> None:
    md = (out / "benchmark.md").read_text().splitlines()
    assert md[2] == "| method | pot1 | bear | average |"
    assert [r.split(" | ")[0].strip("| ") for r in md[4:]] == methods
    rows = (out / "benchmark.csv").read_text().splitlines()
    assert rows[0] == "method,pot1,bear,average"
    assert [r.split(",")[0] for r in rows[1:]] == methods


def test_table_holds_the_mean_angular_error_of_every_method_and_object(folder, tmp_path):
    root, made = folder
    result = run_benchmark(root, FAST, keep_details=False)
    write_benchmark(tmp_path, result)
    _check_table(json.loads((tmp_path / "benchmark.json").read_text()), made, FAST)
    _check_layout(tmp_path, FAST)


@pytest.mark.slow
def test_cli_benchmark_runs_every_method_and_draws_their_maps(folder, tmp_path):
    root, made = folder
    out = tmp_path / "table"
    assert main(["stereo", "--benchmark", str(root), "-o", str(out)]) == 0
    _check_table(json.loads((out / "benchmark.json").read_text()), made, list(METHODS))
    _check_layout(out, list(METHODS))
    page = (out / "report.html").read_text()
    assert page.count("<figure>") == 2 * len(OBJECTS)  # error maps and rejections per object


def _cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "stereo", *args],
        capture_output=True, text=True, timeout=300,
    )


def _refused(root: Path, tmp_path: Path, *needles: str) -> None:
    r = _cli("--benchmark", str(root), "-o", str(tmp_path / "out"))
    assert r.returncode == 2, r.stderr
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1, r.stderr
    for s in needles:
        assert s in lines[0]
    assert not (tmp_path / "out").exists()


def test_a_missing_file_is_named(tmp_path):
    write_folder(tmp_path, {"ball": (8, 8, 0.5)})
    (tmp_path / "pmsData" / "ballPNG" / "Normal_gt.mat").unlink()
    _refused(tmp_path, tmp_path, "Normal_gt.mat", "missing")


def test_lights_and_images_that_disagree_in_number(tmp_path):
    write_folder(tmp_path, {"ball": (8, 8, 0.5)})
    np.savetxt(tmp_path / "pmsData" / "ballPNG" / "light_directions.txt", LIGHTS[:5])
    _refused(tmp_path, tmp_path, "6 images", "5 light directions")


def test_a_mask_of_another_size(tmp_path):
    write_folder(tmp_path, {"ball": (8, 8, 0.5)})
    Image.fromarray(np.full((9, 8), 255, np.uint8)).save(
        tmp_path / "pmsData" / "ballPNG" / "mask.png")
    _refused(tmp_path, tmp_path, "mask.png", "8x9", "8x8")


def test_fewer_lights_than_the_coated_parameters(tmp_path):
    write_folder(tmp_path, {"ball": (8, 8, 0.5)})
    d = tmp_path / "pmsData" / "ballPNG"
    (d / "filenames.txt").write_text("001.png\n002.png\n003.png\n004.png\n")
    np.savetxt(d / "light_directions.txt", LIGHTS[:4])
    np.savetxt(d / "light_intensities.txt", E0[:4])
    _refused(tmp_path, tmp_path, "coated", "ball has 4 images", "at least 5")
