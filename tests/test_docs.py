"""The documentation site: it builds with warnings as errors, and every page of it loads in
headless Chromium without a console error, a missing image, a broken internal link or a
request to another host.

Marked ``docs`` (deselect with ``-m "not docs"``) and ``slow``: the build runs the gallery and
the notebooks, about two minutes of one core, so ``make test`` leaves this file out and
``make test SLOW=1`` (CI), ``make test-all`` and ``make docs`` build the site.
"""

from __future__ import annotations

import functools
import html.parser
import http.server
import threading
import urllib.parse
from collections.abc import Iterator
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_nb")
pytest.importorskip("sphinx_gallery")

pytestmark = [pytest.mark.docs, pytest.mark.slow]
ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def site(docs_site: Path) -> Path:
    """A fresh build of the site (as ``make docs``: -W --keep-going), its HTML folder: built
    once per test run (``conftest.docs_site``) and shared by every test that needs it."""
    return docs_site


def test_site_has_the_generated_pages(site: Path) -> None:
    from roughdiffuse import registry

    for entry in registry.entries():  # one page per registry entry, none hard-coded
        page = site / "models" / f"{entry.id}.html"
        assert page.is_file(), page
        text = page.read_text(encoding="utf-8")
        if entry.cls.traceable:  # a Monte Carlo simulation gets no pictures at build time
            assert f"{entry.id}-sphere.png" in text and f"{entry.id}-furnace.png" in text
        else:
            assert "Monte Carlo simulation" in text
    for name in ("index", "getting_started", "tutorial", "accuracy", "benchmarks",
                 "api/index", "api/roughdiffuse.registry", "auto_gallery/index"):
        assert (site / f"{name}.html").is_file(), name
    assert "sphx-glr-single-img" in (site / "auto_gallery" / "plot_render_sphere.html").read_text(
        encoding="utf-8"
    )  # the gallery ran and drew


def test_lecture_pages_have_their_figures(site: Path) -> None:
    """Every lecture page shows figures drawn at build time (docs/_ext/rd_lecture.py)."""
    import re

    pages = sorted((site / "lecture").glob("*.html"))
    names = {p.stem for p in pages}
    assert {"lambert", "full-moon", "v-cavities", "oren-nayar", "vase", "torrance-sparrow",
            "mixes"} <= names, names
    for page in pages:
        if page.stem == "index":
            continue
        images = re.findall(r'<img[^>]+src="([^"]+\.png)"', page.read_text(encoding="utf-8"))
        assert images, f"{page.name} has no figure"
        for src in images:
            assert (page.parent / src).resolve().is_file(), f"{page.name}: {src}"


def test_model_pages_show_the_accuracy_report_numbers(site: Path) -> None:
    """The full Oren–Nayar page quotes its row of the committed scoreboard (the published-σ
    RMS error against the V-cavity surface at α = 0.5, ρ = 0.9: 0.048 in
    docs/accuracy/index.md, "Against the V-cavity surface")."""
    import json

    scores = json.loads((ROOT / "docs" / "accuracy" / "model_scores.json").read_text("utf-8"))
    row = next(r for r in scores["models"]["oren-nayar-full"]["V-cavity"]
               if r["alpha"] == 0.5 and r["rho"] == 0.9 and r["mapping"] == "published")
    assert f"{row['rms']:.3f}" == "0.048"  # the JSON agrees with the committed Markdown table
    text = (site / "models" / "oren-nayar-full.html").read_text(encoding="utf-8")
    assert "<td><p>0.048</p></td>" in text or ">0.048<" in text


class _Links(html.parser.HTMLParser):
    def __init__(self) -> None:
        super().__init__()
        self.links: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        a = dict(attrs)
        if a.get("id"):
            self.ids.add(a["id"] or "")
        if tag == "a" and a.get("href"):
            self.links.append(a["href"] or "")


@functools.cache
def _parse(path: Path) -> _Links:
    p = _Links()
    p.feed(path.read_text(encoding="utf-8"))
    return p


def test_internal_links_resolve(site: Path) -> None:
    broken = []
    for page in sorted(site.rglob("*.html")):
        if page.relative_to(site).as_posix().startswith("_static/"):
            continue
        for href in _parse(page).links:
            url = urllib.parse.urlsplit(href)
            if url.scheme or url.netloc or href.startswith("mailto:"):
                continue
            target = page if not url.path else (page.parent / urllib.parse.unquote(url.path))
            target = target.resolve()
            if target.is_dir():
                target = target / "index.html"
            if not target.exists():
                broken.append(f"{page.relative_to(site)} -> {href}")
            elif url.fragment and target.suffix == ".html" and url.fragment not in _parse(
                target
            ).ids:
                broken.append(f"{page.relative_to(site)} -> {href} (no such anchor)")
    assert not broken, "\n".join(broken[:30])


@pytest.fixture(scope="module")
def site_url(site: Path) -> Iterator[str]:
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args: object) -> None:
            pass

    handler = functools.partial(Quiet, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    yield f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def test_every_page_loads_cleanly(site: Path, site_url: str, browser) -> None:
    pages = sorted(
        p.relative_to(site).as_posix()
        for p in site.rglob("*.html")
        if not p.relative_to(site).as_posix().startswith("_static/")  # theme templates
    )
    assert len(pages) > 20
    problems: list[str] = []
    context = browser.new_context()
    page = context.new_page()
    current = {"name": ""}
    page.on("console", lambda m: m.type == "error" and problems.append(
        f"{current['name']}: console error {m.text}"))
    page.on("pageerror", lambda e: problems.append(f"{current['name']}: page error {e}"))

    def route(r) -> None:
        if r.request.url.startswith(site_url):
            r.continue_()
        else:
            problems.append(f"{current['name']}: request to another host {r.request.url}")
            r.abort()

    page.route("**/*", route)
    page.on("response", lambda resp: resp.status >= 400 and problems.append(
        f"{current['name']}: HTTP {resp.status} {resp.url}"))
    for name in pages:
        current["name"] = name
        page.goto(f"{site_url}/{name}", wait_until="load")
        missing = page.evaluate(
            "() => Array.from(document.images)"
            ".filter(i => i.complete && i.naturalWidth === 0).map(i => i.src)"
        )
        problems += [f"{name}: image not shown {src}" for src in missing]
    context.close()
    assert not problems, "\n".join(problems[:30])
