"""
Render a sphere
===============

A sphere of each of three diffuse models, lit from 60° to the side: Lambert's disc darkens
towards the terminator, the rough models (Oren–Nayar, EON) look flatter because their facets
tilted towards the light and the viewer brighten the limb.
"""

import math

import matplotlib.pyplot as plt

from roughdiffuse import EON, Lambert, OrenNayar
from roughdiffuse.plots import show_radiance
from roughdiffuse.render import DistantLight, Sphere, render

models = {
    "Lambert": Lambert(albedo=0.8),
    "Oren–Nayar, σ = 0.5": OrenNayar(albedo=0.8, sigma=0.5, variant="full"),
    "EON, r = 0.8": EON(albedo=0.8, roughness=0.8),
}
light = DistantLight(theta=math.radians(60.0))
fig, axes = plt.subplots(1, 3, figsize=(9, 3.2))
for ax, (label, model) in zip(axes, models.items(), strict=True):
    image, mask = render(model, Sphere(), light, size=128)
    show_radiance(ax, image, vmax=0.35, title=label)
    print(f"{label:22s} mean radiance on the disc {image[mask == 1].mean():.4f}")
fig.tight_layout()
plt.show()
