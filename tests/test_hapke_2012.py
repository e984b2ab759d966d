"""Hapke 2012 (porosity, shadow-hiding and coherent-backscatter surges, 2002 H-function).

References, transcribed into scalar Python:

* ``refmod`` (arunoruto/reflectance-models, ``src/refmod/hapke/_core.py``): ``h_function``
  (the 2002 H), ``double_henyey_greenstein``, ``shadow_hiding``, ``coherent_backscatter``,
  and the assembly of ``src/refmod/hapke/amsa.py`` (``_refl_amsa_scalar``) with isotropic
  multiple scattering (M = H(μ0)H(μ) − 1, as ``imsa.py``), returning the bidirectional
  reflectance r; I/F = π r. refmod has no porosity factor: K enters as Hapke 2012, Eq. 12.55
  writes it, K (w/4π) … [… + H(μ0/K) H(μ/K) − 1].
  refmod's roughness correction (``_roughness_impl``) is not used as a reference: its
  effective cosine of the larger angle drops the (ψ/π) E1 term of the denominator of Hapke
  1984, Eq. (48)–(51) (its ``_cos_s_one`` is called with ψ = 0 there), which ISIS's
  ``Hapke.cpp`` keeps; roughdiffuse's roughness is the one checked against ISIS in
  ``test_models_photometric.py`` and shared by every Hapke variant.
* Chandrasekhar's H-function, solved here by iterating its integral equation
  H(μ) = 1/(1 − (w/2) μ ∫0^1 H(μ')/(μ + μ') dμ') on Gauss–Legendre nodes (a different
  algorithm), itself checked against Chandrasekhar's moment identity
  ∫0^1 H dμ = (2/w)(1 − √(1 − w)) (Radiative Transfer, 1960, Ch. V).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.models.hapke import chandrasekhar_h_2002, porosity_factor
from roughdiffuse.models.photometry import radiance_factor


# --- refmod, transcribed ---------------------------------------------------------------
def refmod_h(x, w):
    gamma = math.sqrt(1.0 - w)
    r0 = (1.0 - gamma) / (1.0 + gamma)
    return 1.0 / (1.0 - w * x * (r0 + (1.0 - 2.0 * r0 * x) / 2.0 * math.log((1.0 + x) / x)))


def refmod_dhg(cos_g, b, c):
    return (1.0 + c) / 2.0 * (1.0 - b**2) / (1.0 - 2.0 * b * cos_g + b**2) ** 1.5 + (
        1.0 - c
    ) / 2.0 * (1.0 - b**2) / (1.0 + 2.0 * b * cos_g + b**2) ** 1.5


def refmod_shadow_hiding(tan_a2, h, b0):
    return 1.0 + b0 / (1.0 + tan_a2 / h) if (b0 > 0 and h > 0) else 1.0


def refmod_coherent_backscatter(tan_a2, h, b0):
    hc_2 = tan_a2 / h
    bc = 0.5 * (1.0 + (1.0 - math.exp(-hc_2)) / (hc_2 + 1e-15)) / (1.0 + hc_2) ** 2
    return 1.0 + b0 * bc if (b0 != 0 and h != 0) else 1.0


def refmod_reflectance(w, b, c, inc, ema, cos_a, h_sh, b0_sh, h_cb, b0_cb, k=1.0):
    """``_refl_amsa_scalar`` with θ̄ = 0 and M = H H − 1 (θ̄ = 0: S = 1, μ0e = μ0)."""
    mu0, mu = math.cos(inc), math.cos(ema)
    tan_a2 = math.sqrt(1.0 - cos_a**2) / (1.0 + cos_a)
    p_sh = refmod_dhg(cos_a, b, c) * refmod_shadow_hiding(tan_a2, h_sh, b0_sh)
    m = refmod_h(mu0 / k, w) * refmod_h(mu / k, w) - 1.0
    b_cb = refmod_coherent_backscatter(tan_a2, h_cb, b0_cb)
    return k * mu0 / (mu0 + mu) / (4.0 * math.pi) * b_cb * w * (p_sh + m)


@pytest.mark.parametrize(
    ("w", "b", "c", "h_sh", "b0_sh", "h_cb", "b0_cb", "k"),
    [
        (0.3, 0.3, 0.4, 0.06, 1.5, 0.02, 0.6, 1.0),
        (0.9, 0.2, -0.5, 0.1, 0.4, 0.05, 0.3, 1.0),
        (0.5, 0.45, 0.2, 0.08, 2.3, 0.01, 0.9, 1.7),
        (0.1, 0.0, 0.0, 0.1, 0.0, 0.1, 0.0, 1.2),
    ],
)
def test_hapke_2012_against_refmod(rng, w, b, c, h_sh, b0_sh, h_cb, b0_cb, k):
    # refmod's double HG (1 + c)/2 HG_back(b) + (1 − c)/2 HG_fwd(b) is ISIS's two-term
    # function with ξ = b and the mirrored weight (1 + c)/2
    model = rd.Hapke2012(w, b0_sh, h_sh, b0_cb, h_cb, k, b, (1.0 + c) / 2.0, 0.0)
    n = 200
    inc, ema = rng.uniform(0.01, 1.5, n), rng.uniform(0.01, 1.5, n)
    dphi = rng.uniform(0.0, math.pi, n)
    cos_g = np.cos(inc) * np.cos(ema) + np.sin(inc) * np.sin(ema) * np.cos(dphi)
    cos_g[:5] = np.cos(inc[:5] - ema[:5])  # a few near opposition (Δφ = 0)
    expected = [
        math.pi * refmod_reflectance(w, b, c, i, e, cg, h_sh, b0_sh, h_cb, b0_cb, k)
        for i, e, cg in zip(inc, ema, cos_g, strict=True)
    ]
    got = radiance_factor(model, inc, ema, np.arccos(np.clip(cos_g, -1, 1)))
    np.testing.assert_allclose(got, expected, rtol=1e-10)


def test_hapke_2012_opposition_peak_closed_form():
    """At g = 0: I/F = K (w/8) [(1 + B_S0) p(0) − 1 + H(1/K)²] (1 + B_C0) (Hapke 2012)."""
    w, bs0, bc0, k = 0.4, 1.0, 0.5, 1.3
    m = rd.Hapke2012(w, bs0, 0.05, bc0, 0.02, k)
    h = refmod_h(1.0 / k, w)
    expected = k * w / 8.0 * ((1.0 + bs0) - 1.0 + h * h) * (1.0 + bc0)
    assert float(radiance_factor(m, 0.0, 0.0, 0.0)) == pytest.approx(expected, rel=1e-12)


def exact_h(mu, w, n=64, iterations=4000):
    """Chandrasekhar's H for isotropic scattering by fixed-point iteration on the nodes."""
    x, wt = np.polynomial.legendre.leggauss(n)
    x, wt = 0.5 * (x + 1.0), 0.5 * wt
    h = np.ones(n)
    for _ in range(iterations):
        h_new = 1.0 / (1.0 - 0.5 * w * x * (wt * h / (x[:, None] + x)).sum(axis=1))
        if np.max(np.abs(h_new - h)) < 1e-13:
            h = h_new
            break
        h = h_new
    mu = np.atleast_1d(mu)
    return 1.0 / (1.0 - 0.5 * w * mu * (wt * h / (mu[:, None] + x)).sum(axis=1))


@pytest.mark.parametrize("w", [0.5, 0.9, 0.99])
def test_exact_h_reference_satisfies_moment_identity(w):
    """The reference solver against Chandrasekhar's identity ∫0^1 H dμ = (2/w)(1 − √(1 − w))."""
    x, wt = np.polynomial.legendre.leggauss(64)
    moment = float((0.5 * wt * exact_h(0.5 * (x + 1.0), w)).sum())
    assert moment == pytest.approx(2.0 / w * (1.0 - math.sqrt(1.0 - w)), rel=1e-6)


@pytest.mark.parametrize("w", [0.1, 0.5, 0.9, 0.99])
def test_h_2002_within_one_percent_of_exact(w):
    """Hapke (2002): the approximation is within 1 % of the exact H for every x and w."""
    mu = np.linspace(0.0, 1.0, 41)
    approx = chandrasekhar_h_2002(np, mu, w)
    np.testing.assert_allclose(approx, exact_h(mu, w), rtol=0.01)


def test_porosity_factor_definition():
    """K(φ) = −ln(1 − 1.209 φ^(2/3))/(1.209 φ^(2/3)) (Hapke 2008, Eq. 23): 1 at φ -> 0,
    growing without bound as 1.209 φ^(2/3) -> 1 (φ -> 0.752)."""
    phi = 0.3
    y = 1.209 * phi ** (2 / 3)
    assert porosity_factor(phi) == pytest.approx(-math.log(1 - y) / y, rel=1e-14)
    assert porosity_factor(1e-9) == pytest.approx(1.0, abs=1e-5)
    assert porosity_factor(0.75) > 5.0
    with pytest.raises(ValueError, match="filling_factor"):
        porosity_factor(0.8)


def test_hapke_2012_reduces_to_hapke_up_to_h_function():
    """K = 1, B_C0 = 0: Hapke's 1993 model with the 2002 H: within the H's own 1 % (twice)."""
    inc, ema, g = np.radians([40.0, 20.0, 35.0])
    a = float(
        radiance_factor(rd.Hapke2012(0.6, 1.2, 0.06, 0.0, 0.1, 1.0, -0.3, 0.1, 0.3), inc, ema, g)
    )
    b = float(radiance_factor(rd.Hapke(0.6, 1.2, 0.06, -0.3, 0.3, 0.1), inc, ema, g))
    assert a == pytest.approx(b, rel=0.02)
    assert a != pytest.approx(b, rel=1e-6)
