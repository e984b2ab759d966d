"""Matplotlib figures, made as seaborn and scikit-image make theirs.

Two kinds:

* :func:`pyplot_figure` and :func:`pyplot_subplots` make the figures of the public plotting
  functions (:mod:`roughdiffuse.plots`, :func:`roughdiffuse.energy.plot_albedo`) through
  ``matplotlib.pyplot``, so that pyplot knows them: ``plt.show()`` in a script and Jupyter's
  inline display show them, and ``plt.get_fignums()`` lists them. No backend is chosen or
  changed here: pyplot uses the user's (``MPLBACKEND``, ``matplotlibrc``, ``%matplotlib``),
  and resolves it only when the first figure is made. Those functions also take ``ax=`` (or
  ``fig=``) to draw on the caller's own axes instead.
* :func:`figure` and :func:`subplots` make plain ``matplotlib.figure.Figure`` objects, not
  known to pyplot, for the writers that save a file and forget the figure (``roughdiffuse
  figures``, the reports): nothing accumulates in pyplot's registry during a long run (see
  matplotlib's "Embedding in a web application server" example). :func:`release` lets a
  writer drop a figure that a public plotting function registered.
"""

from __future__ import annotations

import sys
from typing import Any

__all__ = [
    "colormap",
    "displayable",
    "figure",
    "literal",
    "pyplot_figure",
    "pyplot_subplots",
    "release",
    "subplots",
]


def displayable(text: object) -> str:
    r"""``text`` as a string any writer can encode: the undecodable bytes of a file name
    (Python's surrogate escapes) become U+FFFD.

    >>> displayable("flyby-\udce9.csv") == "flyby-\ufffd.csv"
    True
    """
    return str(text).encode("utf-8", "surrogateescape").decode("utf-8", "replace")


def literal(text: object) -> str:
    r"""``text`` as matplotlib shows it literally: :func:`displayable`, and every ``$``
    escaped, so a name such as ``$R_{band}$`` is not parsed as mathtext (a malformed one
    would fail when the figure is drawn).

    >>> print(literal("band $x^2"))
    band \$x^2
    """
    return displayable(text).replace("$", r"\$")


def figure(**kwargs: Any) -> Any:
    """A new ``matplotlib.figure.Figure(**kwargs)`` (``figsize``, ``layout``...), unknown to
    pyplot: for a writer that saves it and lets it go."""
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
    """``(figure, axes)`` as ``pyplot.subplots`` returns them, on a :func:`figure`."""
    fig = figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def pyplot_figure(**kwargs: Any) -> Any:
    """A new figure made by ``matplotlib.pyplot.figure(**kwargs)``: registered with pyplot,
    on the user's backend (none is chosen here)."""
    import matplotlib.pyplot as plt

    return plt.figure(**kwargs)


def pyplot_subplots(
    nrows: int = 1,
    ncols: int = 1,
    *,
    figsize: tuple[float, float] | None = None,
    layout: str | None = None,
    **kwargs: Any,
) -> tuple[Any, Any]:
    """``matplotlib.pyplot.subplots(...)``: ``(figure, axes)``, the figure registered."""
    fig = pyplot_figure(figsize=figsize, layout=layout)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def release(fig: Any) -> None:
    """Forget ``fig`` in pyplot's registry if it is there (after a writer saved it)."""
    plt = sys.modules.get("matplotlib.pyplot")
    if plt is not None:
        plt.close(fig)


def colormap(name: str) -> Any:
    """A registered matplotlib colormap by name (``"viridis"``...)."""
    import matplotlib

    return matplotlib.colormaps[name]
