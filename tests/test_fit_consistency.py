"""One fit everywhere: Python's ``fit()``, ``roughdiffuse fit --json`` and the explorer's
``/api/fit`` and ``/api/rank`` give the same numbers and the same ranking on the shipped
samples, with the same default noise model and the same "at bound" rule."""

from __future__ import annotations

import dataclasses
import json
import math
from importlib import resources

import numpy as np
import pytest

from roughdiffuse.cli import main
from roughdiffuse.explorer.datasets import DatasetStore, fit_model, parse_upload, rank_models
from roughdiffuse.fit import CANDIDATES, Measurements, compare_models, fit, read_csv
from roughdiffuse.fit.summary import AT_BOUND, NOT_DETERMINED, error_notes, result_json

SAMPLES = resources.files("roughdiffuse.data") / "samples.csv"
TRUTH = {"albedo": 0.7, "sigma": 0.35}  # the file's header: how scripts/make_sample_data.py made it
RANKED = ("lambert", "oren-nayar", "oren-nayar-full")


@pytest.fixture(scope="module")
def data() -> Measurements:
    return read_csv(str(SAMPLES))


@pytest.fixture(scope="module")
def python_fit(data):  # noqa: ANN001, ANN201
    c = CANDIDATES["oren-nayar-full"]
    return fit(c.model, data, c.params, c.bounds, fixed=c.fixed)


def _cli_json(capsys, *args: str) -> dict:  # noqa: ANN001
    assert main(["fit", str(SAMPLES), "--json", *args]) == 0
    return json.loads(capsys.readouterr().out)


def test_default_noise_is_relative_and_recovers_truth(python_fit) -> None:  # noqa: ANN001
    assert python_fit.noise == "relative"
    for name, truth in TRUTH.items():  # 1 % noise: within 3 standard errors of the truth
        k = python_fit.names.index(name)
        assert abs(python_fit.values[k] - truth) < 3 * python_fit.errors[k]


def test_python_cli_explorer_same_fit(python_fit, capsys) -> None:  # noqa: ANN001
    cli = _cli_json(capsys, "--model", "oren-nayar-full")["fits"][0]
    ds = parse_upload("csv", "samples.csv", SAMPLES.read_bytes(), DatasetStore())
    web = fit_model(ds, "oren-nayar-full")
    assert cli["noise"] == web["noise"] == "relative"
    for k in range(len(python_fit.names)):
        v, e = python_fit.values[k], python_fit.errors[k]
        assert cli["values"][k] == pytest.approx(v, rel=1e-9)
        assert web["values"][k] == pytest.approx(v, rel=1e-9)
        assert cli["errors"][k] == pytest.approx(e, rel=1e-6)
        assert web["errors"][k] == pytest.approx(e, rel=1e-6)
    assert cli["bic"] == pytest.approx(python_fit.bic, abs=1e-6)
    assert web["bic"] == pytest.approx(python_fit.bic, abs=1e-6)


def test_python_cli_explorer_same_ranking(data, capsys) -> None:  # noqa: ANN001
    py = compare_models(data, list(RANKED))
    cli = _cli_json(capsys, "--compare", "--models", ",".join(RANKED))["fits"]
    ds = parse_upload("csv", "samples.csv", SAMPLES.read_bytes(), DatasetStore())
    web = [rank_models(ds, [m])["ranking"][0] for m in RANKED]  # the page asks one at a time
    web.sort(key=lambda r: r["bic"])
    assert py.best == "oren-nayar-full"  # the model the samples were made with
    assert [f["model"] for f in cli] == list(py.names) == [r["model"] for r in web]
    for a, b, r in zip(cli, web, py.results, strict=True):
        assert a["bic"] == pytest.approx(r.bic, abs=1e-6)
        assert b["bic"] == pytest.approx(r.bic, abs=1e-6)


def test_at_bound_and_undetermined_errors(data) -> None:  # noqa: ANN001
    # the samples have σ ≈ 0.35 rad: an upper bound of 0.2 rad stops σ there
    c = CANDIDATES["oren-nayar-full"]
    r = fit(c.model, data, c.params, {"sigma": (0.0, 0.2)}, fixed=c.fixed)
    k = r.names.index("sigma")
    assert r.values[k] == pytest.approx(0.2)
    assert error_notes(r)[k] == AT_BOUND
    out = result_json("oren-nayar-full", r)
    assert out["errors"][k] is None and out["error_notes"][k] == AT_BOUND
    assert "at bound" in r.table()
    # an error wider than the whole box (Hapke's h ± 3e28), or inf / nan: not determined
    j = r.names.index("albedo")
    for bad in (3e28, math.inf, math.nan):
        errors = np.array(r.errors)
        errors[j] = bad
        broken = dataclasses.replace(r, errors=errors)
        assert error_notes(broken)[j] == NOT_DETERMINED
        assert result_json("x", broken)["errors"][j] is None
        assert NOT_DETERMINED in broken.table()
