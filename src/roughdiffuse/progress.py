"""Progress bars for long jobs: one helper for every command and library loop.

A bar is a :class:`tqdm.tqdm` writing to standard error, shown only when standard error is a
terminal (a log file, a pipe or a test's captured output gets nothing). :func:`finish` ends a
bar that stopped before its total (a fit that converged early): it says why and shows 100 %,
so an early end does not look like an abort.

>>> import io
>>> with progress(3, "demo", enabled=True, file=io.StringIO()) as bar:
...     bar.update(1)
...     finish(bar, "converged")
>>> bar.n, bar.total
(3, 3)
"""

from __future__ import annotations

import sys
from collections.abc import Iterable, Iterator
from typing import IO, Any, TypeVar

__all__ = ["finish", "progress", "progress_enabled", "tracked"]

T = TypeVar("T")


def progress_enabled(file: IO[str] | None = None) -> bool:
    """Whether a bar on ``file`` (default standard error) would be seen: it is a terminal."""
    stream = sys.stderr if file is None else file
    try:
        return bool(stream.isatty())
    except (AttributeError, ValueError):  # closed or not a real stream
        return False


def progress(
    total: int | None,
    desc: str,
    *,
    unit: str = "it",
    enabled: bool | None = None,
    file: IO[str] | None = None,
    **kwargs: Any,
) -> Any:
    """A tqdm bar of ``total`` steps on standard error.

    Parameters
    ----------
    total : int or None
        Steps to the end (None: unknown, a counter).
    desc : str
        What is running ("fit --compare", "Smith random walk", ...).
    unit : str
        What one step is.
    enabled : bool, optional
        Show the bar; default: only when ``file`` is a terminal (:func:`progress_enabled`).
        False gives a bar that counts silently.
    file : text stream, optional
        Where to draw (default: standard error).
    **kwargs
        Passed to :class:`tqdm.tqdm`.
    """
    from tqdm import tqdm

    stream = sys.stderr if file is None else file
    show = progress_enabled(stream) if enabled is None else bool(enabled)
    return tqdm(
        total=total,
        desc=desc,
        unit=unit,
        file=stream,
        disable=not show,
        dynamic_ncols=True,
        **kwargs,
    )


def tracked(
    items: Iterable[T], desc: str, *, total: int | None = None, **kwargs: Any
) -> Iterator[T]:
    """Iterate over ``items`` with a :func:`progress` bar (``total`` defaults to ``len``)."""
    if total is None and hasattr(items, "__len__"):
        total = len(items)  # type: ignore[arg-type]
    with progress(total, desc, **kwargs) as bar:
        for item in items:
            yield item
            bar.update(1)


def finish(bar: Any, reason: str) -> None:
    """End ``bar`` early: note ``reason`` ("converged after 5 of 30") and fill it to 100 %."""
    if bar.total is not None and bar.n < bar.total:
        bar.set_postfix_str(reason, refresh=False)
        bar.update(bar.total - bar.n)
    else:
        bar.set_postfix_str(reason)
