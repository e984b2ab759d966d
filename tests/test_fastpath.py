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
from conftest import all_models, representative_cases, rgb_cases
from roughdiffuse import fastpath
from roughdiffuse.engine.trace import Graph, TraceError, TraceNamespace, scalar_source
from roughdiffuse.models.base import Model, register_pytree


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


def _traced(models: list) -> list:
    """The models the fast path compiles (``traceable``; the others run as NumPy)."""
    return [m for m in models if type(m).traceable]


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


# Each case compiles kernels of its own (a few CPU-seconds each, tens for Coated): `make test`
# compiles every model's grey kernel and the three-channel kernels of the classes whose
# channels are not handled generically; the full set compiles the rest.
CASES = rgb_cases(_traced(all_models()), _traced(all_models(rgb=True)))


@pytest.mark.parametrize("model", CASES)
def test_every_model_float32(rng, model):
    n, l, v = random_geometry(rng, 3000)
    assert_matches_reference(model, n, l, v)


@pytest.mark.parametrize("model", CASES)
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


U32 = 2.0**-24
"""Unit roundoff of float32."""


def condition_scale(model: Model, n, l, v, h: float = 1e-6) -> np.ndarray:
    """|L| + Σ_c |∂L/∂c| + Σ_p |p ∂L/∂p| per row, in float64: the scale of L's float32 error.

    The float32 cosines c = n·l, n·v, l·v of normalised vectors carry absolute errors of a few
    units of roundoff u, and every rounded operation of the formula (a parameter's, an
    exponent's) perturbs L as a relative change of a parameter would; so a float32 evaluation is
    within k u times this scale of the exact value, k a few (the float32 polynomials are accurate
    to 1e-7, 2 u). Derivatives by central differences of the reference path, ``brdf_cosines``.
    """
    if isinstance(model, rd.Mix):  # a weighted sum: the weighted sum of the scales
        return sum(abs(w) * condition_scale(m, n, l, v, h) for w, m in model.components)
    unit = [np.asarray(a, np.float64) for a in (n, l, v)]
    unit = [a / np.linalg.norm(a, axis=-1, keepdims=True) for a in unit]
    cosines = [np.sum(unit[0] * unit[1], -1), np.sum(unit[0] * unit[2], -1)]
    cosines.append(np.sum(unit[1] * unit[2], -1))

    def radiance(m: Model, c: list[np.ndarray]) -> np.ndarray:
        f = np.asarray(m.brdf_cosines(*c))
        mu_i = np.clip(c[0], 0.0, 1.0)
        return f * (mu_i[..., None] if f.ndim > mu_i.ndim else mu_i)

    scale = np.abs(radiance(model, cosines))
    for k in range(3):
        up, down = list(cosines), list(cosines)
        up[k], down[k] = cosines[k] + h, cosines[k] - h
        scale += np.abs(radiance(model, up) - radiance(model, down)) / (2 * h)
    for down in _lowered_parameters(model, h):
        scale += np.abs(radiance(model, cosines) - radiance(down, cosines)) / (2 * h)
    return scale


def _lowered_parameters(model: Model, h: float) -> list[Model]:
    """``model`` with each non-zero parameter in turn times 1 − 2h (it may be its maximum);
    a model-valued parameter (a Coated's base) has its own parameters lowered."""
    out = []
    for name in model.array_fields:
        value = getattr(model, name)
        if value is None:  # an unused alternative (TorranceSparrow's sigma)
            continue
        if isinstance(value, rd.Model):
            out += [dataclasses.replace(model, **{name: m}) for m in _lowered_parameters(value, h)]
            continue
        p = np.asarray(value, np.float64)
        if np.all(p == 0):
            continue
        out.append(dataclasses.replace(model, **{name: p * (1 - 2 * h)}))
    return out


@pytest.mark.parametrize(
    "model",
    [
        rd.TorranceSparrow(1.5, distribution="beckmann", alpha=0.25 * math.sqrt(2)),
        rd.OrenNayar(0.7, 0.4),
        rd.EON(0.7, 1.0),
    ],
    ids=repr,
)
def test_threads_and_chunking_do_not_change_the_result(rng, model):
    n, l, v = random_geometry(rng, 10_001)
    one = fastpath.evaluate(model, n, l, v, threads=1, chunk=1 << 20)
    many = fastpath.evaluate(model, n, l, v, threads=3, chunk=999)
    # equal up to float32 rounding: a chunk's last rows run in the loop's scalar remainder,
    # whose instruction sequence differs from the vectorised body's (FMA contraction,
    # reassociation). Each is within 8 u of the exact value on the condition scale (see
    # condition_scale; 2.3 u measured on an AMD EPYC for the difference), so they differ by
    # at most 16 u of it -- relative differences of 2.6e-5 where Beckmann's exponent is large.
    scale = condition_scale(model, n, l, v)
    assert np.all(np.abs(one - many) <= 16 * U32 * scale)
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
def _compiled(fn_name: str, arity: int, dtype: Any = np.float32):
    import numba

    from roughdiffuse.engine.numba_math import exp2i, exp2i_f64

    g = Graph(dtype)
    xp = TraceNamespace(g)
    args = [g.input(f"x{k}") for k in range(arity)]
    constants, body = scalar_source(g, [getattr(xp, fn_name)(*args)])
    names = ", ".join(f"x{k}" for k in range(arity))
    src = "\n".join(
        ["import math", "import numpy as np", *constants, f"def f({names}):"]
        + ["    " + line for line in body]
        + ["    return r0"]
    )
    ns: dict[str, Any] = {"exp2i": exp2i, "exp2i_f64": exp2i_f64}
    exec(src, ns)  # noqa: S102 - code generated by the module under test
    name = np.dtype(dtype).name
    sig = f"{name}(" + ", ".join([name] * arity) + ")"
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


U64 = 2.0**-53
"""Unit roundoff of float64."""


def test_float64_atan2_against_libm(rng):
    """Cephes' double atan is accurate to about 2 u; the quadrant steps add a rounding each."""
    y = rng.normal(size=200_000)
    x = rng.normal(size=200_000)
    y[:6], x[:6] = [0, 0, 1, -1, 0, 1e-300], [0, -1, 0, 0, 1, 1]
    got = _compiled("atan2", 2, np.float64)(y, x)
    np.testing.assert_allclose(got, np.arctan2(y, x), rtol=8 * U64, atol=1e-300)


@pytest.mark.parametrize("name", ["sin", "cos"])
def test_float64_sin_cos_against_libm(name):
    """Absolute error: the polynomials' 2 u on values <= 1 plus the reduction's rounding of
    r = x − k π/2 (k π/2 in three exact parts, so a few u of |r| <= π/4)."""
    x = np.concatenate([np.linspace(-50, 50, 200_001), [0.0, np.pi / 2, np.pi, 1e-300]])
    got = _compiled(name, 1, np.float64)(x)
    np.testing.assert_allclose(got, getattr(np, name)(x), rtol=0, atol=8 * U64)


def test_float64_exp_against_libm():
    """Relative error: Cephes' 2 u plus the rounding of r = x − k ln 2 (ln 2 in two parts, the
    first exact in k ln 2). Measured on an AMD EPYC: atan2 2.2 u, sin 1 u, cos 2 u, exp 2.8 u;
    the tests allow 8 u."""
    x = np.concatenate([np.linspace(-708, 709, 200_001), [0.0, -1e-300]])
    got = _compiled("exp", 1, np.float64)(x)
    np.testing.assert_allclose(got, np.exp(x), rtol=8 * U64)
    assert _compiled("exp", 1, np.float64)(np.array([-800.0, -710.0]))[0] == 0.0


def _stride3_loop(hint: bool) -> Any:
    """A loop shaped like the generated kernels: (N, 3) rows read in place, float32 (n·l)."""
    import numba

    from roughdiffuse.engine.numba_math import tuned_vector_width

    def f(n, l, out):  # noqa: E741 - the kernels' names
        if hint:
            tuned_vector_width()
        for i in range(out.shape[0]):
            out[i] = n[3 * i] * l[3 * i] + n[3 * i + 1] * l[3 * i + 1] + n[3 * i + 2] * l[3 * i + 2]

    return numba.njit(fastmath={"nsz", "arcp", "contract", "afn", "reassoc"})(f)


def _prefers_256_bit_vectors_with_avx512() -> str | None:
    """None if this CPU has AVX-512 and LLVM's tuning for it prefers 256-bit vectors (Intel's
    Ice Lake, Rocket Lake, Sapphire Rapids...), else the reason the vector-width test does not
    apply: a plain contiguous loop is vectorised at the preferred width, so zmm registers in it
    mean the tuning prefers 512 bits (AMD's Zen 4, LLVM's "znver4", does)."""
    import numba
    from llvmlite import binding

    from roughdiffuse.engine.numba_math import tuned_vector_width

    cpu = binding.get_host_cpu_name()
    if "avx512f" not in binding.get_host_cpu_features().flatten():
        return f"no AVX-512 on this CPU ({cpu}): there are no 512-bit registers to mix"

    def plain(a, b, out):
        tuned_vector_width()
        for i in range(out.shape[0]):
            out[i] = a[i] * b[i] + a[i]

    fn = numba.njit(fastmath={"nsz", "arcp", "contract", "afn", "reassoc"})(plain)
    x = np.ones(64, np.float32)
    fn(x, x, x)
    if "zmm" in fn.inspect_asm(fn.signatures[0]):
        return f"LLVM's tuning for this CPU ({cpu}) prefers 512-bit vectors"
    return None


def test_kernels_keep_to_the_vector_width_the_cpu_prefers(rng):
    """Without the attribute clang sets, LLVM mixed 512-bit shuffles into the 256-bit loops on
    AVX-512 CPUs that prefer 256 bits (qualitative Oren–Nayar 1.7x slower on an Intel Xeon);
    with it a loop is all ymm or all zmm. Only such CPUs can show the defect."""
    n, l, _ = random_geometry(rng, 1000)
    outs = []
    for hint in (False, True):
        fn = _stride3_loop(hint)
        out = np.empty(1000, np.float32)
        fn(n.reshape(-1), l.reshape(-1), out)
        outs.append(out)
        assert '"min-legal-vector-width"="0"' in fn.inspect_llvm(fn.signatures[0]) or not hint
    # the values: a 3-term float32 dot product is within 3 u of each |term| sum (Higham,
    # Accuracy and Stability of Numerical Algorithms, 2nd ed., Eq. 3.5), with or without FMA
    ref = np.einsum("ij,ij->i", n.astype(np.float64), l.astype(np.float64))
    bound = 3 * U32 * np.einsum("ij,ij->i", np.abs(n.astype(np.float64)), np.abs(l))
    for out in outs:
        assert np.all(np.abs(out - ref) <= 1.01 * bound)
    reason = _prefers_256_bit_vectors_with_avx512()
    if reason is not None:
        pytest.skip(reason)
    fn = _stride3_loop(True)
    fn(n.reshape(-1), l.reshape(-1), np.empty(1000, np.float32))
    asm = fn.inspect_asm(fn.signatures[0])
    assert not ("ymm" in asm and "zmm" in asm)


def test_generated_kernels_ask_for_the_preferred_vector_width():
    """Every generated kernel carries the attribute (the call is in its loop's function)."""
    kernel, _, _ = fastpath._kernel_for(
        rd.OrenNayar(0.5, 0.3), np.dtype(np.float32), (False, False, False), np.asarray(1.0)
    )
    src = Path(sys.modules[kernel.py_func.__module__].__file__).read_text()
    assert "    tuned_vector_width()\n" in src


# ------------------------------------------------------------------ the default call
@pytest.fixture
def dispatch_now(monkeypatch):
    """Compile on the first large call (not after 2^20 rows), and count compiled calls."""
    from roughdiffuse.engine import dispatch as _dispatch

    monkeypatch.setattr(_dispatch, "BUILD_ROWS", 0)
    calls = []
    run_entry = fastpath.run_entry

    def counting(model, call):
        calls.append(call.entry)
        return run_entry(model, call)

    monkeypatch.setattr(fastpath, "run_entry", counting)
    return calls


def local_geometry(rng: np.random.Generator, rows: int, dtype: Any = np.float32):
    """Unnormalised local-frame wi, wo (about 1 in 8 below the horizon) and their cosines."""
    wi, wo = (rng.normal(size=(rows, 3)) for _ in range(2))
    for w in (wi, wo):
        w[:, 2] = np.where(rng.random(rows) < 0.875, np.abs(w[:, 2]), w[:, 2])
    ui = wi / np.linalg.norm(wi, axis=-1, keepdims=True)
    uo = wo / np.linalg.norm(wo, axis=-1, keepdims=True)
    cosines = (ui[:, 2], uo[:, 2], np.sum(ui * uo, -1))
    return wi.astype(dtype), wo.astype(dtype), tuple(c.astype(dtype) for c in cosines)


def assert_rounding_apart(got: np.ndarray, ref: np.ndarray, scale: np.ndarray) -> None:
    """Each float32 evaluation is within 8 u of the exact value on the condition scale (see
    condition_scale), so two of them differ by at most 16 u of it."""
    if scale.ndim < got.ndim:
        scale = scale[..., None]
    assert np.all(np.abs(got - ref) <= 16 * U32 * scale + 1e-30)


# brdf and brdf_cosines compile two more kernels per model; the generated prologues that turn
# (wi, wo) or the cosines into the kernel's inputs do not depend on the model, so `make test`
# runs them for models that use each kind of input (cos γ, the half vector, a mixture, a
# phase function), and the full set for every model.
DEFAULT_PATH_CLASSES = frozenset({"Lambert", "OrenNayar", "EON", "TorranceSparrow", "Mix", "Hapke"})


@pytest.mark.parametrize("model", representative_cases(_traced(all_models()), DEFAULT_PATH_CLASSES))
def test_default_brdf_and_brdf_cosines_run_compiled_with_the_reference_values(
    rng, model, dispatch_now
):
    rows = _min_rows()
    wi, wo, (mu_i, mu_o, cos_io) = local_geometry(rng, rows)
    with rd.use_fastpath(False):
        ref_brdf = model.brdf(wi, wo)
        ref_cos = model.brdf_cosines(mu_i, mu_o, cos_io)
    got_brdf = model.brdf(wi, wo)
    got_cos = model.brdf_cosines(mu_i, mu_o, cos_io)
    assert dispatch_now == ["brdf", "brdf_cosines"]
    for got, ref in ((got_brdf, ref_brdf), (got_cos, ref_cos)):
        assert type(got) is np.ndarray and got.dtype == np.float32 and got.shape == ref.shape
        assert np.all(np.isfinite(got))
    z = np.zeros((rows, 3))
    z[:, 2] = 1.0  # the condition scale in the local frame: n = z, l = wi, v = wo
    scale = condition_scale(model, z, wi, wo)
    mu_i = np.clip(mu_i.astype(np.float64), 0.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        brdf_scale = np.where(mu_i > 0, scale / mu_i, np.inf)  # L = f μi: f's scale is L's / μi
    assert_rounding_apart(got_brdf, ref_brdf, brdf_scale)
    assert_rounding_apart(got_cos, ref_cos, brdf_scale)


def _min_rows() -> int:
    from roughdiffuse.engine import dispatch as _dispatch

    return _dispatch.MIN_ROWS


@pytest.mark.parametrize(
    "model", [rd.EON([0.9, 0.5, 0.2], 0.7), rd.TorranceSparrow(1.5, 0.3)], ids=repr
)
def test_default_calls_keep_float64_and_channels(rng, model, dispatch_now):
    rows = _min_rows()
    wi, wo, cosines = local_geometry(rng, rows, np.float64)
    n, l, v = random_geometry(rng, rows, np.float64)
    e0 = np.array([1.0, 2.0, 0.5])
    with rd.use_fastpath(False):
        refs = [model.brdf(wi, wo), model.brdf_cosines(*cosines), model.radiance(n, l, v, e0)]
    gots = [model.brdf(wi, wo), model.brdf_cosines(*cosines), model.radiance(n, l, v, e0)]
    assert dispatch_now == ["brdf", "brdf_cosines", "radiance"]
    for got, ref in zip(gots, refs, strict=True):
        assert got.dtype == np.float64 and got.shape == ref.shape
        np.testing.assert_allclose(got, ref, rtol=1e-9, atol=1e-12 * np.max(np.abs(ref)))


def test_small_arrays_jax_and_the_switch_keep_the_reference_path(rng, dispatch_now, monkeypatch):
    model = rd.OrenNayar(0.8, 0.3)
    rows = _min_rows()
    wi, wo, _ = local_geometry(rng, rows)
    model.brdf(wi[: rows - 1], wo[: rows - 1])  # one row short of the threshold
    with rd.use_fastpath(False):
        assert not rd.fastpath_enabled()
        model.brdf(wi, wo)
    assert rd.fastpath_enabled()
    ones = np.ones((rows, 3), np.int64)
    model.brdf(ones, ones)  # integers: the reference path
    assert dispatch_now == []
    model.brdf(wi, wo)
    assert dispatch_now == ["brdf"]
    jnp = pytest.importorskip("jax.numpy")
    out = model.brdf(jnp.asarray(wi), jnp.asarray(wo))
    assert not isinstance(out, np.ndarray) and dispatch_now == ["brdf"]


def test_the_environment_switch_turns_the_default_off():
    import subprocess

    code = "import roughdiffuse as rd; print(rd.fastpath_enabled())"
    for value, expected in (("0", "False"), ("off", "False"), ("1", "True")):
        proc = subprocess.run(
            [sys.executable, "-P", "-c", code],
            capture_output=True,
            text=True,
            env={**__import__("os").environ, "ROUGHDIFFUSE_FASTPATH": value},
            timeout=120,
        )
        assert proc.stdout.strip() == expected, proc.stderr


def test_an_unreadable_environment_switch_is_refused(monkeypatch, capsys):
    """``ROUGHDIFFUSE_FASTPATH=maybe``: every command stops with one line naming it (exit 2);
    in Python, the first model evaluation raises the same ``ValueError``, and an explicit
    ``use_fastpath`` decides without the variable."""
    from roughdiffuse.cli import main
    from roughdiffuse.engine import dispatch

    monkeypatch.setenv("ROUGHDIFFUSE_FASTPATH", "maybe")
    for argv in (["models"], ["eval", "--model", "lambert"]):
        assert main(argv) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "ROUGHDIFFUSE_FASTPATH" in err[0] and "'maybe'" in err[0]
    monkeypatch.setattr(dispatch, "_ENABLED", None)  # not yet read, as in a new process
    wi = np.array([0.3, 0.0, 1.0])
    with pytest.raises(ValueError, match="ROUGHDIFFUSE_FASTPATH must be one of .*'maybe'"):
        rd.Lambert(0.5).brdf(wi, wi)
    with pytest.raises(ValueError, match="ROUGHDIFFUSE_FASTPATH"):
        rd.fastpath_enabled()
    with rd.use_fastpath(False):
        assert float(rd.Lambert(0.5).brdf(wi, wi)) == pytest.approx(0.5 / math.pi)
    monkeypatch.setenv("ROUGHDIFFUSE_FASTPATH", "off")  # read again after the block
    assert not rd.fastpath_enabled()


class NumpyOnly(Minnaert):
    """Minnaert through NumPy functions: fine on NumPy arrays, not traceable."""

    def _kernel(self, xp, mu_i, mu_o, cos_io, albedo, k):
        prod = np.maximum(np.asarray(mu_i * mu_o), 1e-6)
        return albedo / math.pi * np.power(prod, k - 1.0)


def test_a_model_the_fast_path_cannot_compile_stays_on_the_reference_path(rng, dispatch_now):
    rows = _min_rows()
    wi, wo, _ = local_geometry(rng, rows)
    model = NumpyOnly(0.6, 0.8)
    with pytest.raises(TraceError):
        fastpath.brdf(model, wi, wo)
    with rd.use_fastpath(False):
        ref = model.brdf(wi, wo)
    for _ in range(2):  # no error, the reference path's values, and no second attempt
        np.testing.assert_array_equal(model.brdf(wi, wo), ref)
    assert dispatch_now == []
    # the traceable version of the same formula runs compiled
    np.testing.assert_allclose(Minnaert(0.6, 0.8).brdf(wi, wo), ref, rtol=2e-4, atol=1e-6)
    assert dispatch_now == ["brdf"]


def test_bad_directions_raise_the_reference_paths_error_on_the_default_path(rng, dispatch_now):
    wi, wo, _ = local_geometry(rng, _min_rows())
    wo[5] = 0.0
    with pytest.raises(ValueError, match="^wo must contain non-zero, finite direction vectors"):
        rd.Fujii(0.5, 0.5).brdf(wi, wo)


def test_the_cache_is_used_only_in_a_private_folder(rng, tmp_path, monkeypatch):
    """Numba unpickles its index files: a folder others may write to is not used."""
    import os

    shared = tmp_path / "shared"
    shared.mkdir()
    shared.chmod(0o777)
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(shared))
    assert fastpath.private_cache_dir() is None
    model = rd.LommelSeeliger(0.31)  # a kernel no other test has compiled in this process
    n, l, v = random_geometry(rng, 50)
    assert_matches_reference(model, n, l, v)  # compiled in memory
    assert list(shared.iterdir()) == []
    fresh = tmp_path / "fresh" / "cache"
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(fresh))
    assert fastpath.private_cache_dir() == fresh
    assert fresh.stat().st_mode & 0o777 == 0o700
    link = tmp_path / "link"
    link.symlink_to(fresh)
    monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(link))
    assert fastpath.private_cache_dir() is None
    if os.getuid() == 0:  # root: a folder owned by someone else is refused
        other = tmp_path / "other"
        other.mkdir(mode=0o700)
        os.chown(other, 65534, 65534)
        monkeypatch.setenv("ROUGHDIFFUSE_CACHE_DIR", str(other))
        assert fastpath.private_cache_dir() is None
