"""The Mitsuba plugins against the library: eval, pdf, sample, parameters and gradients.

The reference values come from roughdiffuse's NumPy path (``model.brdf`` × cos θi), which
runs the same formula through another array namespace; the gradients are checked against
central finite differences of that NumPy path.
"""

from __future__ import annotations

import numpy as np
import pytest

import roughdiffuse as rd
from mitsuba_setup import mitsuba_variant

ALBEDO = [0.8, 0.55, 0.3]
PLUGINS = [
    ({"type": "roughdiffuse_lambert"}, lambda a: rd.Lambert(a)),
    ({"type": "roughdiffuse_oren_nayar", "sigma": 0.6}, lambda a: rd.OrenNayar(a, 0.6)),
    (
        {"type": "roughdiffuse_oren_nayar", "sigma": 0.6, "variant": "full"},
        lambda a: rd.OrenNayar(a, 0.6, "full"),
    ),
    ({"type": "roughdiffuse_fujii", "roughness": 0.7}, lambda a: rd.Fujii(a, 0.7)),
    ({"type": "roughdiffuse_eon", "roughness": 0.7}, lambda a: rd.EON(a, 0.7)),
    (
        {"type": "roughdiffuse_torrance_sparrow", "sigma": 0.3, "eta": 1.5},
        lambda a: rd.TorranceSparrow(1.5, 0.3),
    ),
    (
        {"type": "roughdiffuse_torrance_sparrow", "sigma": 0.3, "distribution": "beckmann"},
        lambda a: rd.TorranceSparrow(1.5, 0.3, "beckmann"),
    ),
]
IDS = [d["type"].removeprefix("roughdiffuse_") + str(i) for i, (d, _) in enumerate(PLUGINS)]


def _directions(n: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(2, n, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    v[..., 2] = np.abs(v[..., 2])
    return v[0], v[1]  # towards the light, towards the viewer


def _load(mi, spec):
    d = dict(spec)
    if not d["type"].endswith("torrance_sparrow"):
        d["albedo"] = {"type": "rgb", "value": ALBEDO}
    return mi.load_dict(d)


def _eval_llvm(mi, bsdf, light, view):
    import drjit as dr

    si = dr.zeros(mi.SurfaceInteraction3f, len(light))
    si.wi = mi.Vector3f(*(view.T.astype(np.float32)))
    wo = mi.Vector3f(*(light.T.astype(np.float32)))
    ctx = mi.BSDFContext()
    value, pdf = bsdf.eval_pdf(ctx, si, wo)
    return np.array(value).reshape(3, -1).T, np.array(pdf).ravel()


def _reference(model, light, view):
    f = np.asarray(model.brdf(light, view))
    f = f if f.ndim == 2 else np.repeat(f[:, None], 3, axis=1)
    return f * light[:, 2:3], np.asarray(model.pdf(light, view))


@pytest.mark.parametrize(("spec", "make"), PLUGINS, ids=IDS)
def test_eval_and_pdf_match_the_library_llvm(spec, make):
    mi = mitsuba_variant("llvm_ad_rgb")
    light, view = _directions(2000, 1)
    value, pdf = _eval_llvm(mi, _load(mi, spec), light, view)
    ref_value, ref_pdf = _reference(make(np.array(ALBEDO)), light, view)
    np.testing.assert_allclose(value, ref_value, rtol=2e-4, atol=2e-6)
    np.testing.assert_allclose(pdf, ref_pdf, rtol=2e-4, atol=2e-6)


@pytest.mark.parametrize(("spec", "make"), PLUGINS, ids=IDS)
def test_eval_pdf_and_sample_match_the_library_scalar(spec, make):
    mi = mitsuba_variant("scalar_rgb")
    bsdf = _load(mi, spec)
    model = make(np.array(ALBEDO))
    light, view = _directions(5, 2)
    ctx = mi.BSDFContext()
    for lv, vv in zip(light, view, strict=True):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(*map(float, vv))
        ref_value, ref_pdf = _reference(model, lv[None], vv[None])
        value = np.array(bsdf.eval(ctx, si, mi.Vector3f(*map(float, lv))))
        np.testing.assert_allclose(value, ref_value[0], rtol=2e-5, atol=1e-7)
        assert bsdf.pdf(ctx, si, mi.Vector3f(*map(float, lv))) == pytest.approx(ref_pdf[0], 2e-5)
        u = (0.37, 0.71)
        bs, weight = bsdf.sample(ctx, si, 0.5, mi.Point2f(*u))
        ref = model.sample(np.array(u), vv)
        if ref.pdf > 0:
            np.testing.assert_allclose(np.array(bs.wo), ref.wi, atol=1e-5)
            assert bs.pdf == pytest.approx(float(ref.pdf), rel=1e-4)
        ref_w = np.broadcast_to(np.asarray(ref.weight), (3,))
        np.testing.assert_allclose(np.array(weight), ref_w, rtol=1e-4, atol=1e-7)


@pytest.mark.parametrize(("spec", "make"), PLUGINS, ids=IDS)
def test_zero_below_the_horizon(spec, make):
    mi = mitsuba_variant("llvm_ad_rgb")
    light, view = _directions(200, 3)
    below = light * np.array([1.0, 1.0, -1.0])
    value, pdf = _eval_llvm(mi, _load(mi, spec), below, view)
    assert np.all(value == 0) and np.all(pdf == 0)
    value, pdf = _eval_llvm(mi, _load(mi, spec), light, view * np.array([1.0, 1.0, -1.0]))
    assert np.all(value == 0) and np.all(pdf == 0)


def test_parameters_are_differentiable_and_updatable():
    import drjit as dr

    mi = mitsuba_variant("llvm_ad_rgb")
    bsdf = mi.load_dict({"type": "roughdiffuse_oren_nayar", "sigma": 0.4, "albedo": 0.7})
    params = mi.traverse(bsdf)
    assert {"sigma", "albedo.value"} <= set(params.keys())
    light, view = _directions(500, 4)

    sigma = mi.Float(0.4)
    dr.enable_grad(sigma)
    params["sigma"] = sigma
    params.update()
    si = dr.zeros(mi.SurfaceInteraction3f, len(light))
    si.wi = mi.Vector3f(*(view.T.astype(np.float32)))
    wo = mi.Vector3f(*(light.T.astype(np.float32)))
    value = bsdf.eval(mi.BSDFContext(), si, wo)
    dr.backward(dr.sum(value.x))
    grad = float(dr.grad(params["sigma"])[0])

    def total(s: float) -> float:
        f = np.asarray(rd.OrenNayar(0.7, s).brdf(light, view))
        return float(np.sum(f * light[:, 2]))

    h = 1e-5
    fd = (total(0.4 + h) - total(0.4 - h)) / (2 * h)
    assert grad == pytest.approx(fd, rel=1e-3)

    params["sigma"] = mi.Float(0.9)
    params.update()
    value, _ = _eval_llvm(mi, bsdf, light, view)
    ref = np.asarray(rd.OrenNayar(0.7, 0.9).brdf(light, view)) * light[:, 2]
    np.testing.assert_allclose(value[:, 0], ref, rtol=2e-4, atol=2e-6)


def test_albedo_gradient_of_eon():
    """d/dρ of EON (ρ enters through ρ_ms too, so it is not linear) against finite differences."""
    import drjit as dr

    mi = mitsuba_variant("llvm_ad_rgb")
    bsdf = mi.load_dict({"type": "roughdiffuse_eon", "roughness": 0.8, "albedo": 0.6})
    params = mi.traverse(bsdf)
    light, view = _directions(300, 5)
    dr.enable_grad(params["albedo.value"])
    params.update()
    si = dr.zeros(mi.SurfaceInteraction3f, len(light))
    si.wi = mi.Vector3f(*(view.T.astype(np.float32)))
    value = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(*(light.T.astype(np.float32))))
    dr.backward(dr.sum(value.x))
    grad = float(dr.grad(params["albedo.value"])[0])

    def total(a: float) -> float:
        return float(np.sum(np.asarray(rd.EON(a, 0.8).brdf(light, view)) * light[:, 2]))

    fd = (total(0.6 + 1e-5) - total(0.6 - 1e-5)) / 2e-5
    assert grad == pytest.approx(fd, rel=1e-3)


def test_bad_parameter_is_reported_by_name():
    mi = mitsuba_variant("scalar_rgb")
    with pytest.raises(Exception, match="sigma"):
        mi.load_dict({"type": "roughdiffuse_oren_nayar", "sigma": 3.0})
    with pytest.raises(Exception, match="variant"):
        mi.load_dict({"type": "roughdiffuse_oren_nayar", "variant": "fancy"})
