"""
A Mitsuba 3 scene
=================

Two spheres in Mitsuba 3, one with roughdiffuse's Lambert plugin and one with its full
Oren–Nayar plugin (σ = 0.6 rad), lit by a directional light close to the viewer and rendered
by Mitsuba's path tracer. The rough sphere keeps its limb bright, as the full moon does.

``rdmi.register()`` makes every formula model of the registry a Mitsuba BSDF named
``roughdiffuse_<id>`` (see the developer page on Mitsuba). The render is small (96 × 64 pixels,
64 samples per pixel) so that the site builds quickly. Mitsuba is an optional dependency
(extra ``mitsuba``): without it this example says so and draws nothing.
"""

import importlib.util
import os

import matplotlib.pyplot as plt
import numpy as np

if importlib.util.find_spec("mitsuba") is None:
    print("Mitsuba 3 is not installed (pip install '.[mitsuba]'): nothing to render.")
else:
    import mitsuba as mi

    from roughdiffuse.integrations import mitsuba as rdmi
    from roughdiffuse.integrations.drjit_llvm import llvm_problem

    # the llvm variants are vectorised, but need a recent libLLVM (DRJIT_LIBLLVM_PATH names
    # it; an old one would abort this process); scalar_rgb runs everywhere
    problem = llvm_problem()
    mi.set_variant("scalar_rgb" if problem else "llvm_ad_rgb")
    if problem:
        print(f"scalar_rgb: {problem}")

    rdmi.register()
    spheres = {
        "left": ({"type": "roughdiffuse_lambert", "albedo": 0.8}, -1.1),
        "right": ({"type": "roughdiffuse_oren_nayar_full", "albedo": 0.8, "sigma": 0.6}, 1.1),
    }
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 3},
        "sensor": {
            "type": "orthographic",
            "to_world": mi.ScalarTransform4f().look_at(origin=[0, 0, 10], target=[0, 0, 0],
                                                       up=[0, 1, 0])
            @ mi.ScalarTransform4f().scale([2.25, 2.25, 1.0]),  # x in ±2.25, y in ±1.5
            "film": {"type": "hdrfilm", "width": 96, "height": 64, "pixel_format": "rgb"},
            "sampler": {"type": "independent", "sample_count": 64},
        },
        "sun": {"type": "directional", "direction": [-0.17, 0.0, -0.98], "irradiance": 3.0},
    }
    for name, (bsdf, x) in spheres.items():
        scene[name] = {"type": "sphere", "center": [x, 0, 0], "radius": 1.0, "bsdf": bsdf}
    image = np.asarray(mi.render(mi.load_dict(scene)))[..., 0]
    print(f"variant {mi.variant()}, image {image.shape}, "
          f"DRJIT_LIBLLVM_PATH={'set' if os.environ.get('DRJIT_LIBLLVM_PATH') else 'unset'}")

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(8, 2.8), width_ratios=[1.5, 1])
    ax.imshow(image, cmap="gray", vmin=0, vmax=float(image.max()))
    ax.set_title("Lambert (left), Oren–Nayar full σ = 0.6 (right)", fontsize="small")
    ax.axis("off")
    row = image[image.shape[0] // 2]
    bx.plot(np.linspace(-2.25, 2.25, row.size), row)
    bx.set_xlabel("x (scene units)")
    bx.set_ylabel("radiance (red channel)")
    bx.set_title("the middle row", fontsize="small")
    fig.tight_layout()
    plt.show()
