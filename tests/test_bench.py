"""The benchmark script and its CLI entry (structure and agreement only, no timing)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
import types
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_bench_run_writes_results_and_checks_agreement(tmp_path, monkeypatch):
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(tmp_path / "cache"))
    cmd = [
        sys.executable,
        str(ROOT / "bench" / "run.py"),
        "--sizes", "10",
        "--repeat", "1",
        "--no-first-call",
        "--no-render",
        "--no-fit",
        "--no-simulate",
        "--memory-log2", "0",
        "--brdf-sizes", "10",
        "--startup-repeat", "0",
        "--output-dir", str(tmp_path),
    ]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stderr
    data = json.loads((tmp_path / "results.json").read_text())
    assert "fit" not in data and "simulate" not in data and "startup" not in data
    assert {r["dtype"] for r in data["brdf"]} == {"float32", "float64"}
    for r in data["brdf"]:
        errors = r["max_rel_error_vs_reference"]
        assert errors["default"] < 1e-4  # model.brdf: the reference path's values
        if shutil.which("gcc") and "c" in errors:  # (a model with no C kernel has none)
            # the C transcription of the same formula (float32: rounding of a few dozen
            # operations, amplified near the kinks; float64: the same, 2^29 times smaller)
            assert errors["c"] < (2e-3 if r["dtype"] == "float32" else 1e-9)
            assert r["default_over_c"] > 0
    labels = [r["model"] for r in data["results"]]
    for name in ("Lambert", "qualitative", "full", "Fujii", "EON", "Torrance"):
        assert any(name in x for x in labels)
    for r in data["results"]:
        errors = r["max_rel_error_vs_reference"]
        assert errors["fast"] < 1e-4  # the fast path computes the reference's values
        assert errors["numpy"] == 0.0
        if shutil.which("gcc") and "c" in errors:
            assert errors["c"] < 2e-3  # the C transcription is the same formula
            assert r["fast_over_c"] > 0
        assert r["fast"]["runs"] == 1
    text = (tmp_path / "RESULTS.md").read_text()
    assert "| 2^10 | Oren–Nayar qualitative |" in text
    assert "bench/run.py --sizes 10" in text
    assert "## Fit" not in text and "## V-cavity solver" not in text


@pytest.mark.slow
def test_bench_run_fit_and_solver_sections_at_tiny_scale(tmp_path, monkeypatch):
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(tmp_path / "cache"))
    cmd = [
        sys.executable,
        str(ROOT / "bench" / "run.py"),
        "--sizes", "10",
        "--models", "Lambert",
        "--repeat", "1",
        "--no-c",
        "--no-numpy",
        "--no-first-call",
        "--no-render",
        "--memory-log2", "0",
        "--fit-size", "48",
        "--fit-repeat", "1",
        "--simulate-repeat", "1",
        "--simulate-cavities", "400",
        "--simulate-geometries", "1",
        "--simulate-cases", "closed form,bounces=1",
        "--output-dir", str(tmp_path),
    ]  # fmt: skip
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 0, proc.stderr
    data = json.loads((tmp_path / "results.json").read_text())

    fit = data["fit"]
    assert fit["image_size"] == 48
    assert [r["name"] for r in fit["rows"]] == [
        "Oren-Nayar qualitative, absolute noise",
        "Oren-Nayar qualitative, relative noise",
        "Oren-Nayar full, relative noise",
    ]
    for r in fit["rows"]:
        # the SciPy baseline (finite differences on model.radiance) and our fit (JAX
        # Jacobian, multistart, Gauss-Newton refinement) minimise the same cost
        assert abs(r["albedo"] - r["scipy_albedo"]) < 1e-3
        assert abs(r["sigma"] - r["scipy_sigma"]) < 1e-3
        # and both find the parameters the image was made with (ρ = 0.7, σ = 0.4, 1% noise)
        assert abs(r["albedo"] - 0.7) < 0.01 and abs(r["sigma"] - 0.4) < 0.03
        assert r["ours_s"]["runs"] == 1 and r["scipy_s"]["runs"] == 1
        assert r["scipy_over_ours"] > 0 and r["pixels"] > 1000

    sim = data["simulate"]
    assert sim["environment"]["OPENBLAS_NUM_THREADS"] == "1"
    assert "error" not in sim, sim.get("error")
    names = [r["case"] for r in sim["rows"]]
    assert names == [
        "cavity, 1 bounce (closed form)",
        "surface BRDF, σ=0.3, bounces=1",
        "surface BRDF, σ=0.7, bounces=1",
    ]
    for r in sim["rows"]:
        assert r["numpy"]["runs"] == 1 and r["numpy"]["median"] > 0
        if "jax" in r:  # the JAX path computes the NumPy path's values
            assert r["jax_max_rel_difference_vs_numpy"] < 1e-9
            assert r["jax_over_numpy"] > 0
        else:
            assert r["jax_error"].startswith("not available: ")
        if r["case"].startswith("surface"):
            assert r["table_90x90x180_hours_2_cores_numpy"] > 0

    text = (tmp_path / "RESULTS.md").read_text()
    assert "## Fit of (ρ, σ) to a 48 × 48 image" in text
    assert "| Oren-Nayar full, relative noise |" in text
    assert "## V-cavity solver" in text
    assert "| cavity, 1 bounce (closed form) | 400 |" in text
    assert text.count("--simulate-cases 'closed form,bounces=1'") >= 3  # header + 2 sections


def test_solver_case_reports_a_missing_jax_path_and_goes_on():
    from roughdiffuse.bench import simulate_bench as module

    def numpy_only(x):
        if not isinstance(x, np.ndarray):
            raise TypeError("no JAX path here")
        return 2.0 * x

    fake_jnp = types.SimpleNamespace(asarray=lambda a: a.tolist())  # arrays of another kind
    row = module._case("doubling", 8, numpy_only, (np.arange(8.0),), 2, fake_jnp)
    assert row["jax_error"] == "not available: TypeError: no JAX path here"
    assert "jax" not in row and row["numpy"]["runs"] == 2
    # a call that "works" by returning NumPy is no JAX path either
    row = module._case("doubling", 8, lambda x: 2.0 * np.asarray(x), (np.arange(8.0),), 1, fake_jnp)
    assert row["jax_error"].startswith("not available: TypeError: returned ndarray")


def test_cli_bench_rejects_bad_sizes_in_one_line():
    proc = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "bench", "--sizes", "99"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert proc.returncode == 2
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "--sizes" in lines[0]


@pytest.mark.parametrize("bad", [["--repeat", "0"], ["--models", "nosuchmodel"]])
def test_bench_run_rejects_bad_options(bad):
    proc = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "run.py"), *bad],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert proc.returncode == 2
    assert proc.stderr.strip().startswith("python bench/run.py: error:")


MARKER_CODE = """
import pathlib
pathlib.Path(__file__).resolve().parents[{up}].joinpath("RAN-{name}").write_text("ran")
"""


def plant(folder: Path) -> list[Path]:
    """Files a command must never run: a checkout's bench scripts and modules named like the
    package's benchmark modules, where a command that loaded code by path or by bare module
    name from the current directory would find them."""
    planted = {
        "bench/run.py": 1,
        "bench/layered_bench.py": 1,
        "bench/stereo_bench.py": 1,
        "bench/timing.py": 1,
        "bench/fit_bench.py": 1,
        "bench/simulate_bench.py": 1,
        "bench/__init__.py": 1,
        "timing.py": 0,
        "run.py": 0,
    }
    for rel, up in planted.items():
        path = folder / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(MARKER_CODE.format(up=up, name=rel.replace("/", "_")))
    return sorted(folder.glob("RAN-*"))


def test_no_command_runs_a_bench_script_from_the_current_directory(tmp_path, monkeypatch):
    from roughdiffuse import cli
    from roughdiffuse.commands import COMMANDS

    assert plant(tmp_path) == []
    monkeypatch.chdir(tmp_path)
    monkeypatch.syspath_prepend(str(tmp_path))  # even with the folder on sys.path
    for argv in [["--help"], *([name, "--help"] for name in COMMANDS)]:
        with pytest.raises(SystemExit) as exit_:
            cli.main(argv)
        assert exit_.value.code == 0, argv
    assert sorted(tmp_path.glob("RAN-*")) == []
    # a real, tiny benchmark run and an evaluation, in a new process started in that folder
    runs = [
        ["bench", "--sizes", "6", "--brdf-sizes", "6", "--models", "Lambert", "--repeat", "1",
         "--no-c", "--no-first-call", "--no-render", "--no-fit", "--no-simulate",
         "--memory-log2", "0", "--startup-repeat", "0", "--output-dir", "out"],
        ["eval", "--model", "oren-nayar", "--sigma", "20", "--albedo", "0.8"],
    ]  # fmt: skip
    for args in runs:
        proc = subprocess.run(
            [sys.executable, "-m", "roughdiffuse", *args],
            capture_output=True,
            text=True,
            cwd=tmp_path,
            timeout=300,
        )
        assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "out" / "RESULTS.md").is_file()
    assert sorted(p.name for p in tmp_path.glob("RAN-*")) == []


def test_bench_folder_holds_only_thin_entry_scripts():
    """The benchmark code has one home, the package (``roughdiffuse.bench``): each script in
    a checkout's bench/ only calls the ``main`` of the package module of its name."""
    scripts = sorted((ROOT / "bench").glob("*.py"))
    assert {p.stem for p in scripts} >= {"run", "smith_bench", "layered_bench", "stereo_bench"}
    for path in scripts:
        text = path.read_text(encoding="utf-8")
        assert f"from roughdiffuse.bench.{path.stem} import main" in text, path.name
        assert len(text.splitlines()) <= 30, f"{path.name} holds more than an entry point"
