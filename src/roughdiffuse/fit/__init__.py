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

from .compare import CANDIDATES, Comparison, compare_models
from .csv_samples import read_csv, samples_from_table, write_csv
from .images import image_measurements, read_image, read_normals, shape_normals
from .least_squares import DEFAULT_BOUNDS, DegenerateDataWarning, FitResult, fit
from .measurements import Measurements
from .merl import (
    MERL_SCALE,
    MERL_SHAPE,
    MERLBRDF,
    directions_from_half_diff,
    half_diff_from_directions,
    merl_cell_index,
    read_merl,
    write_merl,
)

__all__ = [
    "CANDIDATES",
    "DEFAULT_BOUNDS",
    "MERLBRDF",
    "MERL_SCALE",
    "MERL_SHAPE",
    "Comparison",
    "DegenerateDataWarning",
    "FitResult",
    "Measurements",
    "compare_models",
    "directions_from_half_diff",
    "fit",
    "half_diff_from_directions",
    "image_measurements",
    "merl_cell_index",
    "read_csv",
    "read_image",
    "read_merl",
    "read_normals",
    "samples_from_table",
    "shape_normals",
    "write_csv",
    "write_merl",
]
