"""The layered walk with a scattering medium in the coat (single-scattering albedo ω,
Henyey–Greenstein g, optical thickness τ): against a closed form, conservation, its limits
and a real renderer.

* Single scattering, closed form: with no interface (η = 1) and a black base, a slab of
  optical thickness τ scatters once with the BRDF ω p(cos Θ) (1 − e^{−τ (1/μi + 1/μo)}) /
  (μi + μo) (Chandrasekhar 1960, "Radiative Transfer", Sec. 46, eq. 11, its p/4π normalised
  to 1 over the sphere), Θ between the directions of travel before and after (cos Θ =
  −ωi · ωo); a small ω makes the multiple scattering O(ω²).
* The white furnace: a conservative medium (ω = 1) over a white base under a smooth or rough
  coat loses nothing (directional albedo 1), for forward and backward scattering.
* ω = 0 is the absorbing walk (the same paths, the same numbers).
* Mitsuba 3's ``volpath`` rendering the layer as geometry (a dielectric box with a
  homogeneous medium over a diffuse plane; :mod:`roughdiffuse.accuracy.layered_medium`),
  smooth and rough coats: within 1 % plus four combined standard errors (slow).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.simulate import layered

pytest.importorskip("numba")

Z_MAX = 4.5


def _hg(cos_t: np.ndarray, g: float) -> np.ndarray:
    """Henyey and Greenstein 1941, normalised to 1 over the sphere."""
    return (1 - g * g) / (4 * math.pi * (1 + g * g - 2 * g * cos_t) ** 1.5)


@pytest.mark.parametrize("g", [0.0, 0.6, -0.4])
def test_single_scattering_of_a_bare_slab_is_chandrasekhars(g: float) -> None:
    ti = np.radians([0.0, 30.0, 60.0, 30.0, 70.0])
    tr = np.radians([40.0, 30.0, 20.0, 75.0, 50.0])
    dp = np.radians([0.0, 180.0, 90.0, 0.0, 180.0])
    omega, tau = 0.02, 0.7
    f, se = layered.brdf(ti, tr, dp, rd.Lambert(0.0), eta=1.0, absorption=tau,
                         medium_albedo=omega, medium_g=g, samples=40_000, seed=3,
                         return_stderr=True)
    mi, mo = np.cos(ti), np.cos(tr)
    wi = np.stack([np.sin(ti), 0 * ti, mi], -1)
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), mo], -1)
    cos_theta = -np.sum(wi * wo, axis=-1)
    ref = omega * _hg(cos_theta, g) * -np.expm1(-tau * (1 / mi + 1 / mo)) / (mi + mo)
    # the multiple scattering left in f is below ω = 2 % of it
    assert np.all(np.abs(f - ref) <= 0.02 * ref + Z_MAX * se), (f, ref, se)


@pytest.mark.parametrize(("alpha", "g"), [(0.0, 0.0), (0.0, 0.8), (0.3, -0.5)])
def test_white_furnace_with_a_conservative_medium(alpha: float, g: float) -> None:
    theta = np.radians([0.0, 45.0, 80.0])
    a, se = layered.directional_albedo(theta, rd.Lambert(1.0), 1.5, alpha, absorption=2.0,
                                       medium_albedo=1.0, medium_g=g, samples=20_000,
                                       return_stderr=True)
    assert np.all(np.abs(a - 1.0) <= Z_MAX * se + 1e-3), (a, se)


def test_a_medium_that_does_not_scatter_is_the_absorbing_walk() -> None:
    kw = dict(absorption=[0.2, 0.5, 1.0], samples=4_000, seed=5)
    plain = layered.brdf(0.4, 0.6, 1.0, rd.Lambert(0.7), 1.5, 0.3, **kw)
    zero = layered.brdf(0.4, 0.6, 1.0, rd.Lambert(0.7), 1.5, 0.3, medium_albedo=0.0,
                        medium_g=0.7, **kw)
    np.testing.assert_array_equal(plain, zero)


def test_a_coloured_medium_gives_one_value_per_channel() -> None:
    """Per channel: the channel with the larger albedo reflects more; a grey base under a
    medium of three albedos gives three channels."""
    f = layered.directional_albedo(0.3, rd.Lambert(0.3), 1.5, absorption=1.0,
                                   medium_albedo=[0.2, 0.5, 0.9], medium_g=0.3,
                                   samples=4_000)
    assert f.shape == (3,) and f[0] < f[1] < f[2]


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"medium_albedo": -0.1}, r"medium_albedo .* in \[0, 1\]"),
        ({"medium_albedo": 1.5}, r"medium_albedo .* in \[0, 1\]"),
        ({"medium_albedo": [0.5, math.nan, 0.5]}, r"medium_albedo .* in \[0, 1\]"),
        ({"medium_g": 1.0}, r"medium_g .* in \(-1, 1\)"),
        ({"medium_g": -1.2}, r"medium_g .* in \(-1, 1\)"),
        ({"medium_g": "forward"}, r"medium_g .* in \(-1, 1\)"),
        ({"absorption": -0.5, "medium_albedo": 0.5}, "absorption"),
        ({"absorption": 1.0, "medium_albedo": 0.5, "engine": "numpy"}, "compiled walk"),
        ({"absorption": 1.0, "medium_albedo": [0.5, 0.5],
          "base": rd.Lambert(np.array([0.2, 0.4, 0.6]))}, "medium_albedo has 2 channels"),
    ],
)
def test_bad_medium_named(kwargs: dict, name: str) -> None:
    args = {"base": rd.Lambert(0.5), **kwargs}
    with pytest.raises(ValueError, match=name):
        layered.brdf(0.3, 0.3, 0.0, samples=10, **args)


@pytest.mark.slow
def test_walk_matches_mitsuba_volpath_slab() -> None:
    """Mitsuba 3's ``volpath`` on the slab of four of the accuracy page's layers (a glaze-like
    medium at 45°, a thick back-scattering one over a bright base, a conservative one over a
    black base, the glaze under a rough ``roughdielectric`` coat against the walk's
    single-scattering interface): the walk's directional albedo within 1 % plus four
    combined standard errors."""
    from mitsuba_setup import mitsuba_variant
    from roughdiffuse.accuracy import layered_medium

    mi = mitsuba_variant("scalar_rgb")
    for case in [layered_medium.CASES[k] for k in (1, 3, 5, 6)]:
        r = layered_medium.compare(mi, case, samples=40_000, spp=64, res=24)
        se = math.hypot(r["walk_se"], r["render_se"])
        assert abs(r["walk"] - r["render"]) <= 0.01 * r["render"] + Z_MAX * se, (case, r)
