"""The explorer's coat α: a slider of its own (``coat_roughness``), whose range, start and
words are Coated's declaration of ``roughness``, apart from EON's (and Fujii's, Burley's…)
``roughness`` r, in headless Chromium."""

from __future__ import annotations

import pytest

from explorer_browser import open_page
from roughdiffuse import registry
from roughdiffuse.explorer.params import DEFAULTS, flat_key, model_from_params, state_keys


def _declared(model_id: str, name: str) -> tuple[float, float]:
    p = registry.get(model_id).param(name)
    return p.fit_range or (p.min, p.max)


def test_the_coat_alpha_has_its_own_key_in_python() -> None:
    coated, eon = registry.get("coated"), registry.get("eon")
    assert flat_key(coated, "roughness") == "coat_roughness"
    assert flat_key(eon, "roughness") == "roughness"
    assert state_keys(coated) == {"roughness": "coat_roughness"}
    assert state_keys(eon) == {}
    # the flat record's roughness is EON's r; the coat reads only its own key
    m = model_from_params({"model": "coated", "roughness": 0.9, "coat_roughness": 0.25})
    assert float(m.roughness) == 0.25
    assert DEFAULTS["coat_roughness"] == registry.get("coated").param("roughness").default


@pytest.mark.slow  # a page load: about 10 CPU-seconds of SwiftShader shader compilation
def test_coat_alpha_slider_is_its_own(browser, explorer_url, tmp_path) -> None:  # noqa: F811
    log = open_page(browser, explorer_url)
    p = log.page
    try:
        shown = lambda k: p.evaluate(f"() => !document.getElementById('a-{k}-row').hidden")  # noqa: E731
        # EON: its r slider; the coat's α hidden
        p.select_option("#a-model", "eon")
        assert shown("roughness") and not shown("coat_roughness")
        p.fill("#a-roughness", "0.9")
        p.dispatch_event("#a-roughness", "input")
        # Coated: the α slider with Coated's declared range and words, not EON's r
        p.select_option("#a-model", "coated")
        assert shown("coat_roughness") and not shown("roughness")
        lo, hi = _declared("coated", "roughness")
        el = p.locator("#a-coat_roughness")
        assert (float(el.get_attribute("min")), float(el.get_attribute("max"))) == (lo, hi)
        label = p.locator("#a-coat_roughness-row").inner_text()
        assert registry.get("coated").param("roughness").description in label
        s = p.evaluate("() => window.rdExplorer.state.a")
        assert s["roughness"] == pytest.approx(0.9)  # EON's r kept for EON
        assert s["coat_roughness"] == registry.get("coated").param("roughness").default
        p.locator("#panel-a").screenshot(path=str(tmp_path / "coat-slider.png"))
        # the range is read from the declaration: a coat declared up to α = 0.5 gets a
        # slider to 0.5 while EON's r keeps [0, 1]
        ranges = p.evaluate(
            """async () => {
                const m = await import("./js/models.js");
                const records = await (await fetch("api/models")).json();
                for (const r of records) if (r.id === "coated") {
                    for (const q of r.parameters) if (q.name === "roughness") {
                        q.max = 0.5; q.fit_range = [0.0, 0.5];
                    }
                }
                m.setModels(records);
                return [m.PARAMS.coat_roughness.hi, m.PARAMS.roughness.hi];
            }"""
        )
        assert ranges == [0.5, _declared("eon", "roughness")[1]]
        assert not log.errors, log.errors
    finally:
        p.close()
