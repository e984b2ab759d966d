"""Gauss–Legendre rules: the one place every quadrature of roughdiffuse takes its nodes from.

The n-point rule integrates polynomials of degree 2n − 1 exactly (Abramowitz and Stegun 1964,
§25.4.29); nodes and weights come from :func:`numpy.polynomial.legendre.leggauss` on [−1, 1]
and are mapped affinely to [a, b]. A leaf module: the models (albedo quadrature, the
Torrance–Sparrow normalisation, the microfacet sampler's CDF) and the V-cavity solver
(:mod:`roughdiffuse.simulate`, which imports nothing from the models) all use it.

>>> t, w = gauss_legendre(3)
>>> round(float(w.sum()), 15), round(float((w * t**5).sum()), 15)  # ∫0^1 t^5 dt = 1/6
(1.0, 0.166666666666667)
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from ._validate import ParameterError

__all__ = ["gauss_legendre"]


@lru_cache(maxsize=64)
def _rule(n: int, a: float, b: float) -> tuple[np.ndarray, np.ndarray]:
    x, w = np.polynomial.legendre.leggauss(n)
    if (a, b) == (0.0, 1.0):  # the common case, written as before the helper existed
        t, v = 0.5 * (x + 1.0), 0.5 * w
    else:
        half = 0.5 * (b - a)
        t, v = a + half * (x + 1.0), half * w
    t.flags.writeable = False  # shared by every caller through the cache
    v.flags.writeable = False
    return t, v


def gauss_legendre(n: int, a: float = 0.0, b: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Nodes and weights (float64, read-only) of the ``n``-point Gauss–Legendre rule on [a, b].

    Parameters
    ----------
    n : int
        Number of nodes, >= 1.
    a, b : float
        The interval (finite, a < b).

    Returns
    -------
    (ndarray (n,), ndarray (n,))
        ``∫_a^b g(t) dt ≈ Σ w_k g(t_k)``.
    """
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise ParameterError(f"n must be an integer >= 1 (got {n!r})")
    a, b = float(a), float(b)
    if not (np.isfinite(a) and np.isfinite(b) and a < b):
        raise ParameterError(f"the interval [a, b] must be finite with a < b (got [{a}, {b}])")
    return _rule(int(n), a, b)
