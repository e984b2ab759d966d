"""Ground truth in, model out: the full Oren–Nayar model fitted to the V-cavity solver.

The tolerance and the reasons for it are in docs/fitting.md ("Ground truth in, model out"):
for σ in [0.1, 0.3] and the solid-angle reading of the slope distribution, the fitted σ is
within 15% of the solver's and ρ within 0.02 (the model is an approximation of the solver,
so the difference is model error, not noise).
"""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.fit import Measurements, fit

surface = pytest.importorskip("roughdiffuse.simulate.surface")


def test_full_oren_nayar_recovers_solver_sigma() -> None:
    sigma, albedo = 0.2, 0.8
    g = np.radians([0.0, 25.0, 50.0, 70.0])
    ti, tr, dp = np.meshgrid(g, g, np.radians([0.0, 90.0, 180.0]), indexing="ij")
    ti, tr, dp = ti.ravel(), tr.ravel(), dp.ravel()
    f = surface.brdf(
        ti, tr, dp, sigma, albedo, bounces="all", settings=surface.Settings(measure="solid-angle")
    )
    r = fit(
        rd.OrenNayar,
        Measurements.from_angles(ti, tr, dp, f),
        fixed={"variant": "full"},
        noise="relative",
    )
    assert abs(r.values[1] / sigma - 1) <= 0.15, r.values
    assert abs(r.values[0] - albedo) <= 0.02, r.values
    assert r.rms_relative < 0.05
