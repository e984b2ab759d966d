"""Fit reflectance models to measurements: BRDF samples, MERL files, images.

>>> import numpy as np, roughdiffuse as rd
>>> from roughdiffuse.fit import Measurements, fit
>>> t = np.radians(np.arange(0.0, 80.0, 10.0))
>>> ti, tr = np.meshgrid(t, t)
>>> f = rd.oren_nayar(ti, tr, 0.0, sigma=0.3, albedo=0.8)
>>> result = fit(rd.OrenNayar, Measurements.from_angles(ti, tr, 0.0, f))
>>> [round(float(v), 6) for v in result.values]
[0.8, 0.3]
"""

from .._lazy import attach

_NAMES: dict[str, tuple[str, ...]] = {
    "between_models": ("Conversion", "convert"),
    "compare": ("CANDIDATES", "Comparison", "compare_models"),
    "csv_samples": ("csv_from_text", "read_csv", "samples_from_table", "write_csv"),
    "images": ("image_measurements", "read_image", "read_normals", "shape_normals"),
    "least_squares": ("DEFAULT_BOUNDS", "DegenerateDataWarning", "FitResult", "fit"),
    "measurements": ("Measurements",),
    "merl": (
        "MERL_FILE_SIZE",
        "MERL_SCALE",
        "MERL_SHAPE",
        "MERLBRDF",
        "directions_from_half_diff",
        "half_diff_from_directions",
        "merl_cell_index",
        "merl_from_bytes",
        "read_merl",
        "write_merl",
    ),
}
"""Each public name, once, under the submodule defining it: ``import roughdiffuse.fit``
imports none of them (the fitting code imports JAX and SciPy), ``roughdiffuse.fit.fit``
imports its module (the ``lazy_loader`` pattern)."""

__getattr__, __dir__ = attach(
    __name__, names={name: module for module, names in _NAMES.items() for name in names}
)

__all__ = sorted(name for names in _NAMES.values() for name in names)
