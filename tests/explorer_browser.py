"""Shared set-up of the explorer tests: the server in a thread, headless Chromium, the page.

The fixtures are session-scoped and made available to every test module by ``conftest.py``
(a test module imports only :func:`open_page`): one server and one Chromium per pytest
process (per xdist worker), shared by the explorer and docs tests. A test opens its own page
(:func:`open_page`, a new browser context) and closes it.
Debian's Chromium through Playwright (``playwright install`` cannot download browsers here),
WebGL2 through SwiftShader (software).
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator

import pytest

CHROMIUM = os.environ.get("ROUGHDIFFUSE_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--no-first-run",
    "--enable-unsafe-swiftshader",
]


def _require_chromium() -> None:
    if not (os.path.exists(CHROMIUM) or shutil.which(CHROMIUM)):
        pytest.fail(
            f"Chromium not found at {CHROMIUM} (apt-get install -y chromium, or set "
            "ROUGHDIFFUSE_CHROMIUM); the explorer tests need it"
        )


@pytest.fixture(scope="session")
def explorer_url() -> Iterator[str]:
    from roughdiffuse.explorer import make_server, serve_in_thread, url_of

    server = make_server("127.0.0.1", None)
    serve_in_thread(server)
    yield url_of(server)
    server.shutdown()
    server.server_close()


@pytest.fixture(scope="session")
def browser() -> Iterator[object]:
    _require_chromium()
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        yield b
        b.close()


class PageWithLog:
    """A loaded explorer page and the console errors and page errors it produced."""

    def __init__(self, page: object) -> None:
        self.page = page
        self.errors: list[str] = []
        page.on("console", lambda m: m.type == "error" and self.errors.append(m.text))
        page.on("pageerror", lambda e: self.errors.append(f"pageerror: {e}"))


def open_page(browser: object, url: str, width: int = 1280, height: int = 720) -> PageWithLog:
    """A new page on the explorer, waited on until it says it is ready."""
    page = browser.new_page(viewport={"width": width, "height": height})
    log = PageWithLog(page)
    page.goto(url)
    page.wait_for_selector("body[data-ready='1']", state="attached", timeout=60_000)
    return log


def frames(p: object) -> None:
    """Wait until the page has drawn what the last input asked for: the explorer redraws in
    the next animation frame (``refresh`` in main.js), so two frames cover a redraw that was
    pending when this was called."""
    p.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
