"""``roughdiffuse stereo --method``: the robust solvers from the command line, and the
flags that do not go together refused in one line."""

from __future__ import annotations

import json

import numpy as np
import pytest

from roughdiffuse.cli import main
from roughdiffuse.stereo import StereoInput

K = 12


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    """A Lambertian sphere (albedo 0.6) under 12 lights with a highlight in two images."""
    d = tmp_path_factory.mktemp("robust_cli")
    rng = np.random.default_rng(5)
    th = np.radians(rng.uniform(15, 55, K))
    ph = 2 * np.pi * (np.arange(K) + 0.5) / K
    lights = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], 1)
    u = (np.arange(20) + 0.5) / 20 * 2 - 1
    x, y = np.meshgrid(u, -u)
    mask = x * x + y * y < 0.8
    n = np.stack([x, y, np.sqrt(np.clip(1 - x * x - y * y, 0, None))], -1)
    imgs = 0.6 / np.pi * np.maximum(np.einsum("hwi,ki->khw", n, lights), 0) * mask
    imgs[3, 8:11, 8:11] += 0.4  # highlights
    imgs[7, 9:12, 9:12] += 0.4
    names = []
    for k in range(K):
        names.append(str(d / f"img{k:02d}.npy"))
        np.save(names[-1], imgs[k])
    (d / "lights.json").write_text(json.dumps({"directions": lights.tolist()}))
    np.save(d / "mask.npy", mask)
    return d, names, n, mask, imgs, lights


def _args(scene, *more: str) -> list[str]:
    d, names, *_ = scene
    return ["stereo", *names, "--lights", str(d / "lights.json"), "--mask", str(d / "mask.npy"),
            *more]


@pytest.mark.slow
def test_method_l1_writes_the_robust_normals_and_its_rejections(scene, tmp_path, capsys):
    d, names, n, mask, imgs, lights = scene
    out = tmp_path / "out"
    assert main(_args(scene, "--method", "l1", "-o", str(out))) == 0
    assert capsys.readouterr().out.startswith("l1: no roughness")
    got = np.load(out / "normals.npy")[mask].astype(np.float64)  # stored as float32
    # the angle by atan2(|a × b|, a · b): arccos of a float32 dot product is off by 0.01°
    err = np.degrees(np.arctan2(np.linalg.norm(np.cross(got, n[mask]), axis=-1),
                                np.sum(got * n[mask], -1)))
    lit = np.all(np.einsum("pi,ki->kp", n[mask], lights) > 0, axis=0)
    assert lit.sum() > 100
    assert err[lit].max() < 1e-3  # where every light reaches, the highlights bend nothing
    params = json.loads((out / "params.json").read_text())
    assert params["model"] == "l1"
    # rejected: at least the 18 highlight observations, at most those and the shadows
    data = StereoInput.from_arrays(imgs, lights, mask=mask)
    grey = data.images[:, mask, 0]
    rejected = params["methods"]["l1"]["rejected_fraction"]
    assert 18 / grey.size <= rejected <= (np.sum(grey == 0) + 18) / grey.size
    page = (out / "report.html").read_text()
    assert "observations left out or rejected" in page


@pytest.mark.parametrize(
    ("more", "needle"),
    [
        (["--method", "l1", "--model", "oren-nayar-full"], "--model applies only to"),
        (["--method", "sparse", "--per-pixel"], "--per-pixel applies only to --method rough"),
        (["--model", "lambert", "--method", "rpca"], "--model lambert is --method lambertian"),
        (["--method", "coated", "--model", "oren-nayar-full"],
         "--method coated fits the coated model"),
        (["--method", "l2"], "invalid choice"),
    ],
)
def test_methods_and_models_that_do_not_go_together(scene, tmp_path, capsys, more, needle):
    with pytest.raises(SystemExit) if "l2" in more else _no_raise():
        code = main(_args(scene, *more, "-o", str(tmp_path / "o")))
        assert code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0]
    assert not (tmp_path / "o").exists()


def test_benchmark_conflicts_with_lights_and_method(tmp_path, capsys):
    for more in (["--lights", "x.json"], ["--method", "l1"]):
        code = main(["stereo", "--benchmark", str(tmp_path), *more, "-o", str(tmp_path / "o")])
        assert code == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--benchmark" in err[0]


class _no_raise:  # noqa: N801 - used as a context manager beside pytest.raises
    def __enter__(self) -> None:
        return None

    def __exit__(self, *exc: object) -> bool:
        return False


def test_method_choices_are_the_method_table():
    """--method offers exactly the methods of roughdiffuse.stereo.methods (kept as a tuple in
    the command so that its parser does not import the solvers)."""
    from roughdiffuse.commands.stereo import DEFAULT_MODEL, METHOD_CHOICES, ROBUST
    from roughdiffuse.stereo.methods import DEFAULT_ROUGH_MODEL

    assert DEFAULT_MODEL == DEFAULT_ROUGH_MODEL  # the command's default is the method table's
    from roughdiffuse.stereo.methods import METHODS
    from roughdiffuse.stereo.robust import ROBUST_METHODS

    assert METHOD_CHOICES == tuple(METHODS)
    assert ROBUST == ROBUST_METHODS
