"""The explorer and the planetary models: B0's slider follows its declaration (unbounded above:
the declared fit box [0, 3] is the slider's range), and the variants without a GLSL copy of
their formula (Hapke–Legendre, Hapke 2012) are listed as left out, not offered."""

from __future__ import annotations

import roughdiffuse as rd
from explorer_browser import open_page


def test_b0_slider_and_left_out_variants(browser, explorer_url):
    log = open_page(browser, explorer_url, 1000, 700)
    p = log.page
    try:
        declared = {q.name: q for q in rd.Hapke.params}["b0"]
        assert declared.max is None and declared.fit_range == (0.0, 3.0)
        slider = p.locator("#a-b0")
        assert float(slider.get_attribute("min")) == 0.0
        assert float(slider.get_attribute("max")) == 3.0
        p.select_option("#a-model", "hapke")
        slider.fill("2.5")
        assert p.locator("#a-b0-out").inner_text() == "2.50"
        left_out = p.locator("#models-left-out").inner_text()
        assert "hapke-legendre" in left_out and "hapke-2012" in left_out
        options = p.locator("#a-model option").evaluate_all("os => os.map(o => o.value)")
        assert "hapke" in options and "hapke-2012" not in options
        assert not log.errors, log.errors
    finally:
        p.close()
