"""The explorer's GLSL, printed from each model's own code, against the Python model.

Every model the page offers (every closed form of the registry, each value of its menus) is
evaluated in headless Chromium by the page's own evaluator (render to an RGBA32F texture, read
back), all in one page load, at each model's test points and at the corners of its parameter
box (each numeric parameter at the ends of its range, the others at their example: roughness
0 and at its maximum, albedo 0 and 1), over geometries that include grazing (μ = 0, 1e-4,
1e-3), normal incidence, below the horizon and Δφ from 0° to 180°. The cosines are rounded
to float32 (what the GPU receives); the Python model evaluates them in float64.

Tolerance: |GLSL − Python| ≤ RTOL |Python| + ATOL max|Python| + TINY, with max|Python| the
largest value of that parameter set over the geometries and TINY float32's smallest normal.
WebGL has float32 alone: each operation rounds at 2^-24 ≈ 6e-8 relative, and the polynomial
substitutes of the float32 trace (sin, cos, exp, atan2, acos; roughdiffuse.engine.trace) are
within about 1e-7 relative; a formula of a few hundred operations whose worst condition
number is of order 10 stays within about 1e-5, so RTOL = 1e-4 leaves a factor 10.
ATOL = 1e-5 of the set's largest value covers values that cancel to nearly 0 (Fujii's 1 + r s
at s → −1, a Lambert sphere's terms of opposite sign growing as 1/(μi + μo) at grazing):
there the absolute error is that of the terms, not of their difference.

Limits of float32 (WebGL has no double), kept out of the comparison and said here:
* a microfacet lobe narrower than the float32 resolution of the cosines (Torrance–Sparrow,
  Mix and the coat with σ or α below 0.03): D's exponent θh²/2σ² multiplies the ~1e-7
  rounding of the cosines; those corners are checked for finiteness only.
* Hapke with macroscopic roughness (θ̄ > 0) within 1° of Δφ = 0° or 180°: its shadowing
  function depends on tan(Δφ/2), whose derivative in cos Δφ is infinite at Δφ = 0, and cos Δφ
  from float32 cosines is known only to about 1e-7; those geometries are left out for Hapke
  with θ̄ > 0.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from example_models import points_of
from explorer_browser import frames, open_page
from roughdiffuse._validate import ParameterError
from roughdiffuse.explorer import model_from_params
from roughdiffuse.explorer.params import explorer_entries, flat_key

RTOL = 1e-4
ATOL = 1e-5
TINY = float(np.finfo(np.float32).tiny)
"""The smallest normal float32 (1.2e-38): smaller values are 0 on the GPU (a coat of optical
depth 50 transmits e^-100 of the light)."""
NARROW = 0.03
"""Lobe widths (σ, α, roughness of a glossy model) below which float32 cosines cannot resolve
the lobe (module docstring): checked for finiteness only."""


def _corners(entry, choices):
    """The corners of the parameter box: each numeric parameter at each end of its range
    (its fit range where the declared range is open or unbounded), the others at their
    example."""
    params = [p for p in entry.applicable(choices) if not p.categorical]
    start = {p.name: p.default if p.example is None else p.example for p in params}
    out = []
    for p in params:
        lo = p.min if p.min is not None and not p.min_open else p.fit_range[0]
        hi = p.max if p.max is not None and math.isfinite(p.max) else p.fit_range[1]
        for v in (lo, hi):
            out.append({**start, p.name: float(v)})
    return out


def _accepted(entry, point) -> bool:
    """Whether the model takes this parameter set: a corner valid parameter by parameter may
    break a rule of the combination (a Legendre phase function that goes negative)."""
    try:
        entry.create(**{k: v for k, v in point.items()
                        if k in {p.name for p in entry.applicable(point)}})
    except ParameterError:
        return False
    return True


def _cases():
    """(registry id, flat record, narrow) for every model and parameter set checked."""
    out = []
    for entry in explorer_entries():
        menus = [p for p in entry.parameters if p.categorical]
        for combo in itertools.product(*(p.choices for p in menus)):
            choices = {p.name: v for p, v in zip(menus, combo, strict=True)}
            points = [dict(pt) for pt in points_of(entry)
                      if all(pt.get(k, v) == v for k, v in choices.items())]
            # the corners of each menu value; a coat (each parameter set one server shader
            # to compile) at its default menus, its other bases at their test points
            default = all(v == entry.param(k).default for k, v in choices.items())
            corners = _corners(entry, choices) if entry.id != "coated" or default else []
            start = {p.name: p.default if p.example is None else p.example
                     for p in entry.parameters}
            # three different channels: each channel reaches its own output
            colour = {p.name: [0.9, 0.5, 0.05] for p in entry.parameters if p.channels}
            points = [{**start, **pt, **choices}
                      for pt in [*points[:1], {**(points or [{}])[0], **colour}, *points[1:],
                                 *corners]]
            seen = []
            for pt in points:
                record = {}
                for name, value in pt.items():
                    if name not in {p.name for p in entry.applicable(pt)}:
                        continue
                    if entry.param(name).channels and np.ndim(value) == 0:
                        value = [value] * 3
                    record[flat_key(entry, name)] = value
                if record in seen or not _accepted(entry, pt):
                    continue
                seen.append(record)
                lobe = {"torrance-sparrow": "sigma", "torrance-sparrow-beckmann": "alpha",
                        "mix": "sigma", "coated": "coat_roughness"}.get(entry.id)
                width = float(record[lobe]) if lobe in record else 1.0
                narrow = width < NARROW and not (entry.id == "coated" and width == 0.0)
                out.append((entry.id, {"model": entry.id, **record}, narrow))
    return out


CASES = _cases()


def _geometries() -> np.ndarray:
    """(N, 3) float32 cosines: a grid with grazing and below-horizon values, and random ones."""
    mus = np.array([-0.2, 0.0, 1e-4, 1e-3, 0.05, 0.3, 0.7, 0.95, 1.0])
    dphi = np.radians([0.0, 45.0, 90.0, 135.0, 180.0])
    mi, mo, dp = (a.ravel() for a in np.meshgrid(mus, mus, dphi, indexing="ij"))
    rng = np.random.default_rng(8)
    mi = np.concatenate([mi, rng.uniform(0.0, 1.0, 60)])
    mo = np.concatenate([mo, rng.uniform(0.0, 1.0, 60)])
    dp = np.concatenate([dp, rng.uniform(0.0, np.pi, 60)])
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


def test_cases_cover_every_model_and_the_corners():
    """Every offered model is checked, with albedo 0 and 1 and roughness 0 and its maximum."""
    ids = {c[0] for c in CASES}
    assert ids == {e.id for e in explorer_entries()}
    assert {"hapke", "hapke-2012", "pbrt3-oren-nayar", "coated", "mix"} <= ids
    eon = [c[1] for c in CASES if c[0] == "eon"]
    assert any(r.get("albedo") == [0.0] * 3 for r in eon)
    assert any(r.get("albedo") == [1.0] * 3 for r in eon)
    assert any(r.get("roughness") == 0.0 for r in eon)
    assert any(r.get("roughness") == 1.0 for r in eon)
    bases = {c[1].get("base") for c in CASES if c[0] == "coated"}
    assert {"lambert", "oren-nayar-full", "fujii", "eon"} <= bases


def test_glsl_matches_python_for_every_model(page):
    """Every case in one page load: GLSL within RTOL |Python| + ATOL max|Python|."""
    c64 = GEOMETRIES.astype(np.float64)
    flat = GEOMETRIES.ravel().tolist()
    records = [c[1] for c in CASES]
    glsl_all = page.page.evaluate(
        "([rs, c]) => rs.map((p) => window.rdExplorer.evaluate(p, c))", [records, flat]
    )
    near = _near_principal_plane(c64)[:, None]
    failures = []
    for (model, params, narrow), glsl in zip(CASES, glsl_all, strict=True):
        glsl = np.asarray(glsl, dtype=np.float64).reshape(-1, 3)
        py = np.asarray(model_from_params(params).brdf_cosines(c64[:, 0], c64[:, 1], c64[:, 2]))
        py = np.broadcast_to(py.reshape(len(c64), -1), glsl.shape)
        assert np.all(np.isfinite(py)), f"{params}: Python model not finite"
        if not np.all(np.isfinite(glsl)):
            failures.append(f"{params}: GLSL not finite")
            continue
        if narrow:
            continue
        bad = ~(np.abs(glsl - py) <= RTOL * np.abs(py) + ATOL * np.max(np.abs(py)) + TINY)
        if model.startswith("hapke") and params.get("theta_bar", 0.0) > 0:
            bad &= ~near
        for k in np.flatnonzero(bad.any(axis=1))[:2]:
            failures.append(
                f"{params} at {_describe(GEOMETRIES[k])}: GLSL {glsl[k].tolist()} "
                f"Python {py[k].tolist()}"
            )
    assert not page.errors, page.errors
    assert not failures, f"{len(failures)} differences:\n" + "\n".join(failures)


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
    frames(p)  # the plot is redrawn in the next animation frame: read it after that
    s = p.evaluate("() => window.rdExplorer.state.a")
    ti = math.radians(p.evaluate("() => window.rdExplorer.state.light.theta"))
    assert s["base"] == "eon"
    model = rd.Coated(rd.EON(s["albedo"][1], s["base_roughness"]), s["eta"], s["coat_roughness"],
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
    check above), traced like any model."""
    from roughdiffuse import registry
    from roughdiffuse.models.alias import Alias

    aliases = [e.id for e in registry.entries() if issubclass(e.cls, Alias)]
    assert "pbrt3-oren-nayar" in aliases and "mitsuba06-roughdiffuse" in aliases
    assert set(aliases) <= {c[0] for c in CASES}


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
    frames(p)
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


@pytest.mark.slow  # its own page and three coat programs in SwiftShader: about 10 s
def test_two_coats_side_by_side_keep_their_own_values(browser, explorer_url):
    """A coat traced on the server beside another model, and beside another coat of the same
    structure with other values: each sphere shows its own coat (the second server function
    under names of its own, with its own uniforms)."""
    log = open_page(browser, explorer_url, 1000, 700)
    p = log.page
    centre = (
        "() => { const c = document.getElementById('sphere'); const g = c.getContext('webgl2');"
        " return [0.25, 0.75].map((x) => { const px = new Uint8Array(4);"
        " g.readPixels(Math.round(c.width * x), c.height >> 1, 1, 1, g.RGBA, g.UNSIGNED_BYTE, px);"
        " return px[1]; }); }"
    )
    try:
        p.select_option("#mode", "1")
        p.select_option("#a-model", "eon")
        p.select_option("#b-model", "coated")
        frames(p)
        eon, coat = p.evaluate(centre)
        p.select_option("#a-model", "coated")
        frames(p)
        assert p.evaluate(centre) == [coat, coat] and 0 < coat < eon
        p.fill("#b-eta", "2.5")
        p.dispatch_event("#b-eta", "input")
        frames(p)
        a, b = p.evaluate(centre)
        assert a == coat and b < coat  # a denser coat reflects more, transmits less
        assert not log.errors, log.errors
    finally:
        p.close()
