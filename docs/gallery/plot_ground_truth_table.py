"""
A ground-truth table
====================

``roughdiffuse simulate`` tabulates the exact BRDF of the V-cavity surface (long symmetric
V-grooves with Lambertian facets, Gaussian slopes; Oren and Nayar 1994, Sec. 3) on a grid of
angles; :func:`roughdiffuse.simulate.load_table` reads such a table. Here the table that ships
with this documentation (all bounces, facet albedo 0.9) is set against three models at the
same geometries, in the plane of incidence at θi = 60°.
"""

import math
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import roughdiffuse as rd
from roughdiffuse.simulate import load_table

here = Path.cwd() if "__file__" not in globals() else Path(__file__).resolve().parent
table = load_table(here.parent / "accuracy" / "tables" / "truth_solid-angle_all.npz")
print("axes: θi", np.degrees(table.theta_i), "σ", table.sigma, "albedo", table.albedo)

j = int(np.argmin(abs(table.theta_i - math.radians(60.0))))
theta_i = float(table.theta_i[j])
fig, axes = plt.subplots(1, 2, figsize=(9, 3.4), sharey=True)
for ax, sigma in zip(axes, (0.3, 0.7), strict=True):
    k = int(np.argmin(abs(table.sigma - sigma)))
    back, fwd = 0, len(table.delta_phi) - 1  # Δφ = 0 (light's side) and 180°
    x = np.concatenate([-np.degrees(table.theta_r[::-1]), np.degrees(table.theta_r)])
    truth = np.concatenate([table.values[j, ::-1, fwd, k], table.values[j, :, back, k]])
    ax.plot(x, truth, "ko", label="exact V-cavity")
    tr = np.radians(x)
    wi = np.array([math.sin(theta_i), 0.0, math.cos(theta_i)])
    wo = np.stack([np.sin(tr), np.zeros_like(tr), np.cos(tr)], axis=-1)
    for label, model in {
        "Oren–Nayar full": rd.OrenNayar(table.albedo, float(table.sigma[k]), variant="full"),
        "Oren–Nayar qualitative": rd.OrenNayar(table.albedo, float(table.sigma[k])),
        "Lambert": rd.Lambert(table.albedo),
    }.items():
        ax.plot(x, np.asarray(model.brdf(wi, wo)), label=label)
    ax.set_title(f"σ = {table.sigma[k]:.1f} rad, θi = 60°")
    ax.set_xlabel("θr (degrees, > 0 on the light's side)")
    ax.grid(alpha=0.3)
axes[0].set_ylabel("BRDF (1/sr)")
axes[0].legend(fontsize="small")
fig.tight_layout()
plt.show()
