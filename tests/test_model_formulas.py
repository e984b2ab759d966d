"""Every registry model declares its formula (``Model.formula``) and the symbol of each of its
parameters (``Model.symbols``): the site's model pages are generated from them."""

from __future__ import annotations

import re
import textwrap

import pytest

from roughdiffuse import registry


def _formula(entry: registry.Entry) -> str:
    text = entry.cls.formula
    return textwrap.dedent(text.get(entry.id, "") if isinstance(text, dict) else text)


@pytest.mark.parametrize("entry", registry.entries(), ids=lambda e: e.id)
def test_model_declares_a_typeset_formula(entry: registry.Entry) -> None:
    text = _formula(entry)
    blocks = re.findall(r"```\{math\}\n(.*?)\n```", text, flags=re.S)
    assert blocks, f"{entry.id}: no math block in its formula"
    assert all(b.count("{") == b.count("}") for b in blocks), entry.id  # balanced LaTeX
    # MathJax drops the line break inside a \text{...}: "variant\n full" reads "variantfull"
    broken = re.findall(r"\\text\{[^}]*\n[^}]*\}", " ".join(blocks))
    assert not broken, f"{entry.id}: a \\text{{}} broken across lines: {broken}"
    latex = " ".join(blocks) + " " + " ".join(re.findall(r"\{math\}`([^`]*)`", text))
    for p in entry.parameters:
        if p.choices is not None or p.name in entry.fixed:
            continue  # a choice selects the formula, it is not a symbol in it
        symbol = entry.cls.symbols.get(p.name)
        assert symbol, f"{entry.id}: parameter {p.name!r} has no symbol"
        assert symbol in latex, f"{entry.id}: {symbol!r} ({p.name}) is not in the formula"


def test_formulas_typeset_without_error_and_fit_the_column(tmp_path, browser) -> None:  # noqa: ANN001
    """Every display of every model's formula, typeset by the MathJax the site ships, has no
    MathJax error and fits the model page's text column (624 px at a 1280 px window)."""
    import html
    import importlib.util
    from pathlib import Path

    spec = importlib.util.find_spec("sphinx-mathjax-offline")
    if spec is None or spec.origin is None:
        pytest.skip("sphinx-mathjax-offline (the docs extra) is not installed")
    mathjax = Path(spec.origin).parent / "static" / "mathjax" / "tex-chtml.js"
    divs = []
    for entry in registry.entries():
        for block in re.findall(r"```\{math\}\n(.*?)\n```", _formula(entry), flags=re.S):
            # as Sphinx wraps a display with line breaks
            body = block if "\\\\" not in block else rf"\begin{{split}}{block}\end{{split}}"
            divs.append(f"<div class=eq data-id='{entry.id}' style='width:624px'>"
                        f"\\[{html.escape(body)}\\]</div>")
    page = tmp_path / "formulas.html"
    page.write_text(f"<html><head><script src='{mathjax.as_uri()}'></script></head>"
                    f"<body style='font-size:16px'>{''.join(divs)}</body></html>", "utf-8")
    if True:  # the session's Chromium (the browser fixture of tests/conftest.py)
        tab = browser.new_page(viewport={"width": 1280, "height": 900})
        tab.goto(page.as_uri(), wait_until="load")
        tab.wait_for_function("() => window.MathJax && MathJax.startup && "
                              "MathJax.startup.promise", timeout=30_000)
        tab.evaluate("() => MathJax.startup.promise")
        rows = tab.evaluate("""() => Array.from(document.querySelectorAll('div.eq')).map(d => [
            d.dataset.id, d.querySelector('mjx-math').getBoundingClientRect().width,
            d.querySelectorAll('mjx-merror').length])""")
        tab.close()
    assert len(rows) == len(divs) > 40
    assert not [r for r in rows if r[2]], [r for r in rows if r[2]]
    assert not [r for r in rows if r[1] > 624], [r for r in rows if r[1] > 624]
