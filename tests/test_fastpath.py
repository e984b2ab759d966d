"""The compiled fast path (roughdiffuse.fastpath) against the reference path, model.radiance.

The reference is the array-API evaluation of the same model on NumPy arrays (a different
algorithm: whole-array passes instead of a traced, compiled scalar loop); the polynomial
float32 math functions are checked against NumPy's libm.
"""

from __future__ import annotations

import dataclasses
import math
import sys
from pathlib import Path
from typing import Any, ClassVar

import numpy as np
import pytest

import roughdiffuse as rd
from conftest import all_models
from roughdiffuse import fastpath
from roughdiffuse._trace import Graph, TraceError, TraceNamespace, scalar_source
from roughdiffuse.models.base import Model, register_pytree


@pytest.fixture(autouse=True, scope="module")
def _cache(tmp_path_factory: pytest.TempPathFactory) -> None:
    """A cache directory of this module's own (the generated kernels are written there)."""
    mp = pytest.MonkeyPatch()
    mp.setenv("ROUGHDIFFUSE_CACHE_DIR", str(tmp_path_factory.mktemp("fastpath-cache")))
    yield
    mp.undo()


def random_geometry(rng: np.random.Generator, rows: int, dtype: Any = np.float32):
    """Unnormalised n, l, v; about a quarter of the rows have l or v below the horizon."""
    n = rng.normal(size=(rows, 3))
    l = rng.normal(size=(rows, 3))
    v = rng.normal(size=(rows, 3))
    for d in (l, v):
        flip = (np.sum(d * n, axis=-1) < 0) & (rng.random(rows) < 0.85)
        d[flip] *= -1
    scale = rng.uniform(0.5, 3.0, size=(rows, 1))
    return (n * scale).astype(dtype), l.astype(dtype), v.astype(dtype)


def degenerate_geometry(dtype: Any = np.float32):
    """Normal incidence, grazing light/view (μ = 0), l = v, l = −v, l = n = v, far below."""
    z = [0.0, 0.0, 1.0]
    x = [1.0, 0.0, 0.0]
    y = [0.0, 1.0, 0.0]
    g = [math.sin(1.5), 0.0, math.cos(1.5)]
    rows = [
        (z, z, z),
        (z, x, z),
        (z, z, x),
        (z, x, x),
        (z, x, [-1.0, 0.0, 0.0]),
        (z, x, y),
        (z, g, g),
        (z, g, [-g[0], 0.0, g[2]]),
        (z, [0.0, 0.0, -1.0], z),
        (z, z, [0.0, 0.3, -0.9]),
        (z, [1e-4, 0.0, 1.0], [0.0, 1e-4, 1.0]),
        (z, [1.0, 0.0, 1e-7], [1.0, 1e-7, 1e-7]),
        ([0.0, 0.0, 5.0], [3.0, 0.0, 4.0], [0.0, -3.0, 4.0]),
    ]
    n, l, v = (np.array([r[k] for r in rows], dtype=dtype) for k in range(3))
    return n, l, v


def assert_matches_reference(model: Model, n, l, v, irradiance: Any = 1.0) -> None:
    got = fastpath.evaluate(model, n, l, v, irradiance)
    ref = np.asarray(model.radiance(n, l, v, irradiance))
    assert got.shape == ref.shape
    assert got.dtype == ref.dtype
    assert np.all(np.isfinite(got))
    if got.dtype == np.float32:
        # float32 rounding of a few dozen operations, relative to the lobe's scale
        scale = np.max(np.abs(ref))
        np.testing.assert_allclose(got, ref, rtol=2e-4, atol=2e-5 * scale)
    else:
        np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("model", all_models() + all_models(rgb=True), ids=repr)
def test_every_model_float32(rng, model):
    n, l, v = random_geometry(rng, 3000)
    assert_matches_reference(model, n, l, v)


@pytest.mark.parametrize("model", all_models() + all_models(rgb=True), ids=repr)
def test_every_model_degenerate_directions(model):
    assert_matches_reference(model, *degenerate_geometry())


@pytest.mark.parametrize(
    "model",
    [rd.OrenNayar(0.8, 0.4, "full"), rd.EON([0.9, 0.5, 0.2], 0.7), rd.TorranceSparrow(1.5, 0.3)],
    ids=repr,
)
def test_float64_input_is_computed_in_float64(rng, model):
    n, l, v = random_geometry(rng, 2000, np.float64)
    assert_matches_reference(model, n, l, v)
    assert_matches_reference(model, *degenerate_geometry(np.float64))


def test_below_horizon_is_zero_and_lambert_is_closed_form(rng):
    n, l, v = random_geometry(rng, 5000, np.float64)
    out = fastpath.evaluate(rd.Lambert(0.6), n, l, v, irradiance=2.0)
    nn = n / np.linalg.norm(n, axis=-1, keepdims=True)
    ln = l / np.linalg.norm(l, axis=-1, keepdims=True)
    vn = v / np.linalg.norm(v, axis=-1, keepdims=True)
    mu_i, mu_o = np.sum(nn * ln, -1), np.sum(nn * vn, -1)
    expected = np.where((mu_i >= 0) & (mu_o >= 0), 0.6 / np.pi * 2.0 * mu_i, 0.0)
    np.testing.assert_allclose(out, expected, rtol=1e-12, atol=1e-15)
    assert np.any(out == 0) and np.any(out > 0)


def test_qualitative_oren_nayar_against_the_lecture_formula(rng):
    """Independent of the package: the angle form ρ/π (A + B max(0, cos Δφ) sin α tan β)."""
    rows = 4000
    ti, tr = rng.uniform(0, 1.5, rows), rng.uniform(0, 1.5, rows)
    pi_, pr = rng.uniform(-np.pi, np.pi, rows), rng.uniform(-np.pi, np.pi, rows)
    l = np.stack([np.sin(ti) * np.cos(pi_), np.sin(ti) * np.sin(pi_), np.cos(ti)], -1)
    v = np.stack([np.sin(tr) * np.cos(pr), np.sin(tr) * np.sin(pr), np.cos(tr)], -1)
    n = np.array([0.0, 0.0, 1.0])
    sigma, rho = 0.5, 0.7
    a = 1 - 0.5 * sigma**2 / (sigma**2 + 0.33)
    b = 0.45 * sigma**2 / (sigma**2 + 0.09)
    alpha, beta = np.maximum(ti, tr), np.minimum(ti, tr)
    f = rho / np.pi * (a + b * np.maximum(0, np.cos(pr - pi_)) * np.sin(alpha) * np.tan(beta))
    got = fastpath.evaluate(rd.OrenNayar(rho, sigma), n, l, v)
    assert got.dtype == np.float64
    np.testing.assert_allclose(got, f * np.cos(ti), rtol=1e-9, atol=1e-12)


def test_broadcasting_rgb_irradiance_out_and_chunks(rng):
    model = rd.EON([0.9, 0.6, 0.3], 0.8)
    n, l, v = random_geometry(rng, 4 * 25)
    n = n.reshape(4, 25, 3)
    light = np.array([0.3, 0.2, 0.9], np.float32)  # one distant light for every row
    e0 = np.array([1.0, 2.0, 0.5])
    ref = np.asarray(model.radiance(n, light, v.reshape(4, 25, 3), e0))
    out = np.empty((4, 25, 3), np.float32)
    res = fastpath.evaluate(model, n, light, v.reshape(4, 25, 3), e0, out=out, chunk=7, threads=2)
    assert res is out
    np.testing.assert_allclose(out, ref, rtol=2e-4, atol=1e-6)
    # a scalar albedo with RGB irradiance gets the channel axis from E0
    lam = fastpath.evaluate(rd.OrenNayar(0.5, 0.3), n, light, v.reshape(4, 25, 3), e0)
    assert lam.shape == (4, 25, 3)
    np.testing.assert_allclose(lam[..., 1], 2.0 * lam[..., 0], rtol=1e-6)


def test_non_contiguous_and_integer_inputs(rng):
    n, l, v = random_geometry(rng, 400, np.float64)
    model = rd.OrenNayar(0.8, 0.3, "full")
    got = fastpath.evaluate(model, n[::2], l[::2], v[::2], chunk=16)
    np.testing.assert_allclose(got, model.radiance(n[::2], l[::2], v[::2]), rtol=1e-9)
    ints = np.array([[0, 0, 1], [1, 0, 1]])
    got = fastpath.evaluate(rd.Lambert(1.0), ints[:1], ints, ints[:1])
    assert got.dtype == np.float64
    np.testing.assert_allclose(got, [1 / np.pi, 1 / np.pi * math.sqrt(0.5)], rtol=1e-12)


def test_threads_and_chunking_do_not_change_the_result(rng):
    n, l, v = random_geometry(rng, 10_001)
    model = rd.TorranceSparrow(1.5, distribution="beckmann", alpha=0.25 * math.sqrt(2))
    one = fastpath.evaluate(model, n, l, v, threads=1, chunk=1 << 20)
    many = fastpath.evaluate(model, n, l, v, threads=3, chunk=999)
    # equal up to float32 rounding: a chunk's last rows run in the loop's scalar remainder,
    # whose instruction sequence differs from the vectorised body's. One ulp (6e-8) in
    # x = tan²θh/α² becomes x ulp in exp(−x); x reaches about 50 where D is still above
    # float32's smallest normal relative to its peak, so rtol = 50 × 6e-8 × 16 ≈ 5e-5.
    np.testing.assert_allclose(one, many, rtol=5e-5, atol=1e-30)
    assert np.count_nonzero(one != many) < 0.05 * one.size


def test_new_parameters_reuse_the_compiled_kernel(rng):
    n, l, v = random_geometry(rng, 100)
    fastpath.evaluate(rd.OrenNayar(0.8, 0.3), n, l, v)
    before = len(fastpath._COMPILED)
    for sigma in (0.1, 0.7, 1.2):
        assert_matches_reference(rd.OrenNayar(0.4, sigma), n, l, v)
    assert len(fastpath._COMPILED) == before
    assert any(fastpath.cache_dir().glob("rdk_*.py"))


def test_streaming_batches(rng):
    n, l, v = random_geometry(rng, 300)
    model = rd.Fujii(0.7, 0.9)
    batches = ((n[a : a + 100], l[a : a + 100], v[a : a + 100]) for a in (0, 100, 200))
    parts = list(fastpath.evaluate_batches(model, batches))
    assert [p.shape for p in parts] == [(100,)] * 3
    np.testing.assert_allclose(np.concatenate(parts), model.radiance(n, l, v), rtol=2e-4, atol=1e-6)


def test_bad_input_raises_value_error(rng):
    n, l, v = random_geometry(rng, 10)
    model = rd.Lambert(0.5)
    n0 = n.copy()
    n0[3] = 0.0
    with pytest.raises(ValueError, match="^n must contain non-zero"):
        fastpath.evaluate(model, n0, l, v)
    v0 = v.copy()
    v0[7, 1] = np.nan
    with pytest.raises(ValueError, match="^v must contain non-zero"):
        fastpath.evaluate(model, n, l, v0)
    with pytest.raises(ValueError, match=r"l must have shape \(\.\.\., 3\)"):
        fastpath.evaluate(model, n, l[:, :2], v)
    with pytest.raises(ValueError, match="do not broadcast"):
        fastpath.evaluate(model, n, l[:4], v)
    with pytest.raises(ValueError, match="out must be"):
        fastpath.evaluate(model, n, l, v, out=np.empty(10, np.float64))
    with pytest.raises(ValueError, match="chunk"):
        fastpath.evaluate(model, n, l, v, chunk=0)


def test_long_and_short_vectors_are_valid_where_the_reference_accepts_them():
    """Squared norms of 1e26 and 1e-26 are fine in float32 (their product is not)."""
    n = np.array([[0.0, 0.0, 1e13], [0.0, 0.0, 1e-13]], np.float32)
    l = np.array([[0.0, 6e12, 8e12], [0.0, 6e-14, 8e-14]], np.float32)
    v = np.array([[3e12, 0.0, 4e12], [3e-14, 0.0, 4e-14]], np.float32)
    model = rd.OrenNayar(0.8, 0.3)
    np.testing.assert_allclose(
        fastpath.evaluate(model, n, l, v), model.radiance(n, l, v), rtol=1e-5
    )


def test_jax_input_is_refused_with_a_pointer_to_radiance():
    jnp = pytest.importorskip("jax.numpy")
    z = jnp.asarray([[0.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match="model.radiance"):
        fastpath.evaluate(rd.Lambert(0.5), z, z, z)


# ------------------------------------------------------------------ a model of one's own
@register_pytree
@dataclasses.dataclass(frozen=True)
class Minnaert(Model):
    """Minnaert's law f = ρ/π (μi μo)^(k−1), a model the fast path has never seen."""

    albedo: Any = 1.0
    k: Any = 0.7
    array_fields: ClassVar[tuple[str, ...]] = ("albedo", "k")
    channel_fields: ClassVar[tuple[str, ...]] = ("albedo",)

    def _kernel(self, xp, mu_i, mu_o, cos_io, albedo, k):
        prod = xp.where(mu_i * mu_o > 1e-6, mu_i * mu_o, 1e-6)
        return albedo / math.pi * xp.exp((k - 1.0) * xp.log(prod))


class Branchy(Minnaert):
    def _kernel(self, xp, mu_i, mu_o, cos_io, albedo, k):
        if mu_i > 0.5:  # a Python branch on values: not a kernel the fast path accepts
            return albedo + 0.0 * mu_i
        return 0.0 * mu_i


def test_a_new_model_compiles_from_its_kernel_alone(rng):
    n, l, v = random_geometry(rng, 2000)
    model = Minnaert([0.8, 0.5, 0.3], 0.6)
    assert_matches_reference(model, n, l, v)
    z = np.array([0.0, 0.0, 1.0])
    np.testing.assert_allclose(fastpath.evaluate(model, z, z, z), np.array([0.8, 0.5, 0.3]) / np.pi)


def test_python_branch_on_values_is_refused():
    z = np.array([[0.0, 0.0, 1.0]], np.float32)
    with pytest.raises(TraceError, match="branch-free"):
        fastpath.evaluate(Branchy(0.5, 0.5), z, z, z)


# ------------------------------------------------------------------ float32 math functions
def _compiled(fn_name: str, arity: int):
    import numba

    from roughdiffuse._numba_math import exp2i

    g = Graph(np.float32)
    xp = TraceNamespace(g)
    args = [g.input(f"x{k}") for k in range(arity)]
    constants, body = scalar_source(g, [getattr(xp, fn_name)(*args)])
    names = ", ".join(f"x{k}" for k in range(arity))
    src = "\n".join(
        ["import math", "import numpy as np", *constants, f"def f({names}):"]
        + ["    " + line for line in body]
        + ["    return r0"]
    )
    ns: dict[str, Any] = {"exp2i": exp2i}
    exec(src, ns)  # noqa: S102 - code generated by the module under test
    sig = "float32(" + ", ".join(["float32"] * arity) + ")"
    return numba.vectorize([sig])(ns["f"])


def test_float32_atan2_against_libm(rng):
    y = rng.normal(size=200_000).astype(np.float32)
    x = rng.normal(size=200_000).astype(np.float32)
    y[:6], x[:6] = [0, 0, 1, -1, 0, 1e-30], [0, -1, 0, 0, 1, 1]
    got = _compiled("atan2", 2)(y, x)
    ref = np.arctan2(y.astype(np.float64), x.astype(np.float64))
    np.testing.assert_allclose(got, ref, rtol=4e-7, atol=1e-37)


@pytest.mark.parametrize("name", ["sin", "cos"])
def test_float32_sin_cos_against_libm(name):
    x = np.concatenate([np.linspace(-50, 50, 200_001), [0.0, np.pi / 2, np.pi, 1e-30]])
    x = x.astype(np.float32)
    got = _compiled(name, 1)(x)
    ref = getattr(np, name)(x.astype(np.float64))
    np.testing.assert_allclose(got, ref, rtol=0, atol=3e-7)


def test_float32_exp_against_libm():
    x = np.concatenate([np.linspace(-87, 88, 200_001), [0.0, -1e-30]]).astype(np.float32)
    got = _compiled("exp", 1)(x)
    np.testing.assert_allclose(got, np.exp(x.astype(np.float64)), rtol=3e-7)
    assert _compiled("exp", 1)(np.float32([-200.0, -90.0]))[0] == 0.0


def _stride3_loop(hint: bool) -> Any:
    """A loop shaped like the generated kernels: (N, 3) rows read in place, float32 (n·l)."""
    import numba

    from roughdiffuse._numba_math import tuned_vector_width

    def f(n, l, out):  # noqa: E741 - the kernels' names
        if hint:
            tuned_vector_width()
        for i in range(out.shape[0]):
            out[i] = n[3 * i] * l[3 * i] + n[3 * i + 1] * l[3 * i + 1] + n[3 * i + 2] * l[3 * i + 2]

    return numba.njit(fastmath={"nsz", "arcp", "contract", "afn", "reassoc"})(f)


def test_kernels_keep_to_the_vector_width_the_cpu_prefers(rng):
    """Without the attribute clang sets, LLVM mixed 512-bit shuffles into the 256-bit loops on
    AVX-512 CPUs that prefer 256 bits (qualitative Oren–Nayar 1.7x slower); with it a loop is
    all ymm or all zmm (this loop without it: both, here)."""
    n, l, _ = random_geometry(rng, 1000)
    outs = []
    for hint in (False, True):
        fn = _stride3_loop(hint)
        out = np.empty(1000, np.float32)
        fn(n.reshape(-1), l.reshape(-1), out)
        outs.append(out)
        if hint:
            sig = fn.signatures[0]
            assert '"min-legal-vector-width"="0"' in fn.inspect_llvm(sig)
            asm = fn.inspect_asm(sig)
            assert not ("ymm" in asm and "zmm" in asm)
    ref = np.einsum("ij,ij->i", n.astype(np.float64), l.astype(np.float64))
    np.testing.assert_allclose(outs[1], ref, rtol=1e-5, atol=1e-5)
    np.testing.assert_allclose(outs[0], outs[1], rtol=1e-6, atol=1e-6)


def test_generated_kernels_ask_for_the_preferred_vector_width():
    """Every generated kernel carries the attribute (the call is in its loop's function)."""
    kernel, _, _ = fastpath._kernel_for(
        rd.OrenNayar(0.5, 0.3), np.dtype(np.float32), (False, False, False), np.asarray(1.0)
    )
    src = Path(sys.modules[kernel.py_func.__module__].__file__).read_text()
    assert "    tuned_vector_width()\n" in src
