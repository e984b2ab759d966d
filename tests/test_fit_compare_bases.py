"""``fit --compare`` ranks ``coated`` once over each of its bases: one row per base, named
``coated base=ID`` in the table, the JSON and the report; on data made by a coat over a
rough base, that base ranks above a coat over Lambert."""

from __future__ import annotations

import json

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import registry
from roughdiffuse.cli import main
from roughdiffuse.fit import Measurements, compare_models
from roughdiffuse.fit.compare import Comparison, fitted_row, rows
from roughdiffuse.fit.summary import row_name
from roughdiffuse.models.coated import COAT_BASES

COATED_ROWS = [f"coated base={b}" for b in COAT_BASES]


def test_rows_are_the_choices_that_decide_the_parameters() -> None:
    # coated's base decides which parameters exist (σ, r or neither): one row per base
    assert [r["base"] for r in rows("coated")] == list(registry.get("coated").param("base").choices)
    # a choice no parameter depends on (the facet distribution) stays at its default
    assert all(set(r) == {"base"} for r in rows("coated"))
    assert rows("lambert") == [{}] and rows("mix") == [{}]
    assert row_name("coated", {"base": "eon"}) == "coated base=eon"
    assert row_name("lambert") == row_name("lambert", {}) == "lambert"


def test_a_fitted_coat_names_its_base() -> None:
    assert fitted_row(rd.Coated(rd.EON(0.5, 0.2))) == ("coated", {"base": "eon"})
    assert fitted_row(rd.Coated(rd.Lambert(0.5))) == ("coated", {"base": "lambert"})
    assert fitted_row(rd.Coated(rd.OrenNayar(0.5, 0.2, "full"))) == (
        "coated", {"base": "oren-nayar-full"})
    assert fitted_row(rd.OrenNayar(0.5, 0.2)) == ("oren-nayar", {})


def _coat_samples(path, base: rd.Model, n: int = 60, seed: int = 3) -> None:  # noqa: ANN001
    """A CSV of a coat (η = 1.5, α = 0.2) over ``base`` with 0.5 % noise."""
    rng = np.random.default_rng(seed)
    ti, tr, dp = rng.uniform(0, 75, n), rng.uniform(0, 75, n), rng.uniform(0, 180, n)
    wi = rd.spherical_to_vector(np.radians(ti), 0.0)
    wo = rd.spherical_to_vector(np.radians(tr), np.radians(dp))
    f = np.asarray(rd.Coated(base, eta=1.5, roughness=0.2).brdf(wi, wo))
    f = f * (1 + 0.005 * rng.standard_normal(n))
    lines = "".join(f"{a},{b},{c},{v}\n" for a, b, c, v in zip(ti, tr, dp, f, strict=True))
    path.write_text("theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n" + lines)


@pytest.mark.slow  # five Coated fits, each compiling its base's model: 3 CPU-minutes
def test_cli_ranks_each_base_and_the_true_one_above_lambert(tmp_path, capsys) -> None:  # noqa: ANN001
    data = tmp_path / "coat.csv"
    _coat_samples(data, rd.OrenNayar(0.7, 0.7, "full"))
    report = tmp_path / "r.html"
    assert main(["fit", str(data), "--compare", "--models", "coated", "--json",
                 "--report", str(report)]) == 0
    fits = json.loads(capsys.readouterr().out)["fits"]
    assert sorted(f["label"] for f in fits) == sorted(COATED_ROWS)
    assert all(f["model"] == "coated" and f["label"] == row_name("coated", f["choices"])
               for f in fits)
    order = [f["choices"]["base"] for f in fits]
    # the base the data were made with fits them to their noise; Lambert (no σ) cannot
    assert order.index("oren-nayar-full") < order.index("lambert")
    best = fits[order.index("oren-nayar-full")]
    assert best["rms_relative"] < 0.01
    assert fits[order.index("lambert")]["rms_relative"] > 2 * best["rms_relative"]
    # each base's own parameters: σ over Oren–Nayar, r over EON, neither over Lambert
    names = {f["choices"]["base"]: f["names"] for f in fits}
    assert "sigma" in names["oren-nayar-full"] and "base_roughness" not in names["oren-nayar-full"]
    assert "base_roughness" in names["eon"] and "sigma" not in names["eon"]
    assert "sigma" not in names["lambert"] and "base_roughness" not in names["lambert"]
    # the report's ranking and sections name the base
    html = report.read_text()
    for label in COATED_ROWS:
        assert f"<td>{label} (" in html
    assert "<h2>coated base=" in html


def test_table_widens_for_the_rows_names() -> None:
    """The table's model column holds the longest row name (``coated base=oren-nayar-full``)
    with the numbers still in their columns."""
    rng = np.random.default_rng(5)
    ti, tr, dp = rng.uniform(0, 1.3, 40), rng.uniform(0, 1.3, 40), rng.uniform(0, np.pi, 40)
    f = np.asarray(rd.Lambert(0.5).brdf(rd.spherical_to_vector(ti, 0.0),
                                        rd.spherical_to_vector(tr, dp)))
    r = compare_models(Measurements.from_angles(ti, tr, dp, f), ["lambert"]).results[0]
    long = "coated base=oren-nayar-full"
    c = Comparison((long, "lambert"), (r, r), ("coated", "lambert"),
                   ({"base": "oren-nayar-full"}, {}))
    head, first, second = c.table().splitlines()
    assert f" {long} " in first and second.split()[1] == "lambert"
    # the RMS column starts at the same place in every line
    assert head.index("RMS") + 3 == first.index(f"{r.rms:.4g}") + len(f"{r.rms:.4g}")
    assert Comparison(("lambert",), (r,)).ids == ("lambert",)  # by hand: names are ids


def test_explorer_fit_takes_the_slots_menus_and_refuses_bad_ones_by_name() -> None:
    from importlib import resources

    from roughdiffuse.explorer.datasets import DatasetStore, fit_model, parse_upload

    samples = resources.files("roughdiffuse.data") / "samples.csv"
    ds = parse_upload("csv", "samples.csv", samples.read_bytes(), DatasetStore())
    with pytest.raises(ValueError, match="base must be one of"):
        fit_model(ds, "coated", {"base": "phong"})
    with pytest.raises(ValueError, match="has no parameter 'colour'"):
        fit_model(ds, "coated", {"colour": "red"})
    with pytest.raises(ValueError, match="choices must map"):
        fit_model(ds, "coated", ["eon"])
    r = fit_model(ds, "lambert", {})
    assert r["model"] == r["label"] == "lambert" and r["choices"] == {}
