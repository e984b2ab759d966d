"""The fit and stereo reports, opened in headless Chromium: their images load, their tables
have no empty column, the fit report's sections are registry ids and its ranking a table, the
stereo report's maps have labelled axes and colour bars."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import roughdiffuse as rd
from explorer_browser import browser  # noqa: F401 - fixture
from roughdiffuse import stereo
from roughdiffuse.fit import Measurements, compare_models, fit
from roughdiffuse.fit.report import write_report
from roughdiffuse.render import Sphere

READ_PAGE = """() => ({
  images: Array.from(document.images).map(i => [i.alt, i.naturalWidth, i.naturalHeight]),
  headings: Array.from(document.querySelectorAll('h2')).map(h => h.textContent),
  tables: Array.from(document.querySelectorAll('table')).map(t => ({
    cls: t.className,
    rows: Array.from(t.rows).map(r => Array.from(r.cells).map(c => c.textContent.trim())),
  })),
  text: document.body.innerText,
})"""


def _open(browser, path: Path) -> dict:  # noqa: F811
    page = browser.new_page(viewport={"width": 1280, "height": 900})
    outside: list[str] = []
    page.route("**/*", lambda r: r.continue_() if r.request.url.startswith(("file:", "data:"))
               else (outside.append(r.request.url), r.abort()))
    page.goto(path.as_uri(), wait_until="load")
    content = page.evaluate(READ_PAGE)
    page.close()
    assert not outside, outside
    return content


def _no_empty_column(table: dict) -> None:
    body = [row for row in table["rows"][1:] if row]
    for k, name in enumerate(table["rows"][0]):
        assert any(k < len(row) and row[k] for row in body), f"column {name!r} is empty"


@pytest.fixture(scope="module")
def samples() -> Measurements:
    """The full Oren–Nayar model on a grid of the plane of incidence and off it."""
    t = np.radians(np.arange(0.0, 81.0, 10.0))
    ti, tr, dp = (a.ravel() for a in np.meshgrid(t, t, np.radians([0.0, 90.0, 180.0])))
    f = rd.oren_nayar(ti, tr, dp, sigma=0.35, albedo=0.7, variant="full")
    return Measurements.from_angles(ti, tr, dp, f, source="oren-nayar-full samples")


def test_fit_report_in_chromium(browser, samples, tmp_path: Path) -> None:  # noqa: F811
    result = fit(rd.OrenNayar, samples, fixed={"variant": "full"})
    path = tmp_path / "fit.html"
    write_report(path, samples, [result])
    page = _open(browser, path)
    assert page["headings"][0] == "oren-nayar-full (Oren–Nayar full)"
    assert all(w > 800 and h > 400 for _, w, h in page["images"]), page["images"]
    (table,) = page["tables"]
    _no_empty_column(table)
    assert table["rows"][0] == ["parameter", "value", "std. error (1σ)"]


def test_fit_compare_report_in_chromium(browser, samples, tmp_path: Path) -> None:  # noqa: F811
    ids = ["oren-nayar-full", "oren-nayar", "lambert", "fujii"]
    comparison = compare_models(samples, ids)
    path = tmp_path / "compare.html"
    write_report(path, samples, list(comparison.results), comparison)
    page = _open(browser, path)
    ranking = next(t for t in page["tables"] if t["cls"] == "ranking")
    assert [row[1] for row in ranking["rows"][1:]][0] == "oren-nayar-full (Oren–Nayar full)"
    assert sorted(row[1].split()[0] for row in ranking["rows"][1:]) == sorted(ids)
    for table in page["tables"]:
        _no_empty_column(table)
    assert page["headings"][0].startswith("Models ranked by BIC")
    assert "BurleyRenormalized" not in page["text"] and "from_params" not in page["text"]
    assert len(page["images"]) == 1 and page["images"][0][1] > 800


@pytest.fixture(scope="module")
def stereo_run():
    model = rd.OrenNayar(0.7, 0.45, "full")
    data, truth = stereo.render_stereo(model, Sphere(), stereo.default_lights(6), 32)
    lam = stereo.lambertian(data)
    res = stereo.rough(data, rd.OrenNayar(0.5, 0.2, "full"), start=lam)
    normals = np.full(data.mask.shape + (3,), np.nan)
    normals[data.mask] = res.normals
    depth = stereo.integrate(normals, data.mask & np.all(np.isfinite(normals), axis=-1))
    return data, truth, res, lam, depth


@pytest.mark.slow  # the rough stereo fit compiles its Jacobian (about a minute on 2 cores)
def test_stereo_report_in_chromium(browser, stereo_run, tmp_path: Path) -> None:  # noqa: F811
    data, truth, res, lam, depth = stereo_run
    stereo.write_outputs(tmp_path, data, res, lam, depth, model_id="oren-nayar-full",
                         truth_normals=truth, extra={"truth": {"sigma": 0.45}})
    page = _open(browser, tmp_path / "report.html")
    names = [alt for alt, _, _ in page["images"]]
    assert names[0] == "the input images and their lights"
    assert {"normals", "albedo (one scale for both)", "depth",
            "relative RMS residual (one scale for both)"} <= set(names), names
    assert all(w > 300 for _, w, _ in page["images"]), page["images"]
    (table,) = page["tables"]
    _no_empty_column(table)
    assert "the true sigma of the rendered object is 0.45" in page["text"]


@pytest.mark.slow  # shares the rough stereo fit above
def test_stereo_maps_have_axes_units_and_colour_bars(stereo_run) -> None:
    from roughdiffuse.stereo import report_figures as rf
    from roughdiffuse.stereo.outputs import result_maps

    data, _, res, lam, depth = stereo_run
    maps, lmaps = result_maps(data, res), result_maps(data, lam)
    figures = [rf.inputs_figure(data),
               rf.pair_figure(maps["albedo"], lmaps["albedo"], "albedo", "fraction", "rough"),
               rf.pair_figure(maps["residual"], lmaps["residual"], "residual", "fraction",
                              "rough"),
               rf.single_figure(depth, "depth", "pixels"),
               rf.normals_figure(maps["normals"], lmaps["normals"], "rough")]
    for fig in figures:
        pictures = [ax for ax in fig.axes if ax.images and ax.get_label() != "<colorbar>"]
        assert pictures
        for ax in pictures:
            assert ax.get_xlabel() and ax.get_ylabel(), ax.get_title()
        numeric = [ax for ax in pictures if ax.images[0].get_array().ndim == 2]
        bars = [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]
        if numeric:  # colour encodes a number: a colour bar with a label and numbers on it
            assert bars and all(b.get_ylabel() for b in bars)
            assert all(len(b.get_yticks()) >= 3 for b in bars)
    shared = figures[1]  # the rough and the Lambertian albedo on one scale
    a, b = (ax.images[0].get_clim() for ax in shared.axes if ax.images and
            ax.get_label() != "<colorbar>")
    assert a == b
    assert math.isfinite(a[1])
