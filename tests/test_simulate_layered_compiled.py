"""The compiled layered walk (Numba) against the NumPy walk, and the traced base functions.

Both interfaces are compared: the single-scattering one, and the multiple-scattering
microsurface walk (the NumPy walk's on arrays of walks, the compiled one path by path; it
also has its own anchors, tests/test_simulate_layered_multiple.py). The two engines draw
different random numbers,
so they agree within their standard errors (|z| below a bound whose odds of being exceeded
by correct walks are below 1e-3). The traced base functions (roughdiffuse.engine.scalar)
are checked against the models' own NumPy evaluation and sampler at random inputs, to
float64 rounding.
"""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd
from mitsuba_setup import random_geometries
from roughdiffuse._validate import ParameterError
from roughdiffuse.simulate import layered

pytest.importorskip("numba")

Z_MAX = 4.5
"""|z| bound per value: with up to 36 values, a 4.5σ excursion of correct walks has odds < 1e-3."""


def _agree(base, interface="single", geometries=6, **kw) -> None:
    ti, tr, dp = random_geometries(geometries, seed=11)
    fc, sc = layered.brdf(ti, tr, dp, base, samples=20_000, seed=1, return_stderr=True,
                          engine="compiled", interface=interface, **kw)
    fn, sn = layered.brdf(ti, tr, dp, base, samples=4_000, seed=2, return_stderr=True,
                          engine="numpy", interface=interface, **kw)
    z = (fc - fn) / np.hypot(sc, sn)
    assert np.all(sc > 0) and np.max(np.abs(z)) < Z_MAX, z


def test_compiled_agrees_rough_ggx_coat_absorbing_oren_nayar() -> None:
    _agree(rd.OrenNayar(0.8, 0.4, "full"), eta=1.5, roughness=0.4,
           absorption=[0.0, 0.2, 1.0])


@pytest.mark.slow
@pytest.mark.parametrize(
    ("base", "kw"),
    [
        (rd.EON(0.8, 0.6), {"eta": 1.3, "roughness": 0.3, "distribution": "beckmann"}),
        (rd.Lambert([0.9, 0.5, 0.2]), {"eta": 2.0, "roughness": 0.0, "absorption": 0.3}),
    ],
    ids=["eon-beckmann", "lambert-rgb-smooth"],
)
def test_compiled_agrees_other_bases(base, kw: dict) -> None:
    _agree(base, **kw)


def test_multiple_interface_engines_agree() -> None:
    """The multiple-scattering interface on both engines: a rough GGX coat (α = 0.6, where
    a third of the light takes a second facet event), absorbing, over Oren–Nayar."""
    _agree(rd.OrenNayar(0.8, 0.4, "full"), "multiple", 4, eta=1.5, roughness=0.6,
           absorption=[0.0, 0.5])


@pytest.mark.slow
def test_multiple_interface_engines_agree_beckmann_dense_coat() -> None:
    _agree(rd.EON(0.9, 0.5), "multiple", 4, eta=2.5, roughness=1.0,
           distribution="beckmann")


def test_numpy_multiple_interface_white_furnace() -> None:
    """The NumPy walk's exact interface conserves energy on its own: a white Lambertian
    base under a rough coat reflects all the light (within 4 standard errors and 1 %)."""
    a, se = layered.directional_albedo(np.radians([0.0, 45.0, 80.0]), rd.Lambert(1.0),
                                       eta=1.5, roughness=0.6, samples=20_000, engine="numpy",
                                       return_stderr=True)
    assert np.all(np.abs(a - 1.0) < np.maximum(4 * se, 0.01)), (a, se)


@pytest.mark.slow  # the V-cavity table is loaded (about 15 s)
def test_a_table_base_gets_the_multiple_interface() -> None:
    """A base the compiled walk cannot run (a table) has the exact interface on the NumPy
    walk ("auto" falls back to it, same seed, same value) instead of being refused."""
    base = rd.VCavity(0.3, 0.8)
    kw = dict(roughness=0.3, interface="multiple", samples=20, seed=4)
    auto = layered.brdf(0.3, 0.3, 0.0, base, engine="auto", **kw)
    assert auto == layered.brdf(0.3, 0.3, 0.0, base, engine="numpy", **kw) > 0


@pytest.mark.parametrize(("interface", "albedo", "alpha"),
                         [("single", 1.0, 0.3), ("multiple", 0.7, 0.5)])
def test_compiled_directional_albedo_agrees(interface: str, albedo: float, alpha: float) -> None:
    """The albedo mode (ωo drawn per path) of the two engines, rough coat; with the multiple
    interface its own reflection scores each walk that leaves upwards."""
    theta = np.array([0.2, 1.2])
    base = rd.OrenNayar(albedo, 0.3, "full")
    kw = dict(eta=1.5, roughness=alpha, samples=20_000, return_stderr=True, interface=interface)
    a, se = layered.directional_albedo(theta, base, engine="compiled", **kw)
    b, sb = layered.directional_albedo(theta, base, engine="numpy", seed=3, **kw)
    assert np.all(np.abs(a - b) < Z_MAX * np.hypot(se, sb)), (a, b, se, sb)


def test_compiled_independent_of_threads() -> None:
    import numba

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("one Numba thread: nothing to compare")
    args = (0.4, 0.7, 1.0, rd.OrenNayar(0.8, 0.4, "full"))
    kw = dict(roughness=0.3, samples=5_000, seed=9, engine="compiled")
    a = layered.brdf(*args, **kw)
    old = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        b = layered.brdf(*args, **kw)
    finally:
        numba.set_num_threads(old)
    assert a == b


def test_compiled_refuses_a_table_base_by_name() -> None:
    base = rd.VCavity(0.3, 0.8)
    with pytest.raises(ParameterError, match="engine='compiled'.*VCavity"):
        layered.brdf(0.3, 0.3, 0.0, base, samples=10, engine="compiled")


def test_auto_runs_a_table_base_on_the_numpy_walk() -> None:
    """engine="auto" falls back to the NumPy walk (same seed, same value) for a base the
    compiled walk cannot run, instead of refusing it."""
    base = rd.VCavity(0.3, 0.8)
    kw = dict(samples=20, seed=4)
    auto = layered.brdf(0.3, 0.3, 0.0, base, engine="auto", **kw)
    assert auto == layered.brdf(0.3, 0.3, 0.0, base, engine="numpy", **kw)


@pytest.mark.parametrize("model", [rd.EON(0.7, 0.8), rd.OrenNayar(0.8, 0.3, "full"),
                                   rd.Lambert([0.9, 0.5, 0.2])], ids=["eon", "on", "lambert"])
def test_traced_base_functions_match_the_model(model) -> None:
    from roughdiffuse.engine.scalar import PRELUDE, scalar_sources

    traced = scalar_sources(model)
    namespace: dict = {}
    exec(PRELUDE + traced.source, namespace)  # noqa: S102 - the code under test
    f, sample = namespace["base_f"].py_func, namespace["base_sample"].py_func
    rng = np.random.default_rng(4)
    n = 200
    u = rng.random((2, n))
    w, v = rng.normal(size=(2, n, 3))
    w[:, 2], v[:, 2] = np.abs(w[:, 2]), np.abs(v[:, 2])
    w /= np.linalg.norm(w, axis=1)[:, None]
    v /= np.linalg.norm(v, axis=1)[:, None]
    ref_s = np.stack(model.sampling_strategy().sample(
        np, u[0], u[1], w[:, 0], w[:, 1], w[:, 2], model.parameter_arrays(np, np.float64)), -1)
    got_s = np.array([sample(*u[:, k], *w[k], traced.sample_params) for k in range(n)])
    np.testing.assert_allclose(got_s, ref_s, rtol=1e-12, atol=1e-14)
    ref_f = np.asarray(model.brdf_cosines(w[:, 2], v[:, 2], np.sum(w * v, 1))).reshape(n, -1)
    out = np.empty(traced.channels)
    got_f = []
    f_o, f_i, f_io, i_as_o = (namespace[name].py_func for name in (
        "base_f_o", "base_f_i", "base_f_io", "base_f_i_as_o"))
    p = traced.f_params
    split_f = []
    for k in range(n):
        f(w[k, 2], v[k, 2], float(w[k] @ v[k]), out, p)
        got_f.append(out.copy())
        # f in the walk's parts: the μi-only and μo-only values, then the rest; the μi part
        # also from the μo part at the same cosine
        for hi in (f_i(w[k, 2], p), i_as_o(w[k, 2], f_o(w[k, 2], p), p)):
            f_io(w[k, 2], v[k, 2], float(w[k] @ v[k]), hi, f_o(v[k, 2], p), out, p)
            split_f.append(out.copy())
    np.testing.assert_allclose(np.array(got_f), ref_f, rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(np.array(split_f), np.repeat(ref_f, 2, axis=0), rtol=1e-12,
                               atol=1e-15)
    # EON and Oren-Nayar treat μi and μo alike: one part serves both
    assert ("    return ho" in traced.source) == (not isinstance(model, rd.Lambert))
