"""Plots: the plane-of-incidence curves against the closed forms, cross-sections, legends."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import plots


def test_lambert_is_flat_in_the_plane_of_incidence():
    tr = np.radians(np.linspace(-89, 89, 7))
    vals = plots.plane_of_incidence(rd.Lambert(0.6), math.radians(50), tr, irradiance=2.0)
    np.testing.assert_allclose(vals, 0.6 / np.pi * 2.0 * math.cos(math.radians(50)), rtol=1e-12)


def test_oren_nayar_backscatter_and_forward_sides():
    rho, sigma, ti = 0.8, 0.5, math.radians(40)
    s2 = sigma**2
    a, b = 1 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)
    tr = np.radians([40.0, 70.0, -70.0])
    vals = plots.plane_of_incidence(rd.OrenNayar(rho, sigma), ti, tr)
    # on the light's side (Δφ = 0): α = max, β = min; on the mirror side max(0, cos π) = 0
    back = [np.sin(ti) * np.tan(ti), np.sin(tr[1]) * np.tan(ti)]
    expected = rho / np.pi * np.cos(ti) * np.array([a + b * back[0], a + b * back[1], a])
    np.testing.assert_allclose(vals, expected, rtol=1e-6)


def test_plane_of_incidence_rejects_bad_angles():
    with pytest.raises(ValueError, match="theta_i"):
        plots.plane_of_incidence(rd.Lambert(0.5), 2.0, np.zeros(2))
    with pytest.raises(ValueError, match="theta_r"):
        plots.plane_of_incidence(rd.Lambert(0.5), 0.2, np.array([2.0]))


def test_cross_section_masks_and_coordinates():
    img = np.arange(12, dtype=float).reshape(3, 4)
    mask = np.array([[0, 1, 0.5, 0.4]] * 3, float)
    x, v = plots.cross_section(img, mask=mask)
    np.testing.assert_allclose(x, [-0.75, -0.25, 0.25, 0.75])
    assert np.isnan(v[0]) and np.isnan(v[3]) and v[1] == 5 and v[2] == 12  # 6 / 0.5
    with pytest.raises(ValueError, match="row"):
        plots.cross_section(img, row=5)


def test_plots_have_legends_and_labels():
    models = {"Lambert": rd.Lambert(0.8), "ON": rd.OrenNayar(0.8, 0.3)}
    ax = plots.plot_plane_of_incidence(models, math.radians(30))
    assert [t.get_text() for t in ax.get_legend().get_texts()] == ["Lambert", "ON"]
    assert "θr" in ax.get_xlabel() and ax.get_ylabel()
    pax = plots.plot_plane_of_incidence(models, math.radians(30), polar=True)
    assert pax.name == "polar" and pax.get_legend() is not None
    cax = plots.plot_cross_section({"a": np.ones((4, 4))})
    assert cax.get_legend() is not None and cax.get_xlabel()


def test_roughness_series_has_one_panel_per_sigma():
    fig = plots.plot_roughness_series(lambda s: rd.OrenNayar(0.8, s), (0.0, 0.3), size=16)
    titles = [ax.get_title() for ax in fig.axes]
    assert titles == ["σ = 0 rad", "σ = 0.3 rad"]
    first = fig.axes[0].get_images()[0].get_array()
    second = fig.axes[1].get_images()[0].get_array()
    # head-on: roughness lowers the centre (A < 1) and brightens the limb relative to it
    assert second[8, 8] < first[8, 8]


def test_plots_register_their_figures_with_pyplot():
    """A figure made without ``ax=`` is known to pyplot (so ``plt.show()`` and Jupyter show
    it), and making it does not change the backend the user has."""
    import matplotlib
    import matplotlib.pyplot as plt

    from roughdiffuse.energy import plot_albedo

    backend = matplotlib.get_backend()
    plt.close("all")
    try:
        ax = plots.plot_plane_of_incidence({"Lambert": rd.Lambert(0.5)}, 0.3, n=5)
        assert plt.get_fignums() == [ax.figure.number]
        plots.plot_cross_section({"a": np.ones((4, 4))})
        fig = plot_albedo({"Lambert": {"ρ = 1": rd.Lambert(1.0)}}, np.radians([0.0, 45.0]))
        assert len(plt.get_fignums()) == 3 and fig.number in plt.get_fignums()
        own = plt.figure()  # with ax=, the caller's figure is drawn on: no new one
        plots.plot_plane_of_incidence({"Lambert": rd.Lambert(0.5)}, 0.3, ax=own.gca(), n=5)
        assert len(plt.get_fignums()) == 4
        assert matplotlib.get_backend() == backend
    finally:
        plt.close("all")
