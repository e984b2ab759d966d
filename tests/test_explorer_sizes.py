"""The explorer at 1280 × 720 and 1920 × 1080: plots that grow with the window, the rank
table without an inner scroll box, presets clear of the model controls, the light moved by
loading data said so, a hover readout that follows the light, the θh/θd map on log scale,
exports (PNG at 2x, SVG with the legend off the data, names for A and B), a short URL that
old links still load, a loading indicator. Headless Chromium (fixtures in explorer_browser.py).
"""

from __future__ import annotations

import io
import json
import re
import urllib.parse
import xml.etree.ElementTree as ET

import pytest
from PIL import Image

from explorer_browser import frames, open_page

SIZES = [(1280, 720), (1920, 1080)]
CSV = "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n" + "".join(
    f"40,{t},{d},0.2\n" for t in range(0, 90, 5) for d in (0, 180)
)


def drop_csv(p, text: str = CSV) -> None:
    p.evaluate(
        """(text) => {
            const dt = new DataTransfer();
            dt.items.add(new File([text], "samples.csv", { type: "text/csv" }));
            document.getElementById("dropzone").dispatchEvent(
                new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
        }""",
        text,
    )
    p.wait_for_function("() => document.body.dataset.csvScatter !== undefined")
    frames(p)


def overlap(a: dict, b: dict) -> bool:
    return not (
        a["x"] + a["width"] <= b["x"]
        or b["x"] + b["width"] <= a["x"]
        or a["y"] + a["height"] <= b["y"]
        or b["y"] + b["height"] <= a["y"]
    )


@pytest.fixture()
def page(browser, explorer_url):
    log = open_page(browser, explorer_url, 1280, 720)
    yield log
    log.page.close()


def test_plots_grow_with_the_window(page):
    """At each of SIZES in turn, the window resized (one page: each page load costs seconds
    of SwiftShader shader compilation)."""
    for w, h in SIZES:
        page.page.set_viewport_size({"width": w, "height": h})
        _plots_fill(page, w, h)


def _plots_fill(log, w: int, h: int) -> None:
    p = log.page
    p.select_option("#mode", "1")
    frames(p)
    plot = p.locator("#plot-cartesian").bounding_box()
    column = p.locator("#plots").bounding_box()
    canvas = p.evaluate("() => [document.getElementById('plot-cartesian').width, "
                        "document.getElementById('plot-cartesian').height]")  # fmt: skip
    assert plot["width"] >= (700 if w >= 1920 else 500), plot
    # drawn at about its size on screen (main.js resizes for changes of 24 px or more)
    assert abs(canvas[0] - plot["width"]) < 24
    # no half-empty screen: the plots column reaches the window's right edge
    assert column["x"] + column["width"] >= w - 40
    assert plot["y"] + plot["height"] <= h
    # the presets and the header stay clear of the model controls
    header = p.locator("header").bounding_box()
    for el in ("#preset", "#mode", "#exposure"):
        box = p.locator(el).bounding_box()
        assert not overlap(box, p.locator("#panel-a").bounding_box()), el
        assert box["y"] + box["height"] <= header["y"] + header["height"]
    assert header["y"] + header["height"] <= p.locator("#panel-a").bounding_box()["y"]
    # the sphere grows with its column too (it stopped at its 480 px canvas), undistorted
    # and drawn at its size on screen: one sphere, then A and B side by side
    for mode, n in (("0", 1), ("1", 2)):
        p.select_option("#mode", mode)
        frames(p)
        view = p.locator("#view").bounding_box()
        box = p.locator("#sphere").bounding_box()
        buffer = p.evaluate("() => [document.getElementById('sphere').width, "
                            "document.getElementById('sphere').height]")  # fmt: skip
        side = min(view["width"] / n, h - 430)
        assert box["width"] <= view["width"] + 1 and box["height"] >= side - 2, (mode, box)
        assert abs(box["width"] - n * box["height"]) <= 2, (mode, box)
        assert abs(buffer[0] - box["width"]) <= 2 and abs(buffer[1] - box["height"]) <= 2
    if w >= 1920:
        assert p.locator("#sphere").bounding_box()["width"] >= 600
    # no half-empty screen: the sphere's column or the plots' reach most of the way down
    low = max(p.locator(s).bounding_box()["y"] + p.locator(s).bounding_box()["height"]
              for s in ("#view", "#plots"))  # fmt: skip
    assert low >= 0.7 * h, low
    assert not log.errors, log.errors


def test_rank_table_shows_eight_rows_without_an_inner_scroll_box(page):
    p = page.page
    drop_csv(p)
    p.evaluate(
        """() => {
            const t = document.getElementById("rank-table");
            t.innerHTML = "<tr><th>#</th><th>model</th><th>ΔBIC</th></tr>" +
                Array.from({length: 12}, (_, k) =>
                    `<tr><td>${k + 1}</td><td>m${k}</td><td>${k}</td></tr>`).join("");
        }"""
    )
    box = p.evaluate(
        """() => { const t = document.getElementById("rank-table");
                   const s = getComputedStyle(t);
                   const shown = [...t.rows].filter(r => r.getBoundingClientRect().height > 0);
                   return {client: t.clientHeight, scroll: t.scrollHeight,
                           overflow: s.overflowY, rows: shown.length}; }"""
    )
    assert box["overflow"] not in ("auto", "scroll")
    assert box["scroll"] <= box["client"] + 1 and box["rows"] >= 9  # header + 8 or more


def test_loading_data_that_moves_the_light_says_so(page):
    p = page.page
    assert p.evaluate("() => window.rdExplorer.state.light.theta") == 0
    drop_csv(p)
    assert p.evaluate("() => window.rdExplorer.state.light.theta") == pytest.approx(40)
    status = p.locator("#data-status").inner_text()
    assert "The light moved from θ = 0.0° to 40.0°" in status
    assert not page.errors, page.errors


def test_hover_readout_follows_light_and_model(page):
    p = page.page
    box = p.locator("#plot-cartesian").bounding_box()
    p.mouse.move(box["x"] + 0.5 * box["width"], box["y"] + 0.6 * box["height"])
    first = p.locator("#readout").inner_text()
    assert first.startswith("θr =")
    p.locator("#light-theta").fill("50")
    frames(p)
    second = p.locator("#readout").inner_text()
    assert second != first and second.startswith("θr =")
    p.select_option("#a-model", "lambert")
    frames(p)
    third = p.locator("#readout").inner_text()
    assert third != second
    assert not page.errors, page.errors


def test_slice_opens_on_log_scale(page):
    p = page.page
    assert not p.locator("#log-scale").is_checked()  # the plane of incidence: linear
    p.click("#view-tabs button[data-view=slice]")
    p.wait_for_function("() => document.body.dataset.view === 'slice'")
    frames(p)
    assert p.locator("#log-scale").is_checked()
    p.click("#view-tabs button[data-view=plane]")
    frames(p)
    assert not p.locator("#log-scale").is_checked()


def test_export_png_2x_svg_legend_off_data_and_names(page, tmp_path):
    p = page.page
    p.select_option("#mode", "1")
    p.select_option("#a-model", "oren-nayar")
    p.select_option("#b-model", "oren-nayar")
    p.locator("#a-sigma").fill("30")
    p.locator("#b-sigma").fill("10")
    frames(p)
    size = p.evaluate("() => { const c = document.getElementById('plot-cartesian'); "
                      "return [c.width, c.height]; }")  # fmt: skip
    with p.expect_download() as d:
        p.click("#export-png")
    assert d.value.suggested_filename == "roughdiffuse-plane-A-oren-nayar-B-oren-nayar.png"
    img = Image.open(io.BytesIO(open(d.value.path(), "rb").read()))
    assert img.size == (2 * size[0], 2 * size[1])
    with p.expect_download() as d:
        p.click("#export-svg")
    assert d.value.suggested_filename.endswith(".svg")
    root = ET.fromstring(open(d.value.path(), encoding="utf-8").read())
    ns = "{http://www.w3.org/2000/svg}"
    assert root.tag == f"{ns}svg" and root.get("width") == str(size[0])
    texts = {t.text: t for t in root.iter(f"{ns}text")}
    labels = [k for k in texts if k and re.match(r"[AB]: ", k)]
    # A and B are one model: the labels say what tells them apart
    assert sorted(labels) == [
        "A: Oren–Nayar qualitative, σ = 30.0°",
        "B: Oren–Nayar qualitative, σ = 10.0°",
    ], labels
    # the two curves, 181 points each (θr = -90°, ..., 90°), in A's and B's colours
    for colour in ("#1f5fa8", "#d35400"):
        curves = [
            e
            for e in root.iter(f"{ns}path")
            if e.get("stroke") == colour and e.get("d").count("L") >= 180
        ]
        assert curves, colour
    plot = p.evaluate(
        "() => { const r = document.getElementById('plot-cartesian').rdPlot; "
        "return {left: r.left, right: r.right, top: r.top, bottom: r.bottom}; }"
    )
    for label in labels:  # legend text beside the plot area or above it, never on the data
        x, y = float(texts[label].get("x")), float(texts[label].get("y"))
        assert x >= plot["right"] or y <= plot["top"], (label, x, y, plot)
    assert not page.errors, page.errors


def test_url_is_short_and_old_links_load(page, browser):  # noqa: F811
    p = page.page
    p.select_option("#a-model", "eon")
    p.locator("#a-roughness").fill("0.7")
    p.select_option("#mode", "1")
    p.locator("#light-theta").fill("40")
    frames(p)
    hash_ = p.url.split("#", 1)[1]
    assert len(hash_) < 160, hash_
    assert "%" not in hash_  # nothing URL-encoded
    before = p.evaluate("() => window.rdExplorer.state")
    base = p.url.split("#")[0]
    # a link in the old form: URL-encoded JSON of each slot and of the view options
    old = urllib.parse.urlencode(
        {
            "a": json.dumps(before["a"]),
            "b": json.dumps(before["b"]),
            "mode": "1",
            "light": "40,0",
            "exposure": "0",
            "view": json.dumps({"tab": "plane", "log": False}),
        }
    )
    for url in (p.url, f"{base}#{old}"):
        other = open_page(browser, url, 1280, 720)
        after = other.page.evaluate("() => window.rdExplorer.state")
        for k in ("a", "b", "mode", "light"):
            assert after[k] == before[k], (url[:80], k)
        assert not other.errors, other.errors
        other.page.close()


def test_loading_indicator_until_ready_and_during_requests(page):
    p = page.page
    assert p.locator("#busy").is_hidden()  # the first frame is drawn, nothing running
    p.route(
        "**/api/groundtruth.json*",
        lambda route: (p.wait_for_timeout(1500), route.continue_()),
    )
    p.locator("#light-theta").fill("30")
    p.check("#gt-show")
    p.locator("#light-theta").fill("31")  # inputs changed: the ground truth is asked for
    p.wait_for_selector("#busy", state="visible", timeout=10_000)
    p.wait_for_selector("#busy", state="hidden", timeout=120_000)
    assert p.evaluate("() => document.body.dataset.busy") == "0"
