"""The compiled Smith random walk: Numba, one thread per range of paths, deterministic.

The same walk as the NumPy reference (:func:`roughdiffuse.simulate.smith.random_walk`,
engine ``"numpy"``), path by path in a compiled loop (``numba.prange`` over blocks of
paths). Every formula is :mod:`.smith_formulas`' (the functions the NumPy walk applies to
arrays, built here from scalar primitives), so the two engines differ only in their random
numbers and in the order they add scores:

* random numbers come from a counter-based generator keyed by (seed, path index, draw
  index) (:mod:`roughdiffuse.engine.numba_random`), not from a generator's state, so the numbers do
  not depend on the thread count or the schedule;
* each block of :data:`BLOCK` paths of one geometry adds its scores in its own slot, and the
  slots are added in block order afterwards: the sums are the same for any thread count.

Imported only when the compiled engine is used (it imports Numba). The kernel is compiled on
first use (tens of seconds, once per machine) and cached on disk in the fast path's private
cache folder (:func:`roughdiffuse.engine.cache.private_cache_dir`), in a subfolder named by
a hash of the sources it is compiled from (this module, :mod:`.smith_formulas`,
:mod:`roughdiffuse.engine.numba_math`, :mod:`roughdiffuse.engine.numba_random`): Numba's
cache notices a change of this file only, not of the functions it calls. Without a private
folder it is compiled in memory, in every process.
"""

from __future__ import annotations

import hashlib
import math
import threading
from pathlib import Path
from types import SimpleNamespace
from typing import Any

import numba
import numpy as np
from numba import prange

from ..engine.cache import Compiled, private_cache_dir
from ..engine.numba_math import erfinv
from ..engine.numba_random import circle_point, normal_pair, path_key, uniform
from .smith_formulas import build

__all__ = ["BLOCK", "FORMULAS", "PRIMITIVES", "run_blocks", "visible_normal", "walk_blocks"]

_LOCK = threading.Lock()
_CALL_LOCK = threading.Lock()
_KERNEL: Any = None

BLOCK = 1024
"""Paths per block: the unit of work of one thread, with its own partial sums."""

_JIT = numba.njit(error_model="numpy")


@_JIT
def _where(c: Any, a: Any, b: Any) -> Any:  # pragma: no cover - compiled by Numba
    return a if c else b


@_JIT
def _erf(x: Any) -> Any:  # pragma: no cover - compiled by Numba
    return math.erf(x)


@_JIT
def _erfc(x: Any) -> Any:  # pragma: no cover - compiled by Numba
    return math.erfc(x)


@_JIT
def _isfinite(x: Any) -> Any:  # pragma: no cover - compiled by Numba
    return math.isfinite(x)


PRIMITIVES = SimpleNamespace(
    jit=_JIT,
    where=_where,
    maximum=np.maximum,
    minimum=np.minimum,
    sqrt=np.sqrt,
    exp=np.exp,
    log1p=np.log1p,
    sin=np.sin,
    cos=np.cos,
    erf=_erf,
    erfinv=erfinv,
    erfc=_erfc,
    isfinite=_isfinite,
)
"""The scalar primitives the formula builders (:mod:`.smith_formulas`,
:mod:`.layered_formulas`) are given for Numba."""

_F = build(PRIMITIVES)
FORMULAS = _F
"""The Smith walk's formulas (:mod:`.smith_formulas`) compiled for Numba."""
_smith_lambda = _F.smith_lambda
_visible_ggx_at = _F.visible_ggx_at
_beckmann_frame = _F.beckmann_frame
_slope_neg = _F.slope_proposal_neg
_beckmann_normal = _F.beckmann_normal
_cosine_about = _F.cosine_about
_height_step = _F.height_step
_next_event = _F.next_event
_TWO_PI = 2.0 * math.pi
_SQRT_PI = math.sqrt(math.pi)


@_JIT
def _slope_gauss(mu, g, u0, u1):  # pragma: no cover - compiled by Numba
    """One try at x̃ ~ (μ − x̃)⁺ exp(−x̃²) for μ ≥ 0 from a N(0, 1/2) number ``g`` and two
    uniforms, without erfinv: x̃, or NaN when rejected.

    The envelope μ e^{−x̃²} + |x̃| e^{−x̃²} 1[x̃ < 0] (masses μ√π and 1/2) equals the target
    for x̃ < 0. With probability 1/2 / (μ√π + 1/2) x̃ = −√(−ln(1 − u1)) (density
    |x̃| e^{−x̃²}, accepted; 1 − u1 is exact); otherwise x̃ = g, accepted with probability
    (μ − x̃)⁺/μ (1 for x̃ < 0), that is when u1 μ < μ − x̃. The acceptance,
    (μ√π/2 (1 + erf μ) + e^{−μ²}/2) / (μ√π + 1/2), is at least 0.76 (near μ = 0.5).
    """
    if u0 * (mu * _SQRT_PI + 0.5) < 0.5:
        return -math.sqrt(-math.log(1.0 - u1))
    return g if u1 * mu < mu - g else math.nan


@_JIT
def visible_normal(ggx, wx, wy, wz, alpha, key, c):  # pragma: no cover - compiled by Numba
    """A visible normal of ω = (wx, wy, wz) (either side of the horizon; GGX if ``ggx``,
    else Beckmann) from the path ``key``'s draws ``c``, ``c + 1``, ...: (mx, my, mz, the next
    unused draw).

    The formulas are the NumPy walk's; the random numbers they take are drawn without
    trigonometric functions or erfinv (:func:`~roughdiffuse.engine.numba_random.circle_point`,
    :func:`~roughdiffuse.engine.numba_random.normal_pair`): GGX's azimuth as a point on the
    circle; Beckmann's slopes from normal pairs, x̃ for μ ≥ 0 by :func:`_slope_gauss` (a
    rejection with a Gaussian proposal) instead of the NumPy walk's erfinv-based
    ``slope_proposal_pos``, so that the two engines check each other's samplers.
    """
    if ggx:
        cphi, sphi, c = circle_point(key, c)
        mx, my, mz = _visible_ggx_at(wx, wy, wz, alpha, cphi, sphi, uniform(key, c))
        return mx, my, mz, c + 1
    mu, cphi, sphi = _beckmann_frame(wx, wy, wz, alpha)
    tx, ty, c = normal_pair(key, c)
    if mu < math.inf:
        g, spare = tx, math.nan  # N(0, 1/2) numbers independent of ty for the tries
        while True:
            if mu >= 0.0:
                x = _slope_gauss(mu, g, uniform(key, c), uniform(key, c + 1))
                c += 2
            else:
                x = _slope_neg(mu, uniform(key, c), uniform(key, c + 1), uniform(key, c + 2))
                c += 3
            if x == x:  # not NaN: accepted
                break
            if mu >= 0.0:
                if spare == spare:
                    g, spare = spare, math.nan
                else:
                    g, spare, c = normal_pair(key, c)
        tx = x
    mx, my, mz = _beckmann_normal(alpha, cphi, sphi, tx, ty)
    return mx, my, mz, c


def _walk_blocks(
    wi, wo, weight, uniform_wo, samples, first, count, alpha, ggx, rho, depth, orders, seed,
    sum1, sum2, ord1, ord2, segments,
):  # pragma: no cover - compiled by Numba
    """Trace blocks ``first`` .. ``first + count − 1`` of paths; block b holds paths
    (b mod n) · BLOCK ... of geometry b // n, n = ⌈samples / BLOCK⌉.

    Per block j (row j of the outputs, which start at zero): ``sum1``, ``sum2`` (count, A)
    the sums of each path's total Σ_k ρ_a^k score_k and of its square; ``ord1``, ``ord2``
    (count, orders) those of each order's score at ρ = 1; ``segments`` (count,) the segments
    traced. ``wi``, ``wo`` (G, 3) and ``weight`` (G,) per geometry; with ``uniform_wo`` each
    path draws ωo uniformly on the hemisphere instead and weighs its scores by 2π.
    """
    per_group = (samples + BLOCK - 1) // BLOCK
    n_a = rho.size
    for j in prange(count):
        b = first + j
        g = b // per_group
        s0 = (b % per_group) * BLOCK
        s1 = min(s0 + BLOCK, samples)
        tot = np.empty(n_a)
        pw = np.empty(n_a)
        nseg = 0
        for s in range(s0, s1):
            key = path_key(seed, g * samples + s)
            c = 0
            if uniform_wo:
                oz = uniform(key, 0)
                phi = _TWO_PI * uniform(key, 1)
                c = 2
                r = math.sqrt(max(1.0 - oz * oz, 0.0))
                ox, oy = r * math.cos(phi), r * math.sin(phi)
                wgt = _TWO_PI
            else:
                ox, oy, oz = wo[g, 0], wo[g, 1], wo[g, 2]
                wgt = weight[g]
            lam_o = _smith_lambda(ggx, oz, alpha)
            rx, ry, rz = -wi[g, 0], -wi[g, 1], -wi[g, 2]
            h = 0.0  # ln u, u = C1(height)
            for a in range(n_a):
                tot[a] = 0.0
                pw[a] = 1.0
            for k in range(1, depth + 1):
                nseg += 1
                lam = _smith_lambda(ggx, rz, alpha)
                escape, h = _height_step(h, lam, rz, uniform(key, c))
                c += 1
                if escape:
                    break
                mx, my, mz, c = visible_normal(ggx, -rx, -ry, -rz, alpha, key, c)
                score = _next_event(ox, oy, oz, mx, my, mz, h, lam_o) * wgt
                for a in range(n_a):
                    pw[a] *= rho[a]
                    tot[a] += pw[a] * score
                if k <= orders:
                    ord1[j, k - 1] += score
                    ord2[j, k - 1] += score * score
                rx, ry, rz = _cosine_about(mx, my, mz, uniform(key, c), uniform(key, c + 1))
                c += 2
            for a in range(n_a):
                sum1[j, a] += tot[a]
                sum2[j, a] += tot[a] * tot[a]
        segments[j] = nseg


def _sources_digest() -> str:
    here = Path(__file__).resolve()
    files = (
        here,
        here.with_name("smith_formulas.py"),
        here.parent.parent / "engine" / "numba_math.py",
        here.parent.parent / "engine" / "numba_random.py",
    )
    h = hashlib.sha1(numba.__version__.encode())
    for f in files:
        h.update(f.read_bytes())
    return h.hexdigest()[:16]


def walk_blocks() -> Any:
    """The compiled kernel (:func:`_walk_blocks`), built or loaded on the first call."""
    global _KERNEL
    with _LOCK:
        if _KERNEL is None:
            flags = dict(parallel=True, nogil=True, error_model="numpy")
            jit = numba.njit(cache=True, **flags)
            directory = private_cache_dir()
            if directory is None:
                _KERNEL = numba.njit(**flags)(_walk_blocks)
            else:
                old = numba.config.CACHE_DIR
                numba.config.CACHE_DIR = str(directory / f"smith_walk_{_sources_digest()}")
                try:  # Numba reads the folder when the dispatcher is made
                    _KERNEL = jit(_walk_blocks)
                finally:
                    numba.config.CACHE_DIR = old
        return _KERNEL


def run_blocks(*args: Any) -> None:
    """Call the kernel (arguments of :func:`_walk_blocks`), one call at a time in the process:
    a call already uses every thread it is given, and not every Numba threading layer accepts
    parallel kernels launched from two Python threads at once."""
    kernel = Compiled(walk_blocks())  # a new signature is compiled under the cache's lock
    with _CALL_LOCK:
        kernel(*args)
