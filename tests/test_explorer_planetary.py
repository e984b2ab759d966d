"""The explorer and the planetary models: B0's slider follows its declaration (accepted up to
1000: the declared fit box [0, 3] is the slider's range); every Hapke variant is offered (its GLSL
printed from its code), and only the models that are not formulas are listed as left out."""

from __future__ import annotations

import roughdiffuse as rd
from explorer_browser import open_page


def test_b0_slider_and_every_hapke_variant_offered(browser, explorer_url):
    log = open_page(browser, explorer_url, 1000, 700)
    p = log.page
    try:
        declared = {q.name: q for q in rd.Hapke.params}["b0"]
        assert declared.max == 1e3 and declared.fit_range == (0.0, 3.0)
        slider = p.locator("#a-b0")
        assert float(slider.get_attribute("min")) == 0.0
        assert float(slider.get_attribute("max")) == 3.0
        p.select_option("#a-model", "hapke")
        slider.fill("2.5")
        assert p.locator("#a-b0-out").inner_text() == "2.50"
        left_out = p.locator("#models-left-out").inner_text()
        assert "hapke" not in left_out
        assert "v-cavity" in left_out and "smith-diffuse-ggx" in left_out
        options = p.locator("#a-model option").evaluate_all("os => os.map(o => o.value)")
        assert {"hapke", "hapke-legendre", "hapke-2012"} <= set(options)
        assert "v-cavity" not in options
        assert not log.errors, log.errors
    finally:
        p.close()
