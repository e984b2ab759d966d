"""Ground truth: the exact reflectance of the V-cavity microsurface (Oren & Nayar 1994).

* :func:`cavity_radiance` — one cavity: shadowing and masking in closed form, N bounces or all
  bounces by radiosity with crossed-strings view factors (:mod:`.cavity`);
* :func:`brdf` — the surface: the cavity radiance averaged over the slope distribution, with
  either reading of its measure (:mod:`.surface`);
* :class:`GroundTruth`, :func:`compute_table` — tables on a grid, chunked, resumable, on Dask
  (:mod:`.table`).

A second ground truth, the Smith microsurface with Lambertian facets (Beckmann or GGX slopes,
one bounce by quadrature, any number by the random walk of Heitz et al. 2016), is
:mod:`roughdiffuse.simulate.smith` (``smith.brdf``, ``smith.random_walk``).
"""

from .cavity import cavity_radiance
from .surface import MEASURES, Settings, brdf, quadrature_convergence
from .table import GroundTruth, compute_table, load_table

__all__ = [
    "MEASURES",
    "GroundTruth",
    "Settings",
    "brdf",
    "cavity_radiance",
    "compute_table",
    "load_table",
    "quadrature_convergence",
]
