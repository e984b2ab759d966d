"""Photometric correction of images (roughdiffuse.planetary.correct, backplanes).

A moon: a sphere whose single-scattering albedo w varies with latitude and longitude
(0.25 ± 25 %), Hapke (B0 = 1.2, h = 0.06, ξ = −0.3, θ̄ = 20°) evaluated per pixel from
the backplanes of two geometries (phase 30° and 51°). Corrected with the "albedo" method and
Hapke at w = 0.25, both images must agree with each other, and with the albedo map — each
pixel's own Hapke I/F at the reference geometry i = e = g = 0 without the surge (ISIS's
standard conditions) — to 1 % where i, e < 70° (away from the limb and terminator).
Hapke's I/F is not proportional to w (multiple scattering), so the correction with one w is
not exact; the measured worst case is 0.6 %.

ISIS's mixed method is checked against its formula transcribed from ``Mixed.cpp``
(``Mixed::NormModelAlgorithm``) with ISIS's ``PhotoModel::PhtTopder`` evaluated here by
central differences on the Lambert model's closed form (a different route to the same
derivative); the backplanes against closed forms at full phase and at the terminator.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.planetary.backplanes import ellipsoid_backplanes
from roughdiffuse.planetary.correct import normalize, phototopder

HAPKE = {"b0": 1.2, "h": 0.06, "xi": -0.3, "theta_bar": math.radians(20.0)}


def albedo_map(lat, lon):
    return 0.25 * (1.0 + 0.15 * np.sin(3.0 * lon) * np.cos(lat) + 0.1 * np.cos(5.0 * lat))


def hapke_iof(w, inc, ema, pha, **p):
    """I/F of Hapke with a per-pixel w, through the model's kernel (π μ0 f)."""
    m = rd.Hapke(0.25, **p)
    mu0, mu = np.cos(inc), np.cos(ema)
    args = {k: np.full(w.shape, v) for k, v in p.items()}
    f = m.kernel(np, mu0, mu, np.cos(pha), albedo=w, hg2=np.zeros(w.shape), **args)
    return math.pi * mu0 * f


def moon(subsolar, shape=(96, 96)):
    bp = ellipsoid_backplanes(shape, subsolar, (0.0, 0.0))
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    iof = np.full(shape, np.nan)
    w = albedo_map(bp.latitude[lit], bp.longitude[lit])
    iof[lit] = hapke_iof(w, bp.incidence[lit], bp.emission[lit], bp.phase[lit], **HAPKE)
    truth = np.full(shape, np.nan)
    zero = np.zeros(w.shape)
    truth[lit] = hapke_iof(w, zero, zero, zero, **{**HAPKE, "b0": 0.0})
    return bp, iof, truth


def test_two_geometries_agree_after_correction():
    model = rd.Hapke(0.25, **HAPKE)
    out = []
    for sun in ((0.0, 30.0), (10.0, -50.0)):
        bp, iof, truth = moon(sun)
        corr = normalize(iof, bp.incidence, bp.emission, bp.phase, model)
        keep = bp.on_body & (bp.incidence < math.radians(70)) & (bp.emission < math.radians(70))
        assert keep.sum() > 1500
        np.testing.assert_allclose(corr[keep], truth[keep], rtol=0.01)
        out.append((corr, keep, truth))
    (a, ka, t), (b, kb, _) = out
    both = ka & kb
    assert both.sum() > 1000
    np.testing.assert_allclose(a[both], b[both], rtol=0.01)
    # before correction the two images differ by far more than that
    _, raw_a, _ = moon((0.0, 30.0))
    _, raw_b, _ = moon((10.0, -50.0))
    assert np.nanmax(np.abs(raw_a[both] / raw_b[both] - 1.0)) > 0.3


def test_nodata_and_limits_are_masked():
    bp, iof, _ = moon((0.0, 30.0), shape=(32, 32))
    iof[16, 16] = np.nan
    corr = normalize(
        iof,
        bp.incidence,
        bp.emission,
        bp.phase,
        rd.Hapke(0.25, **HAPKE),
        max_incidence=math.radians(60.0),
    )
    assert np.isnan(corr[16, 16])
    assert np.all(np.isnan(corr[bp.incidence > math.radians(60.0)]))
    assert np.all(np.isnan(corr[~bp.on_body]))
    lit = bp.on_body & (bp.incidence < math.radians(50))
    lit[16, 16] = False
    assert np.isfinite(corr[lit]).all()


def test_backplanes_closed_forms():
    bp = ellipsoid_backplanes((41, 41), (0.0, 0.0), (0.0, 0.0))
    on = bp.on_body
    np.testing.assert_allclose(bp.incidence[on], bp.emission[on], atol=1e-12)
    np.testing.assert_allclose(bp.phase[on], 0.0, atol=1e-12)
    # sun at 90° longitude: the terminator is the disk's vertical midline, g = 90°
    bp = ellipsoid_backplanes((41, 41), (0.0, 90.0), (0.0, 0.0))
    cos_i = np.cos(bp.latitude) * np.sin(bp.longitude)  # n·s with s = +y on a sphere
    np.testing.assert_allclose(np.cos(bp.incidence[bp.on_body]), cos_i[bp.on_body], atol=1e-12)
    assert bp.phase[20, 20] == pytest.approx(math.pi / 2)
    # an ellipsoid: the normal is the gradient of x²/a² + y²/b² + z²/c², not the radius
    bp = ellipsoid_backplanes((41, 41), (0.0, 0.0), (0.0, 0.0), radii=(1.0, 1.0, 0.5))
    assert bp.on_body.sum() < ellipsoid_backplanes((41, 41), (0, 0), (0, 0)).on_body.sum()


def test_mixed_against_isis_formula():
    """Lambert (P = μ0): Mixed::NormModelAlgorithm transcribed, with P′ by differences."""
    model = rd.Lambert(1.0)
    inc = np.radians([10.0, 40.0, 70.0, 80.0])
    ema = np.radians([5.0, 30.0, 20.0, 60.0])
    pha = np.radians([12.0, 50.0, 75.0, 95.0])
    dn = np.array([0.2, 0.15, 0.05, 0.02])

    def pprime(g, i, e):  # |∇μ0| for a tilt: sin i (the Lambert derivative), ISIS's floor
        return max(1e-15, math.sin(i))

    ref, mat = (0.0, 0.0, 0.0), (math.radians(45), math.radians(45), 0.0)
    p_ref, p_mat = math.cos(ref[1]), math.cos(mat[1])
    pp_ref, pp_mat = pprime(*ref), pprime(*mat)
    anum = math.sqrt(p_ref**2 + (p_mat * pp_ref / pp_mat) ** 2)
    expected = []
    for d, g, i, e in zip(dn, pha, inc, ema, strict=True):
        psurf = math.cos(i)
        aden = math.sqrt(max(1e-30, psurf**2 + (p_mat * pprime(g, i, e) / pp_mat) ** 2))
        expected.append(d * anum / aden + (1.0 / p_ref) * (p_ref - anum / aden * psurf))
    got = normalize(dn, inc, ema, pha, model, method="mixed", max_incidence=math.radians(89))
    # PhtTopder's 0.04° central difference of cos: relative error ~ (0.02°)² ~ 1e-7
    np.testing.assert_allclose(got, expected, rtol=1e-6)


def test_phototopder_of_lambert_is_sin_i():
    """ISIS divides the difference by eps = 0.04 in degrees: |∇P| per degree, sin i · π/180."""
    i = np.radians([20.0, 50.0, 80.0])
    e = np.radians([10.0, 30.0, 40.0])
    g = np.radians([25.0, 60.0, 100.0])
    np.testing.assert_allclose(
        phototopder(rd.Lambert(1.0), g, i, e), np.sin(i) * math.pi / 180, rtol=1e-6
    )


# ISIS's unit tests of its Topo and Shade normalisations (USGS ISIS3,
# isis/src/base/objs/Topo/Topo.truth and unitTest.cpp, Shade/Shade.truth and unitTest.cpp):
# Lambert photometric model, Albedo = 0.0690507 (Topo: Incref = 30, its reference geometry
# (g, i, e) = (Incref, Incref, 0)); (phase, incidence, emission) in degrees, dn, and the
# normalisation value as printed (6 significant digits).
ISIS_GEOMETRIES = [
    (86.7226722, 51.7002388, 38.9414439, 0.0800618902),
    (86.7207248, 51.7031305, 38.9372914, 0.0797334611),
    (86.7187773, 51.7060221, 38.9331391, 0.0794225037),
]


@pytest.mark.parametrize(
    ("method", "incref", "truth"),
    [
        ("topo", 30.0, ["0.0347164", "0.0347101", "0.0347042"]),
        ("shade", 0.0, ["0.042796", "0.0427932", "0.0427905"]),
    ],
)
def test_topo_and_shade_against_isis_truth(method, incref, truth):
    g, i, e, dn = (np.array(col) for col in zip(*ISIS_GEOMETRIES, strict=True))
    ref = math.radians(incref)
    got = normalize(
        dn,
        np.radians(i),
        np.radians(e),
        np.radians(g),
        rd.Lambert(1.0),
        method=method,
        albedo=0.0690507,
        reference=(ref, ref, 0.0),
    )
    assert [f"{v:.6g}" for v in got] == truth


def test_parameter_map_of_the_albedo_corrects_exactly():
    """With w given per pixel (a map of the truth) the albedo method is exact: each pixel's
    Hapke I/F at i = e = g = 0 without the surge, where one w gave 0.6 %."""
    bp, iof, truth = moon((0.0, 30.0))
    w = np.full(iof.shape, np.nan)
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    w[lit] = albedo_map(bp.latitude[lit], bp.longitude[lit])
    got = normalize(
        iof, bp.incidence, bp.emission, bp.phase, rd.Hapke(0.25, **HAPKE), params={"albedo": w}
    )
    keep = lit & (bp.incidence < math.radians(85)) & (bp.emission < math.radians(85))
    assert keep.sum() > 2500
    # rtol: the compiled float64 path against the NumPy one (tests/test_fastpath.py: 1e-9);
    # a scalar parameter runs compiled, a map of values may not
    np.testing.assert_allclose(got[keep], truth[keep], rtol=1e-9)
    # a map of one value is the scalar model, and a map's NaN is NoData
    b0 = np.full(iof.shape, HAPKE["b0"])
    b0[40, 40] = np.nan
    model = rd.Hapke(0.25, **HAPKE)
    one = normalize(iof, bp.incidence, bp.emission, bp.phase, model, method="mixed")
    mapped = normalize(
        iof, bp.incidence, bp.emission, bp.phase, model, method="mixed", params={"b0": b0}
    )
    assert np.isnan(mapped[40, 40]) and np.isfinite(one[40, 40])
    mapped[40, 40] = one[40, 40]
    np.testing.assert_allclose(mapped, one, rtol=1e-9, equal_nan=True)
