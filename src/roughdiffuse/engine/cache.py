"""The private cache folder of compiled code (a leaf module: the standard library only).

The fast path's generated kernels and Numba's cache files (:mod:`.fastpath`), and the
compiled Smith random walk (:mod:`roughdiffuse.simulate.smith_walk_numba`), live in
``$ROUGHDIFFUSE_CACHE_DIR`` or else ``$XDG_CACHE_HOME/roughdiffuse/fastpath`` (default
``~/.cache/roughdiffuse/fastpath``, created with mode 0700). The folder is used only if it
is private, and so are the folders above it (none writable by another user, unless sticky
like ``/tmp``).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

__all__ = ["cache_dir", "private_cache_dir"]


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
