"""A model declares each parameter once, as a field; Model makes the class a frozen dataclass
and a JAX pytree."""

from __future__ import annotations

import dataclasses
import math
from typing import Any, ClassVar

import numpy as np
import pytest

from roughdiffuse.models import Model, Param, param, register_pytree


class _Demo(Model):
    """Minnaert's law f = ρ/π (μi μo)^(k − 1), declared with param() and no decorator."""

    albedo: Any = param("albedo ρ", min=0.0, max=1.0, default=1.0, channels=True)
    k: Any = param("exponent k", min=0.5, max=1.5, default=1.0, example=0.8)
    mode: str = param("a categorical parameter", choices=("a", "b"), default="a")

    ids: ClassVar[dict[str, dict[str, Any]]] = {"declaration-demo": {}}

    def _kernel(self, xp, mu_i, mu_o, cos_io, albedo, k):
        prod = xp.where(mu_i * mu_o > 1e-6, mu_i * mu_o, 1e-6)
        return albedo / math.pi * xp.exp((k - 1.0) * xp.log(prod))


def test_params_are_derived_from_the_fields_in_order():
    assert [p.name for p in _Demo.params] == ["albedo", "k", "mode"]
    assert _Demo.params[1] == Param("k", "exponent k", min=0.5, max=1.5, default=1.0, example=0.8)
    assert [f.default for f in dataclasses.fields(_Demo)] == [1.0, 1.0, "a"]
    assert _Demo.array_fields == ("albedo", "k")
    assert _Demo.channel_fields == ("albedo",)


def test_the_class_is_a_frozen_dataclass():
    m = _Demo(0.5, 0.9)
    assert dataclasses.is_dataclass(m) and _Demo.__dataclass_params__.frozen
    assert repr(m) == "_Demo(albedo=0.5, k=0.9, mode='a')"
    assert m == _Demo(0.5, 0.9) and m != _Demo(0.5, 0.8)
    assert hash(m) == hash(_Demo(0.5, 0.9))
    assert dataclasses.replace(m, k=1.2) == _Demo(0.5, 1.2)
    with pytest.raises(dataclasses.FrozenInstanceError, match="'k'"):
        m.k = 1.0  # type: ignore[misc]
    with pytest.raises(ValueError, match=r"k must be in \[0.5, 1.5\] \(got 3\)"):
        _Demo(0.5, 3.0)


def test_the_class_is_a_pytree_that_jit_traces():
    jax = pytest.importorskip("jax")
    jnp = jax.numpy
    m = _Demo(0.5, 0.8, "b")
    leaves, tree = jax.tree_util.tree_flatten(m)
    assert leaves == [0.5, 0.8]  # numeric fields are leaves, the categorical one static
    assert jax.tree_util.tree_unflatten(tree, leaves) == m
    mu = jnp.asarray([0.3, 0.7])
    got = jax.jit(lambda model, x: model.brdf_cosines(x, x, x))(m, mu)
    # the closed form, by hand: ρ/π (μ²)^(k − 1)
    want = 0.5 / math.pi * np.asarray([0.3, 0.7]) ** (2 * (0.8 - 1.0))
    np.testing.assert_allclose(np.asarray(got), want, rtol=1e-5)


def test_a_class_applying_the_decorators_itself_still_works():
    """Code written before param(): params listed, @register_pytree @dataclass(frozen=True)."""

    @register_pytree
    @dataclasses.dataclass(frozen=True)
    class Old(Model):
        albedo: Any = 1.0
        params: ClassVar[tuple[Param, ...]] = (
            Param("albedo", "albedo ρ", min=0.0, max=1.0, default=1.0, channels=True),
        )

        def _kernel(self, xp, mu_i, mu_o, cos_io, albedo):
            return albedo / math.pi + 0.0 * mu_i

    m = Old(0.4)
    assert repr(m).endswith("Old(albedo=0.4)") and m == Old(0.4) and hash(m) == hash(Old(0.4))
    assert Old.array_fields == ("albedo",)
    with pytest.raises(dataclasses.FrozenInstanceError):
        m.albedo = 0.3  # type: ignore[misc]
    assert float(m.brdf_cosines(0.5, 0.5, 1.0)) == pytest.approx(0.4 / math.pi)
    jax = pytest.importorskip("jax")
    assert jax.tree_util.tree_leaves(m) == [0.4]


def test_a_parameter_declared_twice_is_refused():
    with pytest.raises(TypeError, match="declare each parameter once"):

        class Twice(Model):
            albedo: Any = param("albedo ρ", min=0.0, max=1.0, default=1.0)
            params: ClassVar[tuple[Param, ...]] = (
                Param("albedo", "albedo ρ", min=0.0, max=1.0, default=1.0),
            )


def test_a_declaration_error_shows_when_the_class_is_defined():
    with pytest.raises(ValueError, match=r"k must be in \[0, 1\] \(got 2"):

        class Bad(Model):
            k: Any = param("exponent", min=0.0, max=1.0, default=2.0)
    with pytest.raises(TypeError, match="when="):
        param("exponent", min=0.0, max=1.0, default=0.5, unset=None)


def test_a_factory_lists_its_own_parameters_before_the_fields():
    """Coated: the registry's base id and the base's parameters are from_params arguments
    (factory_params), the coat's own are its fields."""
    from roughdiffuse.models.coated import Coated

    names = [p.name for p in Coated.params]
    assert names[:4] == [p.name for p in Coated.factory_params]
    assert names[4:] == ["eta", "roughness", "distribution", "absorption"]
    fields = {f.name: f.default for f in dataclasses.fields(Coated)}
    assert all(fields[p.name] == p.default for p in Coated.params[4:])
