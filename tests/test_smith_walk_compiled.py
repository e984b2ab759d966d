"""The compiled Smith random walk (engine="compiled", roughdiffuse.simulate.smith_walk_numba).

Its reference is the NumPy walk (engine="numpy"): the two draw different random numbers, so
they are compared by z-scores, |x − y| < 4.5 √(s.e.x² + s.e.y²) (a 4.5σ event has probability
7e-6 per comparison for Gaussian estimates). Its special function is compared with mpmath's
(erfinv, at 40 digits), a different implementation, its generator with the moments of the
uniform distribution.
"""

from __future__ import annotations

import functools
import importlib.util
import math
import os
import re

import numpy as np
import pytest

from roughdiffuse.simulate import smith

sp_erfcx = pytest.importorskip("scipy.special").erfcx

numba = pytest.importorskip("numba")

Z = 4.5


def _loop(f):
    @numba.njit
    def run(x):
        out = np.empty_like(x)
        for i in range(x.size):
            out[i] = f(x[i])
        return out

    return run


def _libm_relative_error(name, x):
    """The relative error of the erf or erfc that compiled code calls (the C library's, which
    differs between machines), measured at each x against mpmath at 40 digits."""
    import mpmath

    with mpmath.workdps(40):
        exact = np.array([float(getattr(mpmath, name)(mpmath.mpf(float(v)))) for v in x])
    return np.abs(_loop(getattr(math, name))(x) - exact) / np.abs(exact).clip(1e-300)


def test_erfinv_against_mpmath_within_the_bound_of_the_libm_it_calls():
    """erfinv is accurate to what the C library's erf/erfc allow.

    Halley's iteration on f = erfc x − (1 − |y|) (|y| ≥ 1/2; erf x − |y| below) stops at the root
    of the computed f, so an erfc with relative error δ moves the result by
    δ erfc(x) / |erfc'(x)| = δ (√π/2) erfcx(x) (δ erf(x) (√π/2) e^{x²} for erf), to which the
    last step adds a rounding of x. The tolerance is twice that, with δ measured on this machine
    at the root itself: glibc's erfc is within 1 ulp on the CPUs seen so far, but the result is
    only as good as the library the machine has.
    """
    import mpmath

    from roughdiffuse.engine.numba_math import erfinv

    tail = 1.0 - np.logspace(-16, -1, 200)
    y = np.concatenate([np.linspace(-0.999, 0.999, 4001), tail, -tail, np.logspace(-300, -1, 50)])
    with mpmath.workdps(40):
        x = np.array([float(mpmath.erfinv(mpmath.mpf(float(v)))) for v in y])
    ax = np.abs(x)
    tail_side = np.abs(y) >= 0.5
    delta = np.maximum(
        np.where(tail_side, _libm_relative_error("erfc", ax), _libm_relative_error("erf", ax)),
        np.finfo(float).eps,
    )
    half_sqrt_pi = math.sqrt(math.pi) / 2
    with np.errstate(over="ignore"):
        moved = np.where(
            tail_side,
            delta * half_sqrt_pi * sp_erfcx(ax),
            delta * np.abs(y) * half_sqrt_pi * np.exp(ax * ax),
        )
    bound = 2 * (np.spacing(ax) + moved) + 1e-300
    err = np.abs(_loop(erfinv)(y) - x)
    worst = np.argmax(err / bound)
    assert np.all(err <= bound), (
        f"erfinv({y[worst]!r}) is off by {err[worst]:.3g}, bound {bound[worst]:.3g} "
        f"(libm relative error there {delta[worst]:.3g})"
    )
    assert _loop(erfinv)(np.array([1.0, -1.0])).tolist() == [math.inf, -math.inf]


def test_inline_in_callers_marks_the_compiled_function():
    """The marker leaves the value alone and asks LLVM to inline the function (the layered
    walk's traced base functions carry it)."""
    from roughdiffuse.engine.numba_math import inline_in_callers

    def twice(x):
        inline_in_callers()
        return 2.0 * x

    f = numba.njit(twice)
    assert f(1.5) == twice(1.5) == 3.0
    ir = f.inspect_llvm(f.signatures[0])
    name = next(line.split("@")[1].split("(")[0] for line in ir.splitlines()
                if line.startswith("define") and "cpython" not in line and "twice" in line)
    attrs = re.search(rf"define [^\n]*@{re.escape(name)}\([^\n]*#(\d+)", ir).group(1)
    assert "alwaysinline" in re.search(rf"^attributes #{attrs} = (.*)$", ir, re.M).group(1)


def test_counter_based_uniforms():
    """Mean 1/2 and variance 1/12 of the draws, uncorrelated along a path and across paths."""
    from roughdiffuse.engine.numba_random import path_key, uniform

    @numba.njit
    def draws(seed, paths, per_path):
        out = np.empty((paths, per_path))
        for p in range(paths):
            key = path_key(seed, p)
            for c in range(per_path):
                out[p, c] = uniform(key, c)
        return out

    u = draws(3, 2000, 64)
    assert u.min() >= 0.0 and u.max() < 1.0
    n = u.size
    assert abs(u.mean() - 0.5) < Z * math.sqrt(1 / 12 / n)
    assert abs(u.var() - 1 / 12) < Z * math.sqrt(1 / 180 / n)  # var of (u − 1/2)² is 1/180
    c = u - 0.5
    for lag in (c[:, 1:] * c[:, :-1], c[1:] * c[:-1]):  # next draw, next path
        assert abs(lag.mean()) < Z * (1 / 12) / math.sqrt(lag.size)
    assert np.array_equal(u, draws(3, 2000, 64)) and not np.array_equal(u, draws(4, 2000, 64))


CASES = [  # (distribution, α, θi, θr, Δφ) for three geometries each
    ("beckmann", 0.3, [0.0, 0.9, 1.45], [0.6, 1.2, 0.2], [0.0, 2.5, 1.0]),
    ("beckmann", 1.5, [0.4, 1.2, 1.5], [1.0, 0.3, 1.4], [3.0, 0.5, 0.0]),
    ("ggx", 0.5, [0.2, 1.0, 1.5], [1.3, 0.7, 0.1], [1.5, 0.0, 3.1]),
    ("ggx", 1.2, [0.7, 1.4, 0.0], [0.7, 1.1, 1.5], [0.0, 2.0, 0.7]),
]


@pytest.mark.parametrize(("dist", "alpha", "ti", "tr", "dp"), CASES)
def test_compiled_walk_agrees_with_numpy_walk(dist, alpha, ti, tr, dp):
    kw = dict(samples=20_000, max_order=3)
    c = smith.random_walk(ti, tr, dp, alpha, (1.0, 0.5), "all", dist, seed=1, engine="compiled",
                          **kw)
    r = smith.random_walk(ti, tr, dp, alpha, (1.0, 0.5), "all", dist, seed=1, engine="numpy",
                          **kw)
    for x, y, sx, sy in ((c.values, r.values, c.stderr, r.stderr),
                         (c.orders, r.orders, c.orders_stderr, r.orders_stderr)):
        assert np.all(sx > 0) and np.all(sy > 0)
        assert np.all(np.abs(x - y) < Z * np.hypot(sx, sy)), (x, y, sx, sy)
    # both trace the same walk: the mean number of segments per path agrees too (about 2 to 4
    # per path here, standard deviation at most about the mean: over 60,000 paths each the
    # relative s.e. of the ratio is below 0.6 %, so 3 % is more than 5 s.e.)
    assert c.segments / r.segments == pytest.approx(1.0, abs=0.03)


@pytest.mark.parametrize("dist", ["beckmann", "ggx"])
def test_compiled_single_scattering_equals_quadrature(dist):
    ti, tr, dp = np.array([0.1, 0.8, 1.4]), np.array([1.2, 0.5, 1.45]), np.array([0.3, 2.0, 3.0])
    q = smith.single_scattering(ti, tr, dp, 0.7, 1.0, dist)
    r = smith.random_walk(ti, tr, dp, 0.7, 1.0, 1, dist, samples=30_000, seed=4,
                          engine="compiled")
    assert np.all(np.abs(r.values[0] - q) < Z * r.stderr[0]), (q, r.values[0], r.stderr[0])


def test_compiled_directional_albedo_agrees_with_numpy():
    for dist in ("beckmann", "ggx"):
        kw = dict(samples=20_000, seed=3)
        a, sa = smith.directional_albedo([0.3, 1.3], 0.9, 0.8, "all", dist, engine="compiled", **kw)
        b, sb = smith.directional_albedo([0.3, 1.3], 0.9, 0.8, "all", dist, engine="numpy", **kw)
        assert np.all(np.abs(a - b) < Z * np.hypot(sa, sb)), (dist, a, b)


def test_same_seed_same_numbers_for_any_thread_count():
    kw = dict(alpha=0.6, albedo=(0.8, 1.0), bounces="all", distribution="beckmann",
              samples=3_000, seed=3, engine="compiled")
    a = smith.random_walk([0.2, 1.0, 1.4], 0.5, 1.0, **kw)
    b = smith.random_walk([0.2, 1.0, 1.4], 0.5, 1.0, **kw)
    assert np.array_equal(a.values, b.values) and np.array_equal(a.orders, b.orders)
    c = smith.random_walk([0.2, 1.0, 1.4], 0.5, 1.0, **{**kw, "seed": 4})
    assert not np.array_equal(a.values, c.values)
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    if numba.config.NUMBA_NUM_THREADS < 2 or (cores or 1) < 2:
        pytest.skip(f"one core or one Numba thread here ({cores} cores): no second thread count")
    before = numba.get_num_threads()
    try:
        numba.set_num_threads(1)
        one = smith.random_walk([0.2, 1.0, 1.4], 0.5, 1.0, **kw)
        numba.set_num_threads(2)
        two = smith.random_walk([0.2, 1.0, 1.4], 0.5, 1.0, **kw)
    finally:
        numba.set_num_threads(before)
    w1 = smith.random_walk([0.2, 1.0, 1.4], 0.5, 1.0, workers=1, **kw)
    for r in (one, two, w1):
        assert np.array_equal(r.values, a.values) and np.array_equal(r.stderr, a.stderr)
        assert np.array_equal(r.orders, a.orders) and r.segments == a.segments


def test_a_walk_of_several_kernel_calls_keys_every_path_by_the_seed():
    """More paths than one kernel call takes (2^18): the run goes in several calls. Path keys
    are (seed, geometry · samples + path), so the first geometry of a long run is the same walk
    as that geometry alone (a regression: the second call once received a string as its key)."""
    kw = dict(alpha=0.5, albedo=0.9, bounces="all", distribution="ggx", seed=11,
              engine="compiled")
    many = smith.random_walk([0.3, 0.9, 1.3], 0.4, 2.0, samples=100_000, **kw)
    alone = smith.random_walk(0.3, 0.4, 2.0, samples=100_000, **kw)
    assert np.all(np.isfinite(many.values)) and np.all(many.values > 0)
    assert np.array_equal(many.values[:, 0], alone.values)  # values: (albedos, geometries)


def test_engine_choice(monkeypatch):
    with pytest.raises(ValueError, match="engine"):
        smith.brdf(0.3, 0.4, 0.0, alpha=0.5, engine="gpu")
    kw = dict(alpha=0.5, albedo=0.7, samples=2_000, seed=5)
    auto = smith.brdf([0.2, 0.9], 0.4, 1.0, **kw)
    assert np.array_equal(auto, smith.brdf([0.2, 0.9], 0.4, 1.0, engine="compiled", **kw))
    # without Numba, "auto" is the NumPy walk, with no error; "compiled" names the cause
    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "numba" else real(name, *a)
    )
    fallback = smith.brdf([0.2, 0.9], 0.4, 1.0, **kw)
    assert np.array_equal(fallback, smith.brdf([0.2, 0.9], 0.4, 1.0, engine="numpy", **kw))
    with pytest.raises(ValueError, match="Numba"):
        smith.brdf(0.3, 0.4, 0.0, bounces=2, engine="compiled", alpha=0.5)


@functools.cache
def _slope_sampler():
    """A Numba loop drawing n accepted slopes x̃ (μ ≥ 0) by the compiled walks' rejection,
    and the number of tries."""
    from roughdiffuse.engine.numba_random import normal_pair, path_key, uniform
    from roughdiffuse.simulate.smith_walk_numba import _slope_gauss

    @numba.njit
    def draw(mu, n):
        out = np.empty(n)
        tries = 0
        for i in range(n):
            key = path_key(11, i)
            c = 0
            while True:
                g, _, c = normal_pair(key, c)
                x = _slope_gauss(mu, g, uniform(key, c), uniform(key, c + 1))
                c += 2
                tries += 1
                if x == x:
                    break
            out[i] = x
        return out, tries

    return draw


@pytest.mark.parametrize("mu", [0.0, 0.5, 3.0])
def test_compiled_beckmann_slope_against_its_density(mu):
    """The compiled walks' slope x̃ for μ ≥ 0 (a Gaussian-proposal rejection, Gaussians from
    polar-method pairs) against the closed-form law (μ − x̃)⁺ e^{−x̃²} (Heitz & d'Eon 2014,
    Sec. 4): a χ² test on 24 bins (expected counts from the CDF
    F(x) ∝ μ √π/2 (1 + erf x) + e^{−x²}/2, failing at probability 1e-6), and the share of
    tries accepted against (μ√π/2 (1 + erf μ) + e^{−μ²}/2) / (μ√π + 1/2) within 4.5σ."""
    from scipy import stats

    n = 200_000
    x, tries = _slope_sampler()(mu, n)
    assert np.all(x <= mu)

    def cdf(t):
        return mu * math.sqrt(math.pi) / 2 * (1 + math.erf(t)) + math.exp(-t * t) / 2

    total = cdf(mu)
    edges = np.concatenate([[-np.inf], np.linspace(-2.5, mu, 24)[1:-1], [mu]])
    p = np.diff([cdf(e) if np.isfinite(e) else 0.0 for e in edges]) / total
    counts = np.histogram(x, bins=np.where(np.isfinite(edges), edges, -1e9))[0]
    chi2 = float(np.sum((counts - n * p) ** 2 / (n * p)))
    assert chi2 < stats.chi2.ppf(1 - 1e-6, p.size - 1), chi2
    accept = total / (mu * math.sqrt(math.pi) + 0.5)
    assert abs(n / tries - accept) < Z * math.sqrt(accept * (1 - accept) / tries) + 1e-12
