"""Moved: image files are read and written by :mod:`roughdiffuse.io.images`.

Deprecated: importing this module warns (``DeprecationWarning``). It re-exports its names so
that code written against the old location keeps working; new code imports from
:mod:`roughdiffuse.io.images` (and the atomic writer from :mod:`roughdiffuse.io.atomic`).
"""

import warnings

from ..io.atomic import atomic_write
from ..io.images import (
    SUFFIXES,
    exposure_scale,
    linear_to_srgb,
    read_png,
    srgb_to_linear,
    write_exr,
    write_image,
    write_npy,
    write_png,
)

warnings.warn(
    "roughdiffuse.render.imagefile is deprecated: import from roughdiffuse.io.images "
    "(and atomic_write from roughdiffuse.io.atomic)",
    DeprecationWarning,
    stacklevel=2,
)

__all__ = [
    "SUFFIXES",
    "atomic_write",
    "exposure_scale",
    "linear_to_srgb",
    "read_png",
    "srgb_to_linear",
    "write_exr",
    "write_image",
    "write_npy",
    "write_png",
]
