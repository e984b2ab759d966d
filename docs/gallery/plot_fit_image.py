"""
Fit an image
============

The package ships a 64 × 64 linear image of a sphere with its normal map and light
(``roughdiffuse.data``: ``sphere.npy``, ``sphere_normals.npy``, ``sphere.json``), rendered
from the full Oren–Nayar model with ρ = 0.6, σ = 0.5 rad. Each usable pixel becomes a BRDF
sample; the fit finds the material back, and Lambert's best fit shows what it misses.
"""

import json

import matplotlib.pyplot as plt
import numpy as np

import roughdiffuse as rd
from roughdiffuse import data
from roughdiffuse.fit import fit, image_measurements, read_image, read_normals

meta = json.loads(data.path("sphere.json").read_text())
image, usable = read_image(data.path("sphere.npy"))
normals = read_normals(data.path("sphere_normals.npy"))
samples = image_measurements(image, normals, np.array(meta["light"]["direction"]), mask=usable)

rough = fit(rd.OrenNayar, samples, fixed={"variant": "full"}, n_starts=2)
flat = fit(rd.Lambert, samples, n_starts=1)
print("truth:  ", meta["model"])
a, s = rough.values
print(f"fitted:  albedo {a:.4f}, sigma {s:.4f}, RMS {100 * rough.rms_relative:.3f} %")
print(f"Lambert: albedo {flat.values[0]:.4f}, RMS {100 * flat.rms_relative:.1f} %")

# radiance along the row through the centre: pixels against both fits
row = image.shape[0] // 2
keep = usable[row] & (np.linalg.norm(normals[row], axis=-1) > 0)  # on the sphere
l = np.array(meta["light"]["direction"])
n = normals[row][keep]
v = np.array([0.0, 0.0, 1.0])
x = np.arange(image.shape[1])[keep]
fig, ax = plt.subplots(figsize=(6, 3.4))
ax.plot(x, image[row][keep], "ko", ms=3, label="pixels")
for label, r in (("Oren–Nayar full (fit)", rough), ("Lambert (fit)", flat)):
    ax.plot(x, np.asarray(r.model.radiance(n, l, v)), label=label)
ax.set_xlabel("pixel column (centre row)")
ax.set_ylabel("radiance (E0 = 1)")
ax.legend()
ax.grid(alpha=0.3)
plt.show()
