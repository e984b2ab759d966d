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
- **Only regular files.** An existing target that is not a regular file (``/dev/null``, a
  FIFO, a socket) is refused, never renamed over (:func:`check_output_path`).
- **Bad paths are found first.** A folder given as the output file, a missing or
  non-folder parent, or a parent that cannot be written is a ``ValueError`` naming the path
  (:func:`check_output_path`), raised before any work is done when a command calls it
  up front.
- **Failures are named.** Any OS error while writing (a full disk, a name too long, no
  permission), and a library's own exception when the disk is full, is a :class:`WriteError`
  (an ``OSError``) naming the target, never an internal error.
- **Temporary names fit.** The temporary name is shortened so that it is never longer than
  the file system allows for a name (``NAME_MAX``, 255 bytes) when the target's name is legal;
  so are the names of a target's companions (a lock, a folder of chunks: :func:`beside`).
- **Existing files are kept when asked.** :func:`keep_existing` marks a target that must not
  replace an existing file (a command without ``--force``): it is then created exclusively
  (``link``), so of two concurrent writers only one writes it; the other gets a
  :class:`WriteError` "exists".
- **Several files together.** Inside :func:`deferred`, every file written by these writers
  is staged and all appear at the end of the block, or none (an exception removes them all).
  :func:`roughdiffuse.io.folder.atomic_folder` does the same for a whole folder.

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
import contextvars
import errno
import os
import re
import secrets
import shutil
import signal
import threading
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO, Any

from .._validate import ParameterError

__all__ = [
    "WriteError",
    "allow_replacing",
    "atomic_open",
    "atomic_write",
    "beside",
    "check_output_path",
    "deferred",
    "keep_existing",
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
_keep: set[str] = set()  # targets that must not replace an existing file (keep_existing)
_Stage = tuple[str, list[tuple[Path, Path, bool]]]  # folder, staged (tmp, target, exclusive)
_staged: contextvars.ContextVar[_Stage | None] = contextvars.ContextVar(
    "roughdiffuse_staged", default=None
)


class WriteError(OSError):
    """A file could not be written: the target, and why (``errno``, ``strerror``).

    ``str()`` is one line: ``cannot write 'PATH': REASON``.
    """

    def __str__(self) -> str:
        return f"cannot write {os.fsdecode(self.filename)!r}: {self.strerror}"


def _write_error(exc: BaseException, path: Path) -> WriteError | None:
    """The :class:`WriteError` an exception raised while writing ``path`` stands for, or None
    (a bug, left as it is). An ``OSError`` anywhere in the exception's chain counts; so does
    any exception when the folder has no free space left."""
    seen: BaseException | None = exc
    while seen is not None:
        if isinstance(seen, WriteError):
            return seen
        if isinstance(seen, OSError) and seen.errno is not None:
            return WriteError(seen.errno, seen.strerror or os.strerror(seen.errno), str(path))
        seen = seen.__cause__ or seen.__context__
    try:
        full = os.statvfs(path.parent if str(path.parent) else ".").f_bavail == 0
    except (OSError, AttributeError):
        full = False
    if full:
        return WriteError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(path))
    return None


def keep_existing(path: PathLike) -> None:
    """Make every later write of ``path`` in this process refuse to replace an existing file
    (the rule of a command run without ``--force``): the file is created exclusively."""
    _keep.add(os.path.abspath(path))


def allow_replacing(path: PathLike | None = None) -> None:
    """Undo :func:`keep_existing` for ``path`` (a command run with ``--force``), or for every
    path (``None``: the command line does this when a command ends)."""
    if path is None:
        _keep.clear()
    else:
        _keep.discard(os.path.abspath(path))


def check_output_path(path: PathLike, what: str = "output file") -> Path:
    """Check that ``path`` can be written as a file; return it as a :class:`~pathlib.Path`.

    Raises
    ------
    ValueError
        If ``path`` is empty, an existing folder or another file that is not a regular one
        (a device such as ``/dev/null``, a FIFO, a socket: never replaced), if its parent
        folder does not exist or is not a folder, or if that folder cannot be written. The
        message names the path and ``what`` (e.g. ``"--table"``).
    """
    p = Path(path)
    if not os.fspath(path) or p.name in ("", ".", ".."):
        raise ParameterError(f"{what} {os.fspath(path)!r} is not a file name")
    if p.is_dir():
        raise ParameterError(f"{what} {str(p)!r} is a folder; give the name of a file")
    if p.exists() and not p.is_file():  # renaming over it would replace a device or FIFO
        raise ParameterError(
            f"{what} {str(p)!r} is not a regular file (a device, FIFO or socket); "
            "give the name of a file"
        )
    folder = p.parent
    if not folder.exists():
        raise ParameterError(f"{what} {str(p)!r}: folder {str(folder)!r} does not exist")
    if not folder.is_dir():
        raise ParameterError(f"{what} {str(p)!r}: {str(folder)!r} is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise ParameterError(f"{what} {str(p)!r}: folder {str(folder)!r} is not writable")
    return p


def _name_max(folder: Path) -> int:
    try:
        return int(os.pathconf(folder if str(folder) else ".", "PC_NAME_MAX"))
    except (OSError, ValueError, AttributeError):
        return 255


def _fit_bytes(text: str, limit: int) -> str:
    """``text`` cut to at most ``limit`` bytes of UTF-8, never inside a character."""
    raw = os.fsencode(text)
    if len(raw) <= limit:
        return text
    return raw[: max(limit, 0)].decode("utf-8", "ignore")


def _temporary_parts(path: Path) -> tuple[str, str]:
    """The prefix ``.STEM.rdtmp-`` and suffix of ``path``'s temporary names, shortened so that
    a whole temporary name fits in ``NAME_MAX`` bytes."""
    # The target's suffix is kept: writers such as matplotlib's savefig choose the format by it.
    stem, suffix = path.stem, path.suffix
    room = _name_max(path.parent) - len(f".{_TAG}{os.getpid()}-{'0' * 8}".encode())
    suffix = _fit_bytes(suffix, min(len(os.fsencode(suffix)), max(room - 1, 0)))
    stem = _fit_bytes(stem, room - len(os.fsencode(suffix)))
    return f".{stem}{_TAG}", suffix


def beside(path: PathLike, tag: str) -> Path:
    """The companion file or folder ``NAME`` + ``tag`` of ``path`` (a lock, a folder of
    chunks), its name shortened to fit ``NAME_MAX`` as the temporary names are: when too long,
    the name is cut and a hash of the whole name keeps it unique.

    >>> beside("/tmp/t.npz", ".lock").name
    't.npz.lock'
    >>> len(os.fsencode(beside("/tmp/" + "a" * 254, ".lock").name)) <= 255
    True
    """
    p = Path(path)
    name = p.name + tag
    limit = _name_max(p.parent)
    if len(os.fsencode(name)) <= limit:
        return p.with_name(name)
    import hashlib

    digest = hashlib.sha1(os.fsencode(p.name)).hexdigest()[:12]
    room = limit - len(os.fsencode(tag)) - len(digest) - 1
    return p.with_name(f"{_fit_bytes(p.name, room)}-{digest}{tag}")


def _temporary_name(path: Path) -> Path:
    prefix, suffix = _temporary_parts(path)
    return path.with_name(f"{prefix}{os.getpid()}-{secrets.token_hex(4)}{suffix}")


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
    prefix, suffix = _temporary_parts(path)
    pattern = re.compile(re.escape(prefix) + r"(\d+)-[0-9a-f]{8}" + re.escape(suffix) + "$")
    removed = []
    try:
        entries = list(path.parent.iterdir()) if str(path.parent) else list(Path(".").iterdir())
    except OSError:
        return removed
    for entry in entries:
        m = pattern.match(entry.name)
        if m and int(m.group(1)) != os.getpid() and not _pid_alive(int(m.group(1))):
            with contextlib.suppress(OSError):
                _remove(entry)
                removed.append(entry)
    return removed


def _remove(tmp: Path) -> None:
    """Remove a temporary file, or a temporary folder and what it holds."""
    if tmp.is_dir() and not tmp.is_symlink():
        shutil.rmtree(tmp, ignore_errors=True)
    else:
        tmp.unlink()


def _on_signal(signum: int, frame: Any) -> None:
    previous = _previous.get(signum, signal.SIG_DFL)
    if callable(previous):  # e.g. an application's handler: it decides; except-paths clean up
        previous(signum, frame)
        return
    if previous == signal.SIG_IGN:
        return
    for tmp in list(_active):
        with contextlib.suppress(OSError):
            _remove(tmp)
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)  # the default action, as if no handler had been installed


@contextlib.contextmanager
def _guard(tmp: Path | None) -> Iterator[None]:
    """Track ``tmp`` (and, in the main thread, remove it on SIGTERM/SIGHUP) while writing;
    ``None`` only installs the signal handlers (for files added to the tracked set later)."""
    global _depth
    main = threading.current_thread() is threading.main_thread()
    with _lock:
        if tmp is not None:
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
            if tmp is not None:
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
            _finish(tmp, path)
        except BaseException as exc:
            with contextlib.suppress(OSError):
                tmp.unlink()
            mapped = _write_error(exc, path) if isinstance(exc, Exception) else None
            if mapped is not None and mapped is not exc:
                raise mapped from exc
            raise
    return path


def place(written: PathLike, path: PathLike) -> Path:
    """Put a file that another program has already written whole (``written``, beside
    ``path``) at ``path``, as :func:`atomic_write` puts its temporary: synced, then renamed,
    refusing an existing ``path`` where :func:`keep_existing` asked so.

    For a product of several files (a PDS4 label and its data file) whose secondary file a
    library writes under a name of its own choosing.

    Returns
    -------
    Path
        ``path``.
    """
    written, path = Path(written), check_output_path(path)
    _fsync(written)
    _finish(written, path)
    return path


def _finish(tmp: Path, path: Path) -> None:
    """Put the written temporary ``tmp`` at ``path`` now, or stage it (:func:`deferred`)."""
    target = os.path.abspath(path)
    exclusive = target in _keep
    stage = _staged.get()
    if stage is not None and os.path.commonpath([stage[0], target]) == stage[0]:
        stage[1].append((tmp, path, exclusive))
        with _lock:
            _active.add(tmp)
        return
    _commit(tmp, path, exclusive)


def _move(src: Path, dst: Path) -> None:
    """Rename ``src`` to ``dst`` (a file over a file, or a folder onto a free name or an empty
    folder): the one rename of the package, here beside the writers that rely on it."""
    os.replace(src, dst)


def _commit(tmp: Path, path: Path, exclusive: bool) -> None:
    if not exclusive:
        _move(tmp, path)
        return
    try:
        os.link(tmp, path)  # fails if path exists, however it came to exist
    except FileExistsError:
        raise WriteError(
            errno.EEXIST, "it exists; use --force to overwrite it", str(path)
        ) from None
    except OSError as exc:
        if exc.errno not in (errno.EPERM, errno.ENOTSUP, errno.EXDEV, errno.EMLINK):
            raise
        # no hard links on this file system: the check and the rename are not one step
        if os.path.lexists(path):
            raise WriteError(
                errno.EEXIST, "it exists; use --force to overwrite it", str(path)
            ) from None
        _move(tmp, path)
        return
    tmp.unlink()


@contextlib.contextmanager
def deferred(folder: PathLike) -> Iterator[None]:
    """Write several files together: every file under ``folder`` that the writers of this
    module write inside the block appears when the block ends normally, and none does if it
    raises. (Files elsewhere, e.g. in a temporary folder the block reads back, are written
    at once.)

    The files are staged as temporaries beside their targets and renamed in the order they
    were written. Nested blocks join the outer one.
    """
    if _staged.get() is not None:
        yield
        return
    staged: list[tuple[Path, Path, bool]] = []
    token = _staged.set((os.path.abspath(folder), staged))
    with _guard(None):
        try:
            yield
            _staged.reset(token)
            token = None
            for tmp, path, exclusive in staged:
                try:
                    _commit(tmp, path, exclusive)
                except BaseException as exc:
                    mapped = _write_error(exc, path) if isinstance(exc, Exception) else None
                    if mapped is not None and mapped is not exc:
                        raise mapped from exc
                    raise
        finally:
            if token is not None:
                _staged.reset(token)
            with _lock:
                for tmp, _, _ in staged:
                    _active.discard(tmp)
                    with contextlib.suppress(OSError):
                        if tmp.exists():
                            tmp.unlink()


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
            _finish(tmp, path)
        except BaseException as exc:
            with contextlib.suppress(OSError):
                tmp.unlink()
            mapped = _write_error(exc, path) if isinstance(exc, OSError) else None
            if mapped is not None and mapped is not exc:
                raise mapped from exc
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
