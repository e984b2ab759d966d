"""USGS ISIS3's unit-test truth files of the simple photometric functions, reproduced.

Each value below is printed (6 significant digits) in the file named beside it, from
``isis/src/base/objs/<Model>/<Model>.truth`` of USGS-Astrogeology/ISIS3, whose
``unitTest.cpp`` calls ``PhotoModel::CalcSurfAlbedo(phase, incidence, emission)`` (degrees)
and prints the radiance factor I/F. Hapke, HapkeLeg and Minnaert are in
``test_models_photometric.py``.

ISIS's functions, transcribed (``PhotoModelAlgorithm`` of each ``.cpp``): Lambert μ0;
LommelSeeliger 2μ0/(μ0 + μ); LunarLambert μ0 [(1 − L) + 2L/(μ0 + μ)]; LunarLambertEmpirical
the same with L(g) and a factor B(g) interpolated by ``NumericalApproximation::CubicClamped``
with end derivatives 1e30, which (as in Numerical Recipes' ``spline``) is the natural spline.
Each returns 0 where μ0 <= 0 or μ <= 0; at i = e = 90° cos(90°) = 6e-17 > 0 in floating point,
so LunarLambertEmpirical's last value is B(180°) L(180°), not 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

import roughdiffuse as rd
from roughdiffuse.models.photometry import radiance_factor

CASES = [(0.0, 0.0, 0.0), (60.0, 45.0, 30.0)]  # (phase, incidence, emission), degrees


def _radf(model, phase, inc, ema):
    return float(radiance_factor(model, *np.radians([inc, ema, phase])))


def _digits(expected):
    """Half a unit in the 6th significant digit ISIS prints."""
    return 0.5 * 10 ** (math.floor(math.log10(abs(expected))) - 5) if expected else 1e-12


@pytest.mark.parametrize(
    ("source", "build", "expected"),
    [
        ("Lambert/Lambert.truth", lambda: rd.Lambert(1.0), [1.0, 0.707107]),
        # ISIS's LommelSeeliger is 2μ0/(μ0 + μ): roughdiffuse's (w/4)μ0/(μ0 + μ) times 8
        ("LommelSeeliger/LommelSeeliger.truth", lambda: rd.LommelSeeliger(1.0), [1.0, 0.898979]),
        (
            "LunarLambert/LunarLambert.truth (L = 1)",
            lambda: rd.LunarLambert(1.0, 1.0),
            [1.0, 0.898979],
        ),
        (
            "LunarLambert/LunarLambert.truth (L = 0)",
            lambda: rd.LunarLambert(1.0, 0.0),
            [1.0, 0.707107],
        ),
        (
            "LunarLambert/LunarLambert.truth (L = 0.5)",
            lambda: rd.LunarLambert(1.0, 0.5),
            [1.0, 0.803043],
        ),
        (
            "LunarLambert/LunarLambert.truth (L = 2)",
            lambda: rd.LunarLambert(1.0, 2.0),
            [1.0, 1.09085],
        ),
    ],
    ids=lambda x: x if isinstance(x, str) else "",
)
def test_isis_truth(source, build, expected):
    model = build()
    scale = 8.0 if source.startswith("LommelSeeliger") else 1.0
    for (phase, inc, ema), value in zip(CASES, expected, strict=True):
        assert scale * _radf(model, phase, inc, ema) == pytest.approx(value, abs=_digits(value))
    # the third case of every truth file: phase 180, incidence 90, emission 90 -> 0
    assert _radf(model, 180.0, 90.0, 90.0) == 0.0


# LunarLambertEmpirical/LunarLambertEmpirical.truth: its first table (the unit test's PVL)
PHASES = np.arange(0.0, 181.0, 10.0)
L_LIST = [
    0.986,
    0.778,
    0.641,
    0.545,
    0.457,
    0.372,
    0.289,
    0.211,
    0.143,
    0.086,
    0.041,
    0.009,
    -0.009,
    -0.020,
    -0.025,
    -0.029,
    -0.027,
    -0.011,
    -0.010,
]
B_LIST = [
    0.03338,
    0.03386,
    0.03350,
    0.03247,
    0.03109,
    0.02949,
    0.02780,
    0.02608,
    0.02432,
    0.02246,
    0.02050,
    0.01832,
    0.01599,
    0.01363,
    0.01134,
    0.009113,
    0.006710,
    0.003510,
    0.0,
]
EMPIRICAL_TRUTH = [  # (phase, incidence, emission, I/F)
    ((0.0, 0.0, 0.0), 0.03338),
    ((38.0, 11.0, 20.0), 0.0314089),
    ((65.0, 45.0, 30.0), 0.0203387),
    ((127.0, 52.0, 33.0), 0.0087672),
]
# its second table: PhaseList 0..140 by 10, LList = phase/100, PhaseCurveList = 0.03 phase
EMPIRICAL_TRUTH_2 = [
    ((38.0, 11.0, 20.0), 1.13647),
    ((65.0, 45.0, 30.0), 1.62206),
    ((127.0, 52.0, 33.0), 3.4634),
]


@pytest.mark.parametrize(
    ("table", "truth"),
    [
        ((PHASES, L_LIST, B_LIST), EMPIRICAL_TRUTH),
        ((PHASES[:15], PHASES[:15] / 100, PHASES[:15] * 0.03), EMPIRICAL_TRUTH_2),
    ],
)
def test_lunar_lambert_empirical_truth(table, truth):
    """ISIS's LunarLambertEmpirical is roughdiffuse's Lunar-Lambert with L = L(g), scaled by
    B(g). Where the interpolated L is negative (g = 127° of the first table: L = −0.0174)
    roughdiffuse's Lunar-Lambert (L >= 0) cannot take it; there the ISIS formula is checked."""
    phases, ls, bs = table
    l_of, b_of = (
        CubicSpline(phases, ls, bc_type="natural"),
        CubicSpline(phases, bs, bc_type="natural"),
    )
    for (phase, inc, ema), value in truth:
        ell, b = float(l_of(phase)), float(b_of(phase))
        if ell >= 0.0:
            # ISIS's test angles are not all one geometry (g = 38° > i + e = 31°); the
            # Lunar-Lambert function does not depend on g, so it is evaluated at g = i + e
            got = b * _radf(rd.LunarLambert(1.0, ell), inc + ema, inc, ema)
        else:
            mu0, mu = math.cos(math.radians(inc)), math.cos(math.radians(ema))
            got = b * mu0 * ((1.0 - ell) + 2.0 * ell / (mu0 + mu))
        assert got == pytest.approx(value, abs=_digits(value))
