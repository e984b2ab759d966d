"""Every grey image that ``roughdiffuse figures`` and ``roughdiffuse plot roughness-series``
draw has a colour bar with a labelled scale beside its row (images sharing a scale share
one bar). Only the layout is checked: a flat disc stands in for each render."""

from __future__ import annotations

import io

import numpy as np
import pytest

from roughdiffuse import figures, plots

SLOW = pytest.mark.slow  # a few seconds each: their plane-of-incidence plots, the exact tables
DRAWN = (
    "1-lambert-sphere",
    "2-full-moon",
    "3-vase",
    "4-roughness-series",
    "6-blurred-highlights",
    pytest.param("7-diffuse-plus-specular", marks=SLOW),
    "8-models-side-by-side",
    pytest.param("9-production-models", marks=SLOW),
    pytest.param("11-against-the-truth", marks=SLOW),  # the exact surface's tables: 15 s
)


def flat_render(*args, **kwargs):  # noqa: ANN002, ANN003, ANN202
    """A disc of radiance 0.2 in place of a render (the image size is the 5th argument)."""
    size = kwargs.get("size", args[4] if len(args) > 4 else 16)
    n = size if isinstance(size, int) else size[0]
    y, x = np.mgrid[-1 : 1 : n * 1j, -1 : 1 : n * 1j]
    disc = (x**2 + y**2 < 1).astype(np.float32)
    return 0.2 * disc, disc


def colourbars(fig) -> list:  # noqa: ANN001
    """Every colour bar's axes: the figure's own and the insets of its axes."""
    axes = list(fig.axes) + [c for ax in fig.axes for c in ax.child_axes]
    return [ax for ax in axes if getattr(ax, "_colorbar", None) is not None]


def assert_every_image_row_has_a_bar(fig, name: str) -> None:  # noqa: ANN001
    fig.savefig(io.BytesIO(), dpi=30)  # lays the figure out: the insets get their places
    bars = colourbars(fig)
    for bar in bars:
        assert bar.get_ylabel(), (name, "a colour bar without a label")
    images = [ax for ax in fig.axes if ax.images and ax not in bars]
    assert images, name
    for ax in images:
        box = ax.get_position()
        beside = [b for b in bars if b.get_position().y0 < box.y1 and box.y0 < b.get_position().y1]
        assert beside, (name, ax.get_title(), "no colour bar beside this image's row")


@pytest.fixture()
def flat(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(figures, "SIZE", 16)
    monkeypatch.setattr(figures, "render", flat_render)
    monkeypatch.setattr(plots, "render", flat_render)


@pytest.mark.parametrize("name", DRAWN)
def test_figure_images_have_colour_bars(flat, monkeypatch, name: str) -> None:  # noqa: ANN001
    # figure 11 fits EON to the exact surface first: a stand-in for the fit
    monkeypatch.setattr(figures, "_eon_fitted_to", lambda truth: (0.8, 0.3))
    entry = next(f for f in figures.FIGURES if f.name == name)
    assert_every_image_row_has_a_bar(entry.draw(), name)


def test_radiance_bar_scale_and_label() -> None:
    from roughdiffuse._figure import subplots

    fig, ax = subplots()
    plots.show_radiance(ax, np.full((4, 4), 0.3), 0.5)
    bar = plots.radiance_colorbar(ax, 0.5)
    assert bar.norm.vmin == 0.0 and bar.norm.vmax == 0.5  # show_radiance's scale
    assert "sr⁻¹" in bar.ax.get_ylabel()
    assert fig.axes == [ax]  # an inset: the figure's list of axes is unchanged


def test_cli_roughness_series_has_a_colour_bar(flat, monkeypatch, tmp_path) -> None:  # noqa: ANN001
    from roughdiffuse.cli import main

    drawn = []
    series = plots.plot_roughness_series
    monkeypatch.setattr(
        plots, "plot_roughness_series", lambda *a, **k: drawn.append(series(*a, **k)) or drawn[-1]
    )
    out = tmp_path / "s.png"
    assert main(["plot", "roughness-series", "--model", "oren-nayar", "--sigma", "0,20",
                 "--size", "16", "--spp", "1", "-o", str(out)]) == 0  # fmt: skip
    assert out.is_file()
    (fig,) = drawn
    assert [ax.get_title() for ax in fig.axes] == ["σ = 0°", "σ = 20°"]  # insets not titled
    assert_every_image_row_has_a_bar(fig, "plot roughness-series")
