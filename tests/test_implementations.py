"""How other renderers' Oren–Nayar and EON differ from roughdiffuse's (docs/implementations.md).

Each function below transcribes one project's formula from its source, on the cosines
NL = n·l, NV = n·v, LV = l·v (arrays), with that project's clamps and parameter conventions:

* MaterialX ``libraries/pbrlib/genglsl/lib/mx_microfacet_diffuse.glsl``
  (``mx_oren_nayar_diffuse``, ``mx_oren_nayar_compensated_diffuse``) and the node
  ``mx_oren_nayar_diffuse_bsdf.glsl``, which clamps NdotL, NdotV and LdotV to [1e-8, 1] and
  multiplies by color/π;
* Blender Cycles ``intern/cycles/kernel/closure/bsdf_oren_nayar.h`` (``bsdf_oren_nayar_setup``,
  ``bsdf_oren_nayar_get_intensity``, ``bsdf_oren_nayar_G``); the closure weight is the base
  colour (``svm/closure.h``: ``bsdf_alloc(..., rgb_to_spectrum(base_color) * ...)``);
* OSL ``src/testrender/shading.cpp`` (``OrenNayar::eval``) and BSDL
  ``src/libbsdl/include/BSDL/MTX/bsdf_oren_nayar_diffuse_impl.h``
  (``OrenNayarDiffuseLobe::eval_impl``, ``E_FON_analytic``);
* MaterialX ``libraries/pbrlib/genosl/pbrlib_genosl_impl.mtlx``
  (``IM_oren_nayar_diffuse_bsdf_genosl``: the OSL closure without ``energy_compensation``);
* Blender Cycles ``intern/cycles/kernel/osl/closures_setup.h``
  (``osl_closure_oren_nayar_diffuse_bsdf_setup``);
* Unity Graphics ``Packages/com.unity.render-pipelines.core/ShaderLibrary/BSDF.hlsl``
  (``DisneyDiffuseNoPI``, ``DisneyDiffuse``; HDRP's ``Lit.hlsl`` calls it by default);
* Filament ``shaders/src/surface_brdf.fs`` (``diffuse``, ``Fd_Lambert``, ``Fd_Burley``);
* Mitsuba 0.6 ``src/bsdfs/roughdiffuse.cpp`` (``RoughDiffuse::eval``; σ = α/√2);
* pbrt-v3 ``src/core/reflection.cpp`` (``OrenNayar::f``; σ given in degrees).

The numbers of docs/implementations.md are asserted at the end.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd

PI = math.pi
MX_EPS = 1e-8
K1 = 0.5 - 2.0 / (3.0 * PI)  # MaterialX FUJII_CONSTANT_1
K2 = 2.0 / 3.0 - 28.0 / (15.0 * PI)  # FUJII_CONSTANT_2


# ----------------------------------------------------------------------------- MaterialX
def mx_oren_nayar_diffuse(nv, nl, lv, roughness):
    s = lv - nl * nv
    stinv = np.where(s > 0.0, s / np.maximum(nl, nv), 0.0)
    sigma2 = roughness * roughness
    a = 1.0 - 0.5 * (sigma2 / (sigma2 + 0.33))
    b = 0.45 * sigma2 / (sigma2 + 0.09)
    return a + b * stinv


def mx_fujii_dir_albedo(cos_theta, roughness):
    a = 1.0 / (1.0 + K1 * roughness)
    b = roughness * a
    si = np.sqrt(np.maximum(0.0, 1.0 - cos_theta * cos_theta))
    g = (
        si * (np.arccos(np.clip(cos_theta, -1.0, 1.0)) - si * cos_theta)
        + 2.0 * ((si / cos_theta) * (1.0 - si * si * si) - si) / 3.0
    )
    return a + b * g / PI


def mx_oren_nayar_compensated_diffuse(nv, nl, lv, roughness, color):
    s = lv - nl * nv
    stinv = np.where(s > 0.0, s / np.maximum(nl, nv), s)
    a = 1.0 / (1.0 + K1 * roughness)
    single = color * a * (1.0 + roughness * stinv)
    dir_v = mx_fujii_dir_albedo(nv, roughness)
    dir_l = mx_fujii_dir_albedo(nl, roughness)
    avg = a * (1.0 + K2 * roughness)
    color_ms = color * color * avg / (1.0 - color * max(0.0, 1.0 - avg))
    multi = (
        color_ms
        * np.maximum(MX_EPS, 1.0 - dir_v)
        * np.maximum(MX_EPS, 1.0 - dir_l)
        / max(MX_EPS, 1.0 - avg)
    )
    return single + multi


def mx_oren_nayar_diffuse_bsdf(nv, nl, lv, roughness, color, energy_compensation):
    """The node's BRDF (response / NdotL): clamps, then color/π times the lobe."""
    nv, nl, lv = (np.clip(x, MX_EPS, 1.0) for x in (nv, nl, lv))
    if energy_compensation:
        return mx_oren_nayar_compensated_diffuse(nv, nl, lv, roughness, color) / PI
    return mx_oren_nayar_diffuse(nv, nl, lv, roughness) * color / PI


# ----------------------------------------------------------------------------- Cycles
def cycles_g(cos_theta):
    c = np.asarray(cos_theta, dtype=np.float64)
    s = np.sqrt(np.maximum(0.0, 1.0 - c * c))
    theta = np.arccos(np.clip(c, -1.0, 1.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        g = s * (theta - 2.0 / 3.0 - s * c) + 2.0 / 3.0 * (s / c) * (1.0 - s * s * s)
    return np.where(c < 1e-6, (PI / 2 - 2.0 / 3.0) - c, g)


def cycles_oren_nayar(nv, nl, lv, roughness, color):
    """BRDF: closure weight (colour) × intensity / NL."""
    sigma = min(max(roughness, 0.0), 1.0)
    a = 1.0 / (PI + sigma * (PI / 2 - 2.0 / 3.0))
    b = sigma * a
    albedo = min(max(color, 0.0), 1.0)
    e_avg = a * PI + ((2 * PI - 5.6) / 3.0) * b
    e_ms = (1.0 / PI) * albedo**2 * (e_avg / (1.0 - e_avg)) / (1.0 - albedo * (1.0 - e_avg))
    nv = np.maximum(nv, 0.0)
    e_v = a * PI + b * cycles_g(nv)
    multiscatter_term = e_ms * (1.0 - e_v)
    nl = np.maximum(nl, 0.0)
    t = lv - nl * nv
    t = np.where(t > 0.0, t / (np.maximum(nl, nv) + np.finfo(np.float32).tiny), t)
    single = a + b * t
    e_l = a * PI + b * cycles_g(nl)
    return color * (single + multiscatter_term * (1.0 - e_l))


# ----------------------------------------------------------------------------- OSL
def osl_oren_nayar(nv, nl, lv, sigma, color):
    """testrender's eval returns A + B s/t with pdf NL/π: the BRDF is colour (A + B s/t)/π."""
    s = lv - nl * nv
    s2 = sigma * sigma
    a = 1 - 0.50 * s2 / (s2 + 0.33)
    b = 0.45 * s2 / (s2 + 0.09)
    stinv = np.where(s > 0, s / np.maximum(nl, nv), 0.0)
    return color * (a + b * stinv) / PI


# ----------------------------------------------------------------------------- angles
def _angles(nv, nl, lv):
    sin_i = np.sqrt(np.maximum(0.0, 1 - nl * nl))
    sin_o = np.sqrt(np.maximum(0.0, 1 - nv * nv))
    den = sin_i * sin_o
    cos_phi = np.where(den > 0, (lv - nl * nv) / np.where(den > 0, den, 1.0), 0.0)
    return sin_i, sin_o, np.clip(cos_phi, -1, 1)


def pbrt3_oren_nayar(nv, nl, lv, sigma_degrees, r):
    sigma = math.radians(sigma_degrees)
    sigma2 = sigma * sigma
    a = 1.0 - (sigma2 / (2.0 * (sigma2 + 0.33)))
    b = 0.45 * sigma2 / (sigma2 + 0.09)
    sin_i, sin_o, cos_phi = _angles(nv, nl, lv)
    max_cos = np.where((sin_i > 1e-4) & (sin_o > 1e-4), np.maximum(0.0, cos_phi), 0.0)
    i_larger = nl > nv
    sin_alpha = np.where(i_larger, sin_o, sin_i)
    tan_beta = np.where(i_larger, sin_i / nl, sin_o / nv)
    return r / PI * (a + b * max_cos * sin_alpha * tan_beta)


def mitsuba06_roughdiffuse(nv, nl, lv, alpha, rho, fast):
    sigma = alpha / math.sqrt(2.0)
    sigma2 = sigma * sigma
    sin_i, sin_o, cos_phi = _angles(nv, nl, lv)
    eps = 1e-4  # Mitsuba's Epsilon (single precision build)
    cos_phi = np.where((sin_i > eps) & (sin_o > eps), cos_phi, 0.0)
    i_larger = nl > nv
    if fast:
        a = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33)
        b = 0.45 * sigma2 / (sigma2 + 0.09)
        sin_alpha = np.where(i_larger, sin_o, sin_i)
        tan_beta = np.where(i_larger, sin_i / nl, sin_o / nv)
        return rho / PI * (a + b * np.maximum(cos_phi, 0.0) * sin_alpha * tan_beta)
    theta_i, theta_o = np.arccos(np.clip(nl, -1, 1)), np.arccos(np.clip(nv, -1, 1))
    alpha_, beta = np.maximum(theta_i, theta_o), np.minimum(theta_i, theta_o)
    sin_alpha = np.where(i_larger, sin_o, sin_i)
    sin_beta = np.where(i_larger, sin_i, sin_o)
    tan_beta = np.where(i_larger, sin_i / nl, sin_o / nv)
    tmp = sigma2 / (sigma2 + 0.09)
    tmp2 = (4 / PI**2) * alpha_ * beta
    tmp3 = 2 * beta / PI
    c1 = 1.0 - 0.5 * sigma2 / (sigma2 + 0.33)
    c2 = 0.45 * tmp * np.where(cos_phi > 0, sin_alpha, sin_alpha - tmp3**3)
    c3 = 0.125 * tmp * tmp2 * tmp2
    c4 = 0.17 * sigma2 / (sigma2 + 0.13)
    tan_half = (sin_alpha + sin_beta) / (
        np.sqrt(np.maximum(0, 1 - sin_alpha**2)) + np.sqrt(np.maximum(0, 1 - sin_beta**2))
    )
    sngl = rho * (c1 + cos_phi * c2 * tan_beta + (1.0 - np.abs(cos_phi)) * c3 * tan_half)
    dbl = rho * rho * (c4 * (1.0 - cos_phi * tmp3 * tmp3))
    return (sngl + dbl) / PI


# ----------------------------------------------------------------------------- helpers
def _cosines(theta_i_deg, theta_r_deg, dphi_deg):
    ti, tr, dp = (
        np.radians(np.asarray(x, dtype=np.float64)) for x in (theta_i_deg, theta_r_deg, dphi_deg)
    )
    nl, nv = np.cos(ti), np.cos(tr)
    return nv, nl, nl * nv + np.sin(ti) * np.sin(tr) * np.cos(dp)


def _random_cosines(rng, n=2000, lo=0.02):
    ti, tr = rng.uniform(0, 88, n), rng.uniform(0, 88, n)
    dp = rng.uniform(0, 180, n)
    nv, nl, lv = _cosines(ti, tr, dp)
    keep = (nv > lo) & (nl > lo) & (np.sin(np.radians(ti)) > 1e-3) & (np.sin(np.radians(tr)) > 1e-3)
    return nv[keep], nl[keep], lv[keep]


def _ours(model, nv, nl, lv):
    return np.asarray(model.brdf_cosines(nl, nv, lv))


def _albedo(fn, mu_o, n=800):
    """∫ f cos θi dωi by the midpoint rule (error O(h²), about 1e-5 here)."""
    mu = (np.arange(n) + 0.5) / n
    ph = (np.arange(n) + 0.5) / n * 2 * PI
    m, p = np.meshgrid(mu, ph, indexing="ij")
    lv = np.sqrt(1 - m * m) * np.cos(p) * math.sqrt(1 - mu_o**2) + m * mu_o
    f = fn(np.full_like(m, mu_o), m, lv)
    return float((f * m).sum() * (1.0 / n) * (2 * PI / n))


# ----------------------------------------------------------------------------- agreement
def test_pbrt3_and_osl_are_the_qualitative_model(rng):
    nv, nl, lv = _random_cosines(rng)
    ours = _ours(rd.OrenNayar(0.8, 0.5), nv, nl, lv)
    np.testing.assert_allclose(
        pbrt3_oren_nayar(nv, nl, lv, math.degrees(0.5), 0.8), ours, rtol=1e-12
    )
    np.testing.assert_allclose(osl_oren_nayar(nv, nl, lv, 0.5, 0.8), ours, rtol=1e-12)


def test_mitsuba06_is_the_model_at_sigma_alpha_over_sqrt2(rng):
    nv, nl, lv = _random_cosines(rng)
    alpha = 0.5 * math.sqrt(2.0)
    np.testing.assert_allclose(
        mitsuba06_roughdiffuse(nv, nl, lv, alpha, 0.8, fast=True),
        _ours(rd.OrenNayar(0.8, 0.5), nv, nl, lv),
        rtol=1e-12,
    )
    np.testing.assert_allclose(
        mitsuba06_roughdiffuse(nv, nl, lv, alpha, 0.8, fast=False),
        _ours(rd.OrenNayar(0.8, 0.5, "full"), nv, nl, lv),
        rtol=1e-9,
    )


def test_materialx_qualitative_takes_sigma_in_radians(rng):
    nv, nl, lv = _random_cosines(rng)
    got = mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.5, 0.8, energy_compensation=False)
    np.testing.assert_allclose(got, _ours(rd.OrenNayar(0.8, 0.5), nv, nl, lv), rtol=1e-12)


def test_materialx_eon_equals_ours_where_the_clamp_does_not_act(rng):
    nv, nl, lv = _random_cosines(rng)
    ok = lv >= MX_EPS
    got = mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.7, 0.8, energy_compensation=True)
    np.testing.assert_allclose(got[ok], _ours(rd.EON(0.8, 0.7), nv, nl, lv)[ok], rtol=1e-12)
    assert np.all(got[~ok] > _ours(rd.EON(0.8, 0.7), nv, nl, lv)[~ok])


def test_materialx_clamp_raises_the_furnace_to_about_1_15_at_grazing():
    """The node clamps L·V to [1e-8, 1]: EON's negative s/t for backward light is lost."""
    node = lambda nv, nl, lv: mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 1.0, 1.0, True)  # noqa: E731
    assert _albedo(node, 1.0) == pytest.approx(1.0, abs=1e-4)
    assert _albedo(node, 0.5) == pytest.approx(1.056, abs=2e-3)
    assert _albedo(node, 0.05) == pytest.approx(1.152, abs=2e-3)  # θo = 87.1°
    ours = float(rd.EON(1.0, 1.0).directional_albedo(np.array([math.sqrt(1 - 0.05**2), 0, 0.05])))
    assert ours == pytest.approx(1.0, abs=1e-9)


def test_cycles_applies_the_albedo_three_times_to_the_multiple_scattering(rng):
    nv, nl, lv = _random_cosines(rng)
    # ρ = 1: the same BRDF as EON
    np.testing.assert_allclose(
        cycles_oren_nayar(nv, nl, lv, 0.6, 1.0), _ours(rd.EON(1.0, 0.6), nv, nl, lv), rtol=1e-10
    )
    # ρ = 0.5: single scattering agrees, the multiple-scattering lobe is ρ times EON's
    rho = 0.5
    ours_ms = _ours(rd.EON(rho, 0.6), nv, nl, lv) - _ours(rd.Fujii(rho, 0.6), nv, nl, lv)
    cyc_ms = cycles_oren_nayar(nv, nl, lv, 0.6, rho) - _ours(rd.Fujii(rho, 0.6), nv, nl, lv)
    np.testing.assert_allclose(cyc_ms, rho * ours_ms, rtol=1e-9, atol=1e-15)


# ----------------------------------------------------------------------------- the doc's numbers
GEOMETRIES = {"A": (60, 60, 0), "B": (60, 60, 180), "C": (30, 70, 90), "D": (85, 85, 180)}

DOC_TABLE = {
    # f in 1/sr, ρ = 0.8; qualitative ON at σ = 0.5 rad = 28.65°, EON/FON at r = 0.5
    "roughdiffuse OrenNayar": {"A": 0.3262, "B": 0.1998, "C": 0.1998, "D": 0.1998},
    "pbrt-v3 (sigma 28.65 deg)": {"A": 0.3262, "B": 0.1998, "C": 0.1998, "D": 0.1998},
    "Mitsuba 0.6 fast (alpha 0.7071)": {"A": 0.3262, "B": 0.1998, "C": 0.1998, "D": 0.1998},
    "OSL (sigma 0.5)": {"A": 0.3262, "B": 0.1998, "C": 0.1998, "D": 0.1998},
    "MaterialX (roughness 0.5)": {"A": 0.3262, "B": 0.1998, "C": 0.1998, "D": 0.1998},
    "roughdiffuse EON": {"A": 0.4018, "B": 0.1513, "C": 0.2357, "D": 0.1125},
    "MaterialX EON": {"A": 0.4018, "B": 0.2070, "C": 0.2357, "D": 0.2221},
    "Cycles EON": {"A": 0.3993, "B": 0.1489, "C": 0.2331, "D": 0.1124},
    "OSL BSDL EON": {"A": 0.4018, "B": 0.1513, "C": 0.2357, "D": 0.1125},
    "MaterialX EON through genosl": {"A": 0.3262, "B": 0.1998, "C": 0.1998, "D": 0.1998},
}


def _doc_values() -> dict[str, dict[str, float]]:
    out: dict[str, dict[str, float]] = {}
    for key, (ti, tr, dp) in GEOMETRIES.items():
        nv, nl, lv = _cosines(ti, tr, dp)
        row = {
            "roughdiffuse OrenNayar": _ours(rd.OrenNayar(0.8, 0.5), nv, nl, lv),
            "pbrt-v3 (sigma 28.65 deg)": pbrt3_oren_nayar(nv, nl, lv, math.degrees(0.5), 0.8),
            "Mitsuba 0.6 fast (alpha 0.7071)": mitsuba06_roughdiffuse(
                nv, nl, lv, 0.5 * math.sqrt(2), 0.8, fast=True
            ),
            "OSL (sigma 0.5)": osl_oren_nayar(nv, nl, lv, 0.5, 0.8),
            "MaterialX (roughness 0.5)": mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.5, 0.8, False),
            "roughdiffuse EON": _ours(rd.EON(0.8, 0.5), nv, nl, lv),
            "MaterialX EON": mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.5, 0.8, True),
            "Cycles EON": cycles_oren_nayar(nv, nl, lv, 0.5, 0.8),
            "OSL BSDL EON": bsdl_oren_nayar_diffuse(nv, nl, lv, 0.5, 0.8, True),
            "MaterialX EON through genosl": materialx_genosl_eon_node(nv, nl, lv, 0.5, 0.8),
        }
        for name, value in row.items():
            out.setdefault(name, {})[key] = float(np.asarray(value).reshape(()))
    return out


def test_the_numbers_in_docs_implementations_md():
    values = _doc_values()
    for name, row in DOC_TABLE.items():
        for key, expected in row.items():
            assert values[name][key] == pytest.approx(expected, abs=5e-5), (name, key)


# ----------------------------------------------------------------------------- game engines
def _pow5(x):
    return x * x * x * x * x


def unreal_diffuse_burley(nv, nl, lv, roughness, color):
    """Unreal ``Engine/Shaders/Private/BRDF.ush``, ``Diffuse_Burley`` (VoH² = (1 + L·V)/2)."""
    voh2 = 0.5 * (1.0 + lv)
    fd90 = 0.5 + 2 * voh2 * roughness
    fdv = 1 + (fd90 - 1) * _pow5(1 - nv)
    fdl = 1 + (fd90 - 1) * _pow5(1 - nl)
    return color * ((1 / PI) * fdv * fdl)


def filament_fd_burley(nv, nl, lv, perceptual_roughness, color):
    """Filament ``shaders/src/brdf.fs``, ``Fd_Burley(roughness, NoV, NoL, LoH)`` with
    roughness = perceptualRoughness² (``getRoughness``), times the diffuse colour."""
    roughness = perceptual_roughness * perceptual_roughness
    loh2 = 0.5 * (1.0 + lv)
    f90 = 0.5 + 2.0 * roughness * loh2
    light = 1.0 + (f90 - 1.0) * _pow5(1.0 - nl)
    view = 1.0 + (f90 - 1.0) * _pow5(1.0 - nv)
    return color * light * view * (1.0 / PI)


def unity_diffuse_ggx(nv, nl, lv, roughness, albedo):
    """Unity ``ShaderLibrary/BSDF.hlsl``, ``DiffuseGGX`` = ``DiffuseGGXNoPI``/π, times the
    diffuse colour (N·H = (N·L + N·V)/|l + v|)."""
    nh = (nl + nv) / np.sqrt(2.0 + 2.0 * lv)
    facing = 0.5 + 0.5 * lv
    rough = facing * (0.9 - 0.4 * facing) * (0.5 / nh + 1)
    transmit_l, transmit_v = 1 - _pow5(1 - nl), 1 - _pow5(1 - nv)
    smooth = transmit_l * transmit_v * 1.05
    single = smooth + (rough - smooth) * roughness
    multiple = roughness * (0.1159 * PI)
    return albedo * (single + albedo * multiple) / PI


def _variant(model_id, **params):
    return rd.registry.get(model_id).create(**params)


VARIANT_CASES = [
    # id, params, transcription (nv, nl, lv) -> f, rtol
    ("cycles-diffuse", {"albedo": 0.5, "roughness": 0.6},
     lambda nv, nl, lv: cycles_oren_nayar(nv, nl, lv, 0.6, 0.5)),
    ("cycles-principled", {"albedo": 0.8, "roughness": 1.0},
     lambda nv, nl, lv: cycles_oren_nayar(nv, nl, lv, 1.0, 0.8)),
    ("materialx-eon", {"albedo": 0.8, "roughness": 0.7},
     lambda nv, nl, lv: mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.7, 0.8, True)),
    ("materialx-oren-nayar", {"albedo": 0.8, "roughness": 0.5},
     lambda nv, nl, lv: mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.5, 0.8, False)),
    ("mitsuba06-roughdiffuse-fast", {"albedo": 0.8, "alpha": 0.7},
     lambda nv, nl, lv: mitsuba06_roughdiffuse(nv, nl, lv, 0.7, 0.8, fast=True)),
    ("mitsuba06-roughdiffuse", {"albedo": 0.8, "alpha": 0.7},
     lambda nv, nl, lv: mitsuba06_roughdiffuse(nv, nl, lv, 0.7, 0.8, fast=False)),
    ("pbrt3-oren-nayar", {"albedo": 0.8, "sigma_deg": 28.65},
     lambda nv, nl, lv: pbrt3_oren_nayar(nv, nl, lv, 28.65, 0.8)),
    ("unreal-burley", {"albedo": 0.8, "roughness": 0.6},
     lambda nv, nl, lv: unreal_diffuse_burley(nv, nl, lv, 0.6, 0.8)),
    ("filament-burley", {"albedo": 0.8, "roughness": 0.6},
     lambda nv, nl, lv: filament_fd_burley(nv, nl, lv, 0.6, 0.8)),
    ("unity-diffuse-ggx", {"albedo": 0.8, "roughness": 0.4},
     lambda nv, nl, lv: unity_diffuse_ggx(nv, nl, lv, 0.4, 0.8)),
]  # fmt: skip


@pytest.mark.parametrize(
    "model_id, params, reference", VARIANT_CASES, ids=[c[0] for c in VARIANT_CASES]
)
def test_each_renderer_variant_agrees_with_its_transcription(rng, model_id, params, reference):
    nv, nl, lv = _random_cosines(rng)
    model = _variant(model_id, **params)
    assert model.reference  # the other project's file and function
    np.testing.assert_allclose(_ours(model, nv, nl, lv), reference(nv, nl, lv), rtol=1e-12)


def test_variants_that_are_a_conversion_equal_their_base_model(rng):
    nv, nl, lv = _random_cosines(rng)
    pairs = [
        (_variant("openpbr-diffuse", albedo=0.7, roughness=0.4), rd.EON(0.7, 0.4)),
        (_variant("unreal-chan", albedo=0.7, roughness=0.6), rd.Chan(0.7, 0.36)),
        (_variant("pbrt3-oren-nayar", albedo=0.7, sigma_deg=90.0), rd.OrenNayar(0.7, PI / 2)),
    ]
    for variant, base in pairs:
        np.testing.assert_allclose(_ours(variant, nv, nl, lv), _ours(base, nv, nl, lv), rtol=1e-14)


def test_cycles_variant_albedo_is_eon_with_the_lobe_times_rho():
    """Closed form vs the midpoint rule on the transcription (error about 1e-5)."""
    for mu in (1.0, 0.5):
        wo = np.array([math.sqrt(1 - mu * mu), 0.0, mu])
        got = float(_variant("cycles-diffuse", albedo=0.5, roughness=1.0).directional_albedo(wo))
        ref = _albedo(lambda nv, nl, lv: cycles_oren_nayar(nv, nl, lv, 1.0, 0.5), mu)
        assert got == pytest.approx(ref, abs=1e-4)
    n = np.array([0.0, 0.0, 1.0])
    cycles = float(_variant("cycles-diffuse", albedo=0.5, roughness=1.0).directional_albedo(n))
    assert cycles == pytest.approx(0.414, abs=5e-4)  # the page's number (EON: 0.439)


# ----------------------------------------------------------------------------- engine defaults
def unity_disney_diffuse(nv, nl, lv, perceptual_roughness, color):
    """Unity ``ShaderLibrary/BSDF.hlsl``, ``DisneyDiffuse`` = INV_PI * ``DisneyDiffuseNoPI``
    (fd90 = 0.5 + (pr + pr LdotV), two ``F_Schlick(1, fd90, ·)``, times rcp(1.03571)),
    times the diffuse colour as HDRP ``Lit.hlsl`` ``BSDF`` applies it."""
    fd90 = 0.5 + (perceptual_roughness + perceptual_roughness * lv)

    def f_schlick(f0, f90, u):
        x = 1.0 - u
        x2 = x * x
        x5 = x * x2 * x2
        return (f90 - f0) * x5 + f0

    light = f_schlick(1.0, fd90, nl)
    view = f_schlick(1.0, fd90, nv)
    return color * (1.0 / PI) * ((1.0 / 1.03571) * (light * view))


def filament_diffuse(nv, nl, lv, perceptual_roughness, color):
    """Filament ``surface_brdf.fs``, ``diffuse()``: ``BRDF_DIFFUSE == DIFFUSE_LAMBERT`` so
    ``Fd_Lambert()`` = 1/π, times the diffuse colour."""
    return color * (1.0 / PI) + 0.0 * (nv + nl + lv + perceptual_roughness)


BSDL_C1 = 0.5 - 2.0 / (3.0 * PI)  # constant1_FON
BSDL_C2 = 2.0 / 3.0 - 28.0 / (15.0 * PI)  # constant2_FON


def bsdl_e_fon_analytic(mu, roughness):
    """BSDL ``OrenNayarDiffuseLobe::E_FON_analytic``."""
    af = 1.0 / (1.0 + BSDL_C1 * roughness)
    bf = roughness * af
    si = np.sqrt(np.maximum(0.0, 1.0 - mu * mu))
    g = si * (np.arccos(mu) - si * mu) + 2.0 * (
        (si / np.maximum(mu, 1e-7)) * (1.0 - si * si * si) - si
    ) * (1.0 / 3.0)
    return af + (bf / PI) * g


def bsdl_oren_nayar_diffuse(nv, nl, lv, roughness, albedo, energy_compensation):
    """BSDL ``OrenNayarDiffuseLobe::eval_impl``: the sample weight (f cos / pdf, pdf =
    cosNI/π) divided by π is the BRDF."""
    r = min(max(roughness, 0.0), 1.0)
    cos_ni, cos_no = np.clip(nl, 0.0, 1.0), np.clip(nv, 0.0, 1.0)
    cos_io = np.clip(lv, -1.0, 1.0)
    s = cos_io - cos_ni * cos_no
    if not energy_compensation:
        s2 = r * r
        a = 1.0 - 0.50 * s2 / (s2 + 0.33)
        b = 0.45 * s2 / (s2 + 0.09)
        stinv = np.where(s > 0.0, s / np.maximum(cos_ni, cos_no), 0.0)
        return albedo * (a + b * stinv) / PI
    af = 1.0 / (1.0 + BSDL_C1 * r)
    stinv = np.where(s > 0.0, s / np.maximum(cos_ni, cos_no), s)
    f_ss = af * (1.0 + r * stinv)
    efo, efi = bsdl_e_fon_analytic(cos_no, r), bsdl_e_fon_analytic(cos_ni, r)
    avg_ef = af * (1.0 + BSDL_C2 * r)
    rho_ms = albedo * albedo * avg_ef / (1 - albedo * max(0.0, 1.0 - avg_ef))
    f_ms = np.maximum(1e-7, 1.0 - efo) * np.maximum(1e-7, 1.0 - efi) / max(1e-7, 1.0 - avg_ef)
    return (albedo * f_ss + rho_ms * f_ms) / PI


def materialx_genosl_eon_node(nv, nl, lv, roughness, color):
    """MaterialX ``pbrlib_genosl_impl.mtlx``: ``{{weight}} * oren_nayar_diffuse_bsdf(
    {{normal}}, {{color}}, {{roughness}})``, no ``energy_compensation``: the closure's
    default, 0 (BSDL's first branch), whatever the node's switch."""
    return bsdl_oren_nayar_diffuse(nv, nl, lv, roughness, color, energy_compensation=False)


def cycles_osl_closure(nv, nl, lv, roughness, albedo, weight=1.0):
    """Cycles' OSL Diffuse BSDF, ``osl/shaders/node_diffuse_bsdf.osl`` (``Roughness == 0``:
    ``Color * diffuse(Normal)``, else ``oren_nayar_diffuse_bsdf(Normal, Color, Roughness)``),
    and ``osl/closures_setup.h``, ``osl_closure_oren_nayar_diffuse_bsdf_setup``: closure weight
    ``weight * albedo``, ``bsdf_oren_nayar_setup(..., color = albedo)`` (no
    ``energy_compensation`` read): the closure weight times the intensity per N·L."""
    if roughness == 0.0:
        return weight * albedo / PI + 0.0 * (nv + nl + lv)
    intensity_per_nl = cycles_oren_nayar(nv, nl, lv, roughness, albedo) / albedo
    return weight * albedo * intensity_per_nl


def _grid_cosines():
    """θi, θo on 0.5°..89° and Δφ on 0°..180°: a grid, every branch of s/t."""
    ti, tr, dp = np.meshgrid(
        np.linspace(0.5, 89.0, 9), np.linspace(0.5, 89.0, 9), np.linspace(0, 180, 7),
        indexing="ij",
    )
    return _cosines(ti.ravel(), tr.ravel(), dp.ravel())


ENGINE_CASES = [
    # id, its parameter name for roughness (None: none), transcription (nv, nl, lv, r, ρ) -> f
    ("unity-disney-diffuse", "roughness", unity_disney_diffuse),
    ("filament-lambert", None, filament_diffuse),
    ("osl-eon", "roughness",
     lambda nv, nl, lv, r, rho: bsdl_oren_nayar_diffuse(nv, nl, lv, r, rho, True)),
    ("materialx-eon-genosl", "roughness", materialx_genosl_eon_node),
    ("cycles-osl", "roughness", cycles_osl_closure),
]  # fmt: skip


@pytest.mark.parametrize(
    "model_id, rough, reference", ENGINE_CASES, ids=[c[0] for c in ENGINE_CASES]
)
def test_engine_variant_equals_its_transcription_on_a_grid(model_id, rough, reference):
    nv, nl, lv = _grid_cosines()
    model_ref = _variant(model_id).reference
    assert model_ref  # the file and function transcribed
    for r in (0.0, 0.1, 0.5, 1.0) if rough else (0.3,):
        for rho in (0.2, 0.8, 1.0):
            params = {"albedo": rho, **({rough: r} if rough else {})}
            got = _ours(_variant(model_id, **params), nv, nl, lv)
            np.testing.assert_allclose(
                got, reference(nv, nl, lv, r, rho), rtol=1e-12, err_msg=f"{model_id} {params}"
            )


def test_materialx_eon_through_genosl_is_not_eon():
    """The OSL output of an EON node differs from EON (and from the GLSL node) by far more
    than rounding: the qualitative model loses energy where EON keeps it."""
    nv, nl, lv = _grid_cosines()
    genosl = materialx_genosl_eon_node(nv, nl, lv, 0.7, 0.8)
    glsl = mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.7, 0.8, energy_compensation=True)
    assert np.max(np.abs(genosl - glsl) / glsl) > 0.1


def test_osl_eon_keeps_the_negative_s_that_materialx_clamps(rng):
    """BSDL has no L·V clamp: where L·V > 1e-8 it is MaterialX's GLSL node (floors aside),
    where L·V < 0 it is EON, below MaterialX's values."""
    nv, nl, lv = _random_cosines(rng)
    osl = bsdl_oren_nayar_diffuse(nv, nl, lv, 0.7, 0.8, True)
    mx = mx_oren_nayar_diffuse_bsdf(nv, nl, lv, 0.7, 0.8, True)
    ok = lv > MX_EPS
    np.testing.assert_allclose(osl[ok], mx[ok], rtol=1e-12)
    np.testing.assert_allclose(osl, _ours(rd.EON(0.8, 0.7), nv, nl, lv), rtol=1e-12)
    assert np.all(osl[lv < 0] < mx[lv < 0])


def test_unity_disney_diffuse_at_normal_view_is_one_at_rho_r_one():
    """HDRP's constant 1.03571 is the directional albedo of Burley at θo = 0, ρ = r = 1: the
    variant's albedo there is 1 to the constant's five digits."""
    n = np.array([0.0, 0.0, 1.0])
    unity = _variant("unity-disney-diffuse", albedo=1.0, roughness=1.0)
    albedo = float(unity.directional_albedo(n))
    assert albedo == pytest.approx(1.0, abs=5e-5)


def test_filament_lambert_ignores_roughness_and_is_lambert(rng):
    nv, nl, lv = _random_cosines(rng)
    np.testing.assert_allclose(
        _ours(_variant("filament-lambert", albedo=0.6), nv, nl, lv), 0.6 / PI, rtol=1e-15
    )
