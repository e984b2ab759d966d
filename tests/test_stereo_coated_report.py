"""The coated fit in the stereo outputs and the benchmark: its σ and α with their standard
errors in params.json, report.html and the benchmark's tables, and their maps when fitted
per pixel. The results are made here (no fit runs), so every number shown is known."""

from __future__ import annotations

import json

import numpy as np
import pytest

from roughdiffuse.stereo import StereoInput
from roughdiffuse.stereo.benchmark import BenchmarkResult, run_benchmark, write_benchmark
from roughdiffuse.stereo.coated import CoatedResult
from roughdiffuse.stereo.lambertian import LambertianResult
from roughdiffuse.stereo.outputs import write_outputs

K, H, W = 6, 6, 7


def _data() -> StereoInput:
    rng = np.random.default_rng(2)
    lights = np.column_stack([rng.uniform(-0.4, 0.4, (K, 2)), np.ones(K)])
    mask = np.zeros((H, W), bool)
    mask[1:5, 1:6] = True
    images = rng.uniform(0.1, 0.3, (K, H, W)) * mask
    return StereoInput.from_arrays(images, lights, mask=mask)


def _coated(p: int, per_pixel: bool, coat: bool = True) -> CoatedResult:
    n = np.tile([0.0, 0.0, 1.0], (p, 1))
    sigma = np.linspace(0.3, 0.5, p) if per_pixel else 0.4
    sigma_se = np.linspace(0.01, 0.03, p) if per_pixel else 0.02
    alpha = np.linspace(0.2, 0.4, p) if per_pixel else 0.3
    alpha_se = np.linspace(0.001, 0.005, p) if per_pixel else 0.012
    return CoatedResult(
        normals=n, albedo=np.full((p, 1), 0.6), roughness=sigma, roughness_name="sigma",
        roughness_se=sigma_se, normal_se=np.full(p, 0.01), albedo_se=np.full((p, 1), 0.01),
        residual=np.full(p, 0.02), weights=np.ones((K, p)), iterations=5,
        alpha=alpha if coat else np.nan, alpha_se=alpha_se if coat else np.nan, eta=1.5,
        coat=coat,
    )


@pytest.fixture(autouse=True)
def _undrawn(monkeypatch):
    """The report's figures are built but not drawn (drawing takes seconds; what is drawn
    is looked at, not tested)."""
    from roughdiffuse.stereo import report_figures

    monkeypatch.setattr(report_figures, "_png", lambda fig: b"PNG")


def _write(tmp_path, res: CoatedResult) -> tuple[dict, str]:
    data = _data()
    p = int(data.mask.sum())
    lam = LambertianResult(res.normals, res.albedo, res.residual, res.weights)
    depth = np.where(data.mask, 0.0, np.nan)
    params = write_outputs(tmp_path, data, res, lam, depth, model_id="coated")
    assert params["pixels"] == p
    return params, (tmp_path / "report.html").read_text()


def test_one_sigma_and_alpha_are_shown_with_their_errors(tmp_path):
    params, page = _write(tmp_path, _coated(20, per_pixel=False))
    assert params["coat"]["alpha"] == {"per_pixel": False, "value": 0.3, "standard_error": 0.012}
    assert params["roughness"]["value"] == 0.4 and params["roughness"]["standard_error"] == 0.02
    assert "sigma = 0.4 ± 0.02 (one for the object)" in page
    assert "coat α = 0.3 ± 0.012 (one for the object), η = 1.5 (fixed)" in page
    assert "coated model" in page
    assert not (tmp_path / "alpha.exr").exists()  # one value: no map


def test_per_pixel_sigma_and_alpha_get_maps_with_their_errors(tmp_path):
    res = _coated(20, per_pixel=True)
    params, page = _write(tmp_path, res)
    a = params["coat"]["alpha"]
    assert a["per_pixel"] and a["median"] == pytest.approx(0.3)  # median of 0.2..0.4
    assert a["median_standard_error"] == pytest.approx(0.003)
    assert "coat α per pixel: median 0.3 (median standard error 0.003)" in page
    for name in ("sigma", "alpha"):
        assert f"{name} per pixel, with its standard error" in page
        for key in (name, f"{name}_se"):
            assert (tmp_path / f"{key}.exr").is_file() and (tmp_path / f"{key}.png").is_file()


def test_a_coat_that_explains_nothing_is_said_so(tmp_path):
    params, page = _write(tmp_path, _coated(20, per_pixel=False, coat=False))
    assert params["coat"]["alpha"] is None
    assert params["coat"]["coat_explains_the_images"] is False
    assert "no coat: a coat does not fit these images better than the bare base" in page


def test_benchmark_tables_hold_the_fitted_sigma_and_alpha(tmp_path, monkeypatch):
    """run_benchmark keeps each fitting method's σ and α ± standard error per object; the
    JSON and the report show them, "–" where no coat was fitted."""
    from roughdiffuse.stereo import methods
    from test_stereo_benchmark import write_folder

    write_folder(tmp_path, {"pot1": (6, 7, 0.8), "bear": (7, 6, 0.6)})
    coats = {}

    def fake(data, *, progress=False):  # a coat on pot1, none on bear
        p = int(data.mask.sum())
        coats[p] = not coats
        return _coated(p, per_pixel=False, coat=coats[p])

    monkeypatch.setitem(methods.METHODS, "coated", fake)
    result = run_benchmark(tmp_path, ["lambertian", "coated"], keep_details=False)
    (tmp_path / "out").mkdir()
    write_benchmark(tmp_path / "out", result)
    table = json.loads((tmp_path / "out" / "benchmark.json").read_text())
    assert "lambertian" not in table["fitted"]
    got = table["fitted"]["coated"]
    assert got["pot1"] == {"sigma": {"value": 0.4, "standard_error": 0.02},
                           "alpha": {"value": 0.3, "standard_error": 0.012}}
    assert got["bear"] == {"sigma": {"value": 0.4, "standard_error": 0.02}}
    rows = result.fitted_rows()
    assert rows == [["method", "parameter", "pot1", "bear"],
                    ["coated", "sigma", "0.400 ± 0.020", "0.400 ± 0.020"],
                    ["coated", "alpha", "0.300 ± 0.012", "–"]]
    page = (tmp_path / "out" / "report.html").read_text()
    assert "Fitted parameters" in page and "0.300 ± 0.012" in page


def test_no_fitted_table_without_a_fitting_method():
    assert BenchmarkResult(["a"], ["lambertian"], {"lambertian": {"a": 1.0}}, {}).fitted_rows() \
        == []
