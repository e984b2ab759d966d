"""
The fast path on a million directions
=====================================

``model.brdf`` on NumPy arrays of 1024 rows or more runs a compiled kernel (Numba) made from
the model's own formula — the values are those of the array-API code, to float rounding.
Here the full Oren–Nayar BRDF is evaluated for one light and a million random viewing
directions, once on the compiled path and once on the reference path
(``rd.use_fastpath(False)``); the two agree to float32 rounding
(:func:`roughdiffuse.engine.fastpath.brdf` is the explicit form, with control of the output buffer,
chunks and threads). The timings printed are those
of this build, on whatever machine built it (the benchmark suite, ``bench/RESULTS.md``,
measures against a C reference).
"""

import time

import matplotlib.pyplot as plt
import numpy as np

import roughdiffuse as rd
from roughdiffuse import fastpath

model = rd.OrenNayar(albedo=0.8, sigma=0.4, variant="full")
rng = np.random.default_rng(0)
wo = rng.normal(size=(2**20, 3)).astype(np.float32)
wo[:, 2] = np.abs(wo[:, 2])  # the upper hemisphere
wo /= np.linalg.norm(wo, axis=1, keepdims=True)
wi = np.broadcast_to(rd.spherical_to_vector(np.radians(50.0), 0.0), wo.shape).astype(np.float32)

fastpath.brdf(model, wi[:2048], wo[:2048])  # compile the kernel (or load it from the cache)
t = time.perf_counter()
fast = fastpath.brdf(model, wi, wo)  # what model.brdf runs on large NumPy arrays
t_fast = time.perf_counter() - t
with rd.use_fastpath(False):
    t = time.perf_counter()
    reference = model.brdf(wi, wo)
    t_ref = time.perf_counter() - t
rel = np.max(np.abs(fast - reference) / np.maximum(np.abs(reference), 1e-30))
print(f"{wo.shape[0]:,} directions, {fast.dtype}: compiled {t_fast * 1e3:.0f} ms, "
      f"reference {t_ref * 1e3:.0f} ms; largest relative difference {rel:.1e}")

theta_r = np.degrees(np.arccos(wo[:, 2]))
fig, ax = plt.subplots(figsize=(6, 3.2))
ax.hexbin(theta_r, fast, gridsize=60, bins="log", cmap="Greys")
ax.axhline(0.8 / np.pi, color="tab:orange", lw=1, label="Lambert, ρ/π")
ax.set_xlabel("viewing angle θr (degrees)")
ax.set_ylabel("f (1/sr)")
ax.set_title("Oren–Nayar full, σ = 0.4, light at 50°: a million directions", fontsize="small")
ax.legend(fontsize="small")
fig.tight_layout()
plt.show()
