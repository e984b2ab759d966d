"""Planetary photometry (Hapke, Minnaert) and d'Eon's Lambert spheres against public code.

References transcribed from their sources into scalar Python on angles in degrees, as the
sources take them: USGS ISIS3 ``isis/src/base/objs/Hapke/Hapke.cpp``
(``Hapke::PhotoModelAlgorithm``, with ``PhotoModel::Hfunc``) and its ``Hapke.truth``;
``isis/src/base/objs/Minnaert/Minnaert.cpp`` and ``Minnaert.truth``; ``eugenedeon/mitsuba``
``src/bsdfs/lambert_sphere.cpp`` and ``lambert_sphere_fast.cpp``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from conftest import midpoint_albedo, random_hemisphere
from roughdiffuse.models.photometry import radiance_factor

PI = math.pi


# --- ISIS3 Hapke::PhotoModelAlgorithm (HapkeHen), angles in degrees -> I/F ----------------
def isis_hapke(phase, incidence, emission, wh, b0, hh, theta, hg1, hg2, legendre=None):
    """ISIS's HapkeHen; with ``legendre=(bh, ch)`` its HapkeLeg (hg1, hg2 then unused)."""
    def hfunc(u, gamma):  # PhotoModel::Hfunc
        return (1.0 + 2.0 * u) / (1.0 + 2.0 * u * gamma)

    pharad, incrad, emarad = (x * PI / 180.0 for x in (phase, incidence, emission))
    munot, mu = math.cos(incrad), math.cos(emarad)
    cost, sint = math.cos(theta * PI / 180.0), math.sin(theta * PI / 180.0)
    cott = cost / max(1.0e-10, sint)
    cot2t = cott * cott
    tant = sint / cost
    tan2t = tant * tant
    sr = math.sqrt(1.0 + PI * tan2t)
    osr = 1.0 / sr
    if incidence >= 90.0:
        return 0.0
    gamma = math.sqrt(1.0 - wh)
    hgs = hg1 * hg1
    cosg = math.cos(pharad)
    tang2 = math.tan(pharad / 2.0)
    bg = 0.0 if hh == 0.0 else b0 / (1.0 + tang2 / hh)
    pg1 = (1.0 - hg2) * (1.0 - hgs) / (1.0 + hgs + 2.0 * hg1 * cosg) ** 1.5
    pg2 = hg2 * (1.0 - hgs) / (1.0 + hgs - 2.0 * hg1 * cosg) ** 1.5
    pg = pg1 + pg2
    if legendre is not None:  # Hapke Legendre
        bh, ch = legendre
        pg = 1.0 + bh * cosg + ch * (1.5 * cosg**2.0 - 0.5)
    if theta <= 0.0:
        return (
            wh
            / 4.0
            * munot
            / (munot + mu)
            * ((1.0 + bg) * pg - 1.0 + hfunc(munot, gamma) * hfunc(mu, gamma))
        )
    sini = math.sin(incrad)
    coti = munot / max(1.0e-10, sini)
    cot2i = coti * coti
    ecoti = math.exp(min(-cot2t * cot2i / PI, 23.0))
    ecot2i = math.exp(min(-2.0 * cott * coti / PI, 23.0))
    u0p0 = osr * (munot + sini * tant * ecoti / (2.0 - ecot2i))
    sine = math.sin(emarad)
    cote = mu / max(1.0e-10, sine)
    cot2e = cote * cote
    cosei = mu * munot
    sinei = sine * sini
    if sinei == 0.0:
        caz, az = 1.0, 0.0
    else:
        caz = (cosg - cosei) / sinei
        if caz <= -1.0:
            az = 180.0
        elif caz > 1.0:
            az = 0.0
        else:
            az = math.acos(caz) * 180.0 / PI
    az2 = az / 2.0
    faz = 0.0 if az2 >= 90.0 else math.exp(min(-2.0 * math.tan(az2 * PI / 180.0), 23.0))
    sin2a2 = math.sin(az2 * PI / 180.0) ** 2
    api = az / 180.0
    ecote = math.exp(min(-cot2t * cot2e / PI, 23.0))
    ecot2e = math.exp(min(-2.0 * cott * cote / PI, 23.0))
    up0 = osr * (mu + sine * tant * ecote / (2.0 - ecot2e))
    q = osr * munot / u0p0 if incidence <= emission else osr * mu / up0
    if incidence <= emission:
        ecei = 2.0 - ecot2e - api * ecot2i
        s2ei = sin2a2 * ecoti
        u0p = osr * (munot + sini * tant * (caz * ecote + s2ei) / ecei)
        up = osr * (mu + sine * tant * (ecote - s2ei) / ecei)
    else:
        ecee = 2.0 - ecot2i - api * ecot2e
        s2ee = sin2a2 * ecote
        u0p = osr * (munot + sini * tant * (ecoti - s2ee) / ecee)
        up = osr * (mu + sine * tant * (caz * ecoti + s2ee) / ecee)
    rr1 = (
        wh / 4.0 * u0p / (u0p + up) * ((1.0 + bg) * pg - 1.0 + hfunc(u0p, gamma) * hfunc(up, gamma))
    )
    rr2 = up * munot / (up0 * u0p0 * sr * (1.0 - faz + faz * q))
    return rr1 * rr2


def _hapke(wh, b0, hh, theta_deg, hg1, hg2=0.0):
    """roughdiffuse's Hapke for ISIS's HapkeHen parameters (Theta in degrees)."""
    return rd.Hapke(wh, b0, hh, hg1, math.radians(theta_deg), hg2)


TRUTH = [
    # (Wh, B0, Hh, Theta, Hg1, Hg2), [(phase, incidence, emission, I/F)] from Hapke.truth
    ((0.5, 0.0, 0.0, 0.0, 0.0, 0.0), [(0, 0, 0, 0.0965097), (60, 45, 30, 0.0832883)]),
    ((0.52, 1.0, 1.0, 30.0, 0.213, 1.0), [(0, 0, 0, 0.286048), (60, 45, 30, 0.1342)]),
]
# HapkeLeg (Wh, B0, Hh, Bh, Ch, Theta) from the same Hapke.truth
TRUTH_LEG = ((0.52, 1.0, 1.0, 0.0, 0.0, 30.0), [(0, 0, 0, 0.16145), (60, 45, 30, 0.111525)])


@pytest.mark.parametrize(("params", "cases"), TRUTH)
def test_hapke_reproduces_isis_truth(params, cases):
    model = _hapke(*params)
    for phase, inc, ema, expected in cases:
        got = float(radiance_factor(model, *np.radians([inc, ema, phase])))
        assert got == pytest.approx(expected, abs=6e-7 * max(1.0, expected / 0.1))  # 6 digits


def test_hapke_leg_reproduces_isis_truth():
    (wh, b0, hh, bh, ch, theta), cases = TRUTH_LEG
    model = rd.HapkeLegendre(wh, b0, hh, bh, ch, math.radians(theta))
    for phase, inc, ema, expected in cases:
        got = float(radiance_factor(model, *np.radians([inc, ema, phase])))
        assert got == pytest.approx(expected, abs=6e-7 * max(1.0, expected / 0.1))


def test_hapke_b0_above_one_as_isis():
    """ISIS accepts any B0 >= 0 (Hapke::SetPhotoB0): B0 = 2.5 against its formula."""
    got = float(radiance_factor(_hapke(0.3, 2.5, 0.05, 20.0, -0.3), *np.radians([10, 15, 5])))
    assert got == pytest.approx(isis_hapke(5, 10, 15, 0.3, 2.5, 0.05, 20.0, -0.3, 0.0), rel=1e-12)


def _random_photometric_angles(rng, n):
    inc = rng.uniform(0.5, 89.0, n)
    ema = rng.uniform(0.5, 89.0, n)
    az = rng.uniform(0.5, 179.5, n)
    ri, re = np.radians(inc), np.radians(ema)
    cosg = np.cos(ri) * np.cos(re) + np.sin(ri) * np.sin(re) * np.cos(np.radians(az))
    return inc, ema, np.degrees(np.arccos(cosg))


@pytest.mark.parametrize(
    "params",
    # (b, c) whose phase function 1 + b x + c P2(x) is non-negative on [-1, 1]: the others
    # are refused (models.constraints)
    [(0.52, 1.0, 1.0, 30.0, -0.4, 0.3), (0.3, 2.2, 0.05, 15.0, 0.7, -0.2), (0.9, 0, 0, 0, 1, 1)],
)
def test_hapke_legendre_against_isis_formula(rng, params):
    wh, b0, hh, theta, bh, ch = params
    model = rd.HapkeLegendre(wh, b0, hh, bh, ch, math.radians(theta))
    inc, ema, phase = _random_photometric_angles(rng, 300)
    expected = [
        isis_hapke(p, i, e, wh, b0, hh, theta, 0.0, 0.0, legendre=(bh, ch))
        for p, i, e in zip(phase, inc, ema, strict=True)
    ]
    got = radiance_factor(model, *np.radians([inc, ema, phase]))
    np.testing.assert_allclose(got, expected, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize(
    "params",
    [
        (0.52, 1.0, 1.0, 30.0, 0.213, 1.0),
        (0.4, 1.8, 0.07, 25.0, 0.45, 0.65),
        (0.3, 0.6, 0.05, 15.0, 0.3, 0.0),
        (0.9, 0.0, 0.0, 45.0, -0.4, 0.0),
        (0.7, 0.4, 0.2, 0.0, 0.1, 0.0),
    ],
)
def test_hapke_against_isis_formula(rng, params):
    model = _hapke(*params)
    inc, ema, phase = _random_photometric_angles(rng, 300)
    expected = [isis_hapke(p, i, e, *params) for p, i, e in zip(phase, inc, ema, strict=True)]
    got = radiance_factor(model, *np.radians([inc, ema, phase]))
    np.testing.assert_allclose(got, expected, rtol=1e-9)


def test_hapke_reciprocal_with_roughness(rng):
    wi, wo = random_hemisphere(rng, 3000), random_hemisphere(rng, 3000)
    m = rd.Hapke(0.6, 0.9, 0.08, -0.35, 0.5)
    np.testing.assert_allclose(m.brdf(wi, wo), m.brdf(wo, wi), rtol=1e-10)


def test_hapke_smooth_w1_isotropic_albedo():
    """θ̄ = 0, B0 = 0, ξ = 0, w = 1: f = (H(μ0) H(μ))/(4π (μ0 + μ)), which with the exact H
    conserves energy; Hapke's (1 + 2x)/(1 + 2x√(1−w)) approximation overestimates H(1) = 2.9078
    (exact) as 3, so the normal albedo lies within 4 % of 1."""
    m = rd.Hapke(1.0, 0.0, 0.0, 0.0, 0.0)
    a = float(m.directional_albedo(np.array([0.0, 0.0, 1.0])))
    assert abs(a - 1.0) < 0.04
    assert a == pytest.approx(float(midpoint_albedo(m, 1.0)), abs=2e-5)


# --- ISIS3 Minnaert::PhotoModelAlgorithm --------------------------------------------------
def isis_minnaert(phase, incidence, emission, k):
    munot, mu = math.cos(math.radians(incidence)), math.cos(math.radians(emission))
    if munot <= 0.0 or mu <= 0.0 or incidence == 90.0 or emission == 90.0:
        return 0.0
    if k == 1.0:
        return munot
    return munot * (munot * mu) ** (k - 1.0)


@pytest.mark.parametrize(
    ("k", "expected"), [(1.0, 0.707107), (0.0, 1.1547), (0.5, 0.903602), (2.0, 0.433013)]
)
def test_minnaert_isis_truth_and_formula(rng, k, expected):
    model = rd.Minnaert(1.0, k)
    got = float(radiance_factor(model, *np.radians([45.0, 30.0, 60.0])))
    assert got == pytest.approx(expected, abs=5e-7 * max(1.0, expected))
    inc, ema = rng.uniform(1, 89, 200), rng.uniform(1, 89, 200)
    phase = np.abs(inc - ema) + 0.5 * (inc + ema - np.abs(inc - ema))
    ref = [isis_minnaert(p, i, e, k) for p, i, e in zip(phase, inc, ema, strict=True)]
    np.testing.assert_allclose(
        radiance_factor(model, *np.radians([inc, ema, phase])), ref, rtol=1e-12
    )


def test_minnaert_k1_is_lambert_and_albedo_closed_form(rng):
    wi, wo = random_hemisphere(rng, 1000), random_hemisphere(rng, 1000)
    np.testing.assert_allclose(rd.Minnaert(0.6, 1.0).brdf(wi, wo), 0.6 / math.pi, rtol=1e-14)
    m = rd.Minnaert(0.8, 1.4)
    for mu in (0.9, 0.4):
        wo1 = np.array([math.sqrt(1 - mu * mu), 0.0, mu])
        assert float(m.directional_albedo(wo1)) == pytest.approx(
            float(midpoint_albedo(m, mu)), abs=1e-5
        )


# --- eugenedeon/mitsuba src/bsdfs/lambert_sphere.cpp -------------------------------------
def deon_c_from_kd(kd):
    return (1 - (1 - kd) ** 2.73556) / (1 - 0.184096 * (1 - kd) ** 2.48423)


def deon_phase(u):
    return (2 * (math.sqrt(1 - u * u) - u * math.acos(u))) / (3.0 * PI * PI)


def deon_h0(u, c):
    cc = math.sqrt(1.0 - c)
    a = (8.216443463470172 + 1.501116252342486 * cc**6.054351911707695) / (
        4.175932557866179 - 1.2122216865199813 * cc
    )
    d = (7.773097842804312 - 0.5658108102188075 * cc**0.9615460393324836) / (
        8.659120811349371 - 0.15997430541238322 * cc**7
    )
    root = math.sqrt(max(0.0, 1 - 2 * ((89 * c) / 288.0 + (59 * c * c) / 288.0 - c**3 / 72.0)))
    return (1 + a * u**d) / (1 + a * root * u**d)


def deon_h1(u, c):
    return math.exp(
        (-0.14483935877260054 * c + 0.024285125615255733 * c * c)
        * u
        ** (
            0.45944184025347456
            - 1.0787917226917565 * u
            + 1.8572804924335546 * u**2
            - 1.1283119660147671 * u**3
        )
    )


def deon_f0(ui, uo, c):
    s = math.sqrt(1 - c)
    a = (69 * c) / 128.0
    b = (
        -0.08446297239646791
        + 0.5153566145541554 * s
        - 0.77757371002123 * (1 - c)
        + 0.34668869623791543 * (1 - c) ** 1.5
    ) / (0.9648932738041012 - 0.6655015709030936 * s + 0.1826019462608555 * (1 - c))
    cc = (
        682.8479477533338
        - 2567.7368047535556 * s
        + 7487.987105705168 * (1 - c)
        - 5602.448801045478 * (1 - c) ** 1.5
    ) / (5850.602606063662 - 4008.3309624647227 * s + 1480.250743805733 * (1 - c))
    d = (
        0.2855294320307508
        + 160.39651500649123 * s
        - 327.42799697993706 * (1 - c)
        + 166.88327184107732 * (1 - c) ** 1.5
    ) / (674.1908010450103 - 412.9837444306491 * s + 596.4232294419696 * (1 - c))
    e = (15 * (1 - c) * c * (3 + (4 * c) / 3.0)) / 128.0
    f = (
        -1.9208967199948512
        - 242.16001167844007 * s
        - 21.914139454773085 * (1 - c)
        + 266.06342182761813 * (1 - c) ** 1.5
    ) / (1499.904420175135 + 457.4200839912641 * s + 215.77342164754094 * (1 - c))
    return (
        0.5
        / PI
        * deon_h0(ui, c)
        * deon_h0(uo, c)
        / (ui + uo)
        * (
            a
            + cc * ui * uo
            + e * ui**2 * uo**2
            + b * (ui + uo)
            + d * ui * uo * (ui + uo)
            + f * (ui**2 + uo**2)
        )
    )


def deon_f1m(ui, uo, c):
    lam = -0.05890107167021953 * c - 0.004740543453386809 * c**2
    h = deon_h1(ui, c) * deon_h1(uo, c)
    return (
        2.0
        / PI
        * (
            -(
                (c * (64 + 45 * ui * uo)) / 48.0
                - (15 * (1 + 0.44 * c) * c * ui * uo * h) / 16.0
                - (4 * c * (1 + lam * ui) * (1 + lam * uo) * h) / 3.0
            )
            / (8.0 * (ui + uo))
        )
    )


def deon_full(wi, wo, kd):
    c = deon_c_from_kd(kd)
    ui, uo = wi[2], wo[2]
    iodot = wi @ wo
    f_single = c * deon_phase(-iodot) / (ui + uo)
    cosphisinisino = iodot - ui * uo
    f0single = (
        c
        / PI
        * (207 + 256 * ui * uo - 45 * uo**2 + 45 * ui**2 * (-1 + 3 * uo**2))
        / (768.0 * (ui + uo))
    )
    return max(0.0, f_single + deon_f0(ui, uo, c) - f0single + deon_f1m(ui, uo, c) * cosphisinisino)


def deon_fast(wi, wo, kd):  # lambert_sphere_fast.cpp: brdfGray
    c = deon_c_from_kd(kd)
    ui, uo = wi[2], wo[2]
    iodot = wi @ wo
    ss = c * deon_phase(-iodot) / (ui + uo)

    def safeacos(x):
        return math.acos(x) if -1.0 < x < 1.0 else 0.0

    s = math.sqrt(max(0.0, (1.0 - ui * ui) * (1.0 - uo * uo)))
    phi = safeacos(-((-iodot + ui * uo) / s))
    cp = math.cos(phi)
    p = ui * uo
    return max(
        0.0,
        0.995917 * ss
        + 0.0684744
        * (
            (safeacos(cp) + math.sqrt(p))
            * (-0.249978 + c)
            / (4.50996 * (safeacos(s) / s + 0.113706))
            + max(1.94208 * kd, 0.0) ** 1.85432
        ),
    )


@pytest.mark.parametrize("kd", [0.05, 0.5, 0.9, 1.0])
@pytest.mark.parametrize(("variant", "reference"), [("full", deon_full), ("fast", deon_fast)])
def test_lambert_sphere_against_deon_plugins(rng, kd, variant, reference):
    wi, wo = random_hemisphere(rng, 400), random_hemisphere(rng, 400)
    keep = (wi[:, 2] > 1e-3) & (wo[:, 2] > 1e-3) & (wi[:, 2] < 0.999) & (wo[:, 2] < 0.999)
    wi, wo = wi[keep], wo[keep]
    expected = [reference(a, b, kd) for a, b in zip(wi, wo, strict=True)]
    got = rd.LambertSphere(kd, variant).brdf(wi, wo)
    np.testing.assert_allclose(got, expected, rtol=1e-11, atol=1e-14)
