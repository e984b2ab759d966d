"""Mitsuba's own chi-square test (``mitsuba.chi2``) on every roughdiffuse plugin.

``test_chi2_every_registry_model`` runs it on the plugin of every registry model (Mix, the
lunar models and models registered from other packages included), at two parameter sets and
200 000 samples; ``test_chi2`` below goes further on the first plugins:

For each plugin, roughness and incident direction (normal to 85°), Mitsuba draws 10⁶
directions with the plugin's ``sample`` and compares their histogram on the sphere with the
integral of the plugin's ``pdf`` over each cell (Pearson's test at Mitsuba's significance
level). Parameter sets: σ (or EON/Fujii's r) in {0, 0.2, 0.5, 1.0}.
Torrance–Sparrow at σ = 0 is a mirror (a Dirac delta, f = 0 as a function): nothing to
sample, so it is not in the list.
"""

from __future__ import annotations

import math

import pytest

from mitsuba_setup import can_sample, mitsuba_variant, parameter_sets

ANGLES = [0.0, 45.0, 85.0]
ROUGHNESS = [0.0, 0.2, 0.5, 1.0]

CASES: list[tuple[str, dict]] = [("roughdiffuse_lambert", {"albedo": 0.7})]
for _r in ROUGHNESS:
    CASES += [
        ("roughdiffuse_oren_nayar", {"sigma": _r, "albedo": 0.7}),
        ("roughdiffuse_oren_nayar", {"sigma": _r, "albedo": 0.7, "variant": "full"}),
        ("roughdiffuse_eon", {"roughness": _r, "albedo": 0.7}),
        ("roughdiffuse_fujii", {"roughness": _r, "albedo": 0.7}),
    ]
    if _r > 0:
        CASES += [("roughdiffuse_torrance_sparrow", {"sigma": _r, "eta": 1.5})]
        if _r < 1.0:  # Beckmann slopes with σ = 1 rad are almost all beyond grazing
            CASES += [("roughdiffuse_torrance_sparrow", {"sigma": _r, "distribution": "beckmann"})]
CASES += [("roughdiffuse_v_cavity", {"sigma": 1.0, "albedo": 0.5})]  # its table, cosine sampling




def _registry_cases() -> list[tuple[str, dict, float]]:
    """Every registry model (a Mix and the lunar models included; third-party ones too) at
    its defaults, seen at 0° and 70° (unless CASES has its plugin already), and at a
    "rough" set seen at 45° (see ``mitsuba_setup.parameter_sets``); a set with nothing to
    sample (a mirror) is left out."""
    from roughdiffuse import registry
    from roughdiffuse.integrations.mitsuba import plugin_name

    covered = {name for name, _ in CASES}  # their defaults are near the cases above
    cases = []
    for entry in registry.entries():
        if not entry.cls.mitsuba:  # a simulation (SmithDiffuse) has no plugin
            continue
        defaults, rough = parameter_sets(entry)
        sets = [(rough, (45.0,))]
        if plugin_name(entry.id) not in covered:
            sets.insert(0, (defaults, (0.0, 70.0)))
        for params, angles in sets:
            if can_sample(entry.create(**params)):
                cases += [(plugin_name(entry.id), params, theta) for theta in angles]
    return cases


REGISTRY_CASES = _registry_cases()


def _id(case: tuple[str, dict]) -> str:
    name, params = case
    return name.removeprefix("roughdiffuse_") + "-" + "-".join(f"{v}" for v in params.values())


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant("llvm_ad_rgb")


@pytest.mark.parametrize("theta", ANGLES)
@pytest.mark.parametrize("case", CASES, ids=[_id(c) for c in CASES])
def test_chi2(mi, case, theta, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # a failing test writes chi2_data.py to the working folder
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    name, params = case
    wi = [math.sin(math.radians(theta)), 0.0, math.cos(math.radians(theta))]
    sample_func, pdf_func = BSDFAdapter(name, {"type": name, **params}, wi=wi)
    # sharp specular lobes need a finer quadrature of the pdf over each histogram cell
    ires = 8 if name.endswith("torrance_sparrow") else 4
    test = ChiSquareTest(
        domain=SphericalDomain(),
        sample_func=sample_func,
        pdf_func=pdf_func,
        sample_dim=3,
        sample_count=1_000_000,
        ires=ires,
    )
    assert test.run(), test.messages


@pytest.mark.parametrize(
    "case", REGISTRY_CASES, ids=[f"{_id(c[:2])}-{c[2]:g}" for c in REGISTRY_CASES]
)
def test_chi2_every_registry_model(mi, case, tmp_path, monkeypatch):
    """Each registry model's plugin, 200 000 samples (lower resolution than above)."""
    monkeypatch.chdir(tmp_path)
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    name, params, theta = case
    wi = [math.sin(math.radians(theta)), 0.0, math.cos(math.radians(theta))]
    sample_func, pdf_func = BSDFAdapter(name, {"type": name, **params}, wi=wi)
    glossy = mi.load_dict({"type": name, **params}).flags() & int(mi.BSDFFlags.Glossy)
    test = ChiSquareTest(
        domain=SphericalDomain(),
        sample_func=sample_func,
        pdf_func=pdf_func,
        sample_dim=3,
        sample_count=200_000,
        res=51,
        ires=8 if glossy else 4,
    )
    assert test.run(), test.messages


def test_chi2_rejects_a_pdf_that_does_not_match_the_sampler(mi, tmp_path, monkeypatch):
    """Negative control: EON's sampler with the cosine pdf must be rejected."""
    monkeypatch.chdir(tmp_path)  # a failing test writes chi2_data.py to the working folder
    import drjit as dr
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    from roughdiffuse import registry
    from roughdiffuse.integrations.mitsuba import _make_plugin_class
    from roughdiffuse.models.sampling import CLTC, COSINE, Strategy

    base = _make_plugin_class(mi, dr, registry.get("eon"))

    class Mismatched(base):
        def _strategy(self, si, active):
            _, p = super()._strategy(si, active)
            return Strategy("mismatched", CLTC.sample, COSINE.pdf), p

    mi.register_bsdf("roughdiffuse_test_mismatched", lambda props: Mismatched(props))
    wi = [math.sin(math.radians(60.0)), 0.0, math.cos(math.radians(60.0))]
    extra = {"type": "roughdiffuse_test_mismatched", "roughness": 1.0}
    sample_func, pdf_func = BSDFAdapter("roughdiffuse_test_mismatched", extra, wi=wi)
    test = ChiSquareTest(
        domain=SphericalDomain(),
        sample_func=sample_func,
        pdf_func=pdf_func,
        sample_dim=3,
        sample_count=200_000,
    )
    assert not test.run()
