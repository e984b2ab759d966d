"""Triangle meshes as binary PLY files (the format Mitsuba 3 and mesh tools read).

One writer for the meshes roughdiffuse makes: the random heightfields of
:mod:`roughdiffuse.simulate.heightfield` and the depth maps of :mod:`roughdiffuse.stereo`.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .._validate import ParameterError
from .atomic import write_bytes

__all__ = ["write_ply"]


def write_ply(path: str | os.PathLike, verts: np.ndarray, faces: np.ndarray) -> Path:
    """Write a binary little-endian PLY: float32 vertex positions (N, 3) and int32
    triangles (M, 3), counter-clockwise seen from the side the normals face; whole or not at
    all (:func:`roughdiffuse.io.write_bytes`).

    >>> import tempfile, pathlib, numpy as np
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = write_ply(pathlib.Path(d) / "t.ply", np.eye(3), np.array([[0, 1, 2]]))
    ...     p.read_bytes().count(b"element")
    2
    """
    verts = np.asarray(verts)
    faces = np.asarray(faces)
    if verts.ndim != 2 or verts.shape[1] != 3 or faces.ndim != 2 or faces.shape[1] != 3:
        raise ParameterError(
            f"verts and faces must have shapes (N, 3) and (M, 3) (got {verts.shape}, {faces.shape})"
        )
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(verts)}\n"
        "property float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    ).encode()
    face_rec = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", (3,))])
    face_rec["n"] = 3
    face_rec["v"] = faces
    return write_bytes(
        path, header + np.ascontiguousarray(verts, dtype="<f4").tobytes() + face_rec.tobytes()
    )
