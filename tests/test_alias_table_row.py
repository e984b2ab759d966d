"""An alias with several ids is one row of the renderers' table: ``alias(ids=..., labels=...,
base_choices=...)``. Mitsuba 0.6's ``roughdiffuse`` is such a row (its ``variant`` selecting
Oren–Nayar's full or qualitative model): id by id it equals Oren–Nayar evaluated directly at
Mitsuba 0.6's σ = α/√2 (src/bsdfs/roughdiffuse.cpp, ``RoughDiffuse::eval``)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.engine.dispatch import use_fastpath
from roughdiffuse.models.alias import alias
from roughdiffuse.models.declaration import Param
from roughdiffuse.models.oren_nayar import OrenNayar
from roughdiffuse.models.renderers import ALPHA_MAX, _colour

Mitsuba06Row = registry.get("mitsuba06-roughdiffuse").cls


def _geometries():
    rng = np.random.default_rng(11)
    w = rng.normal(size=(2, 400, 3))
    w[..., 2] = np.abs(w[..., 2])
    return w[0], w[1]


@pytest.mark.parametrize(
    ("model_id", "base_variant"),
    [("mitsuba06-roughdiffuse", "full"), ("mitsuba06-roughdiffuse-fast", "qualitative")],
)
def test_each_id_of_the_row_is_oren_nayar_at_alpha_over_root_two(model_id, base_variant):
    entry = registry.get(model_id)
    assert entry.cls is Mitsuba06Row and set(Mitsuba06Row.ids) == {
        "mitsuba06-roughdiffuse", "mitsuba06-roughdiffuse-fast"
    }
    wi, wo = _geometries()
    for albedo, a in ((0.7, 0.0), (0.3, 0.4), ([0.9, 0.5, 0.2], ALPHA_MAX)):
        row = Mitsuba06Row(albedo, a, **entry.fixed)
        direct = OrenNayar(albedo, a / math.sqrt(2.0), base_variant)
        with use_fastpath(False):
            np.testing.assert_allclose(row.brdf(wi, wo), direct.brdf(wi, wo), rtol=1e-14)
            np.testing.assert_allclose(
                row.directional_albedo(wo[:6]), direct.directional_albedo(wo[:6]), rtol=1e-12
            )
        got = row.base_model()
        assert type(got) is OrenNayar and got.variant == base_variant


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
