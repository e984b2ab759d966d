"""One implementation, three array libraries: NumPy, JAX (eager, jit, grad) and PyTorch."""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd
from conftest import all_models, random_hemisphere, rgb_cases

jax = pytest.importorskip("jax")
jnp = jax.numpy


@pytest.fixture(autouse=True)
def _x64():
    """float64 JAX for these comparisons only (a global switch would leak into other tests)."""
    with jax.enable_x64(True):
        yield


def _models():
    # the models jax.jit traces (``traceable``; a simulation is not)
    return _traced(all_models() + all_models(rgb=True))


def _traced(models: list) -> list:
    return [m for m in models if type(m).traceable]


@pytest.mark.parametrize("model", rgb_cases(_traced(all_models()), _traced(all_models(rgb=True))))
def test_jax_matches_numpy(rng, model):
    wi, wo = random_hemisphere(rng, 300), random_hemisphere(rng, 300)
    ref = model.brdf(wi, wo)
    out = model.brdf(jnp.asarray(wi), jnp.asarray(wo))
    assert isinstance(out, jax.Array)
    np.testing.assert_allclose(np.asarray(out), ref, rtol=1e-10, atol=1e-12)
    jitted = jax.jit(lambda m, a, b: m.brdf(a, b))(model, jnp.asarray(wi), jnp.asarray(wo))
    np.testing.assert_allclose(np.asarray(jitted), ref, rtol=1e-10, atol=1e-12)
    n = jnp.asarray([0.0, 0.0, 1.0])
    rad = model.radiance(n, jnp.asarray(wi), jnp.asarray(wo), 2.0)
    np.testing.assert_allclose(
        np.asarray(rad), model.radiance(np.asarray(n), wi, wo, 2.0), rtol=1e-10, atol=1e-12
    )


def test_float32_stays_float32(rng):
    wi = random_hemisphere(rng, 100).astype(np.float32)
    wo = random_hemisphere(rng, 100).astype(np.float32)
    for model in _models():
        assert model.brdf(wi, wo).dtype == np.float32, repr(model)
        ref = model.brdf(wi.astype(np.float64), wo.astype(np.float64))
        np.testing.assert_allclose(model.brdf(wi, wo), ref, rtol=2e-4, atol=1e-6)


PARAMS = {
    rd.Lambert: ("albedo",),
    rd.OrenNayar: ("albedo", "sigma"),
    rd.Fujii: ("albedo", "roughness"),
    rd.EON: ("albedo", "roughness"),
    rd.TorranceSparrow: ("eta", "sigma"),
    rd.LommelSeeliger: ("albedo",),
    rd.LunarLambert: ("albedo", "limb_darkening"),
    rd.Coated.from_params: ("albedo", "sigma", "eta", "roughness", "absorption"),
}

GRAD_CASES = [
    (rd.Lambert, {"albedo": 0.5}),
    (rd.OrenNayar, {"albedo": 0.5, "sigma": 0.0}),
    (rd.OrenNayar, {"albedo": 0.5, "sigma": 0.3}),
    (rd.OrenNayar, {"albedo": 0.5, "sigma": 0.0, "variant": "full"}),
    (rd.OrenNayar, {"albedo": 0.5, "sigma": np.pi / 2, "variant": "full"}),
    (rd.Fujii, {"albedo": 0.5, "roughness": 0.0}),
    (rd.EON, {"albedo": 0.5, "roughness": 0.0}),
    (rd.EON, {"albedo": 1.0, "roughness": 1.0}),
    (rd.TorranceSparrow, {"eta": 1.5, "sigma": 0.0}),
    (rd.TorranceSparrow, {"eta": 1.5, "sigma": 0.4}),
    (rd.TorranceSparrow, {"eta": 1.5, "sigma": 0.4, "distribution": "beckmann"}),
    (rd.LommelSeeliger, {"albedo": 0.5}),
    (rd.LunarLambert, {"albedo": 0.5, "limb_darkening": 0.5}),
    # a coat: thousands of array operations per evaluation, run one by one (slow set)
    pytest.param(rd.Coated.from_params, {"albedo": 0.5, "sigma": 0.3, "eta": 1.5,
                 "roughness": 0.0, "absorption": 0.2}, marks=pytest.mark.slow),
    pytest.param(rd.Coated.from_params, {"albedo": 0.5, "sigma": 0.0, "eta": 1.3,
                 "roughness": 0.3, "absorption": 0.0, "distribution": "beckmann"},
                 marks=pytest.mark.slow),
]

# the hard directions: normal incidence, wi = wo, grazing, opposite grazing, generic
DIRS = np.array(
    [
        [[0, 0, 1.0], [0, 0, 1.0]],
        [[0.3, 0.2, 0.9], [0.3, 0.2, 0.9]],
        [[1.0, 0, 0], [0.5, 0, 0.5]],
        [[1.0, 0, 0], [-1.0, 0, 0]],
        [[1.0, 0, 0], [1.0, 0, 0]],
        [[0, 0, 1.0], [0.6, 0.0, 0.8]],
        [[0.4, -0.3, 0.5], [-0.2, 0.6, 0.3]],
    ]
)


@pytest.mark.parametrize(("cls", "kw"), GRAD_CASES, ids=lambda x: getattr(x, "__name__", str(x)))
def test_gradients_finite(cls, kw):
    """jax.grad with respect to every parameter and both directions is finite everywhere."""
    names = PARAMS[cls]
    static = {k: v for k, v in kw.items() if k not in names}

    def f(params, wi, wo):
        model = cls(**dict(zip(names, params, strict=True)), **static)
        return model.brdf(wi, wo)

    for wi, wo in DIRS:
        params = tuple(jnp.asarray(float(kw[n])) for n in names)
        g_params, g_wi, g_wo = jax.grad(f, argnums=(0, 1, 2))(
            params, jnp.asarray(wi), jnp.asarray(wo)
        )
        for g in (*g_params, g_wi, g_wo):
            assert np.all(np.isfinite(np.asarray(g))), (cls.__name__, kw, wi, wo)


def test_gradient_matches_finite_difference():
    wi, wo = jnp.asarray([0.3, 0.1, 0.8]), jnp.asarray([-0.5, 0.2, 0.7])
    g = jax.grad(lambda s: rd.OrenNayar(0.7, s, "full").brdf(wi, wo))(0.4)
    h = 1e-6
    fd = (
        rd.OrenNayar(0.7, 0.4 + h, "full").brdf(wi, wo)
        - rd.OrenNayar(0.7, 0.4 - h, "full").brdf(wi, wo)
    ) / (2 * h)
    assert float(g) == pytest.approx(float(fd), rel=1e-6)


def test_grad_with_numpy_directions():
    """A JAX parameter with NumPy directions: the JAX namespace wins."""
    wi, wo = np.array([0.3, 0.1, 0.8]), np.array([-0.5, 0.2, 0.7])
    g = jax.grad(lambda s: rd.EON(0.7, s).brdf(wi, wo))(0.5)
    assert np.isfinite(float(g)) and float(g) != 0


def test_torch_tensors_in_tensors_out(rng):
    torch = pytest.importorskip(
        "torch", reason="PyTorch is an optional extra (roughdiffuse[torch])"
    )
    wi, wo = random_hemisphere(rng, 200), random_hemisphere(rng, 200)
    for model in _models():
        out = model.brdf(torch.from_numpy(wi), torch.from_numpy(wo))
        assert isinstance(out, torch.Tensor), repr(model)
        np.testing.assert_allclose(out.numpy(), model.brdf(wi, wo), rtol=1e-10, atol=1e-12)
    sigma = torch.tensor(0.3, dtype=torch.float64, requires_grad=True)
    albedo = torch.tensor([0.8, 0.5, 0.2], dtype=torch.float64, requires_grad=True)
    f = rd.OrenNayar(albedo, sigma, "full").brdf(torch.from_numpy(wi), torch.from_numpy(wo))
    f.sum().backward()
    assert sigma.grad is not None and torch.isfinite(sigma.grad) and sigma.grad != 0
    assert albedo.grad is not None and torch.all(torch.isfinite(albedo.grad))


def test_jit_keeps_models_with_the_same_fields_apart():
    """Regression: jax's register_dataclass let Lambert and LommelSeeliger share a cache entry."""
    wi, wo = jnp.asarray([[0.3, 0.1, 0.8]]), jnp.asarray([[-0.5, 0.2, 0.7]])
    lam = rd.Lambert(0.7).brdf(wi, wo)
    ls = rd.LommelSeeliger(0.7).brdf(wi, wo)
    assert float(lam[0]) == pytest.approx(0.7 / np.pi)
    mu = 0.8 / np.linalg.norm([0.3, 0.1, 0.8]) + 0.7 / np.linalg.norm([-0.5, 0.2, 0.7])
    assert float(ls[0]) == pytest.approx(0.7 / (4 * np.pi * mu))
    ts = jax.tree_util.tree_structure
    assert ts(rd.Lambert(0.7)) != ts(rd.LommelSeeliger(0.7))  # equal under register_dataclass
    assert ts(rd.Fujii(0.7, 0.5)) != ts(rd.EON(0.7, 0.5))


def test_rgb_albedo_as_list_under_jit():
    w = jnp.asarray([[0.3, 0.1, 0.8]])
    for model in (rd.Lambert([0.9, 0.5, 0.2]), rd.EON((0.9, 0.5, 0.2), 0.5)):
        out = jax.jit(lambda m, a: m.brdf(a, a))(model, w)
        np.testing.assert_allclose(
            np.asarray(out), model.brdf(np.asarray(w), np.asarray(w)), rtol=1e-12
        )
