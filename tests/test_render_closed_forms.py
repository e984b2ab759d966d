"""The renderer against closed forms (geometry and the lecture's formulas written out here).

Pixel centres are recomputed here from the camera's documented framing: the shape's
projected extent, enlarged by 2 x margin (0.04), centred, square pixels.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.render import (
    Cylinder,
    DistantLight,
    Moon,
    OrthographicCamera,
    Plane,
    Sphere,
    SurfaceOfRevolution,
    pixel_coordinates,
    render,
)

MARGIN = 1.08


def grid(n: int, half_w: float, half_h: float, centre_y: float = 0.0):
    """World (x, y) of pixel centres for an n x n image framing [-half_w, half_w] x [.., ..]."""
    pixel = max(2 * half_w * MARGIN / n, 2 * half_h * MARGIN / n)
    x = (np.arange(n) + 0.5 - n / 2) * pixel
    y = centre_y + (n / 2 - np.arange(n) - 0.5) * pixel
    return x, y, pixel


def on_qualitative_angles(rho, sigma, ti, tr, cos_dphi):
    """The lecture's final expression, in angles: ρ/π (A + B max(0, cos Δφ) sin α tan β)."""
    s2 = sigma**2
    a = 1 - 0.5 * s2 / (s2 + 0.33)
    b = 0.45 * s2 / (s2 + 0.09)
    alpha, beta = np.maximum(ti, tr), np.minimum(ti, tr)
    return rho / np.pi * (a + b * np.maximum(0, cos_dphi) * np.sin(alpha) * np.tan(beta))


def test_lambert_sphere_head_on_is_rho_over_pi_times_nz():
    n, rho, e0 = 65, 0.8, 2.0
    img, mask = render(
        rd.Lambert(rho), Sphere(), DistantLight(0.0, 0.0, e0), size=n, samples_per_pixel=1
    )
    x, y, _ = grid(n, 1.0, 1.0)
    xx, yy = np.meshgrid(x, y)
    r2 = xx**2 + yy**2
    inside = r2 < 1
    expected = rho / np.pi * e0 * np.sqrt(np.where(inside, 1 - r2, 0))
    assert img.dtype == np.float32 and img.shape == (n, n)
    np.testing.assert_allclose(img[inside], expected[inside], atol=1e-5)
    assert np.all(img[~inside] == 0)
    np.testing.assert_array_equal(mask, inside.astype(np.float32))


@pytest.mark.parametrize("sigma", [0.2, 0.5, 1.0])
def test_oren_nayar_sphere_centre_is_rho_a_over_pi(sigma):
    rho = 0.7
    img, _ = render(
        rd.OrenNayar(rho, sigma), Sphere(), DistantLight(0.0), size=33, samples_per_pixel=1
    )
    a = 1 - 0.5 * sigma**2 / (sigma**2 + 0.33)
    assert img[16, 16] == pytest.approx(rho * a / np.pi, abs=1e-6)


def test_oren_nayar_full_sphere_centre_adds_the_interreflection_term():
    rho, sigma = 0.9, 0.6
    img, _ = render(
        rd.OrenNayar(rho, sigma, "full"), Sphere(), DistantLight(0.0), size=33, samples_per_pixel=1
    )
    s2 = sigma**2
    c1 = 1 - 0.5 * s2 / (s2 + 0.33)
    l2 = 0.17 * rho**2 / np.pi * s2 / (s2 + 0.13)  # β = 0: [1 − c (2β/π)²] = 1
    assert img[16, 16] == pytest.approx(rho / np.pi * c1 + l2, abs=1e-6)


@pytest.mark.parametrize(
    ("ti", "pi", "tv", "pv"),
    [(30, 0, 50, 0), (60, 0, 20, 180), (40, 30, 70, 100), (0, 0, 45, 0)],
)
def test_plane_image_is_the_model_at_its_one_geometry(ti, pi, tv, pv):
    rho, sigma, e0 = 0.6, 0.4, 1.5
    img, mask = render(
        rd.OrenNayar(rho, sigma),
        Plane(),
        DistantLight(math.radians(ti), math.radians(pi), e0),
        OrthographicCamera(math.radians(tv), math.radians(pv)),
        size=(12, 20),
    )
    expected = (
        on_qualitative_angles(
            rho, sigma, math.radians(ti), math.radians(tv), math.cos(math.radians(pv - pi))
        )
        * e0
        * math.cos(math.radians(ti))
    )
    assert img.shape == (12, 20)
    np.testing.assert_allclose(img, expected, rtol=2e-5)
    assert np.all(mask == 1)


def test_cylinder_cross_section_follows_the_model_along_its_curve():
    n, radius, rho, sigma, tl = 101, 0.5, 0.8, 0.5, math.radians(40.0)
    img, mask = render(
        rd.OrenNayar(rho, sigma),
        Cylinder(radius, 2.0),
        DistantLight(tl, 0.0),
        size=n,
        samples_per_pixel=1,
    )
    x, _, pixel = grid(n, radius, 1.0)
    row = img[n // 2]
    inside = np.abs(x) < radius - pixel
    # in the cross-section plane the normal is at angle ψ from the view (z), the light at tl
    psi = np.arcsin(x[inside] / radius)
    tr, ti = np.abs(psi), np.abs(tl - psi)
    same_side = np.sign(-psi) * np.sign(tl - psi) > 0
    expected = on_qualitative_angles(rho, sigma, ti, tr, np.where(same_side, 1.0, -1.0))
    expected = np.where(ti < np.pi / 2, expected * np.cos(ti), 0.0)
    np.testing.assert_allclose(row[inside], expected, atol=2e-5)
    assert np.all(mask[n // 2][np.abs(x) > radius + pixel] == 0)


def test_cast_shadow_under_an_overhang_is_black():
    # a stem of radius 0.3 under a disc of radius 0.8 (0 < y < 0.2); light from above-front
    r1, r2 = 0.3, 0.8
    shape = SurfaceOfRevolution(profile=[(-1.0, r1), (0.0, r1), (0.0, r2), (0.2, r2)])
    tl = math.radians(30.0)
    light = DistantLight(tl, math.pi / 2)  # l = (0, sin 30°, cos 30°)
    n, rho = 121, 0.8
    img, mask = render(rd.Lambert(rho), shape, light, size=n, samples_per_pixel=1)
    free, _ = render(rd.Lambert(rho), shape, light, size=n, samples_per_pixel=1, shadows=False)
    _, y, _ = grid(n, r2, 0.6, centre_y=-0.4)
    col = n // 2  # x = 0: the stem's front, normal (0, 0, 1)
    # the ray from (0, y, r1) towards l meets the disc's underside iff 0 < -y < (r2 - r1) tan 30°
    depth = (r2 - r1) * math.sin(tl) / math.cos(tl)
    shadowed = (y < -0.02) & (y > -depth + 0.02)
    lit = (y < -depth - 0.02) & (y > -0.95)
    assert shadowed.sum() > 10 and lit.sum() > 10
    assert np.all(mask[shadowed, col] == 1)
    assert np.all(img[shadowed, col] == 0)
    lambert = rho / np.pi * math.cos(tl)
    np.testing.assert_allclose(img[lit, col], lambert, atol=2e-5)
    np.testing.assert_allclose(free[shadowed, col], lambert, atol=2e-5)


def test_several_lights_add():
    model, shape = rd.OrenNayar(0.7, 0.4), SurfaceOfRevolution(segments=32)
    a, b = DistantLight(0.5, 0.2, 1.0), DistantLight(1.0, 2.5, 0.5)
    both, _ = render(model, shape, [a, b], size=40)
    one, _ = render(model, shape, a, size=40)
    two, _ = render(model, shape, b, size=40)
    np.testing.assert_allclose(both, one + two, atol=1e-6)


def test_rgb_albedo_gives_channels_that_scale_with_albedo():
    img, _ = render(rd.Lambert([0.9, 0.45, 0.0]), Sphere(), DistantLight(0.3), size=24)
    assert img.shape == (24, 24, 3)
    np.testing.assert_allclose(img[..., 1], 0.5 * img[..., 0], rtol=1e-6, atol=1e-9)
    assert np.all(img[..., 2] == 0)


def test_moon_uses_the_lunar_albedo():
    img, _ = render(rd.Lambert(0.8), Moon(), DistantLight(0.0), size=33, samples_per_pixel=1)
    assert img[16, 16] == pytest.approx(0.12 / np.pi, abs=1e-7)


def test_supersampled_coverage_integrates_the_disc_area():
    n = 64
    _, mask = render(rd.Lambert(1.0), Sphere(), size=n, samples_per_pixel=16)
    _, _, pixel = grid(n, 1.0, 1.0)
    assert mask.sum() * pixel**2 == pytest.approx(np.pi, rel=2e-3)
    edge = (mask > 0) & (mask < 1)
    assert edge.sum() > 0.8 * 2 * np.pi / pixel  # partly covered pixels all along the limb


def test_pixel_coordinates_match_the_framing():
    x, y = pixel_coordinates(Sphere(2.0), None, (10, 20))
    pixel = max(4 * MARGIN / 20, 4 * MARGIN / 10)
    np.testing.assert_allclose(np.diff(x), pixel)
    np.testing.assert_allclose(x.mean(), 0.0, atol=1e-12)
    assert y[0] > y[-1]


def test_vase_profile_silhouette_matches_the_profile_radius():
    vase = SurfaceOfRevolution()
    n = 201
    _, mask = render(rd.Lambert(0.5), vase, size=n, samples_per_pixel=1)
    x, y = pixel_coordinates(vase, None, n)
    pixel = x[1] - x[0]
    r = rd.render.clay_vase_profile(y)
    for i in range(10, n - 10, 10):
        if -0.98 < y[i] < 0.98:
            width = mask[i].sum() * pixel
            assert width == pytest.approx(2 * r[i], abs=2.5 * pixel)


@pytest.mark.parametrize(
    ("kwargs", "word"),
    [
        ({"size": 0}, "size"),
        ({"size": (10, 10, 3)}, "size"),
        ({"samples_per_pixel": 3}, "samples_per_pixel"),
        ({"light": "sun"}, "light"),
        ({"camera": 5}, "camera"),
    ],
)
def test_bad_arguments_raise_value_error_naming_them(kwargs, word):
    with pytest.raises(ValueError, match=word):
        render(rd.Lambert(0.5), Sphere(), **kwargs)


def test_bad_shapes_and_lights_raise_value_error():
    with pytest.raises(ValueError, match="radius"):
        Sphere(-1.0)
    with pytest.raises(ValueError, match="theta"):
        DistantLight(4.0)
    with pytest.raises(ValueError, match="profile radius"):
        SurfaceOfRevolution(profile=[(0, 1), (1, -1)])
    with pytest.raises(ValueError, match="model"):
        render("lambert", Sphere())


def test_the_renderer_evaluates_the_models_own_kernel():
    # a model whose formula exists nowhere else: f = c μo (so L = c μo μi E0)
    from dataclasses import dataclass
    from typing import ClassVar

    from roughdiffuse.models.base import Model, register_pytree

    @register_pytree
    @dataclass(frozen=True)
    class ViewCosine(Model):
        c: float = 1.0
        array_fields: ClassVar[tuple[str, ...]] = ("c",)

        def _kernel(self, xp, mu_i, mu_o, cos_io, c):
            return c * mu_o

    n = 33
    img, _ = render(ViewCosine(0.5), Sphere(), DistantLight(0.0), size=n, samples_per_pixel=1)
    x, y, _ = grid(n, 1.0, 1.0)
    xx, yy = np.meshgrid(x, y)
    inside = xx**2 + yy**2 < 1
    nz = np.sqrt(np.where(inside, 1 - xx**2 - yy**2, 0))
    np.testing.assert_allclose(img[inside], 0.5 * nz[inside] ** 2, atol=1e-6)


@pytest.mark.parametrize("traceable", [True, False])
def test_function_profile_of_a_sphere_shades_like_the_sphere(traceable):
    # r(y) = sqrt(1 - y²) is the unit sphere: head-on Lambert radiance is ρ/π n_z exactly
    def jax_profile(y):
        import jax.numpy as jnp

        return jnp.sqrt(1.0 - y * y)

    def numpy_profile(y):
        return np.sqrt(1.0 - np.asarray(y, dtype=np.float64) ** 2)

    profile = jax_profile if traceable else numpy_profile
    shape = SurfaceOfRevolution(profile=profile, y_range=(-0.95, 0.95), segments=48)
    assert shape.exact is traceable
    n, rho = 81, 0.8
    img, _ = render(rd.Lambert(rho), shape, DistantLight(0.0), size=n, samples_per_pixel=1)
    x, y = pixel_coordinates(shape, None, n)
    xx, yy = np.meshgrid(x, y)
    r2 = xx**2 + yy**2
    sel = (r2 < 0.9**2) & (np.abs(yy) < 0.9)
    err = np.abs(img[sel] - rho / np.pi * np.sqrt(1 - r2[sel]))
    if traceable:
        assert err.max() < 2e-5
    else:  # slope interpolated between 49 nodes: close, not exact
        assert 2e-5 < err.max() < 2e-3


def test_rgb_irradiance_with_a_grey_model():
    img, _ = render(
        rd.Lambert(0.5),
        Sphere(),
        DistantLight(0.0, 0.0, (1.0, 0.5, 0.0)),
        size=9,
        samples_per_pixel=1,
    )
    assert img.shape == (9, 9, 3)
    assert img[4, 4, 0] == pytest.approx(0.5 / np.pi, abs=1e-7)  # centre: n·l = 1
    np.testing.assert_allclose(img[..., 1], 0.5 * img[..., 0], rtol=1e-6, atol=1e-9)
    assert np.all(img[..., 2] == 0)
