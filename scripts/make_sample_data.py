"""Remake the sample files of ``src/roughdiffuse/data`` from their known models.

    python scripts/make_sample_data.py

The truths are stated in ``roughdiffuse.data``'s docstring and in ``sphere.json``.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from roughdiffuse import OrenNayar
from roughdiffuse.fit import shape_normals
from roughdiffuse.render import DistantLight, Sphere, render

OUT = Path(__file__).resolve().parent.parent / "src" / "roughdiffuse" / "data"


def samples_csv() -> None:
    model = OrenNayar(albedo=0.7, sigma=0.35, variant="full")
    rng = np.random.default_rng(0)
    rows = ["# Oren-Nayar (full), albedo 0.7, sigma 0.35 rad, 1 % Gaussian noise (seed 0)",
            "# made by scripts/make_sample_data.py",
            "theta_i_deg,theta_r_deg,delta_phi_deg,brdf"]
    for dphi in (0.0, 90.0, 180.0):
        for ti in range(0, 90, 10):
            for tr in range(0, 90, 10):
                a, b, p = math.radians(ti), math.radians(tr), math.radians(dphi)
                wi = np.array([math.sin(a), 0.0, math.cos(a)])
                wo = np.array([math.sin(b) * math.cos(p), math.sin(b) * math.sin(p), math.cos(b)])
                f = float(model.brdf(wi, wo)) * (1.0 + 0.01 * rng.standard_normal())
                rows.append(f"{ti},{tr},{dphi:g},{f:.6f}")
    (OUT / "samples.csv").write_text("\n".join(rows) + "\n", encoding="utf-8")


def sphere() -> None:
    model = OrenNayar(albedo=0.6, sigma=0.5, variant="full")
    light = DistantLight(theta=math.radians(30.0), phi=0.0)
    image, _ = render(model, Sphere(), light, size=64, samples_per_pixel=1)
    normals, _ = shape_normals(Sphere(), 64)
    np.save(OUT / "sphere.npy", np.asarray(image, dtype=np.float32))
    np.save(OUT / "sphere_normals.npy", np.asarray(normals, dtype=np.float32))
    meta = {
        "model": repr(model),
        "light": {"theta_deg": 30.0, "phi_deg": 0.0, "irradiance": 1.0,
                  "direction": [float(x) for x in light.direction]},
        "view": [0.0, 0.0, 1.0],
        "size": 64,
        "samples_per_pixel": 1,
        "made_by": "scripts/make_sample_data.py",
    }
    (OUT / "sphere.json").write_text(json.dumps(meta, indent=1) + "\n", encoding="utf-8")


def lights() -> None:
    from roughdiffuse.stereo import default_lights

    spec = {
        "directions": [[round(float(x), 12) for x in d] for d in default_lights(8)],
        "intensities": [1.0] * 8,
        "note": "8 lights on a 35-degree ring around the view axis (+z); "
        "made by scripts/make_sample_data.py",
    }
    (OUT / "lights.json").write_text(json.dumps(spec, indent=1) + "\n", encoding="utf-8")


if __name__ == "__main__":
    samples_csv()
    sphere()
    lights()
