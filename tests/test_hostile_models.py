"""No model returns a negative or meaningless value for accepted parameters: combinations
valid one by one but not together are refused naming both, and every closed-form registry
model is finite and non-negative over its declared box (hypothesis)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from roughdiffuse import registry
from roughdiffuse.engine.dispatch import use_fastpath
from roughdiffuse.models.constraints import legendre_minimum


def test_hapke_legendre_with_a_negative_phase_function_is_refused_naming_both():
    with pytest.raises(ValueError, match="bh and ch together") as info:
        registry.create("hapke-legendre", bh=-1.0, ch=-1.0)
    assert "bh=-1" in str(info.value) and "ch=-1" in str(info.value)
    registry.create("hapke-legendre", bh=-0.4, ch=0.3)  # ISIS's example: accepted


@given(st.floats(-1.0, 1.0), st.floats(-1.0, 1.0))
def test_legendre_minimum_is_the_least_value_on_a_fine_grid(b, c):
    """Against brute force: p(x) = 1 + b x + c (3x² − 1)/2 sampled at 20,001 points."""
    x = np.linspace(-1.0, 1.0, 20_001)
    brute = float(np.min(1.0 + b * x + c * (1.5 * x * x - 0.5)))
    assert float(legendre_minimum(b, c)) == pytest.approx(brute, abs=1e-7)


@pytest.mark.parametrize("eta", [1e-154, 0.0, 0.5, 5.5, 1e3, math.nan])
def test_coated_refuses_eta_outside_its_physical_range_naming_it(eta):
    """η below 1 (the coat's internal reflectance from above assumes η ≥ 1; η ≈ 1e-154 made
    η² underflow to NaN) or above 5 (beyond any transparent material) is refused, the
    message naming η and its range."""
    with pytest.raises(ValueError, match=r"eta must be in \[1, 5\]"):
        registry.create("coated", eta=eta)


def test_coated_at_the_ends_of_its_eta_range_is_finite_and_non_negative():
    """η = 1 (no interface) and η = 5, smooth and rough, over an Oren–Nayar base: finite and
    non-negative at grazing and normal directions."""
    theta = np.radians([0.0, 45.0, 89.0, 90.0])
    ti, to = (a.ravel() for a in np.meshgrid(theta, theta, indexing="ij"))
    wi = np.stack([np.sin(ti), 0 * ti, np.cos(ti)], -1)
    wo = np.stack([-np.sin(to), 0 * to, np.cos(to)], -1)
    for eta in (1.0, 5.0):
        for alpha in (0.0, 1.0):
            m = registry.create("coated", eta=eta, roughness=alpha, albedo=1.0, sigma=1.5)
            with use_fastpath(False):
                f = np.asarray(m.brdf(wi, wo))
            assert np.all(np.isfinite(f)) and np.all(f >= 0.0), (eta, alpha, f)


def test_accepted_legendre_models_are_non_negative_at_every_phase():
    m = registry.create("hapke-legendre", bh=1.0, ch=0.0)  # p(π) = 0: the edge, accepted
    theta = np.linspace(0.0, math.pi / 2 - 1e-6, 64)
    wi = np.stack([np.sin(theta), 0 * theta, np.cos(theta)], -1)
    wo = np.stack([-np.sin(theta), 0 * theta, np.cos(theta)], -1)
    with use_fastpath(False):
        assert np.all(np.asarray(m.brdf(wi, wo)) >= 0.0)


CLOSED_FORM = [e for e in registry.entries() if getattr(e.cls, "closed_form", True)]


def _value(p, draw):
    if p.categorical:
        return draw(st.sampled_from(p.choices))
    lo = p.min if p.min is not None else -10.0
    hi = p.max if p.max is not None else 10.0
    hi = min(hi, lo + 100.0)  # unbounded above: a wide but finite part of the box
    value = draw(st.floats(lo, hi, allow_nan=False, exclude_min=p.min_open))
    return value


@st.composite
def parameters(draw, entry):
    values = {}
    for p in entry.parameters:  # categorical first: they decide which numbers apply
        if p.categorical:
            values[p.name] = _value(p, draw)
    for p in entry.parameters:
        if not p.categorical and p.applies(values):
            values[p.name] = _value(p, draw)
    return values


ANGLE = st.floats(0.0, math.pi / 2, allow_nan=False)


@pytest.mark.parametrize("entry", CLOSED_FORM, ids=lambda e: getattr(e, "id", str(e)))
@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_every_model_is_finite_and_non_negative_over_its_declared_box(entry, data):
    params = data.draw(parameters(entry))
    try:
        model = entry.create(**params)
    except ValueError as exc:  # a combination refused by its declaration, naming the parameters
        assert " and " in str(exc) and "together" in str(exc), exc
        return
    ti, to = data.draw(ANGLE), data.draw(ANGLE)
    dphi = data.draw(st.floats(0.0, 2 * math.pi))
    wi = np.array([[math.sin(ti), 0.0, math.cos(ti)]])
    wo = np.array([[math.sin(to) * math.cos(dphi), math.sin(to) * math.sin(dphi), math.cos(to)]])
    with use_fastpath(False):
        f = np.asarray(model.brdf(wi, wo), dtype=float)
    assert np.all(np.isfinite(f)), (params, ti, to, dphi, f)
    assert np.all(f >= 0.0), (params, ti, to, dphi, f)
