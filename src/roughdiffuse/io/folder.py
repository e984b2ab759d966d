"""A results folder written whole or not at all: :func:`atomic_folder`.

A command that writes several files into a folder of its own (``stereo -o DIR``) writes them
into a temporary folder beside the target, ``.DIR.rdtmp-PID-XXXXXXXX``, and renames it to the
target when every file is written. So the target holds the files of one run or does not
exist: a run that fails, is interrupted or killed leaves nothing new (a killed run's
temporary folder is removed by the next run, as :func:`~roughdiffuse.io.atomic.
remove_stale_temporaries` does for files), and a run with ``replace=True`` (``--force``)
swaps the old folder out only after the new one is complete.

Commands that write several files into a folder they share with other files (``bench
--output-dir``, ``simulate --report``) use :func:`roughdiffuse.io.atomic.deferred` instead:
their files appear together at the end, or none does.

>>> import pathlib, tempfile
>>> with tempfile.TemporaryDirectory() as d:
...     target = pathlib.Path(d) / "out"
...     try:
...         with atomic_folder(target) as tmp:
...             _ = (tmp / "a.txt").write_text("half of a result")
...             raise RuntimeError("interrupted")
...     except RuntimeError:
...         pass
...     sorted(p.name for p in pathlib.Path(d).iterdir())
[]
"""

from __future__ import annotations

import contextlib
import os
import shutil
from collections.abc import Iterator
from pathlib import Path

from .._validate import ParameterError
from .atomic import (
    WriteError,
    _guard,
    _move,
    _temporary_name,
    _write_error,
    check_output_path,
    remove_stale_temporaries,
)

__all__ = ["atomic_folder", "check_output_folder"]


def check_output_folder(
    path: str | os.PathLike[str], *, replace: bool = False, marker: str | None = None
) -> Path:
    """Check, before any work, that :func:`atomic_folder` can write ``path``.

    Raises
    ------
    ValueError
        If ``path`` is a file, its parent folder is missing or not writable, or it is a
        folder that holds files and may not be replaced: without ``replace`` any non-empty
        folder; with it, a folder without ``marker`` (the file every result of the command
        holds), so that ``--force`` never deletes a folder of other files.
    """
    target = Path(path)
    if not target.is_dir():
        check_output_path(target, "output folder")  # parent exists, is a folder, is writable
    else:
        check_output_path(target.parent / ".probe", "output folder")  # writable parent
    if target.exists() and not target.is_dir():
        raise ParameterError(f"output folder {str(target)!r} exists and is not a folder")
    if target.is_dir() and any(target.iterdir()):
        if marker is not None and not (target / marker).is_file():
            raise ParameterError(
                f"output folder {str(target)!r} holds files but no {marker}: it is not a "
                "result of this command and is not replaced; choose another folder"
            )
        if not replace:
            raise ParameterError(
                f"output folder {str(target)!r} already holds results; add --force to replace them"
            )
    return target


@contextlib.contextmanager
def atomic_folder(
    path: str | os.PathLike[str], *, replace: bool = False, marker: str | None = None
) -> Iterator[Path]:
    """Yield an empty temporary folder; when the block ends normally it becomes ``path``.

    Parameters
    ----------
    path : path
        The results folder. Checked as :func:`check_output_folder` does (before and after).
    replace : bool
        Replace an existing folder of results (``--force``).
    marker : str, optional
        A file name every result holds; a non-empty folder without it is never replaced.

    Raises
    ------
    ValueError
        See :func:`check_output_folder`.
    WriteError
        The folder could not be renamed into place (e.g. another run made it meanwhile).
    """
    target = check_output_folder(path, replace=replace, marker=marker)
    remove_stale_temporaries(target)
    tmp = _temporary_name(target)
    with _guard(tmp):
        try:
            os.mkdir(tmp, 0o777)
            yield tmp
            _swap(tmp, target, replace, marker)
        except BaseException as exc:
            shutil.rmtree(tmp, ignore_errors=True)
            mapped = _write_error(exc, target) if isinstance(exc, OSError) else None
            if mapped is not None and mapped is not exc:
                raise mapped from exc
            raise


def _swap(tmp: Path, target: Path, replace: bool, marker: str | None) -> None:
    check_output_folder(target, replace=replace, marker=marker)  # again: it may have changed
    old = None
    if target.is_dir():
        old = _temporary_name(target)  # a killed swap leaves it for the next run to remove
        _move(target, old)
    try:
        _move(tmp, target)  # onto a name that is free (or an empty folder) only
    except OSError as exc:
        if old is not None:
            _move(old, target)
        raise WriteError(
            exc.errno or 0, f"could not move the results into place ({exc.strerror})", str(target)
        ) from exc
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)
