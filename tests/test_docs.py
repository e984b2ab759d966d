"""The documentation site: it builds with warnings as errors, and every page of it loads in
headless Chromium without a console error, a missing image, a broken internal link or a
request to another host.

Marked ``docs`` (deselect with ``-m "not docs"``) and ``slow``: the build runs the gallery and
the notebooks, about two minutes of one core, so ``make test`` leaves this file out and
``make test SLOW=1``, ``make test-all`` and ``make docs`` build the site.
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


# ---------------------------------------------------------------- figures shown, formulas typeset
def _figure_sources() -> dict[str, int]:
    """Built page -> how many figures its source shows (one per ``plt.show()``): the executed
    Markdown pages, the notebooks and the gallery scripts."""
    import json

    docs = ROOT / "docs"
    out = {}
    for md in docs.glob("*.md"):
        text = md.read_text(encoding="utf-8")
        if "file_format: mystnb" in text and text.count("plt.show()"):
            out[f"{md.stem}.html"] = text.count("plt.show()")
    for nb in docs.glob("*.ipynb"):
        cells = json.loads(nb.read_text(encoding="utf-8"))["cells"]
        n = sum("plt.show()" in "".join(c["source"]) for c in cells if c["cell_type"] == "code")
        if n:
            out[f"{nb.stem}.html"] = n
    for script in (docs / "gallery").glob("plot_*.py"):
        n = script.read_text(encoding="utf-8").count("plt.show()")
        if n:
            out[f"auto_gallery/{script.stem}.html"] = n
    return out


def test_pages_that_make_figures_show_them(site: Path) -> None:
    """Every page whose source shows a figure has a PNG for it in the HTML (the notebooks'
    kernels draw inline, the plotting functions register their figures with pyplot)."""
    import re

    sources = _figure_sources()
    assert {"getting_started.html", "tutorial.html",
            "auto_gallery/plot_fit_csv.html"} <= set(sources), sources
    short = []
    for name, wanted in sorted(sources.items()):
        page = site / name
        if not page.is_file():  # a gallery script left out of this build (PyTorch missing)
            assert name == "auto_gallery/plot_pytorch.html", name
            continue
        text = page.read_text(encoding="utf-8")
        images = [s for s in re.findall(r'<img[^>]+src="([^"]+)"', text)
                  if s.endswith(".png") and "_thumb" not in s]
        if len(images) != wanted:  # fewer: a figure not shown; more: one leaked from elsewhere
            short.append(f"{name}: {len(images)} image(s) for {wanted} plt.show()")
        for src in images:
            assert (page.parent / src).resolve().is_file(), f"{name}: {src}"
    assert not short, "\n".join(short)


def test_gallery_thumbnails_are_not_the_placeholder(site: Path, tmp_path: Path) -> None:
    """Each example's thumbnail is its own figure, not sphinx-gallery's stock picture."""
    import numpy as np
    from PIL import Image
    from sphinx_gallery.utils import scale_image

    stock = Path(__import__("sphinx_gallery").__file__).parent / "_static" / "no_image.png"
    thumbs = sorted((site / "_images").glob("sphx_glr_plot_*_thumb.png"))
    assert len(thumbs) >= 7, thumbs
    placeholders = []
    for thumb in thumbs:
        mine = np.asarray(Image.open(thumb).convert("RGB"), dtype=float)
        ref_file = tmp_path / "stock.png"
        scale_image(str(stock), str(ref_file), mine.shape[1], mine.shape[0])
        ref = np.asarray(Image.open(ref_file).convert("RGB"), dtype=float)
        if ref.shape == mine.shape and np.mean(np.abs(ref - mine)) < 2.0:
            placeholders.append(thumb.name)
    assert not placeholders, placeholders


def test_model_pages_state_their_formulas(site: Path) -> None:
    """Every model page has a typeset formula (MathJax input in the HTML, the page loads the
    site's own MathJax) and a symbol table naming the declared parameters."""
    from roughdiffuse import registry

    for entry in registry.entries():
        text = (site / "models" / f"{entry.id}.html").read_text(encoding="utf-8")
        assert 'class="math notranslate nohighlight"' in text, entry.id
        assert "_static/mathjax/tex-chtml.js" in text, entry.id
        for p in entry.parameters:
            if p.name in entry.cls.symbols and p.name not in entry.fixed:
                code = f'<code class="docutils literal notranslate"><span class="pre">{p.name}'
                assert code in text, (entry.id, p.name)
    assert (site / "_static" / "mathjax" / "tex-chtml.js").stat().st_size > 100_000
    # the equation numbers a formula cites say whether they were checked against the paper
    full = (site / "models" / "oren-nayar-full.html").read_text(encoding="utf-8")
    assert "Equation numbers (Eq. 27; Eq. 31)" in full and "not checked" in full
    lambert = (site / "models" / "lambert.html").read_text(encoding="utf-8")
    assert "Equation numbers" not in lambert  # cites none
    lecture = (site / "lecture" / "oren-nayar.html").read_text(encoding="utf-8")
    for symbol in ("C_1 =", "C_2 =", "C_3 =", "L_2 ="):
        assert symbol in lecture, symbol


def test_formulas_render_offline_in_chromium(site: Path, site_url: str, browser) -> None:  # noqa: F811
    """The Oren–Nayar page, opened with every request to another host blocked, typesets its
    formulas: MathJax (from this site) leaves its output elements, and nothing left the host."""
    outside: list[str] = []
    context = browser.new_context(viewport={"width": 1280, "height": 900})
    page = context.new_page()

    def route(r) -> None:
        if r.request.url.startswith((site_url, "data:", "file:")):
            r.continue_()
        else:
            outside.append(r.request.url)
            r.abort()

    page.route("**/*", route)
    page.goto(f"{site_url}/models/oren-nayar-full.html", wait_until="load")
    page.wait_for_function("() => window.MathJax && MathJax.startup && MathJax.startup.promise",
                           timeout=30_000)
    page.evaluate("() => MathJax.startup.promise")
    rendered = page.evaluate("() => document.querySelectorAll('mjx-container').length")
    errors = page.evaluate("() => document.querySelectorAll('mjx-merror').length")
    context.close()
    assert rendered >= 6, rendered  # L1, C1, C2, C3, L2, f and the inline symbols
    assert errors == 0
    assert not outside, outside


def test_api_reference_is_organised_by_task(site: Path) -> None:
    """The API index has one section per task, keeps the command-line and benchmark modules
    on the internals page, and ``roughdiffuse.fit`` documents ``fit()`` itself."""
    import re

    page = (site / "api" / "index.html").read_text(encoding="utf-8")
    index = page[page.index("<article"):page.index("</article>")]  # not the sidebar's tree
    headings = re.findall(r"<h2>([^<]+)<a", index)
    assert headings[:4] == ["Models", "Evaluation", "Rendering and plots", "Fitting"], headings
    assert {"Ground truth", "Photometric stereo", "Integrations"} <= set(headings), headings
    for internal in ("roughdiffuse.bench", "roughdiffuse.commands", "roughdiffuse.cli"):
        assert f'href="{internal}.html"' not in index, internal
    internals = (site / "api" / "internals.html").read_text(encoding="utf-8")
    assert 'href="roughdiffuse.commands.fit.html"' in internals
    fit_page = (site / "api" / "roughdiffuse.fit.html").read_text(encoding="utf-8")
    assert re.search(r'<dt class="sig sig-object py"[^>]*>\s*<span class="sig-prename[^>]*>'
                     r'<span class="pre">roughdiffuse\.fit\.least_squares\.</span></span>'
                     r'<span class="sig-name descname"><span class="pre">fit</span>', fit_page)
    for page in site.rglob("*.html"):
        assert "the issue" not in page.read_text(encoding="utf-8").lower(), page


def test_navigation_bar_is_one_row_at_1280(site: Path, site_url: str, browser) -> None:  # noqa: F811
    """At 1280 px the header's links (and its "More" menu) sit on one row."""
    context = browser.new_context(viewport={"width": 1280, "height": 800})
    page = context.new_page()
    page.goto(f"{site_url}/index.html", wait_until="load")
    tops = page.evaluate(
        "() => Array.from(document.querySelectorAll('.bd-header .navbar-nav > li'))"
        ".filter(li => li.offsetParent !== null)"
        ".map(li => Math.round(li.getBoundingClientRect().top))"
    )
    context.close()
    assert len(tops) >= 4, tops
    assert max(tops) - min(tops) <= 4, tops  # a second row would be ~40 px lower
