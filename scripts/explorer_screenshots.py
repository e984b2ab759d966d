"""Screenshots of the explorer for the README (docs/images/explorer-*.png).

Besides the two full-page images, one window each at 1280 × 720 and 1920 × 1080
(explorer-1280x720.png, explorer-1920x1080.png), as a user sees it without scrolling, saved
with a 256-colour palette to stay small.

Run from the repository root: ``python scripts/explorer_screenshots.py``. Needs Chromium
(/usr/bin/chromium) and Playwright, as the explorer tests do.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from playwright.sync_api import sync_playwright

from roughdiffuse import OrenNayar
from roughdiffuse.explorer import make_server, serve_in_thread, url_of

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from explorer_browser import CHROMIUM, CHROMIUM_ARGS  # noqa: E402


def csv_text() -> str:
    """Noisy samples of a rough surface (Oren–Nayar, σ = 30°, ρ = 0.8, 3 % noise), θi = 60°."""
    rng = np.random.default_rng(1)
    model = OrenNayar(0.8, math.radians(30))
    lines = ["theta_i_deg,theta_r_deg,delta_phi_deg,brdf"]
    for dp in (0, 180):
        for tr in range(0, 90, 6):
            ti = 60.0
            wi = np.array([math.sin(math.radians(ti)), 0, math.cos(math.radians(ti))])
            st, a = math.sin(math.radians(tr)), math.radians(dp)
            wo = np.array([st * math.cos(a), st * math.sin(a), math.cos(math.radians(tr))])
            f = float(model.brdf(wi, wo)) * (1 + 0.03 * rng.standard_normal())
            lines.append(f"{ti},{tr},{dp},{f:.6f}")
    return "\n".join(lines) + "\n"


def drop_csv(page, text: str) -> None:
    """Drop a CSV file on the page, as a user would."""
    page.evaluate(
        """(text) => {
            const dt = new DataTransfer();
            dt.items.add(new File([text], "rough-samples.csv", { type: "text/csv" }));
            document.getElementById("dropzone").dispatchEvent(
                new DragEvent("drop", { dataTransfer: dt, bubbles: true, cancelable: true }));
        }""",
        text,
    )
    page.wait_for_function("() => document.body.dataset.csvScatter !== undefined")


def small_png(data: bytes, path: Path) -> None:
    """Save a screenshot with a 256-colour palette (a third of the bytes, no visible loss)."""
    import io

    from PIL import Image

    Image.open(io.BytesIO(data)).convert("RGB").quantize(256).save(path, optimize=True)


def windows(browser, url: str, out: Path) -> None:
    """The page at 1280 × 720 (A and B side by side, CSV samples, the plane of incidence with
    the one-bounce V-cavity ground truth) and at 1920 × 1080 (the difference of A and B with
    its colour scale, the 3-D lobe)."""
    page = browser.new_page(viewport={"width": 1280, "height": 720})
    page.goto(url)
    page.wait_for_selector("body[data-ready='1']", state="attached")
    page.select_option("#a-model", "oren-nayar-full")
    page.locator("#a-sigma").fill("30")
    page.select_option("#mode", "1")
    drop_csv(page, csv_text())
    page.locator("#light-theta").fill("60")
    page.check("#gt-show")
    page.check("#gt-bounces-1")
    page.wait_for_function(
        "() => document.getElementById('gt-status').textContent.includes('one bounce')",
        timeout=120_000,
    )
    page.wait_for_timeout(500)
    box = page.locator("#plot-cartesian").bounding_box()
    page.mouse.move(box["x"] + 0.7 * box["width"], box["y"] + 0.5 * box["height"])
    small_png(page.screenshot(), out / "explorer-1280x720.png")
    page.close()
    page = browser.new_page(viewport={"width": 1920, "height": 1080})
    page.goto(url)
    page.wait_for_selector("body[data-ready='1']", state="attached")
    page.select_option("#preset", "eon-vs-on")
    page.select_option("#mode", "2")
    page.locator("#exposure").fill("1")
    page.click("#view-tabs button[data-view=lobe]")
    page.wait_for_function("() => document.body.dataset.view === 'lobe'")
    page.wait_for_timeout(500)
    small_png(page.screenshot(), out / "explorer-1920x1080.png")
    page.close()


def main() -> None:
    out = ROOT / "docs" / "images"
    out.mkdir(parents=True, exist_ok=True)
    server = make_server()
    serve_in_thread(server)
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1500, "height": 960})
        page.goto(url_of(server))
        page.wait_for_selector("body[data-ready='1']", state="attached")
        page.select_option("#preset", "vase")
        page.wait_for_function(
            "() => ['vase-a', 'vase-b'].every(id => document.getElementById(id).complete"
            " && document.getElementById(id).naturalWidth > 0)",
            timeout=120_000,
        )
        page.wait_for_timeout(300)
        page.screenshot(path=str(out / "explorer-vase.png"), full_page=True)
        page.select_option("#preset", "on-vs-lambert")
        drop_csv(page, csv_text())
        page.check("#gt-show")
        page.wait_for_function("() => document.body.dataset.gtPoints === '45'", timeout=120_000)
        page.wait_for_timeout(500)
        page.screenshot(path=str(out / "explorer-on-vs-lambert.png"), full_page=True)
        page.close()
        windows(browser, url_of(server), out)
        browser.close()
    server.shutdown()


if __name__ == "__main__":
    main()
