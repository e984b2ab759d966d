"""The model registry and the declarations it reads, and values no model may take (None,
booleans, strings, NaN, out of range: refused, naming the parameter)."""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import registry
from roughdiffuse.models.sampling import CLTC, COSINE, Strategy

Z = np.array([0.0, 0.0, 1.0])


def test_ids_are_the_documented_ones():
    assert registry.ids()[:10] == [
        "lambert",
        "oren-nayar",
        "oren-nayar-full",
        "fujii",
        "eon",
        "torrance-sparrow",
        "torrance-sparrow-beckmann",
        "mix",
        "lommel-seeliger",
        "lunar-lambert",
    ]


@pytest.mark.parametrize("entry", registry.entries(), ids=lambda e: e.id)
def test_declaration_agrees_with_the_class(entry):
    """Defaults in the declaration = the dataclass defaults; pytree leaves = numeric params."""
    cls = entry.cls
    if hasattr(cls, "from_params"):  # Mix: the declared parameters are the factory's
        import inspect

        sig = inspect.signature(cls.from_params)
        for p in entry.parameters:  # one that exists only for some choices: None (unset)
            assert sig.parameters[p.name].default == (p.default if p.when is None else None)
        return
    fields = {f.name: f for f in dataclasses.fields(cls)}
    for p in cls.params:
        assert p.name in fields
        if p.when is None:
            assert fields[p.name].default == p.default, p.name
    numeric = {p.name for p in cls.params if not p.categorical}
    # a tabulated model (VCavity: traced by JAX, not a closed form) has static parameters
    tabulated = cls.traceable and not cls.closed_form
    assert set(cls.array_fields) == (set() if tabulated else numeric)
    assert set(cls.channel_fields) == {p.name for p in cls.params if p.channels}
    assert isinstance(cls.sampling, Strategy)
    # the model built from the declared defaults has exactly those values
    model = entry.create()
    for p in entry.parameters:
        assert getattr(model, p.name) == pytest.approx(p.default)
    for k, v in entry.fixed.items():
        assert getattr(model, k) == v


def test_one_default_for_the_lunar_lambert_and_the_mix_weight():
    """They disagreed before (1.0 vs 0.5, 0 vs 0.1): now the declaration holds one value."""
    assert rd.LunarLambert().limb_darkening == 0.5
    assert registry.get("lunar-lambert").defaults()["limb_darkening"] == 0.5
    assert registry.get("mix").defaults()["weight"] == 0.1
    w = [float(c[0]) for c in registry.create("mix").components]
    assert w == pytest.approx([0.9, 0.1])


def test_sampling_strategies_are_objects():
    assert rd.Lambert.sampling is COSINE and rd.EON.sampling is CLTC and rd.Fujii.sampling is CLTC
    assert rd.TorranceSparrow(1.5, 0.3).sampling_strategy().name == "microfacet-gaussian"
    beckmann = rd.TorranceSparrow(1.5, alpha=0.3, distribution="beckmann")
    assert beckmann.sampling_strategy().name == "microfacet-beckmann"


def test_json_records():
    records = json.loads(json.dumps(registry.to_json()))  # JSON-clean (no inf, no NaN)
    by_id = {r["id"]: r for r in records}
    ts = by_id["torrance-sparrow"]
    assert ts["lobe"] == "glossy" and ts["glsl"] is True
    assert [p["name"] for p in ts["parameters"]] == ["eta", "sigma"]
    sigma = ts["parameters"][1]
    assert sigma["unit"] == "radians" and sigma["max"] == pytest.approx(math.pi / 2)
    assert sigma["choices"] is None
    on = by_id["oren-nayar-full"]
    assert on["fixed"] == {"variant": "full"}
    assert "variant" not in [p["name"] for p in on["parameters"]]
    mix = {p["name"]: p for p in by_id["mix"]["parameters"]}
    assert mix["distribution"]["choices"] == ["gaussian", "beckmann"]
    assert mix["distribution"]["min"] is None
    for r in records:
        assert set(r) >= {"id", "class", "label", "lobe", "reference", "glsl", "parameters"}
        for p in r["parameters"]:
            assert set(p) >= {"name", "description", "unit", "min", "max", "default", "channels"}


def test_create_refuses_a_parameter_the_model_does_not_take():
    with pytest.raises(ValueError, match="'eon' has no parameter 'sigma'"):
        registry.create("eon", sigma=0.3)
    with pytest.raises(ValueError, match="unknown model 'nope'"):
        registry.get("nope")
    with pytest.raises(ValueError, match="has no parameter 'sigma'"):
        registry.create("torrance-sparrow-beckmann", sigma=0.3)


def test_id_of_a_model():
    assert registry.id_of(rd.OrenNayar(0.5, 0.2, "full")) == "oren-nayar-full"
    assert registry.id_of(rd.TorranceSparrow(1.5, 0.3, "beckmann")) == "torrance-sparrow-beckmann"


# ------------------------------------------------------------------ σ and α of Torrance–Sparrow
def test_beckmann_alpha_is_the_rms_slope():
    """D(n) = 1/(π α²) at normal incidence; with F = ((η−1)/(η+1))² and G = 1,
    f = F D / 4 (Beckmann and Spizzichino 1963; Walter et al. 2007, Eq. 25)."""
    for alpha in (0.1, 0.5, 1.3):
        m = rd.TorranceSparrow(1.5, distribution="beckmann", alpha=alpha)
        f = float(m.brdf(Z, Z))
        assert f == pytest.approx(0.04 / (4 * math.pi * alpha**2), rel=1e-12)


def test_sigma_with_beckmann_keeps_its_old_meaning():
    """Code written before α: σ per slope component, α = √2 σ, the same values."""
    old = rd.TorranceSparrow(1.5, 0.3, "beckmann")
    assert old.sigma is None and old.alpha == pytest.approx(math.sqrt(2) * 0.3)
    new = rd.TorranceSparrow(1.5, distribution="beckmann", alpha=math.sqrt(2) * 0.3)
    wi = rd.spherical_to_vector(0.4, 0.0)
    assert float(old.brdf(wi, Z)) == float(new.brdf(wi, Z))


def test_alpha_refused_for_the_gaussian_and_both_refused_together():
    with pytest.raises(ValueError, match="alpha applies only with distribution='beckmann'"):
        rd.TorranceSparrow(1.5, 0.3, alpha=0.2)
    with pytest.raises(ValueError, match="not sigma as well"):
        rd.TorranceSparrow(1.5, 0.3, "beckmann", alpha=0.2)


# ------------------------------------------------------------------ values that fail
@pytest.mark.parametrize(
    ("build", "match"),
    [
        (lambda: rd.Lambert(None), r"albedo must be a real number .*\[0, 1\].*got None"),
        (lambda: rd.OrenNayar(0.8, None), r"sigma must be a real number in \[0, π/2\] radians"),
        (lambda: rd.EON(0.8, None), r"roughness must be a real number in \[0, 1\]"),
        (lambda: rd.TorranceSparrow(None, 0.3), r"eta must be a real number in \(0, 1000\]"),
        (lambda: rd.Lambert(True), "albedo .*got True"),
        (lambda: rd.Lambert(np.bool_(True)), "albedo"),
        (lambda: rd.Lambert([True, False, True]), "albedo"),
        (lambda: rd.Lambert(np.array([True, False])), "albedo"),
        (lambda: rd.Lambert("0.5"), "albedo"),
        (lambda: rd.Lambert(object()), "albedo"),
        (lambda: rd.OrenNayar(0.5, float("nan")), "sigma"),
        (lambda: rd.TorranceSparrow(1e300, 0.3), r"eta must be in \(0, 1000\] \(got 1e\+300\)"),
        (lambda: rd.TorranceSparrow(math.inf, 0.3), r"eta must be in \(0, 1000\] \(got inf\)"),
        (lambda: rd.OrenNayar(0.5, 0.3, "rough"), "variant must be one of 'qualitative', 'full'"),
    ],
)
def test_values_that_should_not_pass(build, match):
    with pytest.raises(ValueError, match=match):
        build()


def test_an_infinite_upper_end_is_shown_open():
    with pytest.raises(ValueError, match=r"weight must be in \[0, ∞\) \(got inf\)"):
        rd.Mix([(math.inf, rd.Lambert(0.5))])


@pytest.mark.parametrize(
    "bad", [["0", "0", "1"], np.array(["0", "0", "1"]), np.array([0, 0, 1]) > 0]
)
def test_directions_must_be_numbers(bad):
    with pytest.raises(ValueError, match="wi must hold real numbers"):
        rd.Lambert(0.5).brdf(bad, Z)


@pytest.mark.parametrize("e0", [-1.0, math.nan, math.inf, [1.0, -0.5, 1.0], True, None])
def test_irradiance_must_be_finite_and_non_negative(e0):
    with pytest.raises(ValueError, match="irradiance"):
        rd.Lambert(0.5).radiance(Z, Z, Z, irradiance=e0)


def test_largest_eta_gives_a_finite_value():
    """η at its upper end, 1000: F → 1 − 4/η at normal incidence (finite, close to 1)."""
    m = rd.TorranceSparrow(1e3, 0.3)
    wi = rd.spherical_to_vector(np.linspace(0, 1.5, 16), 0.0)
    f = np.asarray(m.brdf(wi, Z))
    assert np.all(np.isfinite(f))
    # at wi = wo = n: F = ((η − 1)/(η + 1))², D = exp(0) × norm, G = 1: compare with η = 1.5
    ratio = float(m.brdf(Z, Z)) / float(rd.TorranceSparrow(1.5, 0.3).brdf(Z, Z))
    assert ratio == pytest.approx(((999 / 1001) ** 2) / 0.04, rel=1e-12)
