"""Moved: image files are read and written by :mod:`roughdiffuse.io.images`.

This module re-exports its names so that code written against the old location keeps
working; new code imports from :mod:`roughdiffuse.io.images` (and the atomic writer from
:mod:`roughdiffuse.io.atomic`).
"""

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
