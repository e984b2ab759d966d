"""End-to-end tests of the explorer page in headless Chromium (Playwright, Debian's Chromium).

Pixels are read from the sphere canvas itself (``toDataURL``; the canvas keeps its drawing
buffer) and compared with closed forms: a sphere lit head-on along the view axis, with
θi = θr = θ and Δφ = 0 at every point, has radiance L = ρ (A cos θ + B sin²θ) under the
qualitative Oren–Nayar model with E0 = π (the lecture's expression; Lambert is A = 1, B = 0).
"""

from __future__ import annotations

import base64
import io
import math

import numpy as np
import pytest
from PIL import Image

from explorer_browser import frames, open_page
from roughdiffuse import OrenNayar

RADIUS_FRACTION = 0.46  # sphere.frag: radius = 0.46 min(width, height)


@pytest.fixture()
def page(browser, explorer_url):  # noqa: F811 - fixtures
    log = open_page(browser, explorer_url)
    yield log
    log.page.close()


@pytest.fixture(scope="module")
def shared_page(browser, explorer_url):  # noqa: F811 - fixtures
    """One page for the tests that do not depend on the state they find it in (they only call
    its scripts, or drop their own files and move a slider away from wherever it is): loading
    the page costs about 10 CPU-seconds of SwiftShader shader compilation each time."""
    log = open_page(browser, explorer_url)
    yield log
    log.page.close()


def canvas_pixels(p) -> np.ndarray:
    """The sphere canvas as float sRGB values in [0, 1], shape (H, W, 3), row 0 at the top."""
    url = p.evaluate("() => document.getElementById('sphere').toDataURL('image/png')")
    data = base64.b64decode(url.split(",", 1)[1])
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB"), dtype=np.float64) / 255.0


def srgb_to_linear(v: np.ndarray) -> np.ndarray:
    return np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def sphere_coordinates(h: int, w: int) -> tuple[np.ndarray, np.ndarray]:
    """Normalised (x, y) of every pixel centre of a single-sphere canvas (y up)."""
    radius = RADIUS_FRACTION * min(w, h)
    j, i = np.meshgrid(np.arange(w), np.arange(h))
    x = (j + 0.5 - w / 2) / radius
    y = ((h - 1 - i) + 0.5 - h / 2) / radius
    return x, y


def set_model(p, slot: str, model: str, **sliders: float) -> None:
    p.select_option(f"#{slot}-model", model)
    for name, value in sliders.items():
        p.locator(f"#{slot}-{name}").fill(str(value))
    frames(p)


def on_head_on_radiance(albedo: float, sigma: float, mu: np.ndarray) -> np.ndarray:
    """L = ρ (A μ + B (1 − μ²)): qualitative Oren–Nayar, θi = θr, Δφ = 0, E0 = π."""
    s2 = sigma * sigma
    a = 1 - 0.5 * s2 / (s2 + 0.33)
    b = 0.45 * s2 / (s2 + 0.09)
    return albedo * (a * mu + b * (1 - mu * mu))


def test_page_loads_without_console_errors(page):
    p = page.page
    assert p.title() == "roughdiffuse explorer"
    assert p.locator("#error").is_hidden()
    assert p.locator("#light-readout").inner_text() == "light θ = 0.0°, φ = 0.0°"
    # the σ slider shows degrees and radians
    p.locator("#a-sigma").fill("30")
    assert p.locator("#a-sigma-out").inner_text() == "30.0° = 0.524 rad"
    for mode in ("1", "2", "0"):
        p.select_option("#mode", mode)
        frames(p)
    for preset in ("on-vs-lambert", "full-moon", "highlights", "eon-vs-on"):
        p.select_option("#preset", preset)
        frames(p)
    assert not page.errors, page.errors


def test_sigma_brightens_the_limb_of_a_head_on_lit_sphere(page):
    """σ from 0 to 60°: the limb gets brighter, the centre darker, both as the closed form says."""
    p = page.page
    set_model(p, "a", "oren-nayar", sigma=0, **{"albedo-g": 0.8})
    smooth = canvas_pixels(p)
    p.locator("#a-sigma").fill("60")
    frames(p)
    rough = canvas_pixels(p)
    h, w, _ = smooth.shape
    x, y = sphere_coordinates(h, w)
    r = np.hypot(x, y)
    limb = (r > 0.85) & (r < 0.97)
    centre = r < 0.2
    assert rough[limb].mean() > smooth[limb].mean() + 0.05
    assert rough[centre].mean() < smooth[centre].mean() - 0.02
    mu = np.sqrt(np.clip(1 - r * r, 0, 1))
    for img, sigma in ((smooth, 0.0), (rough, math.radians(60))):
        expected = on_head_on_radiance(0.8, sigma, mu)
        got = srgb_to_linear(img[..., 1])
        inside = r < 0.97
        # 8-bit sRGB: one level is at most ~1.5 % of a linear value above 0.05
        assert np.allclose(got[inside], expected[inside], rtol=0.02, atol=2e-3), sigma
    assert not page.errors, page.errors


def test_dragging_moves_the_light(page):
    p = page.page
    set_model(p, "a", "lambert", **{"albedo-g": 1.0})
    box = p.locator("#sphere").bounding_box()
    cx, cy = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    radius = RADIUS_FRACTION * box["width"]
    # drag from the centre to half the radius towards +x: the light goes to θ = asin(0.5) = 30°
    p.mouse.move(cx, cy)
    p.mouse.down()
    p.mouse.move(cx + 0.25 * radius, cy, steps=3)
    p.mouse.move(cx + 0.5 * radius, cy, steps=3)
    p.mouse.up()
    frames(p)
    text = p.locator("#light-readout").inner_text()
    theta, phi = (float(v.split("=")[1].strip(" °")) for v in text.split(","))
    assert abs(theta - 30.0) < 0.6 and abs(phi) < 0.6, text
    # Lambert: the brightest point of the sphere is where n = l, under the pointer
    img = canvas_pixels(p)[..., 1]
    h, w = img.shape
    x, y = sphere_coordinates(h, w)
    lum = np.where(np.hypot(x, y) < 1, img, 0)
    top = lum >= lum.max()  # 8-bit values: a plateau; its centroid
    cx_top, cy_top = x[top].mean(), y[top].mean()
    assert abs(cx_top - 0.5) < 0.03 and abs(cy_top) < 0.03, (cx_top, cy_top)
    # the shading follows n·l for the new light
    l = np.array([0.5, 0.0, math.sqrt(0.75)])
    z = np.sqrt(np.clip(1 - x * x - y * y, 0, 1))
    expected = np.clip(x * l[0] + z * l[2], 0, None)
    inside = np.hypot(x, y) < 0.97
    assert np.allclose(srgb_to_linear(img)[inside], expected[inside], rtol=0.02, atol=2e-3)
    # drag up-left beyond the rim: the light goes behind the sphere (a crescent)
    p.mouse.move(cx, cy)
    p.mouse.down()
    p.mouse.move(cx - 1.5 * radius / math.sqrt(2), cy - 1.5 * radius / math.sqrt(2), steps=4)
    p.mouse.up()
    frames(p)
    text = p.locator("#light-readout").inner_text()
    theta, phi = (float(v.split("=")[1].strip(" °")) for v in text.split(","))
    assert abs(theta - 135.0) < 1.0 and abs(phi - 135.0) < 1.0, text
    img = canvas_pixels(p)[..., 1]
    assert (img[np.hypot(x, y) < 0.5] < 0.01).all()  # the centre faces away from the light
    assert not page.errors, page.errors


def _csv_of_model(model, rows) -> str:
    lines = [
        "# samples of OrenNayar(0.8, 20 deg), written by the test",
        "theta_i_deg, theta_r_deg, delta_phi_deg, brdf",
    ]
    for ti, tr, dp in rows:
        wi = np.array([math.sin(math.radians(ti)), 0.0, math.cos(math.radians(ti))])
        a = math.radians(dp)
        st = math.sin(math.radians(tr))
        wo = np.array([st * math.cos(a), st * math.sin(a), math.cos(math.radians(tr))])
        lines.append(f"{ti}, {tr}, {dp}, {float(model.brdf(wi, wo)):.9g}")
    return "\n".join(lines) + "\n"


def drop_csv(p, text: str, name: str) -> None:
    p.evaluate(
        """([text, name]) => {
            const dt = new DataTransfer();
            dt.items.add(new File([text], name, { type: "text/csv" }));
            const zone = document.getElementById("dropzone");
            const init = { dataTransfer: dt, bubbles: true, cancelable: true };
            zone.dispatchEvent(new DragEvent("dragover", init));
            zone.dispatchEvent(new DragEvent("drop", init));
        }""",
        [text, name],
    )


def test_csv_drop_plots_points_against_the_model(page):
    """Samples of the page's default model A: plotted, and 0.0 % from the model."""
    p = page.page
    in_plane = [(30, tr, dp) for dp in (0, 180) for tr in range(0, 90, 10)]  # 18
    off_plane = [(30, tr, 90) for tr in range(0, 90, 10)] + [(60, 40, 0), (60, 50, 180)]  # 11
    text = _csv_of_model(OrenNayar(0.8, math.radians(20), "full"), in_plane + off_plane)
    drop_csv(p, text, "samples.csv")
    p.wait_for_function("() => document.body.dataset.csvScatter !== undefined")
    frames(p)
    status = p.locator("#data-status")
    assert "samples.csv: 29 samples" in status.inner_text()
    assert "RMS relative difference to model A: 0.0%" in status.inner_text()
    assert "error" not in (status.get_attribute("class") or "")
    assert p.evaluate("() => document.body.dataset.csvPoints") == "18"
    assert p.evaluate("() => document.body.dataset.csvScatter") == "29"
    assert p.locator("#light-readout").inner_text().startswith("light θ = 30.0°")
    # the points are on the plot: red markers on the Cartesian canvas
    url = p.evaluate("() => document.getElementById('plot-cartesian').toDataURL('image/png')")
    img = np.asarray(Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGB"))
    red = (img[..., 0] > 170) & (img[..., 1] < 90) & (img[..., 2] < 90)
    assert red.sum() > 18 * 10
    # the "data vs A" view's CSV export: every sample, with the model's value beside it
    table = p.evaluate("() => window.rdExplorer.tables().scatter")
    columns = ["theta_i_deg", "theta_r_deg", "delta_phi_deg", "measured", "model_a"]
    assert table["columns"] == columns
    rows = np.array(table["rows"], dtype=float)
    np.testing.assert_allclose(rows[:, :3], np.array(in_plane + off_plane, float), atol=1e-4)
    measured = [float(line.split(",")[3]) for line in text.splitlines()[2:]]
    np.testing.assert_allclose(rows[:, 3], measured, rtol=1e-6)
    np.testing.assert_allclose(rows[:, 4], measured, rtol=1e-4, atol=1e-7)  # GLSL's float32 bound
    assert not page.errors, page.errors


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n10,30,0,0.2\n10,abc,0,0.2\n",
            "line 4: column 'theta_r_deg': not a number ('abc')",
        ),
        (
            "# note\ntheta_i,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n",
            "line 2: column 'theta_i' must state its unit",
        ),
        (
            "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,0.2\n\n10,95,0,0.2\n",
            "line 4: column 'theta_r_deg': angle 95 out of range [0, 90] degrees",
        ),
        (
            "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0,-0.2\n",
            "line 2: column 'brdf': negative value -0.2",
        ),
        (
            "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n10,20,0\n",
            "line 2: expected 4 values (as in the header), found 3",
        ),
        ("theta_i_deg,theta_r_deg,brdf\n10,20,0.1\n", "line 1: no azimuth"),
    ],
)
def test_bad_csv_shows_its_message_and_the_page_keeps_working(
    shared_page, text, message, tmp_path
):
    import re

    from roughdiffuse.fit import read_csv

    # roughdiffuse.fit.read_csv rejects the same file, at the same line when it names one
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ValueError) as exc:
        read_csv(path)
    py_line = re.search(r"line (\d+)", str(exc.value))
    if py_line:
        assert message.startswith(f"line {py_line.group(1)}:"), (str(exc.value), message)
    page = shared_page
    p = page.page
    errors_before = len(page.errors)
    status = p.locator("#data-status")
    shown = status.text_content()  # the shared page may show an earlier test's file
    drop_csv(p, text, "bad.csv")
    p.wait_for_function(
        "(shown) => !['', shown].includes(document.getElementById('data-status').textContent)",
        arg=shown,
    )
    assert message in status.inner_text(), status.inner_text()
    assert "error" in status.get_attribute("class")
    assert p.locator("#error").is_hidden()
    # still working: a good file loads after the bad one, sliders still redraw
    good = "theta_i_deg,theta_r_deg,delta_phi_deg,brdf\n0,0,0,0.2\n0,40,0,0.2\n"
    drop_csv(p, good, "good.csv")
    p.wait_for_function(
        "() => document.getElementById('data-status').textContent.startsWith('good.csv')"
    )
    before = canvas_pixels(p)
    sigma = "20" if p.locator("#a-sigma").input_value() == "70" else "70"  # away from where it is
    p.locator("#a-sigma").fill(sigma)
    frames(p)
    assert np.abs(canvas_pixels(p) - before).max() > 0.02
    assert not page.errors[errors_before:], page.errors[errors_before:]


def test_difference_mode_is_zero_for_equal_models_and_signed_otherwise(page):
    p = page.page
    set_model(p, "a", "lambert")
    set_model(p, "b", "lambert")
    p.select_option("#mode", "2")
    frames(p)
    img = canvas_pixels(p)
    h, w, _ = img.shape
    x, y = sphere_coordinates(h, w)
    inside = np.hypot(x, y) < 0.97
    assert img[inside].max() < 1 / 255 + 1e-9  # A − B = 0: black
    # rough A against Lambert B, head-on: A brighter at the limb (red-orange), darker at the
    # centre (blue), from L = ρ(Aμ + B(1 − μ²)) against ρμ
    set_model(p, "a", "oren-nayar", sigma=60)
    img = canvas_pixels(p)
    r = np.hypot(x, y)
    limb, centre = (r > 0.85) & (r < 0.97), r < 0.2
    assert (img[limb][:, 0] > img[limb][:, 2] + 0.2).all()
    assert (img[centre][:, 2] > img[centre][:, 0] + 0.2).all()
    assert not page.errors, page.errors


GOOD_CSVS = {
    "degrees": "theta_i_deg, theta_r_deg, delta_phi_deg, brdf\n30, 45, 0, 0.25\n0, 80, 120, 0.1\n",
    "radians, bracket units, comments": (
        "# a comment\ntheta_i [rad], theta_o (rad), phi_d_rad, brdf [1/sr]\n"
        "0.5, 1.0, 3.0, 0.3\n\n# another\n1.5, 0.2, -1, 0.05\n"
    ),
    "phi_i and phi_r, colour": (
        "theta_i_deg,theta_r_deg,phi_i_deg,phi_r_deg,brdf_r,brdf_g,brdf_b\n"
        "20,40,10,190,0.3,0.2,0.1\n90,0,0,0,0.1,0.1,0.1\n"
    ),
    "radiance with an irradiance line": (
        "# irradiance = 2.5\ntheta_i_deg,theta_r_deg,delta_phi_deg,radiance\n60,30,45,0.2\n"
    ),
    "radiance with an irradiance column": (
        "theta_i_deg,theta_r_deg,delta_phi_deg,radiance,irradiance\n10,30,45,0.2,3\n"
    ),
}


@pytest.mark.parametrize("name", list(GOOD_CSVS))
def test_browser_csv_parser_agrees_with_fit_read_csv(shared_page, name, tmp_path):
    """The page's parser and roughdiffuse.fit.read_csv (written separately) read one file alike."""
    from roughdiffuse.fit import read_csv

    text = GOOD_CSVS[name]
    path = tmp_path / "s.csv"
    path.write_text(text)
    m = read_csv(path)
    page = shared_page
    js = page.page.evaluate(
        """async (text) => {
            const { parseBrdfCsv } = await import("./js/csv.js");
            return parseBrdfCsv(text).samples;
        }""",
        text,
    )
    ti = np.array([s["thetaI"] for s in js])
    tr = np.array([s["thetaR"] for s in js])
    dp = np.array([s["deltaPhi"] for s in js])
    np.testing.assert_allclose(np.cos(ti), m.mu_i, atol=1e-12)
    np.testing.assert_allclose(np.cos(tr), m.mu_o, atol=1e-12)
    cos_io = np.cos(ti) * np.cos(tr) + np.sin(ti) * np.sin(tr) * np.cos(dp)
    np.testing.assert_allclose(cos_io, m.cos_io, atol=1e-12)
    brdf = np.asarray(m.value) / (np.asarray(m.scale)[:, None] if m.value.ndim == 2 else m.scale)
    if brdf.ndim == 1:
        brdf = np.repeat(brdf[:, None], 3, axis=1)
    np.testing.assert_allclose(np.array([s["value"] for s in js]), brdf, rtol=1e-12)
    assert not page.errors, page.errors


def test_ground_truth_overlay_from_the_solver(page):
    """The checkbox asks the server's V-cavity solver; its curve lands on the plots."""
    p = page.page
    set_model(p, "a", "oren-nayar", sigma=0.5)  # nearly flat: the solver is quick here
    p.locator("#light-theta").fill("30")
    p.check("#gt-show")
    p.wait_for_function("() => document.body.dataset.gtPoints === '45'", timeout=60_000)
    frames(p)
    assert "σ = 0.5°, θi = 30.0°, ρ = 0.800" in p.locator("#gt-status").inner_text()
    url = p.evaluate("() => document.getElementById('plot-cartesian').toDataURL('image/png')")
    img = np.asarray(Image.open(io.BytesIO(base64.b64decode(url.split(",", 1)[1]))).convert("RGB"))
    green = (img[..., 1] > 110) & (img[..., 0] < 80) & (img[..., 2] < 110)
    assert green.sum() > 200  # the dashed curve (the legend alone is ~16 pixels)
    # a model without σ: the page says why there is no curve
    set_model(p, "a", "eon")
    p.wait_for_function(
        "() => document.getElementById('gt-status').textContent.includes('Oren–Nayar')"
    )
    assert not page.errors, page.errors


def test_specular_highlight_sits_where_the_normal_halves_light_and_view(page):
    """Torrance–Sparrow, σ = 3°: the highlight is at n = (l + v)/|l + v|, here θ = 30°."""
    p = page.page
    set_model(p, "a", "torrance-sparrow", sigma=3)
    p.locator("#light-theta").fill("60")
    frames(p)
    img = canvas_pixels(p)[..., 1]
    h, w = img.shape
    x, y = sphere_coordinates(h, w)
    top = (img >= img.max()) & (np.hypot(x, y) < 1)
    assert img.max() > 0.5
    assert abs(x[top].mean() - 0.5) < 0.03 and abs(y[top].mean()) < 0.03
    assert not page.errors, page.errors
