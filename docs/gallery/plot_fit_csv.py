"""
Fit a CSV of BRDF samples
=========================

The package ships a small CSV of BRDF samples (``roughdiffuse.data.path("samples.csv")``,
made from Oren–Nayar with ρ = 0.7, σ = 0.35 rad plus 1 % noise). :func:`roughdiffuse.fit.read_csv`
reads it, :func:`roughdiffuse.fit.fit` finds the parameters back.
"""

import math

import matplotlib.pyplot as plt

import roughdiffuse as rd
from roughdiffuse import data
from roughdiffuse.fit import fit, read_csv
from roughdiffuse.plots import plot_plane_of_incidence

samples = read_csv(data.path("samples.csv"))
result = fit(rd.OrenNayar, samples)
print(result)
print("albedo", round(float(result.values[0]), 3), "sigma", round(float(result.values[1]), 3))

fitted = result.model
ax = plot_plane_of_incidence({"fitted Oren–Nayar": fitted,
                              "truth": rd.OrenNayar(albedo=0.7, sigma=0.35)},
                             math.radians(45.0))
plt.show()
