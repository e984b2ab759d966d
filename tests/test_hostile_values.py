"""Hostile values at the edges of the declared boxes: huge, denormal and infinite parameters,
the horizon, an azimuth of 1e308 degrees, and cosines that no pair of directions has. Valid
input gives a finite, non-negative value; invalid input one line naming the parameter and its
range (exit status 2 on the command line)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import cli, registry
from roughdiffuse._validate import ParameterError
from roughdiffuse.engine.dispatch import use_fastpath
from roughdiffuse.fit.measurements import Measurements
from roughdiffuse.frames import check_cosines


def _error_line(capsys, argv, *words):
    try:
        status = cli.main(argv)
    except SystemExit as stop:  # argparse's own errors
        status = stop.code
    out, err = capsys.readouterr()
    assert status == 2, (out, err)
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in err, err
    for w in words:
        assert w in lines[0], lines[0]
    return lines[0]


# ------------------------------------------------------------------ parameters
# every numeric parameter that ISIS leaves unbounded above: its ceiling, and one beyond it
UNBOUNDED_IN_ISIS = [
    ("lunar-lambert", "limb_darkening"),
    ("hapke", "b0"),
    ("hapke-legendre", "b0"),
    ("hapke-2012", "bs0"),
    ("hapke-2012", "bc0"),
    ("hapke-2012", "porosity"),
]


@pytest.mark.parametrize(("model", "name"), UNBOUNDED_IN_ISIS)
@pytest.mark.parametrize("value", [1e308, 1.0001e3, math.inf, -math.inf, math.nan])
def test_huge_parameters_are_refused_naming_the_range(model, name, value):
    with pytest.raises(ParameterError, match=rf"^{name} must be .*1000") as info:
        registry.create(model, **{name: value})
    assert "\n" not in str(info.value)


def _corners():
    """θi, θr in {0, 45°, 90°} and Δφ in {0, 90°, 180°}: (wi, wo) of shape (27, 3)."""
    t = np.radians([0.0, 45.0, 90.0])
    ti, to, dp = (a.ravel() for a in np.meshgrid(t, t, 2 * t, indexing="ij"))
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], -1)
    wo = np.stack([np.sin(to) * np.cos(dp), np.sin(to) * np.sin(dp), np.cos(to)], -1)
    return wi, wo


@pytest.mark.parametrize(("model", "name"), UNBOUNDED_IN_ISIS)
def test_at_the_ceiling_every_corner_is_finite_and_non_negative(model, name):
    m = registry.create(model, **{name: 1e3})
    wi, wo = _corners()
    with use_fastpath(False):
        f = np.asarray(m.brdf(wi, wo))
        a = np.asarray(m.directional_albedo(wo))
    assert np.all(np.isfinite(f)) and np.all(f >= 0.0)
    assert np.all(np.isfinite(a)) and np.all(a >= 0.0)


def test_a_denormal_limb_darkening_is_lambert():
    """L → 0 is Lambert: f = ρ/π (McEwen 1991) at every corner."""
    m = rd.LunarLambert(0.6, limb_darkening=5e-324)
    wi, wo = _corners()
    with use_fastpath(False):
        f = np.asarray(m.brdf(wi, wo))
    np.testing.assert_allclose(f, 0.6 / math.pi, rtol=1e-15)


@pytest.mark.parametrize("value", ["1e308", "inf", "-1e-320", "nan"])
def test_param_value_on_the_command_line_is_one_line(capsys, value):
    argv = ["eval", "--model", "lunar-lambert", "--param", f"limb_darkening={value}"]
    _error_line(capsys, argv, "limb_darkening", "[0, 1000]")


# ------------------------------------------------------------------ the horizon
def test_minnaert_k0_at_the_limb_is_its_stated_floor():
    """k = 0: f = ρ/π (μi μo)^(−1), each cosine floored at 1e-6 (the formula's stated limit):
    at θi = 0, θr = 90° that is ρ/π · 1e6."""
    m = rd.Minnaert(0.5, k=0.0)
    wi, wo = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    with use_fastpath(False):
        f = float(m.brdf(wi, wo))
    assert f == pytest.approx(0.5 / math.pi * 1e6, rel=1e-12)


CLOSED_FORM = [e for e in registry.entries() if getattr(e.cls, "closed_form", True)]


@pytest.mark.parametrize("entry", CLOSED_FORM, ids=lambda e: e.id)
def test_every_model_is_finite_on_the_horizon(entry):
    """θ = 90° exactly (the stated limit: each model's floors), for the declared example."""
    m = entry.create()
    wi, wo = _corners()
    with use_fastpath(False):
        f = np.asarray(m.brdf(wi, wo), dtype=float)
    assert np.all(np.isfinite(f)) and np.all(f >= 0.0), f


_H = math.pi / 2
HORIZON_CORNERS = {  # (θi, θr, Δφ): each with θ = 90° for at least one direction
    "light on the horizon": (_H, 0.0, 0.0),
    "view on the horizon": (0.0, _H, 0.0),
    "both, same side": (_H, _H, 0.0),
    "both, opposite (wi = -wo)": (_H, _H, math.pi),
    "both, at right angles": (_H, _H, _H),
    "light on the horizon, view at 45": (_H, math.pi / 4, 0.0),
    "view on the horizon, light at 45": (math.pi / 4, _H, math.pi),
}
NO_LIMIT = {  # wi = -wo along the horizon: the half vector is 0; f has no limit there
    ("torrance-sparrow", "both, opposite (wi = -wo)"),
    ("torrance-sparrow-beckmann", "both, opposite (wi = -wo)"),
    ("mix", "both, opposite (wi = -wo)"),  # its Torrance-Sparrow lobe
    ("lambert-sphere", "both, opposite (wi = -wo)"),  # phase function 0 times 1/(μi + μo)
}


def _f(model, ti, to, dp):
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.array([math.sin(to) * math.cos(dp), math.sin(to) * math.sin(dp), math.cos(to)])
    with use_fastpath(False):
        return float(np.ravel(np.asarray(model.brdf(wi, wo), dtype=float))[0])


def _horizon_cases():
    for entry in CLOSED_FORM:
        for corner in HORIZON_CORNERS:
            if (entry.id, corner) not in NO_LIMIT:
                yield pytest.param(entry, corner, id=f"{entry.id}: {corner}")


@pytest.mark.parametrize(("entry", "corner"), list(_horizon_cases()))
def test_the_horizon_is_the_value_just_above_it(entry, corner):
    """The stated rule of θ = 90°: the value 1e-7 rad above the horizon, i.e. the formula's
    limit where it is finite, and where it diverges its value with the cosine (or the sum of
    cosines) it divides by floored at 1e-6, which 1e-7 rad is already below."""
    ti, to, dp = HORIZON_CORNERS[corner]
    m = entry.create()
    on = _f(m, ti, to, dp)
    above = _f(m, ti - 1e-7 if ti == _H else ti, to - 1e-7 if to == _H else to, dp)
    assert math.isfinite(on) and on >= 0.0
    # Chan's limit is approached as a power of log(1/δ): 0.2 % at 1e-7 rad; a limit of 0
    # linearly (Unity's diffuse GGX: 1.7e-7 at 1e-7 rad)
    assert on == pytest.approx(above, rel=5e-3, abs=1e-6)


@pytest.mark.parametrize("model_id", ["lommel-seeliger", "lunar-lambert", "hapke",
                                      "hapke-legendre", "hapke-2012"])  # fmt: skip
@pytest.mark.parametrize("corner", ["both, same side", "both, at right angles"])
def test_both_directions_on_the_horizon_is_the_floor_of_the_sum(model_id, corner):
    """f ∝ 1/(μi + μo) near the horizon (Lommel–Seeliger's factor, Hapke 2012 Eq. 10.17):
    on it, the sum is the floor 1e-6, so f(90°) · 1e-6 = f(90° − δ) · 2 sin δ where the sum
    2 sin δ is still above the floor (the other factors change by O(δ))."""
    _, _, dp = HORIZON_CORNERS[corner]
    m = registry.create(model_id)
    delta = 1e-4
    near = _f(m, _H - delta, _H - delta, dp) * 2.0 * math.sin(delta)
    assert _f(m, _H, _H, dp) * 1e-6 == pytest.approx(near, rel=2e-3)


def test_minnaert_k0_on_both_horizons_is_each_cosine_at_the_floor():
    """k = 0: f = ρ/π (μi μo)^(−1) with each cosine 1e-6: ρ/π · 1e12."""
    m = rd.Minnaert(0.5, k=0.0)
    assert _f(m, _H, _H, 0.0) == pytest.approx(0.5 / math.pi * 1e12, rel=1e-12)


# ------------------------------------------------------------------ the azimuth
def _brdf_line(capsys, delta_phi):
    argv = ["eval", "--model", "oren-nayar-full", "--theta-i", "60", "--theta-r", "30"]
    assert cli.main([*argv, "--delta-phi", delta_phi]) == 0
    out = capsys.readouterr().out
    return next(line for line in out.splitlines() if line.startswith("brdf")), out


def test_a_huge_azimuth_is_reduced_exactly():
    """Δφ = 1e308° is an integer number of degrees: Python's integers give its residue mod
    360 exactly (an independent reduction), and the BRDF there equals the one at 1e308°."""
    residue = int(1e308) % 360
    assert residue == 296


def test_a_huge_azimuth_on_the_command_line(capsys):
    huge, out = _brdf_line(capsys, "1e308")
    assert "≡ 296° mod 360" in out
    same, _ = _brdf_line(capsys, str(int(1e308) % 360))
    mirrored, _ = _brdf_line(capsys, str(360 - int(1e308) % 360))  # isotropic: ±Δφ
    assert huge == same == mirrored


def test_an_azimuth_beyond_every_float_in_degrees_is_one_line(capsys):
    argv = ["eval", "--model", "eon", "--delta-phi", "1e308rad"]
    _error_line(capsys, argv, "--delta-phi", "1e308rad")


# ------------------------------------------------------------------ cosines
@pytest.mark.parametrize(
    ("mu_i", "mu_o", "cos_io", "named", "gram"),
    [
        (1.5, 0.5, 0.5, "mu_i", False),
        (0.5, -1.01, 0.5, "mu_o", False),
        (0.5, 0.5, 2.0, "cos_io", False),
        (1.0, 1.0, 0.5, "cos_io", True),  # both along the normal: wi·wo = 1
        (0.0, 0.0, 0.0, None, False),  # both on the horizon, 90° apart: possible
        (0.5, 0.5, -0.9, "cos_io", True),  # wi·wo >= cos(60° + 60°) = −0.5
        (math.inf, 0.5, 0.5, "mu_i", False),
    ],
)
def test_cosines_no_pair_of_directions_has_are_refused(mu_i, mu_o, cos_io, named, gram):
    """A cosine beyond ±1 is refused everywhere; a triple off the Gram condition only where
    cosines come from the user's data (Measurements): a model takes it (renderers clamp μ at
    the horizon), finite and non-negative."""
    model = rd.Lambert(0.5)
    if named is None or gram:
        assert float(model.brdf_cosines(mu_i, mu_o, cos_io)) == pytest.approx(0.5 / math.pi)
        if named is None:
            return
    else:
        with pytest.raises(ParameterError, match=rf"^{named} must be in"):
            model.brdf_cosines(mu_i, mu_o, cos_io)
    with pytest.raises(ParameterError, match=rf"^{named} must be"):
        Measurements(
            np.array([abs(mu_i) if named != "mu_i" else mu_i]),
            np.array([abs(mu_o) if named != "mu_o" else mu_o]),
            np.array([cos_io]),
            np.array([0.1]),
            np.array([1.0]),
        )


def test_cosines_of_real_directions_in_float32_pass():
    """Cosines computed in float32 from random unit vectors, grazing ones included, are never
    refused (their rounding is within the check's tolerance)."""
    rng = np.random.default_rng(7)
    v = rng.normal(size=(2, 20_000, 3))
    v[:, :, 2] = np.abs(v[:, :, 2]) * (rng.random((2, 20_000)) < 0.5)  # half on the horizon
    v = (v / np.linalg.norm(v, axis=-1, keepdims=True)).astype(np.float32)
    wi, wo = v
    check_cosines(wi[:, 2], wo[:, 2], np.sum(wi * wo, axis=-1))


def test_nodata_cosines_pass_the_check():
    check_cosines(np.array([np.nan, 0.5]), np.array([0.5, 0.5]), np.array([0.2, 0.25]))
