"""A counter-based random number generator for Numba kernels: SplitMix64 keyed by a path.

Each Monte Carlo path draws its numbers from its own key and a counter, the uniform number
being a hash of (seed, path index, draw index), so the numbers a path sees do not depend on
which thread traces it, in what order, or how many threads there are. The hash is the
finaliser of SplitMix64 (G. Steele, D. Lea, C. Flood 2014, "Fast splittable pseudorandom
number generators", OOPSLA; the constants of S. Vigna's splitmix64.c): the stream of key k
is mix(k + (c + 1) γ), c = 0, 1, ..., as SplitMix64 itself, with γ the golden-ratio
increment, and a path's key is mix(mix(seed + γ) ⊕ index).
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np

__all__ = ["circle_point", "normal_pair", "path_key", "uniform"]

_GAMMA = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)
_S30, _S27, _S31, _S11 = np.uint64(30), np.uint64(27), np.uint64(31), np.uint64(11)
_ONE = np.uint64(1)
_TO_UNIT = 2.0**-53


@numba.njit(inline="always", cache=True)
def _mix(z: Any) -> Any:  # pragma: no cover - compiled by Numba
    z = (z ^ (z >> _S30)) * _M1
    z = (z ^ (z >> _S27)) * _M2
    return z ^ (z >> _S31)


@numba.njit(inline="always", cache=True)
def path_key(seed: Any, index: Any) -> Any:  # pragma: no cover - compiled by Numba
    """The key of path ``index`` (int ≥ 0) under ``seed`` (int ≥ 0), a uint64."""
    return _mix(_mix(np.uint64(seed) + _GAMMA) ^ np.uint64(index))


@numba.njit(inline="always", cache=True)
def uniform(key: Any, counter: Any) -> Any:  # pragma: no cover - compiled by Numba
    """Draw number ``counter`` (int ≥ 0) of the path ``key``: a float64 in [0, 1)."""
    z = _mix(key + (np.uint64(counter) + _ONE) * _GAMMA)
    return float(z >> _S11) * _TO_UNIT


@numba.njit(inline="always", cache=True)
def _disc_point(key: Any, counter: Any) -> Any:  # pragma: no cover - compiled by Numba
    """A point (x, y) uniform in the unit disc but its centre, from pairs of draws of the path
    ``key`` from ``counter`` on (uniform in the square, rejected outside; 4/π pairs on
    average): (x, y, s = x² + y², the next unused draw)."""
    while True:
        x = 2.0 * uniform(key, counter) - 1.0
        y = 2.0 * uniform(key, counter + 1) - 1.0
        counter += 2
        s = x * x + y * y
        if 0.0 < s < 1.0:
            return x, y, s, counter


@numba.njit(inline="always", cache=True)
def circle_point(key: Any, counter: Any) -> Any:  # pragma: no cover - compiled by Numba
    """The cosine and sine of a uniform angle from draws ``counter``, ``counter + 1``, ... of
    the path ``key``, without trigonometric functions: (cos, sin, the next unused draw).

    A point (x, y) uniform in the unit disc (pairs of uniforms in the square, rejected
    outside; 4/π pairs on average) has a uniform polar angle θ, and so has 2θ:
    cos 2θ = (x² − y²)/s, sin 2θ = 2xy/s, s = x² + y² (J. von Neumann 1951, "Various
    techniques used in connection with random digits", NBS Appl. Math. Series 12).
    """
    x, y, s, counter = _disc_point(key, counter)
    return (x * x - y * y) / s, 2.0 * x * y / s, counter


@numba.njit(inline="always", cache=True)
def normal_pair(key: Any, counter: Any) -> Any:  # pragma: no cover - compiled by Numba
    """Two independent N(0, 1/2) numbers from draws ``counter``, ``counter + 1``, ... of the
    path ``key`` by the polar method (G. Marsaglia, T. A. Bray 1964, "A convenient method for
    generating normal variables", SIAM Review 6(3)): (x, y) uniform in the unit disc,
    s = x² + y², (x, y) √(−ln s / s) (one logarithm, no trigonometric function).
    Returns (g1, g2, the next unused draw)."""
    x, y, s, counter = _disc_point(key, counter)
    f = math.sqrt(-math.log(s) / s)
    return x * f, y * f, counter
