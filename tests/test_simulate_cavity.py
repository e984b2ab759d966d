"""The V-cavity solver: limits, energy conservation, reciprocity, and an independent ray tracer."""

from __future__ import annotations

import math

import numpy as np
import pytest

from cavity_montecarlo import cavity_radiance_mc
from roughdiffuse.simulate.cavity import cavity_radiance, view_factors


def _dir(theta: float, phi: float) -> np.ndarray:
    return np.array(
        [math.sin(theta) * math.cos(phi), math.sin(theta) * math.sin(phi), math.cos(theta)]
    )


def _random_dir(rng: np.random.Generator, theta_max: float = 1.45) -> np.ndarray:
    return _dir(rng.uniform(0.0, theta_max), rng.uniform(0.0, 2 * math.pi))


def test_flat_cavity_is_lambert():
    rng = np.random.default_rng(0)
    for _ in range(20):
        wi, wo = _random_dir(rng), _random_dir(rng)
        for b in (1, 3, "all"):
            val = cavity_radiance(0.0, rng.uniform(0, 6), wi, wo, 0.7, b)
            assert val == pytest.approx(0.7 / math.pi * wi[2], rel=1e-12)


def test_normal_light_and_view_closed_form():
    # l = v = n: both facets fully lit and seen; one bounce gives ρ/π cos θa (each facet's
    # radiance ρ/π cos θa, projected lengths adding up to the width)
    z = np.array([0.0, 0.0, 1.0])
    for ta in (0.2, 0.7, 1.3):
        assert cavity_radiance(ta, 0.4, z, z, 0.6, 1) == pytest.approx(0.6 / math.pi * math.cos(ta))


def test_single_bounce_linear_in_albedo():
    rng = np.random.default_rng(1)
    ta = rng.uniform(0, 1.5, 50)
    pa = rng.uniform(0, 6.3, 50)
    wi = np.stack([_random_dir(rng) for _ in range(50)])
    wo = np.stack([_random_dir(rng) for _ in range(50)])
    a = cavity_radiance(ta, pa, wi, wo, 0.3, 1)
    b = cavity_radiance(ta, pa, wi, wo, 0.9, 1)
    np.testing.assert_allclose(b, 3.0 * a, rtol=1e-13, atol=1e-300)
    # with interreflection it is not linear (ρ² and higher terms)
    c = cavity_radiance(ta, pa, wi, wo, 0.3, "all")
    d = cavity_radiance(ta, pa, wi, wo, 0.9, "all")
    assert np.max(d / np.maximum(c, 1e-300)) > 3.0 * 1.01


def test_reciprocity_of_cavity_brdf():
    # Helmholtz reciprocity holds for the cavity's BRDF L / cos θi, bounce by bounce: exactly
    # for the closed form, to the element accuracy (the scheme treats l and v differently)
    # with interreflection
    rng = np.random.default_rng(2)
    for _ in range(30):
        ta, pa = rng.uniform(0, 1.4), rng.uniform(0, 6.3)
        wi, wo = _random_dir(rng), _random_dir(rng)
        for b, tol in ((1, 1e-12), (2, 1e-4), ("all", 1e-4)):
            f1 = cavity_radiance(ta, pa, wi, wo, 0.8, b, 128) / wi[2]
            f2 = cavity_radiance(ta, pa, wo, wi, 0.8, b, 128) / wo[2]
            assert f1 == pytest.approx(f2, rel=tol, abs=1e-14)


def test_view_factor_rows_match_closed_form():
    # whole facet to whole facet: F = (2ℓ - 1)/(2ℓ) = 1 - cos θa, ℓ = 1/(2 cos θa) (the
    # three-surface enclosure of a V with unit opening, Modest §4.8);
    # rows of the element matrix must add up to it when weighted by element length
    for ta in (0.3, 0.9, 1.4):
        for k in (1, 7):
            from roughdiffuse.simulate.cavity import element_edges

            e = element_edges(k)
            f = view_factors(ta, e)
            total = np.sum(f * np.diff(e)[:, None])
            assert total == pytest.approx(1.0 - math.cos(ta), rel=1e-12)


def _outgoing_flux(ta: float, pa: float, wi: np.ndarray, k: int, n: int = 20_000) -> float:
    """Flux per unit width leaving the opening: ∫ L (n·v) dω, reduced to the in-plane angle.

    For a long cavity the radiance depends on v only through its in-plane angle ψ; the
    out-of-plane angle integrates to π/2. The ψ integral is the midpoint rule on ``n`` points
    in one vectorised call: the integrand is smooth between the kinks where the visible part
    of a facet or element changes, and the rule's error is O(h²) there too, about 1e-9 of the
    flux at n = 20 000 (1e-11 at 200 000: checked against each other and against an adaptive
    quadrature), far below the 1e-6 the test asks.
    """
    a = np.array([math.cos(pa), math.sin(pa), 0.0])
    z = np.array([0.0, 0.0, 1.0])
    psi = -math.pi / 2 + (np.arange(n) + 0.5) * (math.pi / n)
    v = np.sin(psi)[:, None] * a + np.cos(psi)[:, None] * z
    values = cavity_radiance(ta, pa, wi, v, 1.0, "all", k) * np.cos(psi)
    return 0.5 * math.pi * float(np.sum(values)) * (math.pi / n)


@pytest.mark.parametrize("k", [4, pytest.param(16, marks=pytest.mark.slow)])
def test_energy_conserved_per_cavity_at_unit_albedo(k):
    # what enters the opening (E0 cos θi per unit width) leaves it, to 1e-6
    rng = np.random.default_rng(3)
    for _ in range(6):
        ta, pa = rng.uniform(0.05, 1.5), rng.uniform(0, 6.3)
        wi = _random_dir(rng, 1.5)
        out = _outgoing_flux(ta, pa, wi, k)
        assert out == pytest.approx(wi[2], rel=1e-6)


def test_element_convergence():
    # the error against K = 256 falls as K grows; at K = 64 it is below 1e-3 for θa <= 1.4
    # (single cavities: where the visible segment ends inside an element the error is O(1/K);
    # over the slope distribution these errors average out, see test_simulate_surface.py)
    rng = np.random.default_rng(4)
    for _ in range(8):
        ta, pa = rng.uniform(0.1, 1.4), rng.uniform(0, 6.3)
        wi, wo = _random_dir(rng), _random_dir(rng)
        ref = cavity_radiance(ta, pa, wi, wo, 0.95, "all", 256)
        errs = [abs(cavity_radiance(ta, pa, wi, wo, 0.95, "all", k) / ref - 1) for k in (8, 64)]
        assert errs[1] < 1e-3
        assert errs[1] <= errs[0] + 1e-9


def test_monte_carlo_ray_tracer_agrees():
    """200 random cavities and directions, 1, 2 and all bounces, against an independent
    2-D path tracer. With 600 comparisons, some |z| > 3 are expected by chance (0.27% each);
    the test asserts the distribution: at most 2% beyond 3 s.e., none beyond 5, mean z²
    near 1 and mean z near 0."""
    rng = np.random.default_rng(5)
    zs = []
    for _ in range(200):
        ta, pa = rng.uniform(0.05, 1.4), rng.uniform(0.0, 2 * math.pi)
        wi, wo = _random_dir(rng), _random_dir(rng)
        rho = rng.uniform(0.3, 0.95)
        for b in (1, 2, None):
            mc, se = cavity_radiance_mc(ta, pa, wi, wo, rho, b, 3000, rng)
            exact = float(cavity_radiance(ta, pa, wi, wo, rho, "all" if b is None else b, 64))
            if se <= 1e-9 * abs(mc):  # every path gave the same value (fully lit and seen, or dark)
                # a lit-and-seen part too small for any of the 3000 rays to find is allowed
                assert abs(mc - exact) <= 10.0 * rho / math.pi / 3000 / wo[2]
                continue
            zs.append((mc - exact) / se)
    z = np.array(zs)
    assert len(z) > 400
    assert np.mean(np.abs(z) > 3.0) <= 0.02
    assert np.max(np.abs(z)) < 5.0
    assert 0.8 < np.mean(z * z) < 1.25
    assert abs(np.mean(z)) < 4.0 / math.sqrt(len(z))


@pytest.mark.parametrize(
    "kw, word",
    [
        ({"bounces": 0}, "bounces"),
        ({"bounces": "many"}, "bounces"),
        ({"elements": 0}, "elements"),
        ({"albedo": 1.5}, "albedo"),
        ({"theta_a": math.pi / 2}, "theta_a"),
        ({"theta_a": -0.1}, "theta_a"),
    ],
)
def test_bad_input_names_parameter(kw, word):
    args = {"theta_a": 0.3, "phi_a": 0.0, "wi": _dir(0.2, 0), "wo": _dir(0.3, 1), **kw}
    with pytest.raises(ValueError, match=word):
        cavity_radiance(**args)
