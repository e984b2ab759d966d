"""The captions of ``roughdiffuse figures`` (figures/index.html) describe what is drawn."""

from __future__ import annotations

import numpy as np
import pytest

from roughdiffuse import figures

NUMBERS = {"Two": 2, "Three": 3, "Four": 4, "Five": 5, "Six": 6}


def test_full_moon_caption_counts_and_names_the_spheres(monkeypatch: pytest.MonkeyPatch) -> None:
    # only the layout is checked: a flat disc stands in for each render
    monkeypatch.setattr(figures, "SIZE", 16)
    monkeypatch.setattr(figures, "render", lambda *a, size, **k: (np.ones((size, size)),
                                                                  np.ones((size, size))))
    entry = next(f for f in figures.FIGURES if f.name == "2-full-moon")
    fig = entry.draw()
    spheres = [ax for ax in fig.axes if ax.images]
    first = entry.caption.split()[0]
    assert NUMBERS.get(first) == len(spheres) == 5, (first, len(spheres))
    for ax in spheres:  # each sphere's model is named in the caption
        name = ax.get_title().split(",")[0].split(" (")[0]
        assert name.split()[0] in entry.caption, name
