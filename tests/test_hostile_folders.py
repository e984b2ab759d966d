"""Rule: a results folder (or a set of files written together) is whole, or visibly not.

Every command that writes several files: ``stereo`` (a folder of its own, swapped in whole),
``bench`` and ``simulate --report`` (files appearing together in a shared folder),
``figures`` (index.html is the completion marker, kept files are checked and named)."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from roughdiffuse.cli import main
from roughdiffuse.io import atomic_folder, deferred, write_text
from roughdiffuse.io.images import write_npy, write_png


def _names(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.iterdir())


def test_atomic_folder_failure_leaves_nothing_new(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic_folder(tmp_path / "out") as tmp:
            write_text(tmp / "normals.npy", "new")
            raise RuntimeError("killed mid-write")
    assert _names(tmp_path) == []


def test_atomic_folder_replaces_whole_and_only_when_complete(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "params.json").write_text("old run")
    (out / "roughness.png").write_text("old run only")
    with pytest.raises(ValueError, match="already holds results; add --force"):
        with atomic_folder(out, marker="params.json"):
            pass
    with pytest.raises(RuntimeError):  # an interrupted --force run: the old folder stays
        with atomic_folder(out, replace=True, marker="params.json") as tmp:
            (tmp / "normals.npy").write_text("new")
            raise RuntimeError
    assert _names(out) == ["params.json", "roughness.png"]
    assert _names(tmp_path) == ["out"]
    with atomic_folder(out, replace=True, marker="params.json") as tmp:
        (tmp / "params.json").write_text("new run")
    assert _names(out) == ["params.json"]  # never a mix of two runs
    assert (out / "params.json").read_text() == "new run"


def test_force_never_replaces_a_folder_of_other_files(tmp_path):
    (tmp_path / "thesis.tex").write_text("precious")
    with pytest.raises(ValueError, match="not a result of this command"):
        with atomic_folder(tmp_path, replace=True, marker="params.json"):
            pass
    assert (tmp_path / "thesis.tex").read_text() == "precious"


def test_deferred_files_appear_together_or_not_at_all(tmp_path):
    (tmp_path / "RESULTS.md").write_text("old")
    with pytest.raises(RuntimeError):
        with deferred(tmp_path):
            write_text(tmp_path / "results.json", "{}")
            write_npy(tmp_path / "a.npy", np.zeros(2))
            assert not (tmp_path / "results.json").exists()  # staged, not yet there
            raise RuntimeError("interrupted between the files")
    assert _names(tmp_path) == ["RESULTS.md"]
    with deferred(tmp_path):
        write_text(tmp_path / "results.json", "{}")
        write_text(tmp_path / "RESULTS.md", "new")
    assert _names(tmp_path) == ["RESULTS.md", "results.json"]
    assert (tmp_path / "RESULTS.md").read_text() == "new"


def test_deferred_writes_files_outside_its_folder_at_once(tmp_path):
    (tmp_path / "report").mkdir()
    with deferred(tmp_path / "report"):
        write_text(tmp_path / "scratch.ply", "read back inside the block")
        assert (tmp_path / "scratch.ply").read_text() == "read back inside the block"


@pytest.fixture(scope="module")
def tiny_stereo(tmp_path_factory):
    """Four 12 x 12 images of a Lambertian hemisphere (closed form n·l) and their lights."""
    d = tmp_path_factory.mktemp("stereo")
    lights = np.array([[0.3, 0.0, 1.0], [-0.3, 0.0, 1.0], [0.0, 0.3, 1.0], [0.0, -0.3, 1.0]])
    lights /= np.linalg.norm(lights, axis=1, keepdims=True)
    y, x = np.mgrid[-1:1:12j, -1:1:12j] * 0.9
    n = np.stack([x, y, np.sqrt(np.clip(1 - x * x - y * y, 0, None))], axis=-1)
    names = []
    for k, light in enumerate(lights):
        np.save(d / f"i{k}.npy", 0.7 / np.pi * np.clip(n @ light, 0, None))
        names.append(str(d / f"i{k}.npy"))
    (d / "lights.json").write_text(
        json.dumps({"directions": lights.tolist(), "intensities": [1.0] * 4})
    )
    return d, names


@pytest.fixture
def quick_rough(monkeypatch):
    """``stereo.rough`` replaced by the Lambertian start with σ = 0.3 ± inf (as four identical
    images give): these tests are about the files, not the fit."""
    from roughdiffuse import stereo
    from roughdiffuse.stereo.rough import RoughResult

    def rough(data, model, *, start, **kwargs):
        p = start.normals.shape[0]
        return RoughResult(
            normals=start.normals,
            albedo=start.albedo,
            roughness=0.3,
            roughness_name="sigma",
            roughness_se=float("inf"),
            normal_se=np.zeros(p),
            albedo_se=np.zeros_like(start.albedo),
            residual=start.residual,
            weights=np.ones((data.count, p)),
            iterations=0,
        )

    monkeypatch.setattr(stereo, "rough", rough)


@pytest.mark.parametrize(
    "extra",
    [["--model", "no-such-model"], ["--lights", "/nonexistent/lights.json"]],
)
def test_a_failed_stereo_run_leaves_no_folder(tiny_stereo, tmp_path, extra):
    d, names = tiny_stereo
    args = ["stereo", *names, "--lights", str(d / "lights.json"), "-o", str(tmp_path / "o")]
    assert main([*args, *extra]) == 2
    assert _names(tmp_path) == []


def test_stereo_killed_mid_write_keeps_the_old_results(
    tiny_stereo, quick_rough, tmp_path, monkeypatch
):
    from roughdiffuse import stereo

    d, names = tiny_stereo
    out = tmp_path / "o"
    args = ["stereo", *names, "--lights", str(d / "lights.json"), "--model", "oren-nayar"]
    assert main([*args, "-o", str(out)]) == 0
    params = json.loads((out / "params.json").read_text())  # strict JSON: null, not Infinity
    assert params["roughness"]["standard_error"] is None
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    real = stereo.write_outputs

    def half(folder, *a, **k):
        write_npy(Path(folder) / "normals.npy", np.zeros((2, 2, 3)))
        raise KeyboardInterrupt  # as Ctrl-C between two files

    monkeypatch.setattr(stereo, "write_outputs", half)
    assert main([*args, "-o", str(out), "--force"]) == 130
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert _names(tmp_path) == ["o"]
    monkeypatch.setattr(stereo, "write_outputs", real)
    assert main([*args, "-o", str(out)]) == 2  # still refused without --force: it is whole


def test_bench_output_dir_that_is_a_file_is_refused_before_any_benchmark(tmp_path, capsys):
    f = tmp_path / "file"
    f.write_text("x")
    assert main(["bench", "--output-dir", str(f / "sub"), "--sizes", "4"]) == 2
    err = capsys.readouterr().err
    assert "is not a folder" in err and "C reference" not in err


def test_figures_only_empty_is_refused(tmp_path, capsys):
    with pytest.raises(SystemExit) as stop:  # by the parser, as every empty option value
        main(["figures", "-o", str(tmp_path / "f"), "--only", ""])
    assert stop.value.code == 2
    assert "--only: empty value" in capsys.readouterr().err
    assert not (tmp_path / "f").exists()


def test_figures_planted_file_is_refused_and_a_kept_png_is_named(tmp_path, capsys):
    from roughdiffuse.figures import FIGURES

    folder = tmp_path / "f"
    folder.mkdir()
    name = FIGURES[0].name
    (folder / f"{name}.png").write_text("<script>planted</script>")
    assert main(["figures", "-o", str(folder), "--only", "1", "--no-progress"]) == 2
    assert "is not a PNG image" in capsys.readouterr().err
    write_png(folder / f"{name}.png", np.zeros((2, 2)))
    assert main(["figures", "-o", str(folder), "--only", "1", "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert "wrote 0 figures" in out and f"kept 1 already there: {name}" in out
    assert (folder / "index.html").exists()


def test_stereo_refuses_a_fit_with_a_residual_of_the_datas_size(
    tiny_stereo, quick_rough, tmp_path, monkeypatch, capsys
):
    from roughdiffuse import stereo

    d, names = tiny_stereo
    fitted = stereo.rough

    def useless(*a, **k):
        r = fitted(*a, **k)
        r.residual = np.ones_like(r.residual)  # the model explains none of the data
        return r

    monkeypatch.setattr(stereo, "rough", useless)
    argv = ["stereo", *names, "--lights", str(d / "lights.json"), "-o", str(tmp_path / "o")]
    assert main(argv) == 2
    assert "relative RMS residual of 100%" in capsys.readouterr().err
    assert _names(tmp_path) == []
