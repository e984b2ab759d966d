"""Photometric stereo with a coated model (roughdiffuse.stereo.coated), and its test data.

The coated sphere is rendered by roughdiffuse's renderer with ``Coated`` itself (exact ray
intersection and shading of the model), so the truth is the renderer's geometry and the
model's parameters; the cast shadows are checked against a step whose shadow has a closed
form; the DiLiGenT writer against the reader and its own quantisation.
"""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import stereo
from roughdiffuse._validate import ParameterError
from roughdiffuse.render import Sphere
from roughdiffuse.stereo.coated import cast_shadows, model_weights, parameter_count
from roughdiffuse.stereo.diligent import diligent_lights, write_diligent

SIGMA, ALPHA, ALBEDO = 0.4, 0.3, 0.6


@pytest.fixture(scope="module")
def coated_sphere():
    """A coated full Oren–Nayar sphere (ρ 0.6, σ 0.4, η 1.5, GGX α 0.3) under 12 lights on
    a 35° ring, 1% noise on each value; its true normals; the rough and coated fits."""
    truth = rd.Coated(rd.OrenNayar(ALBEDO, SIGMA, "full"), 1.5, ALPHA)
    clean, normals = stereo.render_stereo(truth, Sphere(), stereo.default_lights(12), 28)
    rng = np.random.default_rng(3)
    noisy = clean.images * (1.0 + rng.normal(0.0, 0.01, clean.images.shape))
    data = stereo.StereoInput.from_arrays(np.abs(noisy), clean.directions, mask=clean.mask)
    rough = stereo.rough(data, rd.OrenNayar(variant="full"))
    return data, normals[data.mask], rough, stereo.coated(data, start=rough)


@pytest.mark.slow
def test_coated_fit_recovers_normals_sigma_and_alpha(coated_sphere):
    data, truth, _, res = coated_sphere
    err = np.nanmean(stereo.angular_error(res.normals, truth))
    assert err < 0.5  # degrees
    # σ and α within three of their standard errors of the truth, and the errors small
    assert abs(res.sigma - SIGMA) < 3 * res.sigma_se
    assert abs(res.alpha - ALPHA) < 3 * res.alpha_se
    assert 0 < res.sigma_se < 0.05 and 0 < res.alpha_se < 0.02
    np.testing.assert_allclose(np.nanmedian(res.albedo), ALBEDO, rtol=0.02)
    # the reported angular standard errors describe the actual errors (within a factor 2)
    se = np.degrees(np.nanmean(res.normal_se))
    assert 0.5 * se < err < 2 * se


@pytest.mark.slow
def test_rough_fit_is_biased_by_the_coat(coated_sphere):
    """The rough fit takes the highlights for diffuse light: several times the coated fit's
    error."""
    _, truth, rough, res = coated_sphere
    rough_err = np.nanmean(stereo.angular_error(rough.normals, truth))
    coated_err = np.nanmean(stereo.angular_error(res.normals, truth))
    assert rough_err > 1.0
    assert rough_err > 3 * coated_err


def test_cast_shadow_of_a_step_has_its_closed_form():
    """A wall of height 6 at columns 20–21 on a flat ground, lit from +x at elevation e: a
    ground pixel at column j < 20 is in its shadow iff 6 − tolerance > (20 − j) tan e."""
    h, w = 8, 32
    z = np.zeros((h, w))
    z[:, 20:22] = 6.0
    mask = np.ones((h, w), bool)
    elevations = np.radians([30.0, 50.0, 70.0])
    dirs = np.stack([np.cos(elevations), 0 * elevations, np.sin(elevations)], 1)
    shadow = cast_shadows(z, mask, dirs, tolerance=0.5).reshape(3, h, w)
    cols = np.arange(w)
    for k, e in enumerate(elevations):
        expected = (cols < 20) & (5.5 > (20 - cols) * math.tan(e))
        assert np.array_equal(shadow[k, 0], expected), k
        assert np.all(shadow[k] == shadow[k, :1])  # every row alike
    # from the other side (−x) the wall shadows the ground beyond it, columns 22 on
    back = cast_shadows(z, mask, np.array([[-1.0, 0.0, 1.0]]), tolerance=0.5).reshape(h, w)
    assert np.array_equal(back[0], (cols >= 22) & (5.5 > (cols - 21) * 1.0))


def _marched(z, directions, tolerance):
    """Cast shadows by following each ray on its own (the definition of
    :func:`cast_shadows`, without its sweep): across the image one column (or row, where the
    light runs more along y) at a time, the surface linearly between the two pixels the ray
    passes (the nearer one where one is outside), shadowed when it stands more than
    ``tolerance`` above the ray."""
    h, w = z.shape
    height = np.where(np.isfinite(z), z, -np.inf)
    rows, cols = np.nonzero(np.isfinite(z))
    out = np.zeros((len(directions), rows.size), bool)
    for k, (lx, ly, lz) in enumerate(directions):
        along_x = abs(lx) >= abs(ly)
        run = abs(lx) if along_x else abs(ly)
        for p, (r, c) in enumerate(zip(rows, cols, strict=True)):
            for j in range(1, max(h, w)):
                if along_x:
                    b, a = c + j * np.sign(lx), r - j * ly / run  # rows grow along −y
                    inside = 0 <= b < w and -0.5 < a < h - 0.5
                else:
                    b, a = r - j * np.sign(ly), c + j * lx / run
                    inside = 0 <= b < h and -0.5 < a < w - 0.5
                if not inside:
                    break
                line = height[:, int(b)] if along_x else height[int(b), :]
                a0 = min(max(math.floor(a), 0), line.size - 1)
                a1 = min(a0 + 1, line.size - 1)
                f = min(max(a - a0, 0.0), 1.0) if a1 > a0 else 0.0
                lo, hi = line[a0], line[a1]
                s = lo + f * (hi - lo) if np.isfinite(lo) and np.isfinite(hi) else (
                    hi if f > 0.5 else lo)
                if s > z[r, c] + j * lz / run + tolerance:
                    out[k, p] = True
                    break
    return out


def test_cast_shadows_sweep_matches_each_ray_followed_on_its_own():
    """Along the axes and the diagonals every ray crosses the next column at a pixel, and
    the sweep is each ray's march exactly; in other directions it takes the next column's
    horizon linearly between two rays, and agrees on all but a few per cent of the
    observations on these bumps one or two pixels wide (measured: 1.6 %), the worst case of
    that interpolation."""
    rng = np.random.default_rng(5)
    h, w = 20, 26
    y, x = np.mgrid[0:h, 0:w].astype(float)
    z = np.zeros((h, w))
    for _ in range(8):  # steep bumps
        cx, cy, r, top = rng.uniform(0, w), rng.uniform(0, h), rng.uniform(1, 2), rng.uniform(3, 8)
        z += top * np.exp(-((x - cx) ** 2 + (y - cy) ** 2) / (2 * r * r))
    z[(x - 12) ** 2 + (y - 9) ** 2 > 90] = np.nan  # outside the object
    mask = np.isfinite(z)
    exact = np.array([[1, 0, 0.5], [-1, 0, 0.3], [0, 1, 0.7], [0, -1, 0.4], [1, 1, 0.6],
                      [-1, 1, 0.6], [1, -1, 0.9], [-1, -1, 1]], float)
    exact /= np.linalg.norm(exact, axis=1, keepdims=True)
    got = cast_shadows(z, mask, exact, tolerance=0.3)
    assert np.array_equal(got, _marched(z, exact, 0.3))
    assert got.mean() > 0.05  # the bumps do shadow each other
    angles = rng.uniform(0, 2 * np.pi, 12)
    elevation = rng.uniform(0.2, 0.8, 12)
    other = np.stack([np.cos(angles) * np.cos(elevation), np.sin(angles) * np.cos(elevation),
                      np.sin(elevation)], axis=1)
    got = cast_shadows(z, mask, other, tolerance=0.3)
    assert got.mean() > 0.05
    assert np.mean(got != _marched(z, other, 0.3)) < 0.03


def test_a_convex_sphere_casts_no_shadow_and_attached_shadows_follow_n_dot_l():
    data, normals = stereo.render_stereo(
        rd.Lambert(0.5), Sphere(), stereo.default_lights(6, 60.0), 32
    )
    n = normals[data.mask]
    w = model_weights(data, n)
    lit = (n @ data.directions.T).T > 0
    assert np.array_equal(w > 0, lit)  # the sphere shadows nothing beyond its terminator
    assert not lit.all()  # 60° lights: part of every image is in the attached shadow


def test_model_weights_take_given_kept_observations_and_refuse_another_shape():
    """``kept`` (the threshold's weights, when at hand) is applied as given: an observation
    left out there stays out; one of another shape is refused, not read out of bounds."""
    data, normals = stereo.render_stereo(
        rd.Lambert(0.5), Sphere(), stereo.default_lights(6, 60.0), 16
    )
    n = normals[data.mask]
    kept = np.ones(data.observed.shape, dtype=bool)
    kept[2, :] = False
    w = model_weights(data, n, kept=kept)
    lit = (n @ data.directions.T).T > 0
    assert np.array_equal(w > 0, lit & kept)
    with pytest.raises(ParameterError, match=r"kept must have shape \(6, \d+\)"):
        model_weights(data, n, kept=kept[:, :-1])


def test_coated_fit_refuses_too_few_lights_and_unknown_bases():
    data = stereo.synthetic_sphere(rd.Lambert(0.5), size=8, lights=4, noise=0.0)
    assert parameter_count(1) == parameter_count(3) == 5
    with pytest.raises(ParameterError, match=r"at least 5 lights \(got 4\)"):
        stereo.coated(data)
    with pytest.raises(ParameterError, match="base must be one of"):
        stereo.coated(data, base="lambert")


def test_cli_refuses_coated_with_fewer_lights_than_parameters(tmp_path):
    import json

    lights = stereo.default_lights(4)
    names = []
    for k in range(4):
        np.save(tmp_path / f"i{k}.npy", np.full((6, 6), 0.2 + 0.1 * k))
        names.append(str(tmp_path / f"i{k}.npy"))
    (tmp_path / "lights.json").write_text(json.dumps({"directions": lights.tolist()}))
    out = subprocess.run(
        [
            sys.executable,
            "-m",
            "roughdiffuse",
            "stereo",
            *names,
            "--lights",
            str(tmp_path / "lights.json"),
            "--model",
            "coated",
            "-o",
            str(tmp_path / "o"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert out.returncode == 2
    lines = out.stderr.strip().splitlines()
    assert len(lines) == 1 and "at least 5 lights (got 4)" in lines[0]
    assert not (tmp_path / "o").exists()


def test_diligent_lights_pattern():
    d = diligent_lights()
    assert d.shape == (96, 3)
    np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0)
    angle = np.degrees(np.arccos(d[:, 2]))
    assert 30 < angle.max() < 45 and angle.min() < 5


def test_written_diligent_folder_reads_back_quantised(tmp_path):
    """write_diligent → read_diligent: the same lights and mask; the values are the images
    scaled to 90 % of the 12-bit range at the full scale, rounded to a 12-bit code."""
    from scipy.io import loadmat

    data, normals = stereo.render_stereo(rd.Lambert(0.5), Sphere(), stereo.default_lights(5), 16)
    top = float(data.images.max())
    folder = write_diligent(tmp_path / "ballPNG", data, normals, noise=0.0, full_scale=top)
    back = stereo.read_diligent(folder)
    np.testing.assert_allclose(back.directions, data.directions, atol=1e-6)
    assert np.array_equal(back.mask, data.mask)
    code = np.rint(data.images[..., 0] / top * 0.9 * 4095)
    np.testing.assert_allclose(back.images[..., 0], code * 16 / 65535, atol=1e-9)
    # the intensities hold the scale: image / intensity is the radiance, to half a code
    radiance = back.images[..., 0] / back.intensities[:, None, None, 0]
    np.testing.assert_allclose(radiance, data.images[..., 0], atol=0.5 * top / (0.9 * 4095))
    gt = loadmat(folder / "Normal_gt.mat")["Normal_gt"]
    np.testing.assert_allclose(gt[data.mask], normals[data.mask])


def test_projected_step_holds_a_value_at_its_bound():
    """S = diag(2, 1), rhs = (2, −1): the Gauss–Newton step −S⁻¹ rhs = (−1, 1); with the
    first value at its lower bound the step would push it out, so it is held and the second
    moves alone, by −rhs₂/S₂₂ = 1."""
    import importlib

    module = importlib.import_module("roughdiffuse.stereo.rough")
    s, rhs = np.diag([2.0, 1.0]), np.array([2.0, -1.0])
    lo, hi = np.zeros(2), np.ones(2)
    np.testing.assert_allclose(module._newton_step(s, rhs, np.array([0.5, 0.5]), lo, hi), [-1, 1])
    np.testing.assert_allclose(module._newton_step(s, rhs, np.array([0.0, 0.5]), lo, hi), [0, 1])
    # coupled: S = [[2, 1], [1, 2]]; value 1 held at 0, value 2 steps by −rhs₂ / S₂₂
    s2 = np.array([[2.0, 1.0], [1.0, 2.0]])
    step = module._newton_step(s2, np.array([3.0, -1.0]), np.array([0.0, 0.5]), lo, hi)
    np.testing.assert_allclose(step, [0.0, 0.5])
    # a value whose derivative vanishes (σ of Oren–Nayar at 0): its standard error is
    # infinite; the other's is B₂₂ n/(n − 1) / S₂₂² = 2 · 2 / 16 (scores ±1, n = 2)
    scores = np.array([[0.0, 1.0], [0.0, -1.0]])
    np.testing.assert_allclose(module._sandwich_diagonal(np.diag([0.0, 4.0]), scores),
                               [np.inf, 0.25])


def test_sandwich_by_hand():
    """S = [[2, 1], [1, 2]], scores (1, 0) and (−1, 0): B n/(n − 1) = [[4, 0], [0, 0]],
    S⁻¹ = [[2, −1], [−1, 2]] / 3, so S⁻¹ B S⁻¹ = [[16, −8], [−8, 4]] / 9."""
    import importlib

    module = importlib.import_module("roughdiffuse.stereo.rough")
    s = np.array([[2.0, 1.0], [1.0, 2.0]])
    got = module._sandwich_diagonal(s, np.array([[1.0, 0.0], [-1.0, 0.0]]))
    np.testing.assert_allclose(got, [16 / 9, 4 / 9])


@pytest.mark.parametrize("shared", [0.0, 1.0])
def test_sandwich_matches_the_spread_of_repeated_fits(shared):
    """Least squares y_pk = x_pk·g + e_pk over 400 clusters (pixels) of 12 values: the
    sandwich's variance against the variance of ĝ over 300 repeated draws (Monte Carlo, an
    independent measure). Independent noise (``shared`` 0): both equal σ² S⁻¹. A part of
    the noise common to a cluster, as a pixel the model misfits as a whole (``shared`` 1,
    its standard deviation equal to the independent part's): s² S⁻¹ falls far short, the
    sandwich does not. Tolerance: the variance of a variance estimate from n draws is
    2/n relatively (300 draws: 8 %; the sandwich's own, 400 clusters: 7 %), so 35 %."""
    import importlib

    module = importlib.import_module("roughdiffuse.stereo.rough")
    rng = np.random.default_rng(7)
    n, k = 400, 12
    x = rng.normal(size=(n, k, 2)) + np.array([1.0, 0.0])  # (clusters, values, G)
    s = np.einsum("pki,pkj->ij", x, x)
    fits, sandwiches, classical = [], [], []
    for _ in range(300):
        e = rng.normal(size=(n, k)) + shared * rng.normal(size=(n, 1)) * x[..., 0]
        y = x @ np.array([0.5, -0.3]) + e
        g = np.linalg.solve(s, np.einsum("pki,pk->i", x, y))
        r = y - x @ g
        fits.append(g)
        sandwiches.append(module._sandwich_diagonal(s, np.einsum("pki,pk->pi", x, r)))
        classical.append(np.diag(np.linalg.inv(s)) * np.sum(r**2) / (n * k - 2))
    spread = np.var(np.array(fits), axis=0, ddof=1)
    np.testing.assert_allclose(np.mean(sandwiches, axis=0), spread, rtol=0.35)
    if shared:
        assert np.all(np.mean(classical, axis=0)[0] < 0.5 * spread[0])


@pytest.mark.slow
def test_cli_coated_on_a_diligent_folder(tmp_path):
    """``roughdiffuse stereo --diligent DIR --model coated``: a coated sphere written in the
    DiLiGenT layout (12-bit, no noise), its coat's α and its normals recovered."""
    import json

    truth = rd.Coated(rd.OrenNayar(ALBEDO, SIGMA, "full"), 1.5, ALPHA)
    data, normals = stereo.render_stereo(truth, Sphere(), stereo.default_lights(12), 24)
    folder = write_diligent(tmp_path / "ballPNG", data, normals, noise=0.0)
    out = subprocess.run(
        [sys.executable, "-m", "roughdiffuse", "stereo", "--diligent", str(folder),
         "--model", "coated", "-o", str(tmp_path / "o")],
        capture_output=True, text=True, timeout=1200,
    )
    assert out.returncode == 0, out.stderr
    assert "coat α = 0.3" in out.stdout
    params = json.loads((tmp_path / "o" / "params.json").read_text())
    assert params["coat"]["alpha"]["value"] == pytest.approx(ALPHA, abs=0.01)
    assert params["roughness"]["value"] == pytest.approx(SIGMA, abs=0.05)
    fitted = np.load(tmp_path / "o" / "normals.npy")[data.mask]
    assert np.nanmean(stereo.angular_error(fitted, normals[data.mask])) < 0.5


def test_subsample_drawn_among_the_smoothest():
    """With a spread, every pixel drawn is among the SMOOTH fraction (at least the count) of
    the well-lit pixels with the least spread; without, any well-lit pixel may be drawn."""
    import importlib

    module = importlib.import_module("roughdiffuse.stereo.coated")
    p = 4000
    weights = np.ones((10, p), dtype=bool)
    ok = np.ones(p, dtype=bool)
    spread = np.random.default_rng(3).uniform(size=p)
    pick = module._well_lit(weights, ok, 200, spread)
    assert pick.size == 200
    assert spread[pick].max() <= np.quantile(spread, module.SMOOTH) + 1e-12
    assert spread[module._well_lit(weights, ok, 200)].max() > 0.5
