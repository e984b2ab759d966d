"""The GLSL copy of every model (explorer/static/glsl/brdf.glsl) against the Python model.

Test vectors come from Python: local cosines (μi, μo, cos ψ) over the whole domain — grazing
(μ = 0, 1e-4, 1e-3), normal (μ = 1), below the horizon (μ = −0.2), Δφ from 0° to 180° — plus
random geometries. They are rounded to float32 (what the GPU receives), the Python model
evaluates them in float64, and headless Chromium evaluates the GLSL (the page's own evaluator:
render to an RGBA32F texture, read back). Agreement required: |GLSL − Python| ≤ 1e-4 |Python|
+ 1e-7 sr⁻¹ (the absolute term only matters where a value cancels to nearly 0, e.g. Fujii's
1 + r s at s → −1; it is 3e-7 of 1/π).

Limits of float32 (WebGL has no double), kept out of the domain and said here:
* Torrance–Sparrow with σ < 0.03 rad (1.7°): D's exponent θh²/2σ² multiplies the ~1e-7
  rounding of the cosines (σ = 0.02 misses by about 1e-5 sr⁻¹ in the lobe's tail, σ = 0.01 by
  far). σ from 0.03 rad is tested.
* η < 1 exactly at the critical angle, where the Fresnel factor has an infinite derivative:
  η = 0.75 (total internal reflection on part of the grid, no grid point on the boundary).
* Hapke with macroscopic roughness (θ̄ > 0) within 1° of Δφ = 0° or 180°: its shadowing
  function depends on tan(Δφ/2), whose derivative in cos Δφ is infinite at Δφ = 0, and cos Δφ
  from float32 cosines is known only to about 1e-7, Δφ to about 3e-4 rad; the value then
  moves by up to 0.4 % (0° at grazing) and can round below 0 at 180° with both directions
  grazing. Those grid points are left out for Hapke with θ̄ > 0.
* d'Eon's Lambert spheres: relative tolerance 3e-4. Both variants add terms of opposite sign
  that grow as 1/(μi + μo); with both directions at μ = 1e-4 they cancel about 1000-fold
  (the full variant missed 1e-4 by 1.1e-4 there).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from example_models import points_of
from explorer_browser import open_page
from roughdiffuse.explorer import model_from_params
from roughdiffuse.explorer.params import explorer_entries, flat_key

RTOL = 1e-4
ATOL = 1e-7



def _parameter_sets() -> dict[str, list[dict]]:
    """Registry id -> the flat records (``model_from_params``'s input) the GLSL is checked at:
    each model class's ``glsl_test_points`` (else its example and test points), colour
    parameters as three channels, parameter names as the GLSL's keys. An alias (its base
    model's GLSL after the conversion the page evaluates) is checked against its own Python
    kernel, which converts with the numeric ``to_base``."""
    out = {}
    for entry in explorer_entries():
        sets = []
        for point in entry.glsl_test_points() or points_of(entry):
            record = {}
            for name, value in point.items():
                if entry.param(name).channels and np.ndim(value) == 0:
                    value = [value] * 3
                record[flat_key(entry, name)] = value
            sets.append(record)
        out[entry.id] = sets
    return out


PARAMETER_SETS = _parameter_sets()


def _geometries() -> np.ndarray:
    """(N, 3) float32 cosines: a grid with grazing and below-horizon values, and random ones."""
    mus = np.array(
        [-0.2, 0.0, 1e-4, 1e-3, 0.01, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 0.95, 0.99, 0.999, 1.0]
    )
    dphi = np.radians([0.0, 15.0, 45.0, 89.0, 90.0, 91.0, 135.0, 170.0, 180.0])
    mi, mo, dp = (a.ravel() for a in np.meshgrid(mus, mus, dphi, indexing="ij"))
    rng = np.random.default_rng(8)
    mi = np.concatenate([mi, rng.uniform(0.0, 1.0, 400)])
    mo = np.concatenate([mo, rng.uniform(0.0, 1.0, 400)])
    dp = np.concatenate([dp, rng.uniform(0.0, np.pi, 400)])
    cos_io = np.clip(mi * mo + np.sqrt(1 - mi**2) * np.sqrt(1 - mo**2) * np.cos(dp), -1.0, 1.0)
    return np.stack([mi, mo, cos_io], axis=-1).astype(np.float32)


GEOMETRIES = _geometries()


@pytest.fixture(scope="module")
def page(browser, explorer_url):  # noqa: F811 - fixtures
    log = open_page(browser, explorer_url, 800, 600)
    yield log
    log.page.close()


def _describe(cos: np.ndarray) -> str:
    mu_i, mu_o, c = (float(x) for x in cos)
    deg = lambda x: math.degrees(math.acos(max(min(x, 1.0), -1.0)))  # noqa: E731
    si, so = math.sqrt(max(1 - mu_i**2, 0)), math.sqrt(max(1 - mu_o**2, 0))
    dphi = f"{deg((c - mu_i * mu_o) / (si * so)):.3f}" if si * so > 0 else "undefined"
    return (
        f"mu_i={mu_i:.7g} mu_o={mu_o:.7g} cos_io={c:.7g} (theta_i={deg(mu_i):.4f} deg, "
        f"theta_r={deg(mu_o):.4f} deg, delta_phi={dphi} deg)"
    )


def _near_principal_plane(cos: np.ndarray, degrees: float = 1.0) -> np.ndarray:
    """Geometries within ``degrees`` of Δφ = 0° or 180° (see the module docstring: Hapke)."""
    mu_i, mu_o, c = cos[:, 0], cos[:, 1], cos[:, 2]
    s = np.sqrt(np.clip(1 - mu_i**2, 0, 1) * np.clip(1 - mu_o**2, 0, 1))
    cos_phi = np.divide(c - mu_i * mu_o, s, out=np.ones_like(s), where=s > 0)
    return np.abs(cos_phi) >= math.cos(math.radians(degrees))


@pytest.mark.parametrize("model", list(PARAMETER_SETS))
def test_glsl_matches_python(page, model):
    """Every parameter set of ``model``: GLSL within 1e-4 relative of Python everywhere."""
    c64 = GEOMETRIES.astype(np.float64)
    flat = GEOMETRIES.ravel().tolist()
    failures = []
    for params in PARAMETER_SETS[model]:
        params = {"model": model, **params}
        glsl = page.page.evaluate("([p, c]) => window.rdExplorer.evaluate(p, c)", [params, flat])
        glsl = np.asarray(glsl, dtype=np.float64).reshape(-1, 3)
        py = np.asarray(model_from_params(params).brdf_cosines(c64[:, 0], c64[:, 1], c64[:, 2]))
        py = np.broadcast_to(py.reshape(len(c64), -1), glsl.shape)
        assert np.all(np.isfinite(py)), f"{params}: Python model not finite"
        rtol = 3e-4 if model == "lambert-sphere" else RTOL
        bad = ~(np.abs(glsl - py) <= rtol * np.abs(py) + ATOL)
        if model == "hapke" and params.get("theta_bar", 0.0) > 0:
            bad &= ~_near_principal_plane(c64)[:, None]
        for k in np.flatnonzero(bad.any(axis=1))[:3]:
            failures.append(
                f"{params} at {_describe(GEOMETRIES[k])}: GLSL {glsl[k].tolist()} "
                f"Python {py[k].tolist()}"
            )
    assert not page.errors, page.errors
    assert not failures, f"GLSL and Python differ for {model}:\n" + "\n".join(failures)


def test_geometries_cover_the_domain():
    """The test vectors include grazing, normal, below-horizon and backward geometries."""
    mu = GEOMETRIES[:, :2]
    assert (mu == 0).any() and (mu == 1).any() and (mu < 0).any()
    assert (np.abs(mu - 1e-4) < 1e-9).any()
    assert (GEOMETRIES[:, 2] <= -0.999).any()


@pytest.mark.slow  # two redraws of the coat in SwiftShader: about 10 s
def test_coated_base_menu_shows_the_chosen_base_sliders(page):
    """Coated's base menu (its declared ``base``): the sliders of the chosen base only, and
    the plotted curve is the coat over that base (Python's Coated(EON(...)))."""
    import roughdiffuse as rd

    p = page.page
    shown = lambda k: p.evaluate(f"() => !document.getElementById('a-{k}-row').hidden")  # noqa: E731
    p.select_option("#a-model", "coated")
    assert shown("base") and shown("sigma") and not shown("base_roughness")
    p.select_option("#a-base", "eon")
    assert shown("base_roughness") and not shown("sigma")
    s = p.evaluate("() => window.rdExplorer.state.a")
    ti = math.radians(p.evaluate("() => window.rdExplorer.state.light.theta"))
    assert s["base"] == "eon"
    model = rd.Coated(rd.EON(s["albedo"][1], s["base_roughness"]), s["eta"], s["roughness"],
                      s["distribution"])
    rows = [r for r in p.evaluate("() => window.rdExplorer.tables().plane.rows")
            if r[0].startswith("A") and r[1] in (-60, 0, 40)]
    for _, theta_r, radiance in rows:  # θr > 0 on the light's side
        tr = math.radians(abs(theta_r))
        wo = [math.sin(tr) * (1 if theta_r >= 0 else -1), 0.0, math.cos(tr)]
        ref = float(model.brdf([math.sin(ti), 0.0, math.cos(ti)], wo)) * math.pi * math.cos(ti)
        assert radiance == pytest.approx(ref, rel=RTOL)
    assert len(rows) == 3 and not page.errors, page.errors


def test_every_alias_is_offered_and_checked():
    """Each renderer variant declared as an Alias is in the page's menus (so in the GLSL
    check above), evaluated by its base model's GLSL."""
    from roughdiffuse import registry
    from roughdiffuse.models.alias import Alias

    aliases = [e.id for e in registry.entries() if issubclass(e.cls, Alias)]
    assert "pbrt3-oren-nayar" in aliases and "mitsuba06-roughdiffuse" in aliases
    assert set(aliases) <= set(PARAMETER_SETS)


def test_alias_in_the_menu_plot_and_url(page):
    """pbrt-v3's OrenNayar picked in A's menu at σ = 20° (its own slider, in degrees): the
    plane plot's radiance is Python's, and the URL reads back as the same slot.

    Reference: pbrt-v3 ``OrenNayar::f`` (src/core/reflection.cpp), transcribed: σ in radians,
    A = 1 − σ²/(2(σ² + 0.33)), B = 0.45 σ²/(σ² + 0.09), f = ρ/π (A + B max(0, cos Δφ) sin α
    tan β), α = max(θi, θr), β = min(θi, θr); in the plane of incidence cos Δφ = 1 on the
    light's side (θr > 0) and −1 opposite."""
    p = page.page
    p.select_option("#a-model", "pbrt3-oren-nayar")
    note = p.locator("#a-alias-note").inner_text()
    assert note == "= Oren–Nayar qualitative with sigma = sigma_deg * 0.0174533", note
    p.fill("#a-sigma_deg", "20")
    p.dispatch_event("#a-sigma_deg", "input")
    p.evaluate("window.rdExplorer.setLight(40, 0)")
    p.wait_for_function(
        "() => (window.rdExplorer.tables().plane?.rows ?? []).some(r => r[0].includes('pbrt-v3'))"
        " && window.rdExplorer.state.light.theta === 40"
    )
    p.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    rows = [r for r in p.evaluate("window.rdExplorer.tables().plane.rows") if r[0].startswith("A")]
    theta_r = np.radians([r[1] for r in rows])
    got = np.array([r[2] for r in rows])
    ti, sigma, rho = math.radians(40.0), math.radians(20.0), 0.8
    a = 1 - sigma**2 / (2 * (sigma**2 + 0.33))
    b = 0.45 * sigma**2 / (sigma**2 + 0.09)
    tr = np.abs(theta_r)
    alpha, beta = np.maximum(ti, tr), np.minimum(ti, tr)
    cos_dphi = np.where(theta_r > 0, 1.0, 0.0)  # max(0, cos Δφ)
    f = rho / math.pi * (a + b * cos_dphi * np.sin(alpha) * np.tan(beta))
    want = f * math.pi * math.cos(ti)  # L = f E0 cos θi, E0 = π
    inside = tr < math.radians(89.5)
    assert np.allclose(got[inside], want[inside], rtol=2e-4), (got[::30], want[::30])
    round_trip = p.evaluate(
        """async () => {
          const u = await import(new URL("js/urlstate.js", location.href).href);
          return u.decodeState(window.rdExplorer.encodeHash()).a;
        }"""
    )
    assert round_trip["model"] == "pbrt3-oren-nayar" and round_trip["sigma_deg"] == 20
    shorts = p.evaluate(
        """async () => {
          const m = await import(new URL("js/models.js", location.href).href);
          return m.MODELS.map((x) => x.short);
        }"""
    )
    assert len(set(shorts)) == len(shorts), shorts  # the legends tell every model apart
    assert not page.errors, page.errors
