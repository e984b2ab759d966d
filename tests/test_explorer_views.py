"""The explorer's views, URL state, export, ground-truth switch and layout.

Headless Chromium through Playwright (fixtures in explorer_browser.py). Reference values come
from the Python models (roughdiffuse.models), never from the page's JavaScript: the page's
BRDF values are the GLSL printed from the Python models, held to them to 1e-4 relative by
tests/test_explorer_glsl.py, and float32 on the GPU, so the tolerances below are 2e-4 relative.
"""

from __future__ import annotations

import csv
import io
import math
import re

import numpy as np
import pytest
from PIL import Image

from explorer_browser import frames, open_page
from roughdiffuse import OrenNayar

VIEWS = ("plane", "polar", "lobe", "albedo", "slice")
CANVAS = {"plane": "plot-cartesian"} | {v: f"plot-{v}" for v in VIEWS[1:]}


@pytest.fixture()
def page(browser, explorer_url):  # noqa: F811 - fixtures
    log = open_page(browser, explorer_url, 1280, 720)
    yield log
    log.page.close()


def canvas_rgb(p, canvas_id: str) -> np.ndarray:
    import base64

    url = p.evaluate(f"() => document.getElementById('{canvas_id}').toDataURL('image/png')")
    data = base64.b64decode(url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), dtype=np.int32)


def coloured_pixels(img: np.ndarray) -> int:
    """Pixels that are neither white nor grey: curves, wireframes, colour maps."""
    spread = img.max(axis=-1) - img.min(axis=-1)
    return int((spread > 40).sum())


def show_view(p, view: str) -> None:
    p.click(f"#view-tabs button[data-view={view}]")
    p.wait_for_function(f"() => document.body.dataset.view === '{view}'")
    frames(p)


def set_model(p, slot: str, model: str, **sliders: float) -> None:
    p.select_option(f"#{slot}-model", model)
    for name, value in sliders.items():
        p.locator(f"#{slot}-{name}").fill(str(value))
    frames(p)


def rows_of(p, view: str, series_prefix: str) -> list[list[float]]:
    rows = p.evaluate(f"() => window.rdExplorer.tables()['{view}'].rows")
    return [r[1:] for r in rows if r[0].startswith(series_prefix)]


def test_each_view_draws_reads_out_and_takes_log_scale(page):
    p = page.page
    p.select_option("#mode", "1")
    for view in VIEWS:
        show_view(p, view)
        canvas = p.locator(f"#{CANVAS[view]}")
        assert canvas.is_visible(), view
        assert coloured_pixels(canvas_rgb(p, CANVAS[view])) > 500, view
        box = canvas.bounding_box()
        p.mouse.move(box["x"] + 0.45 * box["width"], box["y"] + 0.6 * box["height"])
        text = p.locator("#readout").inner_text()
        if view == "lobe":
            assert "drag" in text
        else:
            assert re.search(r"\d\.\d{3}", text), (view, text)
    # the log scale redraws the plane, polar and albedo plots with other pixels
    for view in ("plane", "polar", "albedo"):
        show_view(p, view)
        linear = canvas_rgb(p, CANVAS[view])
        p.check("#log-scale")
        frames(p)
        logged = canvas_rgb(p, CANVAS[view])
        p.uncheck("#log-scale")
        frames(p)
        assert np.abs(linear - logged).sum(axis=-1).astype(bool).sum() > 500, view
    assert not page.errors, page.errors


def test_albedo_view_is_the_python_directional_albedo(page):
    """Lambert: a = ρ at every θo (exactly, for the midpoint rule); full Oren–Nayar: the Python
    model's Gauss–Legendre directional_albedo, to the midpoint rule's error: O(1/N²) with
    N = 48 nodes per axis, about 4e-4 for a smooth f, more where f has its kink (θi = θo) and
    its grazing rise; 2e-3 allowed."""
    p = page.page
    set_model(p, "a", "lambert", **{"albedo-g": 0.5})
    show_view(p, "albedo")
    rows = np.array(rows_of(p, "albedo", "A:"))
    np.testing.assert_allclose(rows[:, 1], 0.5, rtol=2e-4)
    set_model(p, "a", "oren-nayar-full", sigma=30, **{"albedo-g": 0.8})
    rows = np.array(rows_of(p, "albedo", "A:"))
    model = OrenNayar(albedo=0.8, sigma=math.radians(30), variant="full")
    t = np.radians(rows[:, 0])
    wo = np.stack([np.sin(t), np.zeros_like(t), np.cos(t)], axis=-1)
    expected = np.asarray(model.directional_albedo(wo)).reshape(len(t), -1).mean(axis=-1)
    np.testing.assert_allclose(rows[:, 1], expected, rtol=2e-3)
    assert not page.errors, page.errors


def test_url_state_round_trips(page, browser):  # noqa: F811 - fixture
    p = page.page
    set_model(p, "a", "eon", roughness=0.7)
    set_model(p, "b", "oren-nayar", sigma=35)
    p.select_option("#mode", "2")
    p.locator("#light-theta").fill("40")
    p.locator("#light-phi").fill("20")
    p.locator("#exposure").fill("1.5")
    show_view(p, "albedo")
    p.check("#log-scale")
    # the data slice (data.js), set as its controls would be: Δφ = 30°, the green channel
    p.evaluate(
        """() => {
            const set = (id, v, type) => {
                const el = document.getElementById(id);
                el.value = v;
                el.dispatchEvent(new Event(type, { bubbles: true }));
            };
            set("data-dphi", "30", "input");
            set("data-channel", "1", "change");
        }"""
    )
    frames(p)
    keys = "({a, b, mode, light, exposure, view}) => ({a, b, mode, light, exposure, view})"
    before = p.evaluate(f"() => ({keys})(window.rdExplorer.state)")
    url = p.url
    assert "#" in url
    other = open_page(browser, url, 1280, 720)
    q = other.page
    frames(q)
    after = q.evaluate(f"() => ({keys})(window.rdExplorer.state)")
    for k, v in before.items():
        if isinstance(v, dict):
            diff = {n: (x, after[k].get(n)) for n, x in v.items() if after[k].get(n) != x}
            assert not diff, (k, diff)
    assert after == before
    assert before["a"]["model"] == "eon" and before["light"] == {"theta": 40, "phi": 20}
    assert q.locator("#a-model").input_value() == "eon"
    assert q.locator("#a-roughness").input_value() == "0.7"
    assert q.locator("#mode").input_value() == "2"
    assert q.locator("#log-scale").is_checked()
    assert q.locator("#data-dphi").input_value() == "30"
    assert q.locator("#data-channel").input_value() == "1"
    assert q.evaluate("() => document.body.dataset.view") == "albedo"
    assert not other.errors, other.errors
    q.close()
    # a damaged hash is ignored value by value: the page still loads
    bad = open_page(browser, url.split("#")[0] + '#a={"model":"nope"}&light=x,1&mode=7', 1280, 720)
    assert bad.page.evaluate("() => window.rdExplorer.state.a.model") == "oren-nayar-full"
    assert not bad.errors, bad.errors
    bad.page.close()
    assert not page.errors, page.errors


def test_export_png_and_csv_of_the_plane_plot(page, tmp_path):
    p = page.page
    set_model(p, "a", "oren-nayar-full", sigma=20, **{"albedo-g": 0.5})
    p.locator("#light-theta").fill("30")
    frames(p)
    with p.expect_download() as d:
        p.click("#export-png")
    png = tmp_path / "plot.png"
    d.value.save_as(png)
    img = Image.open(png)
    w, h = p.evaluate(
        "() => ['width', 'height'].map(k => document.getElementById('plot-cartesian')[k])"
    )
    assert img.format == "PNG" and img.size == (2 * w, 2 * h)  # twice the resolution on screen
    assert coloured_pixels(np.asarray(img.convert("RGB"), dtype=np.int32)) > 300
    with p.expect_download() as d:
        p.click("#export-csv")
    assert d.value.suggested_filename.endswith(".csv")
    path = tmp_path / "plot.csv"
    d.value.save_as(path)
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    assert rows[0] == ["series", "theta_r_deg", "radiance"]
    a = np.array([[float(v) for v in r[1:]] for r in rows[1:] if r[0].startswith("A:")])
    assert len(a) == 181
    # reference: the Python model, L = f E0 cos θi with E0 = π (θr > 0 on the light's side)
    ti, tr = math.radians(30), np.radians(a[:, 0])
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.stack([np.sin(tr), np.zeros_like(tr), np.cos(tr)], axis=-1)
    model = OrenNayar(albedo=0.5, sigma=math.radians(20), variant="full")
    f = np.asarray(model.brdf(wi, wo)).reshape(len(tr), -1).mean(axis=-1)
    expected = f * math.pi * math.cos(ti)
    inside = np.abs(a[:, 0]) < 90  # at ±90° the view is on the horizon: L is 0 or its limit
    np.testing.assert_allclose(a[inside, 1], expected[inside], rtol=2e-4, atol=1e-6)
    assert not page.errors, page.errors


def gt_curve(p, bounces: str) -> np.ndarray:
    p.check(f"#gt-bounces-{bounces}")
    word = "one bounce" if bounces == "1" else "all bounces"
    p.wait_for_function(
        f"() => document.getElementById('gt-status').textContent.includes('{word}')",
        timeout=60_000,
    )
    frames(p)
    return np.array(rows_of(p, "plane", "V-cavity"))


def test_ground_truth_one_bounce_below_all_bounces(page):
    """Interreflection only adds light: the all-bounce curve is above the one-bounce curve,
    and by more than the solver's tolerance where the cavities are deep (σ = 30°)."""
    p = page.page
    assert p.locator("#a-model").input_value() == "oren-nayar-full"  # the fair default
    set_model(p, "a", "oren-nayar-full", sigma=30, **{"albedo-g": 0.9})
    p.locator("#light-theta").fill("30")
    p.check("#gt-show")
    one = gt_curve(p, "1")
    every = gt_curve(p, "all")
    assert len(one) == len(every) == 45
    np.testing.assert_array_equal(one[:, 0], every[:, 0])
    assert np.all(every[:, 1] >= one[:, 1] * (1 - 1e-3))
    assert np.mean(every[:, 1] / one[:, 1]) > 1.05
    assert not page.errors, page.errors


def test_preset_turns_custom_when_a_parameter_or_the_light_moves(page):
    p = page.page
    for preset, move in (("full-moon", "#light-theta"), ("on-vs-lambert", "#a-sigma")):
        p.select_option("#preset", preset)
        frames(p)
        assert p.locator("#preset").input_value() == preset
        p.locator(move).fill("45")
        frames(p)
        assert p.locator("#preset").input_value() == "custom", move
    assert not page.errors, page.errors


def test_layout_keeps_status_errors_and_data_in_view(page):
    """At 1280 x 720, then with the window resized to 1920 x 1080 (one page: each page load
    costs seconds of SwiftShader shader compilation)."""
    for size in ((1280, 720), (1920, 1080)):
        page.page.set_viewport_size({"width": size[0], "height": size[1]})
        _layout_in_view(page, *size)


def _layout_in_view(log, w: int, h: int) -> None:
    p = log.page
    p.select_option("#mode", "1")
    show = "{hidden: false, textContent: 'x'}"
    p.evaluate(f"() => Object.assign(document.getElementById('error'), {show})")
    p.evaluate("() => { document.getElementById('gt-status').textContent = 'status'; }")
    frames(p)
    # measured data loaded: the data panel grows by its slice controls and the fit buttons
    p.evaluate(
        """(text) => {
            const dt = new DataTransfer();
            dt.items.add(new File([text], "samples.csv", { type: "text/csv" }));
            document.getElementById("dropzone").dispatchEvent(
                new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
        }""",
        "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n"
        + "".join(f"30,{t},{d},0.2\n" for t in range(0, 90, 5) for d in (0, 180)),
    )
    p.wait_for_function("() => document.body.dataset.csvScatter !== undefined")
    frames(p)
    ids = ["error", "light-readout", "gt-status", "readout", "data-status", "dropzone", "label-a",
           "label-b", "export-csv", "data", "data-controls", "fit-panel", "tab-scatter"]
    for el in ids:
        box = p.locator(f"#{el}").bounding_box()
        assert box is not None, el
        assert box["x"] >= 0 and box["y"] >= 0, el
        assert box["x"] + box["width"] <= w and box["y"] + box["height"] <= h, (el, box)
    # the labels sit on the two spheres, A on the left
    a, b = (p.locator(f"#label-{s}").bounding_box() for s in "ab")
    assert a["x"] < b["x"]
    p.select_option("#mode", "2")
    frames(p)
    box = p.locator("#diff-legend").bounding_box()
    assert box["y"] + box["height"] <= h
    assert "A brighter" in p.locator("#diff-hi").inner_text()
    assert p.locator("#label-a").is_hidden()
    assert not log.errors, log.errors
