"""Shape and reflectance of rough objects from images: photometric stereo.

K ≥ 3 images of a still object, seen by an orthographic camera under known distant lights,
give per-pixel normals, albedo and roughness. Lambertian photometric stereo (Woodham 1980)
is the baseline and the starting point; :func:`rough` then fits a rough-diffuse model of the
registry (e.g. the full Oren–Nayar model) to every pixel, with the roughness global or per
pixel;
:func:`coated` fits a dielectric coat over such a base (glossy objects: highlights in the
model, shadows found from it), and :func:`integrate` turns the normals into a depth map.
:func:`robust` holds the robust Lambertian solvers (L1, sparse Bayesian, RPCA),
:data:`METHODS` every method by name, and :func:`run_benchmark` the DiLiGenT protocol.

>>> import numpy as np
>>> import roughdiffuse as rd
>>> from roughdiffuse import stereo
>>> data = stereo.synthetic_sphere(rd.OrenNayar(0.7, 0.4, "full"), size=24, noise=0.0)
>>> lam = stereo.lambertian(data)
>>> res = stereo.rough(data, rd.OrenNayar(variant="full"))
>>> round(float(res.roughness), 3)
0.4
"""

from .benchmark import run_benchmark, write_benchmark
from .coated import CoatedResult, coated
from .depth import gradients, integrate, write_ply
from .inputs import StereoInput, load_images, read_diligent, read_lights, read_mask
from .lambertian import LambertianResult, lambertian, observation_weights
from .methods import METHODS
from .outputs import result_maps, write_outputs
from .robust import robust
from .rough import RoughResult, rough, roughness_parameter
from .synthetic import angular_error, default_lights, render_stereo, synthetic_sphere

__all__ = [
    "METHODS",
    "CoatedResult",
    "LambertianResult",
    "RoughResult",
    "StereoInput",
    "angular_error",
    "coated",
    "default_lights",
    "gradients",
    "integrate",
    "lambertian",
    "load_images",
    "observation_weights",
    "read_diligent",
    "read_lights",
    "read_mask",
    "render_stereo",
    "result_maps",
    "robust",
    "rough",
    "roughness_parameter",
    "run_benchmark",
    "synthetic_sphere",
    "write_benchmark",
    "write_outputs",
    "write_ply",
]
