"""Planetary units and angles (roughdiffuse.planetary.conventions) against closed forms.

References: Hapke 2012, Eq. 10.5–10.9 (r = f μ0, I/F = π r, REFF = π f) on a white Lambertian
surface (f = 1/π: I/F = cos i, REFF = 1); the phase angle from the two direction vectors'
dot product (vectors built from (θi, θr, Δφ) in the surface frame, another algorithm than the
law of cosines the module uses).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.models.photometry import radiance_factor
from roughdiffuse.planetary import convert, local_to_photometric, photometric_to_local


def _vec(theta, phi):
    return np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1
    )


def test_units_on_a_white_lambertian_surface():
    i = np.radians([0.0, 30.0, 60.0, 89.0])
    f = np.full(4, 1.0 / math.pi)
    np.testing.assert_allclose(convert(f, "brdf", "iof", i), np.cos(i), rtol=1e-14)
    np.testing.assert_allclose(convert(f, "brdf", "reff", i), 1.0, rtol=1e-14)
    np.testing.assert_allclose(convert(f, "brdf", "r", i), np.cos(i) / math.pi, rtol=1e-14)
    np.testing.assert_allclose(convert(np.cos(i), "iof", "reff", i), 1.0, rtol=1e-12)
    for a in ("brdf", "r", "iof", "reff"):
        for b in ("brdf", "r", "iof", "reff"):
            back = convert(convert(f, "brdf", a, i), a, b, i)
            np.testing.assert_allclose(back, convert(f, "brdf", b, i), rtol=1e-12)


def test_unlit_is_nan_not_inf():
    assert np.isnan(convert(0.3, "iof", "brdf", math.pi / 2))


def test_angles_against_vectors(rng):
    n = 500
    ti, tr = rng.uniform(0, math.pi / 2, n), rng.uniform(0, math.pi / 2, n)
    dphi = rng.uniform(0, math.pi, n)
    cos_g = np.sum(_vec(ti, 0.0) * _vec(tr, dphi), axis=-1)
    i, e, g = local_to_photometric(ti, tr, dphi)
    np.testing.assert_allclose(np.cos(g), cos_g, atol=1e-12)
    ti2, tr2, dphi2 = photometric_to_local(i, e, g)
    np.testing.assert_allclose(ti2, ti, rtol=0, atol=0)
    keep = np.sin(ti) * np.sin(tr) > 1e-3  # Δφ is ill-conditioned near the zenith
    np.testing.assert_allclose(dphi2[keep], dphi[keep], atol=1e-6)


@pytest.mark.parametrize(
    ("iedeg", "dphi"),
    [
        ((0.0, 40.0, 40.0), 0.0),
        ((35.0, 0.0, 35.0), 0.0),
        ((30.0, 40.0, 10.0), 0.0),
        ((30.0, 40.0, 70.0), 180.0),
        ((0.0, 0.0, 0.0), 0.0),
    ],
)
def test_degenerate_and_limiting_geometries(iedeg, dphi):
    _, _, got = photometric_to_local(*np.radians(iedeg))
    assert math.degrees(float(got)) == pytest.approx(dphi, abs=1e-6)


@pytest.mark.parametrize(
    ("args", "match"),
    [
        ((0.3, 0.2, 3.5), "phase must be in"),
        ((-0.1, 0.2, 0.2), "incidence must be in"),
        ((0.3, 1.7, 1.6), "emission must be in"),
        ((0.3, 0.2, 1.0), r"phase must be in \[\|incidence − emission\|"),
        ((0.3, float("nan"), 0.2), "emission"),
    ],
)
def test_bad_angles_are_refused(args, match):
    with pytest.raises(ValueError, match=match):
        photometric_to_local(*args)


def test_radiance_factor_uses_the_same_azimuth():
    """The models' I/F at (i, e, g) is π μ0 f at the (θi, θr, Δφ) the module gives."""
    m = rd.Hapke(0.4, 1.5, 0.06, -0.3, 0.4, 0.2)
    i, e, g = np.radians([50.0, 30.0, 65.0])
    ti, tr, dp = photometric_to_local(i, e, g)
    f = float(m.brdf(_vec(ti, 0.0), _vec(tr, dp)))
    assert float(radiance_factor(m, i, e, g)) == pytest.approx(math.pi * math.cos(i) * f, rel=1e-12)
