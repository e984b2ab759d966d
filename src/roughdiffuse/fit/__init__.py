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

from typing import TYPE_CHECKING

from .._lazy import attach

if TYPE_CHECKING:  # for type checkers; at run time each name is imported on first use
    from .compare import CANDIDATES, Comparison, compare_models
    from .csv_samples import csv_from_text, read_csv, samples_from_table, write_csv
    from .images import image_measurements, read_image, read_normals, shape_normals
    from .least_squares import DEFAULT_BOUNDS, DegenerateDataWarning, FitResult, fit
    from .measurements import Measurements
    from .merl import (
        MERL_FILE_SIZE,
        MERL_SCALE,
        MERL_SHAPE,
        MERLBRDF,
        directions_from_half_diff,
        half_diff_from_directions,
        merl_cell_index,
        merl_from_bytes,
        read_merl,
        write_merl,
    )

_SUBMODULE = {
    "CANDIDATES": "compare",
    "Comparison": "compare",
    "compare_models": "compare",
    "csv_from_text": "csv_samples",
    "read_csv": "csv_samples",
    "samples_from_table": "csv_samples",
    "write_csv": "csv_samples",
    "image_measurements": "images",
    "read_image": "images",
    "read_normals": "images",
    "shape_normals": "images",
    "DEFAULT_BOUNDS": "least_squares",
    "DegenerateDataWarning": "least_squares",
    "FitResult": "least_squares",
    "fit": "least_squares",
    "Measurements": "measurements",
    "MERL_FILE_SIZE": "merl",
    "MERL_SCALE": "merl",
    "MERL_SHAPE": "merl",
    "MERLBRDF": "merl",
    "directions_from_half_diff": "merl",
    "half_diff_from_directions": "merl",
    "merl_cell_index": "merl",
    "merl_from_bytes": "merl",
    "read_merl": "merl",
    "write_merl": "merl",
}
"""Where each public name lives: ``import roughdiffuse.fit`` imports none of them (the
fitting code imports JAX and SciPy), ``roughdiffuse.fit.fit`` imports its module."""

__getattr__, __dir__ = attach(__name__, names=_SUBMODULE)

__all__ = [
    "CANDIDATES",
    "DEFAULT_BOUNDS",
    "MERLBRDF",
    "MERL_FILE_SIZE",
    "MERL_SCALE",
    "MERL_SHAPE",
    "Comparison",
    "DegenerateDataWarning",
    "FitResult",
    "Measurements",
    "compare_models",
    "csv_from_text",
    "directions_from_half_diff",
    "fit",
    "half_diff_from_directions",
    "image_measurements",
    "merl_cell_index",
    "merl_from_bytes",
    "read_csv",
    "read_image",
    "read_merl",
    "read_normals",
    "samples_from_table",
    "shape_normals",
    "write_csv",
    "write_merl",
]
