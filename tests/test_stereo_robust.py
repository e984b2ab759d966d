"""Robust Lambertian photometric stereo (L1, sparse Bayesian, RPCA) against the reference.

The reference is yasumat/RobustPhotometricStereo (Matsushita; GPL, so not copied here): its
outputs on a synthetic sphere with highlights, attached and cast shadows (24 lights) were
written by ``tests/reference/robust_ps/make_reference.py``, which runs its code unmodified.
"Converged" for the reference: its solver returned the same x with max_ite = 999 as with
1000 (it stopped on its own criterion), and for L1 its x also reaches the minimum of the L1
cost (within 1e-6 of the optimum HiGHS finds for the same linear programme): its IRLS can
stop at a vertex that is not the minimum, which ours then solves as the linear programme.
For ours: 999 and 1000 iterations give the same normals to 1e-12.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import linprog

from roughdiffuse._validate import ParameterError
from roughdiffuse.stereo import StereoInput
from roughdiffuse.stereo.robust import ROBUST_METHODS, robust

REFERENCE = Path(__file__).parent / "reference" / "robust_ps" / "reference.npz"


@pytest.fixture(scope="module")
def reference():
    z = dict(np.load(REFERENCE))
    data = StereoInput.from_arrays(z["images"], z["lights"], 1.0, mask=z["mask"])
    return z, data


def _angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.degrees(np.arccos(np.clip(np.sum(a * b, axis=-1), -1.0, 1.0)))


def _l1_optimum(lights: np.ndarray, obs: np.ndarray, a: np.ndarray | None = None) -> object:
    """min ‖L b − m‖₁ as the linear programme min Σ t, −t ≤ L b − m ≤ t (HiGHS); ``a`` is
    its constraint matrix, built once for many pixels."""
    k = lights.shape[0]
    c = np.r_[np.zeros(3), np.ones(k)]
    if a is None:
        a = np.block([[lights, -np.eye(k)], [-lights, -np.eye(k)]])
    bounds = [(None, None)] * 3 + [(0, None)] * k
    return linprog(c, A_ub=a, b_ub=np.r_[obs, -obs], bounds=bounds, method="highs")


def _reaches_the_l1_minimum(z: dict) -> np.ndarray:
    m, lights = z["images"][:, z["mask"]], z["lights"]
    k = lights.shape[0]
    a = np.block([[lights, -np.eye(k)], [-lights, -np.eye(k)]])
    out = np.zeros(m.shape[1], dtype=bool)
    for j in np.flatnonzero(z["l1_converged"]):
        cost = np.abs(lights @ z["l1_x"][j] - m[:, j]).sum()
        out[j] = cost <= _l1_optimum(lights, m[:, j], a).fun * (1 + 1e-6)
    return out


@pytest.mark.parametrize("method", ROBUST_METHODS)
def test_normals_agree_with_the_reference_implementation(reference, method):
    z, data = reference
    ours = robust(data, method)
    ours_before = robust(data, method, iterations=999)
    ours_converged = np.all(np.abs(ours.normals - ours_before.normals) < 1e-12, axis=-1)
    both = z[f"{method}_converged"] & ours_converged
    if method == "l1":
        both &= _reaches_the_l1_minimum(z)
    assert both.mean() > 0.9  # the comparison covers nearly every pixel
    assert np.max(_angle(ours.normals[both], z[f"{method}_normals"][both])) < 0.1


def test_l1_normals_are_those_of_the_linear_programme(reference):
    """Every 47th pixel: the normal of min ‖L b − m‖₁, solved as a linear programme by
    HiGHS, is ours (the minimiser is unique for data in general position)."""
    z, data = reference
    m = z["images"][:, z["mask"]]
    lights = z["lights"]
    res = robust(data, "l1")
    for j in range(0, m.shape[1], 47):
        lp = _l1_optimum(lights, m[:, j])
        b = lp.x[:3] / np.linalg.norm(lp.x[:3])
        assert _angle(res.normals[j], b) < 0.01


def test_planted_outliers_are_rejected_and_the_normal_is_exact():
    """A Lambertian pixel under 20 lights with 3 large corruptions: L1 and SBL recover the
    normal exactly and reject exactly the corrupted observations."""
    rng = np.random.default_rng(3)
    k = 20
    th = np.radians(rng.uniform(10, 60, k))
    ph = rng.uniform(0, 2 * np.pi, k)
    lights = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], 1)
    normal = np.array([0.2, -0.1, 1.0]) / np.linalg.norm([0.2, -0.1, 1.0])
    clean = 0.5 / np.pi * np.maximum(lights @ normal, 0)
    imgs = clean.copy()
    bad = [2, 9, 15]
    imgs[bad] += [0.3, 0.5, 0.2]  # highlights
    data = StereoInput.from_arrays(imgs.reshape(k, 1, 1), lights)
    for method in ("l1", "sparse"):
        r = robust(data, method)
        assert _angle(r.normals[0], normal) < 1e-4
        assert r.albedo[0, 0] == pytest.approx(0.5, rel=1e-6)
        assert np.flatnonzero(r.weights[:, 0] == 0).tolist() == bad


def test_shadow_threshold_leaves_dark_observations_out(reference):
    z, data = reference
    r = robust(data, "rpca", shadow=0.05)
    grey = z["images"][:, z["mask"]]
    dark = grey <= 0.05 * grey.max(axis=0)
    assert np.all(r.weights[dark] == 0)


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"method": "l2"}, "method must be one of l1, sparse, rpca"),
        ({"method": "l1", "outlier": 0.0}, "outlier must be"),
        ({"method": "l1", "iterations": 0}, "iterations must be"),
        ({"method": "l1", "tol": float("nan")}, "tol must be"),
    ],
)
def test_bad_arguments_are_refused(reference, kwargs, needle):
    _, data = reference
    with pytest.raises(ParameterError, match=needle):
        robust(data, **kwargs)
