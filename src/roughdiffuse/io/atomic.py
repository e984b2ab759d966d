"""The one atomic file writer: a file is written whole or not at all.

How: the content goes to a temporary file beside the target (same folder, so same file
system), is flushed to disk (``fsync``), and is renamed over the target with
:func:`os.replace`, which POSIX makes atomic: a reader sees the old file or the new one,
never half of one.

The rules every file written by roughdiffuse follows:

- **Mode.** The temporary file is created with mode 0666 minus the process umask, as
  ``open(path, "w")`` would create the target, so tables, images and reports get the same
  mode (the umask's, usually 0644).
- **Nothing left behind.** An exception (``KeyboardInterrupt`` from Ctrl-C included) removes
  the temporary file. So does SIGTERM or SIGHUP arriving while a write is in progress in the
  main thread: the handler removes it, then lets the signal act as before (the default
  handler still ends the process). A process killed outright (SIGKILL) cannot clean up; its
  temporary files are named ``.NAME.rdtmp-PID-XXXXXXXX.SUFFIX`` and the next write of the
  same file removes those whose process is gone (:func:`remove_stale_temporaries`).
- **Bad paths are found first.** A folder given as the output file, a missing or
  non-folder parent, or a parent that cannot be written is a ``ValueError`` naming the path
  (:func:`check_output_path`), raised before any work is done when a command calls it
  up front.

>>> import pathlib, tempfile
>>> with tempfile.TemporaryDirectory() as d:
...     target = pathlib.Path(d) / "a.txt"
...     _ = write_text(target, "first")
...     try:
...         with atomic_open(target, "w") as fh:
...             _ = fh.write("half")
...             raise RuntimeError("interrupted")
...     except RuntimeError:
...         pass
...     target.read_text(), sorted(p.name for p in pathlib.Path(d).iterdir())
('first', ['a.txt'])
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import signal
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

from .._validate import ParameterError

__all__ = [
    "atomic_open",
    "atomic_write",
    "check_output_path",
    "remove_stale_temporaries",
    "write_bytes",
    "write_text",
]

PathLike = str | os.PathLike[str]

_TAG = ".rdtmp-"
_SIGNALS = tuple(getattr(signal, name) for name in ("SIGTERM", "SIGHUP") if hasattr(signal, name))

_lock = threading.RLock()
_active: set[Path] = set()  # temporary files being written now
_previous: dict[int, Any] = {}  # signal handlers replaced while writes are in progress
_depth = 0  # writes in progress in the main thread


def check_output_path(path: PathLike, what: str = "output file") -> Path:
    """Check that ``path`` can be written as a file; return it as a :class:`~pathlib.Path`.

    Raises
    ------
    ValueError
        If ``path`` is an existing folder, if its parent folder does not exist or is not a
        folder, or if that folder cannot be written. The message names the path and
        ``what`` (e.g. ``"--table"``).
    """
    p = Path(path)
    if not str(path) or p.name in ("", ".", ".."):
        raise ParameterError(f"{what} {str(path)!r} is not a file name")
    if p.is_dir():
        raise ParameterError(f"{what} {str(p)!r} is a folder; give the name of a file")
    folder = p.parent
    if not folder.exists():
        raise ParameterError(f"{what} {str(p)!r}: folder {str(folder)!r} does not exist")
    if not folder.is_dir():
        raise ParameterError(f"{what} {str(p)!r}: {str(folder)!r} is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ParameterError(f"{what} {str(p)!r}: folder {str(folder)!r} is not writable")
    return p


def _temporary_name(path: Path) -> Path:
    # The target's suffix is kept: writers such as matplotlib's savefig choose the format by it.
    return path.with_name(f".{path.stem}{_TAG}{os.getpid()}-{secrets.token_hex(4)}{path.suffix}")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # another user's process
        return True
    return True


def remove_stale_temporaries(path: PathLike) -> list[Path]:
    """Remove the temporary files left beside ``path`` by writers that were killed.

    Only files named like this module's temporaries for this very target, whose process
    no longer exists, are removed. Returns the removed paths.
    """
    path = Path(path)
    pattern = re.compile(
        re.escape(f".{path.stem}{_TAG}") + r"(\d+)-[0-9a-f]{8}" + re.escape(path.suffix) + "$"
    )
    removed = []
    try:
        entries = list(path.parent.iterdir()) if str(path.parent) else list(Path(".").iterdir())
    except OSError:
        return removed
    for entry in entries:
        m = pattern.match(entry.name)
        if m and int(m.group(1)) != os.getpid() and not _pid_alive(int(m.group(1))):
            with contextlib.suppress(OSError):
                entry.unlink()
                removed.append(entry)
    return removed


def _on_signal(signum: int, frame: Any) -> None:
    previous = _previous.get(signum, signal.SIG_DFL)
    if callable(previous):  # e.g. an application's handler: it decides; except-paths clean up
        previous(signum, frame)
        return
    if previous == signal.SIG_IGN:
        return
    for tmp in list(_active):
        with contextlib.suppress(OSError):
            tmp.unlink()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)  # the default action, as if no handler had been installed


@contextlib.contextmanager
def _guard(tmp: Path) -> Iterator[None]:
    """Track ``tmp`` (and, in the main thread, remove it on SIGTERM/SIGHUP) while writing."""
    global _depth
    main = threading.current_thread() is threading.main_thread()
    with _lock:
        _active.add(tmp)
        if main:
            if _depth == 0:
                for sig in _SIGNALS:
                    with contextlib.suppress(ValueError, OSError):
                        _previous[sig] = signal.signal(sig, _on_signal)
            _depth += 1
    try:
        yield
    finally:
        with _lock:
            _active.discard(tmp)
            if main:
                _depth -= 1
                if _depth == 0:
                    for sig, handler in _previous.items():
                        with contextlib.suppress(ValueError, OSError, TypeError):
                            signal.signal(sig, handler)
                    _previous.clear()


def _fsync(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def atomic_write(path: PathLike, write: Callable[[Path], Any]) -> Path:
    """Call ``write(tmp)`` on a temporary file beside ``path``, then rename it to ``path``.

    ``write`` receives the path of an empty file that already exists (with the mode the
    umask gives) and must write the content there, e.g. ``lambda tmp: fig.savefig(tmp)``.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If ``path`` cannot be written as a file (:func:`check_output_path`).
    """
    path = check_output_path(path)
    remove_stale_temporaries(path)
    tmp = _temporary_name(path)
    with _guard(tmp):
        try:
            os.close(os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666))
            write(tmp)
            if not tmp.is_file():
                raise RuntimeError(f"the writer of {path} did not write its temporary file {tmp}")
            _fsync(tmp)
            os.replace(tmp, path)
        except BaseException:
            with contextlib.suppress(OSError):
                tmp.unlink()
            raise
    return path


@contextlib.contextmanager
def atomic_open(path: PathLike, mode: str = "wb", **kwargs: Any) -> Iterator[IO[Any]]:
    """Open a file for writing that appears at ``path`` only when the block ends normally.

    ``mode`` is ``"w"`` or ``"wb"`` (plus ``kwargs`` for :func:`open`, e.g. ``encoding``).
    """
    if mode not in ("w", "wb"):
        raise ParameterError(f"mode must be 'w' or 'wb' (got {mode!r})")
    if mode == "w":
        kwargs.setdefault("encoding", "utf-8")
    path = check_output_path(path)
    remove_stale_temporaries(path)
    tmp = _temporary_name(path)
    with _guard(tmp):
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
            with open(fd, mode, **kwargs) as fh:
                yield fh
                fh.flush()
                os.fsync(fh.fileno())
            os.replace(tmp, path)
        except BaseException:
            with contextlib.suppress(OSError):
                tmp.unlink()
            raise


def write_bytes(path: PathLike, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return the path."""
    with atomic_open(path, "wb") as fh:
        fh.write(data)
    return Path(path)


def write_text(path: PathLike, text: str, encoding: str = "utf-8") -> Path:
    """Write ``text`` to ``path`` atomically; return the path."""
    with atomic_open(path, "w", encoding=encoding) as fh:
        fh.write(text)
    return Path(path)
