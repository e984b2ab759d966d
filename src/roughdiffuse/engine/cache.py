"""The private cache folder of compiled code (a leaf module: the standard library and NumPy).

The fast path's generated kernels and Numba's cache files (:mod:`.fastpath`), and the
compiled Smith random walk (:mod:`roughdiffuse.simulate.smith_walk_numba`), live in
``$ROUGHDIFFUSE_CACHE_DIR`` or else ``$XDG_CACHE_HOME/roughdiffuse/fastpath`` (default
``~/.cache/roughdiffuse/fastpath``, created with mode 0700). The folder is used only if it
is private, and so are the folders above it (none writable by another user, unless sticky
like ``/tmp``).

Numba's disk cache is not safe when two processes compile different signatures of one
function at the same time: each numbers its new entry from the index it read, both write
``<name>.1.nbc``, and the index left may point at the other signature's machine code, which
the next process to load it runs on the wrong argument types (Numba issue 4807,
``numba/core/caching.py``, ``IndexDataCacheFile.save``). :func:`compile_lock` serialises
compilations across processes with a lock file in the cache folder; :class:`Compiled` calls
a kernel, compiling a new signature under that lock first.
"""

from __future__ import annotations

import contextlib
import os
import stat
import threading
import weakref
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

try:
    import fcntl
except ImportError:  # pragma: no cover - not POSIX: no lock between processes
    fcntl = None  # type: ignore[assignment]

__all__ = ["Compiled", "cache_dir", "compile_lock", "private_cache_dir"]

_THREAD_LOCK = threading.RLock()


def cache_dir() -> Path:
    """Directory of the generated kernels and Numba's cache (created when first needed)."""
    env = os.environ.get("ROUGHDIFFUSE_CACHE_DIR")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "roughdiffuse" / "fastpath"


def private_cache_dir() -> Path | None:
    """:func:`cache_dir`, created with mode 0700 if missing, if it is safe to use: a real
    directory (not a symbolic link) owned by this user that no one else may write to.
    Otherwise ``None``: kernels are then compiled in memory, without a disk cache (Numba
    unpickles its cache index files, so a folder others can write to could run their code).
    """
    path = cache_dir()
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        try:
            path.mkdir(mode=0o700)
        except FileExistsError:
            pass
        st = os.lstat(path)
    except OSError:
        return None
    if not stat.S_ISDIR(st.st_mode) or st.st_mode & 0o022:
        return None
    if hasattr(os, "getuid") and st.st_uid != os.getuid():
        return None
    if not os.access(path, os.W_OK | os.X_OK):
        return None
    if not _safe_parents(path):
        return None
    return path


def _safe_parents(path: Path) -> bool:
    """Whether no other user can replace ``path`` by renaming one of its parent folders, as
    ``ssh`` checks the folders above its key files: every parent is owned by this user or
    root and is not writable by group or others -- unless its sticky bit is set (as on
    ``/tmp``), which keeps others from renaming or removing what they do not own."""
    if not hasattr(os, "getuid"):  # pragma: no cover - not POSIX
        return True
    uid = os.getuid()
    for parent in Path(os.path.realpath(path)).parents:
        try:
            st = os.stat(parent)
        except OSError:
            return False
        if st.st_uid not in (0, uid):
            return False
        if st.st_mode & 0o022 and not st.st_mode & stat.S_ISVTX:
            return False
    return True


@contextlib.contextmanager
def compile_lock() -> Iterator[None]:
    """Hold the lock of Numba compilations: one thread of this process and no other process
    using the same cache folder compiles (and writes Numba's cache) meanwhile."""
    with _THREAD_LOCK:
        directory = private_cache_dir()
        if directory is None or fcntl is None:  # no shared cache, nothing to race for
            yield
            return
        with open(directory / "compile.lock", "a+b") as handle:
            fcntl.flock(handle.fileno(), fcntl.LOCK_EX)
            try:
                yield
            finally:
                fcntl.flock(handle.fileno(), fcntl.LOCK_UN)


class Compiled:
    """A Numba dispatcher called from Python whose new signatures are compiled (or loaded
    from the cache) under :func:`compile_lock`, then run without it.

    The argument types are the dispatcher's own (``typeof_pyval``, about 15 µs an array), so
    a call finds the signature compiled here exactly; they are worked out only for a layout
    of the arguments (type; dtype, dimensions, contiguity and writeability of an array) not
    seen before with this kernel, a few attribute reads a call otherwise.
    """

    def __init__(self, kernel: Any) -> None:
        self.kernel = kernel

    def __call__(self, *args: Any) -> Any:
        kernel = self.kernel
        layout = tuple(_layout(a) for a in args)
        try:
            seen = _SEEN[kernel]
        except KeyError:
            seen = _SEEN.setdefault(kernel, set())
        if layout not in seen:
            signature = tuple(kernel.typeof_pyval(a) for a in args)
            if signature not in kernel.overloads:
                with compile_lock():
                    kernel.compile(signature)
            seen.add(layout)
        return kernel(*args)


_SEEN: weakref.WeakKeyDictionary[Any, set[tuple[Any, ...]]] = weakref.WeakKeyDictionary()
"""Per kernel, the argument layouts whose signature :class:`Compiled` has compiled."""


def _layout(a: Any) -> Any:
    """What of an argument decides its Numba type: for an array its dtype, dimensions,
    contiguity and writeability (and alignment); otherwise its type (a tuple: its items')."""
    if isinstance(a, np.ndarray):
        f = a.flags
        return (a.dtype.str, a.ndim, f.c_contiguous, f.f_contiguous, f.writeable, f.aligned)
    if isinstance(a, tuple):
        return tuple(_layout(x) for x in a)
    return type(a)
