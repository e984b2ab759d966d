"""Matplotlib figures made as a library should make them: ``matplotlib.figure.Figure``
objects, without pyplot, so that no backend is chosen or changed and no figure is kept in
pyplot's registry (see matplotlib's "Embedding in a web application server" example).

Save with ``fig.savefig(path)``; to show one interactively, hand it to pyplot yourself
(``plt.figure(fig.number)`` does not apply: make it with ``plt.figure`` and draw on its axes,
or display the saved image).
"""

from __future__ import annotations

from typing import Any

__all__ = ["colormap", "figure", "subplots"]


def figure(**kwargs: Any) -> Any:
    """A new ``matplotlib.figure.Figure(**kwargs)`` (``figsize``, ``layout``...)."""
    from matplotlib.figure import Figure

    return Figure(**kwargs)


def subplots(
    nrows: int = 1,
    ncols: int = 1,
    *,
    figsize: tuple[float, float] | None = None,
    layout: str | None = None,
    **kwargs: Any,
) -> tuple[Any, Any]:
    """``(figure, axes)`` as ``pyplot.subplots`` returns them, without pyplot."""
    fig = figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def colormap(name: str) -> Any:
    """A registered matplotlib colormap by name (``"viridis"``...)."""
    import matplotlib

    return matplotlib.colormaps[name]
