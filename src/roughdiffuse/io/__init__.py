"""Reading and writing files: the atomic writer (:mod:`roughdiffuse.io.atomic`), images
(:mod:`roughdiffuse.io.images`) and meshes (:mod:`roughdiffuse.io.mesh`).

Every file roughdiffuse writes goes through :func:`atomic_write`: whole or not at all, with
the mode the umask gives, and no temporary file left behind by an exception or a signal.

>>> from roughdiffuse.io import write_text
>>> import tempfile, pathlib
>>> with tempfile.TemporaryDirectory() as d:
...     p = write_text(pathlib.Path(d) / "note.txt", "hello")
...     p.read_text()
'hello'
"""

from .atomic import (
    atomic_open,
    atomic_write,
    check_output_path,
    remove_stale_temporaries,
    write_bytes,
    write_text,
)

__all__ = [
    "atomic_open",
    "atomic_write",
    "check_output_path",
    "remove_stale_temporaries",
    "write_bytes",
    "write_text",
]
