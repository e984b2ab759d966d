"""The same sphere rendered by Mitsuba 3 (our plugins) and by roughdiffuse's own renderer.

Scene: a unit sphere, a directional light of irradiance 1, an orthographic camera framing the
sphere as :class:`roughdiffuse.render.OrthographicCamera` does (4 % margin), Mitsuba's
``path`` integrator with ``max_depth`` 2 (direct light only, as roughdiffuse computes), 256
samples per pixel with a box filter. roughdiffuse's image is its ray tracer
(:func:`roughdiffuse.render.render`, 4 × 4 stratified samples per pixel), an independent
implementation of the camera, the intersection and the shading. Pixels compared: fully
covered ones (no silhouette pixels) where the radiance is above 2 % of the maximum (the
terminator, where a relative error means nothing, is left out).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from mitsuba_setup import mitsuba_variant
from roughdiffuse._mitsuba_scene import orthographic_sensor
from roughdiffuse.render import DistantLight, OrthographicCamera, Sphere, direction, render

SIZE = 64
MARGIN = 0.04
CONFIGS = [  # (light θ, φ), (camera θ, φ) in degrees
    ((50.0, 0.0), (0.0, 0.0)),
    ((60.0, 30.0), (35.0, 90.0)),
]


@pytest.fixture(scope="module")
def mi():
    return mitsuba_variant("llvm_ad_rgb")


def _mitsuba_image(mi, bsdf: dict, light: tuple, camera: tuple, spp: int = 256) -> np.ndarray:
    l = direction(*np.radians(light))
    v = direction(*np.radians(camera))
    half = 1.0 + 2.0 * MARGIN  # half width of the frame for a unit sphere
    to_world = mi.ScalarTransform4f().look_at(
        origin=(10.0 * v).tolist(), target=[0, 0, 0], up=[0, 1, 0]
    ) @ mi.ScalarTransform4f().scale([half, half, 1.0])
    scene = mi.load_dict(
        {
            "type": "scene",
            "integrator": {"type": "path", "max_depth": 2},
            "sensor": orthographic_sensor(to_world, SIZE, spp),
            "light": {"type": "directional", "direction": (-l).tolist(), "irradiance": 1.0},
            "sphere": {"type": "sphere", "bsdf": bsdf},
        }
    )
    return np.array(mi.render(scene, seed=7))


def _our_image(model: rd.Model, light: tuple, camera: tuple) -> tuple[np.ndarray, np.ndarray]:
    image, mask = render(
        model,
        Sphere(),
        DistantLight(*np.radians(light)),
        OrthographicCamera(*np.radians(camera), margin=MARGIN),
        size=SIZE,
        samples_per_pixel=16,
    )
    return image, mask


def _compare(ours: np.ndarray, mask: np.ndarray, theirs: np.ndarray) -> tuple[float, float]:
    if ours.ndim == 3:
        ours, theirs = ours[..., 0], theirs[..., 0]
    else:
        theirs = theirs[..., 0]
    keep = (mask == 1) & (ours > 0.02 * ours.max())
    assert keep.sum() > 0.3 * SIZE * SIZE / 4  # a good part of the lit hemisphere
    scale = float(np.mean(ours[keep]))
    mean_abs = float(np.mean(np.abs(theirs - ours)[keep])) / scale
    bias = float(np.mean((theirs - ours)[keep])) / scale
    return mean_abs, bias


ALBEDO = [0.8, 0.6, 0.4]
MODELS = [
    ({"type": "roughdiffuse_lambert"}, rd.Lambert(np.array(ALBEDO))),
    ({"type": "roughdiffuse_oren_nayar", "sigma": 0.5}, rd.OrenNayar(np.array(ALBEDO), 0.5)),
    (
        {"type": "roughdiffuse_oren_nayar", "sigma": 0.5, "variant": "full"},
        rd.OrenNayar(np.array(ALBEDO), 0.5, "full"),
    ),
    ({"type": "roughdiffuse_eon", "roughness": 0.8}, rd.EON(np.array(ALBEDO), 0.8)),
    ({"type": "roughdiffuse_fujii", "roughness": 0.8}, rd.Fujii(np.array(ALBEDO), 0.8)),
]


@pytest.mark.parametrize(("light", "camera"), CONFIGS)
@pytest.mark.parametrize(
    ("bsdf", "model"), MODELS, ids=[m[0]["type"] + m[0].get("variant", "") for m in MODELS]
)
def test_mitsuba_plugin_matches_our_renderer(mi, bsdf, model, light, camera):
    bsdf = {**bsdf, "albedo": {"type": "rgb", "value": ALBEDO}}
    theirs = _mitsuba_image(mi, bsdf, light, camera)
    ours, mask = _our_image(model, light, camera)
    mean_abs, bias = _compare(ours, mask, theirs)
    assert mean_abs < 0.01, (mean_abs, bias)
    assert abs(bias) < 0.003, (mean_abs, bias)


@pytest.mark.parametrize(("light", "camera"), CONFIGS)
def test_lambert_plugin_matches_mitsuba_diffuse(mi, light, camera):
    """Our Lambert plugin and Mitsuba's built-in ``diffuse``: same scene, same seed."""
    albedo = {"type": "rgb", "value": ALBEDO}
    ours = _mitsuba_image(mi, {"type": "roughdiffuse_lambert", "albedo": albedo}, light, camera)
    builtin = _mitsuba_image(mi, {"type": "diffuse", "reflectance": albedo}, light, camera)
    lit = builtin[..., 0] > 0.02 * builtin[..., 0].max()
    rel = np.abs(ours - builtin)[lit].mean() / builtin[lit].mean()
    assert rel < 0.01
    # and our renderer against Mitsuba's own diffuse material
    image, mask = _our_image(rd.Lambert(np.array(ALBEDO)), light, camera)
    mean_abs, bias = _compare(image, mask, builtin)
    assert mean_abs < 0.01 and abs(bias) < 0.003, (mean_abs, bias)


def test_comparison_detects_a_wrong_roughness(mi):
    """Negative control: σ = 0.5 in Mitsuba against σ = 0.3 here must fail the 1 % bound."""
    light, camera = CONFIGS[0]
    theirs = _mitsuba_image(mi, {"type": "roughdiffuse_oren_nayar", "sigma": 0.5}, light, camera)
    ours, mask = _our_image(rd.OrenNayar(1.0, 0.3), light, camera)
    mean_abs, _ = _compare(ours, mask, theirs)
    assert mean_abs > 0.01


def test_lit_fraction_is_where_the_light_is(mi):
    """Orientation check: with the light towards +x the right half of the image is brighter."""
    theirs = _mitsuba_image(mi, {"type": "roughdiffuse_lambert"}, (60.0, 0.0), (0.0, 0.0), 16)
    left, right = theirs[:, : SIZE // 2, 0].sum(), theirs[:, SIZE // 2 :, 0].sum()
    assert right > 3 * left
    assert math.isfinite(float(theirs.sum()))


def test_v_cavity_plugin_matches_our_renderer(mi):
    """The exact V-cavity surface (its table read by ``dr.gather`` in Mitsuba, by ``take``
    under ``jax.jit`` here): one grey channel, σ = 0.3, ρ = 1 (the table of
    tests/test_mitsuba_registry.py's defaults)."""
    light, camera = CONFIGS[0]
    theirs = _mitsuba_image(
        mi, {"type": "roughdiffuse_v_cavity", "sigma": 0.3, "albedo": 1.0}, light, camera
    )
    ours, mask = _our_image(rd.VCavity(1.0, 0.3), light, camera)
    mean_abs, bias = _compare(ours, mask, theirs)
    assert mean_abs < 0.01, (mean_abs, bias)
    assert abs(bias) < 0.003, (mean_abs, bias)
