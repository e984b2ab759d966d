"""Write reference.npz: yasumat/RobustPhotometricStereo run as it is on a synthetic sphere.

Usage (a Python with numpy, scikit-learn and opencv-python, the reference's dependencies)::

    python make_reference.py CHECKOUT [OUT]

CHECKOUT is a checkout of https://github.com/yasumat/RobustPhotometricStereo (its rps.py,
rpsnumerics.py and psutil.py are imported unmodified from there; they are GPL-licensed and
not part of this repository). The inputs are built here with numpy alone, so the file holds
the inputs and the reference's outputs side by side.

Convergence of the reference, per pixel: the solvers of rpsnumerics stop when
‖x − x_prev‖ < 1e-8 or after max_ite = 1000 iterations. A pixel counts as converged when the
same function, as it is, called with max_ite = 999 returns bit for bit the same x: it stopped
on its own criterion before the cap. RPCA converged when it returned without its
"Exceeded the maximum number of iterations" warning.
"""

from __future__ import annotations

import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np

SIZE = 24
LIGHTS = 24
SEED = 7


def sphere_inputs() -> dict[str, np.ndarray]:
    """A Lambertian sphere of varying albedo under 24 lights, with sparse corruptions:
    a sharp specular lobe (highlights), attached shadows (max(n·l, 0)), a cast shadow over
    one corner for lights from the left, and 0.2 % noise."""
    rng = np.random.default_rng(SEED)
    u = (np.arange(SIZE) + 0.5) / SIZE * 2.0 - 1.0
    x, y = np.meshgrid(u, -u)
    r2 = x * x + y * y
    mask = r2 < 0.9**2
    n = np.stack([x, y, np.sqrt(np.clip(1.0 - r2, 0.0, None))], axis=-1)
    theta = np.radians(rng.uniform(15.0, 65.0, LIGHTS))
    phi = rng.uniform(0.0, 2.0 * np.pi, LIGHTS)
    lights = np.stack(
        [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=1
    )
    albedo = 0.5 + 0.3 * np.cos(3.0 * x) * np.cos(2.0 * y)
    ndl = np.einsum("hwi,ki->khw", n, lights)
    diffuse = albedo * np.maximum(ndl, 0.0)
    half = lights + np.array([0.0, 0.0, 1.0])
    half /= np.linalg.norm(half, axis=1, keepdims=True)
    ndh = np.maximum(np.einsum("hwi,ki->khw", n, half), 0.0)
    specular = 1.5 * ndh**200 * (ndl > 0)
    cast = (x[None] < -0.4) & (y[None] > 0.3) & (lights[:, 0, None, None] < -0.3)
    images = np.where(cast, 0.0, diffuse + specular)
    images = np.maximum(images + rng.normal(0.0, 0.002, images.shape), 0.0)
    return {"images": images, "lights": lights, "mask": mask, "normals": n}


def main(checkout: str, out: str) -> None:
    sys.path.insert(0, checkout)
    import rps  # noqa: PLC0415 - the reference, imported as it is
    import rpsnumerics  # noqa: PLC0415

    data = sphere_inputs()
    k, h, w = data["images"].shape
    fg = np.flatnonzero(data["mask"].reshape(-1))
    result = dict(data)
    m = data["images"].reshape(k, -1).T  # (p, f), rows pixels: the reference's M
    for name, method, fn in (
        ("l1", rps.RPS.L1_SOLVER, rpsnumerics.L1_residual_min),
        ("sparse", rps.RPS.SBL_SOLVER, rpsnumerics.sparse_bayesian_learning),
        ("rpca", rps.RPS.RPCA_SOLVER, None),
    ):
        solver = rps.RPS()
        solver.M, solver.L = m, data["lights"].T
        solver.height, solver.width = h, w
        solver.foreground_ind = fg  # the mask as indices, as load_mask sets them
        solver.background_ind = np.flatnonzero(~data["mask"].reshape(-1))
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            solver.solve(method)
        result[f"{name}_normals"] = solver.N[fg]
        if fn is None:
            ok = not any("Exceeded" in str(c.message) for c in caught)
            result[f"{name}_converged"] = np.full(fg.size, ok)
            continue
        conv = np.zeros(fg.size, dtype=bool)
        raw = np.zeros((fg.size, 3))
        for j, i in enumerate(fg):
            full = fn(data["lights"], m[i][:, None])
            short = fn(data["lights"], m[i][:, None], max_ite=999)
            conv[j] = np.array_equal(full, short)
            raw[j] = full.ravel()
        result[f"{name}_converged"] = conv
        result[f"{name}_x"] = raw  # the solver's x before the normalisation of rps.py
    git = ["git", "-C", checkout, "rev-parse", "HEAD"]
    commit = subprocess.run(git, capture_output=True, text=True).stdout.strip()
    result["reference_commit"] = np.array(commit or "unknown")
    np.savez_compressed(out, **result)


if __name__ == "__main__":
    here = Path(__file__).with_name("reference.npz")
    main(sys.argv[1], sys.argv[2] if len(sys.argv) > 2 else str(here))
