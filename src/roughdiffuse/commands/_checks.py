"""Checks the commands make before and after their work.

Before: an output path that cannot be written, and a job that cannot fit in memory, are
refused before any work is done (:func:`output_file`, :func:`output_folder`,
:func:`fits_in_memory`). While reading: a file that cannot be read is named in a one-line
message (:func:`reading`). After: a result that holds NaN or infinity is never printed or
written (:func:`require_finite`). Every refusal is a :class:`~roughdiffuse.commands.UsageError`:
one line, exit status 2.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import struct
import tempfile
import zipfile
import zlib
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import Any

from . import UsageError

__all__ = [
    "available_memory",
    "bounded_float",
    "finite_float",
    "fits_in_memory",
    "output_file",
    "output_folder",
    "reading",
    "require_finite",
]


def bounded_float(lo: float, hi: float) -> Callable[[str], float]:
    """argparse type: a number in [lo, hi], refused when parsed rather than when a later
    product with it overflows (the message states the range)."""

    def parse(text: str) -> float:
        value = finite_float(text)
        if not lo <= value <= hi:
            raise argparse.ArgumentTypeError(
                f"expected a number in [{lo:g}, {hi:g}] (got {text!r})"
            )
        return value

    parse.__name__ = "number"
    return parse


def finite_float(text: str) -> float:
    """argparse type: a finite number (``nan``, ``inf`` and overflowing ``1e400`` refused, so
    that the message names the option the user typed)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number (got {text!r})") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number (got {text!r})")
    return value


def _probe(folder: Path, option: str) -> None:
    """Create and remove a file in ``folder``: the one test of writability that holds for
    root, read-only mounts and ACLs alike."""
    try:
        fd, tmp = tempfile.mkstemp(prefix=".roughdiffuse-probe-", dir=folder)
    except OSError as exc:
        raise UsageError(
            f"{option}: cannot write in folder {str(folder)!r} ({exc.strerror or exc})"
        ) from None
    os.close(fd)
    os.unlink(tmp)


def _existing_folder(folder: Path, option: str) -> None:
    if folder.is_dir():
        return
    for parent in (folder, *folder.parents):
        if parent.exists() and not parent.is_dir():
            raise UsageError(f"{option}: {str(parent)!r} is not a folder")
    raise UsageError(f"{option}: output folder {str(folder)!r} does not exist")


def output_file(
    path: str | os.PathLike[str],
    suffixes: tuple[str, ...] | None = None,
    *,
    force: bool = False,
    option: str = "-o",
    overwrite: bool = False,
) -> Path:
    """The output file ``path``, checked before any work: its suffix, its folder (exists, is
    a folder, can be written), and the file itself (not a folder; kept unless ``force``).

    Parameters
    ----------
    path : path
        The output file the user named.
    suffixes : tuple of str, optional
        Accepted suffixes (lower case, with the dot).
    force : bool
        The user gave ``--force``: an existing file may be replaced.
    option : str
        The option that named the path, for the message.
    overwrite : bool
        The command replaces an existing file without ``--force`` (its documented habit).

    Raises
    ------
    UsageError
        Naming the option and the path.
    """
    if not os.fspath(path):
        raise UsageError(f"{option}: empty file name; give the name of a file")
    out = Path(path)
    if suffixes is not None and out.suffix.lower() not in suffixes:
        raise UsageError(f"{option}: file must end in {', '.join(suffixes)} (got {str(path)!r})")
    folder = out.parent if str(out.parent) else Path(".")
    _existing_folder(folder, option)
    if out.is_dir():
        raise UsageError(f"{option}: {str(path)!r} is a folder, not a file")
    if out.exists() and not out.is_file():  # a device, FIFO or socket: never replaced
        raise UsageError(f"{option}: {str(path)!r} is not a regular file (a device, FIFO, socket)")
    if out.exists() and not (force or overwrite):
        raise UsageError(f"{str(path)} exists; use --force to overwrite it")
    _probe(folder, option)
    from ..io.atomic import allow_replacing, keep_existing

    # the check above and the write at the end are not one step: without --force the file is
    # created exclusively, so a file another run wrote meanwhile is not replaced either
    if force or overwrite:
        allow_replacing(out)
    else:
        keep_existing(out)
    return out


def output_folder(path: str | os.PathLike[str], *, option: str = "-o") -> Path:
    """The output folder ``path``, checked before any work and not created: it is a folder
    that can be written, or it does not exist yet and its parent is one.

    Raises
    ------
    UsageError
        Naming the option and the path.
    """
    folder = Path(path)
    if folder.exists():
        if not folder.is_dir():
            raise UsageError(f"{option}: {str(path)!r} is not a folder")
        _probe(folder, option)
        return folder
    parent = folder.parent if str(folder.parent) else Path(".")
    _existing_folder(parent, option)
    _probe(parent, option)
    return folder


_UNREADABLE = (
    OSError,
    ValueError,
    EOFError,
    struct.error,
    zlib.error,
    zipfile.BadZipFile,
    UnicodeDecodeError,
)


def _reason(exc: BaseException) -> str:
    if isinstance(exc, UnicodeDecodeError):
        return f"not UTF-8 text (byte 0x{exc.object[exc.start]:02x} at offset {exc.start})"
    if isinstance(exc, OSError) and exc.strerror:
        return exc.strerror
    if isinstance(exc, struct.error | EOFError):
        return f"truncated or not the format its name says ({exc})"
    return str(exc) or type(exc).__name__


@contextlib.contextmanager
def reading(path: str | os.PathLike[str], what: str = "file") -> Iterator[None]:
    """Turn a failure to read the user's file ``path`` into one line naming it.

    Catches what the readers raise on a bad file: ``OSError``, ``ValueError`` (refusals),
    ``UnicodeDecodeError``, truncated data (``EOFError``, ``struct.error``, ``zlib.error``,
    ``zipfile.BadZipFile``) and the ``RuntimeError`` of the OpenEXR bindings for a file that
    is not OpenEXR.
    """
    name = os.fspath(path)
    try:
        yield
    except UsageError:
        raise
    except _UNREADABLE as exc:
        reason = _reason(exc)
        if name in reason or os.path.basename(name) in reason:
            raise UsageError(f"cannot read {what}: {reason}") from None
        raise UsageError(f"cannot read {what} {name!r}: {reason}") from None
    except RuntimeError as exc:
        if Path(name).suffix.lower() != ".exr":
            raise
        raise UsageError(f"cannot read {what} {name!r}: not an OpenEXR file ({exc})") from None


def available_memory() -> int | None:
    """Bytes of memory this process can still use: MemAvailable of ``/proc/meminfo``, lowered
    by a cgroup v2 limit (``memory.max`` − ``memory.current``) when one is set; None where
    neither can be read."""
    avail: int | None = None
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    avail = int(line.split()[1]) * 1024
                    break
    except (OSError, ValueError, IndexError):
        avail = None
    if avail is None:
        try:
            avail = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
        except (AttributeError, OSError, ValueError):
            avail = None
    try:
        limit = Path("/sys/fs/cgroup/memory.max").read_text().strip()
        used = Path("/sys/fs/cgroup/memory.current").read_text().strip()
        if limit != "max":
            room = max(int(limit) - int(used), 0)
            avail = room if avail is None else min(avail, room)
    except (OSError, ValueError):
        pass
    return avail


def _size(nbytes: float) -> str:
    for unit, scale in (("TB", 1e12), ("GB", 1e9), ("MB", 1e6)):
        if nbytes >= scale:
            return f"{nbytes / scale:.3g} {unit}"
    return f"{nbytes / 1e3:.3g} kB"


def fits_in_memory(nbytes: float, what: str, *, available: int | None = None) -> None:
    """Refuse a job whose estimated memory ``nbytes`` exceeds what is available.

    Parameters
    ----------
    nbytes : float
        The estimate (the caller states how it is made, in ``what``).
    what : str
        The options that set the size and the rate, e.g. ``"--size 8192 --spp 256 (about
        13 bytes per sample)"``.
    available : int, optional
        Bytes available (default: :func:`available_memory`); no check when unknown.
    """
    room = available_memory() if available is None else available
    if room is not None and nbytes > room:
        raise UsageError(
            f"{what} needs about {_size(nbytes)} of memory; {_size(room)} is available"
        )


def require_finite(value: Any, what: str, hint: str = "") -> None:
    """Refuse to print or write ``value`` if it holds NaN or infinity.

    Parameters
    ----------
    value : array-like
        The result about to leave the command.
    what : str
        What it is (``"the BRDF"``, ``"the image"``).
    hint : str
        The inputs that led there, named as the user typed them.
    """
    import numpy as np

    arr = np.asarray(value)
    if arr.dtype.kind not in "fc":
        return
    bad = ~np.isfinite(arr)
    if np.any(bad):
        kinds = sorted({"NaN" if np.isnan(x) else "infinity" for x in arr[bad].flat[:1000]})
        extra = f" for {hint}" if hint else ""
        raise UsageError(
            f"{what} holds {' and '.join(kinds)} ({int(bad.sum())} of {arr.size} values){extra}: "
            "refused"
        )
