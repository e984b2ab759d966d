"""An alias with several ids is one row of the renderers' table: ``alias(ids=..., labels=...,
base_choices=...)``. The row below (Mitsuba 0.6's ``roughdiffuse``, its ``variant`` selecting
Oren–Nayar's full or qualitative model) equals the hand-written class it is to replace, id by
id, at every geometry, and its conversion is Mitsuba 0.6's α = √2 σ
(src/bsdfs/roughdiffuse.cpp, ``RoughDiffuse::eval``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.engine.dispatch import use_fastpath
from roughdiffuse.models.alias import alias
from roughdiffuse.models.declaration import Param
from roughdiffuse.models.oren_nayar import OrenNayar
from roughdiffuse.models.renderers import _ORDER, ALPHA_MAX, _colour, _unit

Mitsuba06Row = alias(
    "Mitsuba06Row", __name__,
    ids={"mitsuba06-roughdiffuse": {"variant": "full"},
         "mitsuba06-roughdiffuse-fast": {"variant": "fast"}},
    labels={"mitsuba06-roughdiffuse": "Mitsuba 0.6 roughdiffuse",
            "mitsuba06-roughdiffuse-fast": "Mitsuba 0.6 roughdiffuse (useFastApprox)"},
    base=OrenNayar,
    base_choices={"variant": {"full": {"variant": "full"}, "fast": {"variant": "qualitative"}}},
    params=(_colour("reflectance ρ"),
            _unit("alpha", "alpha = √2 σ (Beckmann RMS slope)", 0.5, ALPHA_MAX),
            Param("variant", "full, or useFastApprox", choices=("full", "fast"), default="full")),
    to_base=lambda albedo, alpha: {"albedo": albedo, "sigma": alpha * (1.0 / math.sqrt(2.0))},
    rule="σ = α/√2", order=_ORDER + 40,
    reference="Mitsuba 0.6, src/bsdfs/roughdiffuse.cpp, RoughDiffuse::eval",
    symbols={"albedo": r"\rho", "alpha": r"\alpha"},
    formula=r"""
        ```{math}
        f = f_{\mathrm{ON}}\Bigl(\rho, \sigma = \frac{\alpha}{\sqrt{2}}\Bigr)
        ```

        Full Oren–Nayar (`oren-nayar-full`), or the qualitative model for the fast variant,
        with Mitsuba 0.6's α = √2 σ.
        """,
    doc="""Mitsuba 0.6 ``roughdiffuse``: Oren–Nayar with α, the Beckmann RMS slope, σ = α/√2;
    the full model by default, the qualitative one with ``useFastApprox``.""",
)  # fmt: skip


def _geometries():
    rng = np.random.default_rng(11)
    w = rng.normal(size=(2, 400, 3))
    w[..., 2] = np.abs(w[..., 2])
    return w[0], w[1]


@pytest.mark.parametrize("model_id", ["mitsuba06-roughdiffuse", "mitsuba06-roughdiffuse-fast"])
def test_the_row_equals_the_class_id_by_id(model_id):
    entry = registry.get(model_id)
    assert Mitsuba06Row.ids[model_id] == entry.cls.ids[model_id]
    assert Mitsuba06Row.labels[model_id] == entry.cls.labels[model_id]
    assert [p.to_json() for p in Mitsuba06Row.params] == [p.to_json() for p in entry.cls.params]
    wi, wo = _geometries()
    for albedo, a in ((0.7, 0.0), (0.3, 0.4), ([0.9, 0.5, 0.2], ALPHA_MAX)):
        row = Mitsuba06Row(albedo, a, **entry.fixed)
        cls = entry.cls(albedo, a, **entry.fixed)
        with use_fastpath(False):
            np.testing.assert_allclose(row.brdf(wi, wo), cls.brdf(wi, wo), rtol=1e-14)
            np.testing.assert_allclose(
                row.directional_albedo(wo[:6]), cls.directional_albedo(wo[:6]), rtol=1e-14
            )
        got, want = row.base_model(), cls.base_model()
        assert type(got) is type(want) and got.variant == want.variant
        np.testing.assert_array_equal(got.albedo, want.albedo)
        assert got.sigma == want.sigma


def test_the_row_converts_as_mitsuba_06():
    """α = √2 σ: α = √2 is σ = 1 rad, of the full model or (useFastApprox) the qualitative."""
    full = Mitsuba06Row(0.5, math.sqrt(2.0)).base_model()
    fast = Mitsuba06Row(0.5, math.sqrt(2.0), variant="fast").base_model()
    assert full.variant == "full" and full.sigma == pytest.approx(1.0, rel=1e-15)
    assert fast.variant == "qualitative" and fast.sigma == pytest.approx(1.0, rel=1e-15)
    assert Mitsuba06Row.conversion()["text"]["sigma"] == "alpha * 0.707107"


def test_base_choices_must_cover_the_categorical_parameter():
    with pytest.raises(TypeError, match="base_choices"):
        alias(
            "Broken", __name__, ids={"x-a": {"variant": "a"}}, labels={"x-a": "x"},
            base=OrenNayar, base_choices={"variant": {"a": {}}},
            params=(_colour(), Param("variant", "v", choices=("a", "b"), default="a")),
            to_base=lambda albedo: {"albedo": albedo}, rule="r", reference="r", formula="f",
            doc="d", order=1,
        )  # fmt: skip
    with pytest.raises(TypeError, match="model_id and label, or ids and labels"):
        alias(
            "Broken", __name__, base=OrenNayar, params=(_colour(),),
            to_base=lambda albedo: {"albedo": albedo}, rule="r", reference="r", formula="f",
            doc="d", order=1,
        )  # fmt: skip
