"""Reading and writing files: the atomic writer (:mod:`roughdiffuse.io.atomic`), images
(:mod:`roughdiffuse.io.images`) and meshes (:mod:`roughdiffuse.io.mesh`).

Every file roughdiffuse writes goes through :func:`atomic_write`: whole or not at all, with
the mode the umask gives, and no temporary file left behind by an exception or a signal.
Several files go together with :func:`deferred` (into a shared folder) or
:func:`atomic_folder` (a results folder of their own). Every file read from a user goes
through :mod:`roughdiffuse.io.reading` (a regular file, a stated size limit, bounded JSON
depth and CSV field size).

>>> from roughdiffuse.io import write_text
>>> import tempfile, pathlib
>>> with tempfile.TemporaryDirectory() as d:
...     p = write_text(pathlib.Path(d) / "note.txt", "hello")
...     p.read_text()
'hello'
"""

from .atomic import (
    WriteError,
    allow_replacing,
    atomic_open,
    atomic_write,
    check_output_path,
    deferred,
    keep_existing,
    remove_stale_temporaries,
    write_bytes,
    write_text,
)
from .folder import atomic_folder, check_output_folder

__all__ = [
    "WriteError",
    "allow_replacing",
    "atomic_folder",
    "check_output_folder",
    "deferred",
    "keep_existing",
    "atomic_open",
    "atomic_write",
    "check_output_path",
    "remove_stale_temporaries",
    "write_bytes",
    "write_text",
]
