"""Mitsuba's own chi-square test (``mitsuba.chi2``) on every roughdiffuse plugin.

For each plugin, roughness and incident direction (normal to 85°), Mitsuba draws 10⁶
directions with the plugin's ``sample`` and compares their histogram on the sphere with the
integral of the plugin's ``pdf`` over each cell (Pearson's test at Mitsuba's significance
level). Parameter sets follow the issue: σ (or EON/Fujii's r) in {0, 0.2, 0.5, 1.0}.
Torrance–Sparrow at σ = 0 is a mirror (a Dirac delta, f = 0 as a function): nothing to
sample, so it is not in the list.
"""

from __future__ import annotations

import math

import pytest

from mitsuba_setup import mitsuba_variant

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


def test_chi2_rejects_a_pdf_that_does_not_match_the_sampler(mi, tmp_path, monkeypatch):
    """Negative control: EON's sampler with the cosine pdf must be rejected."""
    monkeypatch.chdir(tmp_path)  # a failing test writes chi2_data.py to the working folder
    import drjit as dr
    from mitsuba.chi2 import BSDFAdapter, ChiSquareTest, SphericalDomain

    from roughdiffuse.integrations.mitsuba import _make_plugin_class
    from roughdiffuse.models import EON
    from roughdiffuse.models.sampling import CLTC, COSINE, Strategy

    base = _make_plugin_class(mi, dr, EON)

    class Mismatched(base):
        def __init__(self, props):
            super().__init__(props)
            self.strategy = Strategy("mismatched", CLTC.sample, COSINE.pdf)

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
