"""
Fit a CSV of BRDF samples
=========================

The package ships a small CSV of BRDF samples (``roughdiffuse.data.path("samples.csv")``):
243 values of the **full** Oren–Nayar model with ρ = 0.7, σ = 0.35 rad, each multiplied by
1 + 0.01 ε with ε standard normal (1 % relative noise; ``scripts/make_sample_data.py``).
:func:`roughdiffuse.fit.read_csv` reads it; :func:`roughdiffuse.fit.fit` fits the model the
data came from, with the noise model that matches how they were made (``noise="relative"``),
and finds ρ and σ back within their standard errors. The plot shows the samples in the
plane of incidence grouped by θi, each group with the fitted model's curve at its θi
(:func:`roughdiffuse.fit.report.plot_plane_fit`).
"""

import matplotlib.pyplot as plt

import roughdiffuse as rd
from roughdiffuse import data
from roughdiffuse.fit import fit, read_csv
from roughdiffuse.fit.report import plot_plane_fit

samples = read_csv(data.path("samples.csv"))
result = fit(rd.OrenNayar, samples, fixed={"variant": "full"}, noise="relative")
print(result.table())

truth = {"albedo": 0.7, "sigma": 0.35}
for name, value in truth.items():
    got, err = result.params[name], result.stderr[name]
    print(f"{name}: fitted {got:.4f} ± {err:.4f}, truth {value}, "
          f"off by {abs(got - value) / err:.1f} standard errors")

ax = plot_plane_fit(samples, result)
ax.figure.set_size_inches(8.0, 4.2)
plt.show()
