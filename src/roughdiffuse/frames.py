"""Directions, angles and the local shading frame.

Convention (fixed here, used everywhere): the local frame has the surface normal along +z.
``wi`` points towards the light, ``wo`` towards the viewer. θ is measured from the normal,
φ is the azimuth in the xy-plane. Every isotropic model depends on a pair of directions only
through three numbers, the *local cosines*::

    mu_i = cos θi = n·wi,   mu_o = cos θr = n·wo,   cos_io = wi·wo,

so kernels take those three arrays (structure of arrays) rather than (..., 3) vectors.
The Oren–Nayar quantity s = cos_io − mu_i mu_o equals sin θi sin θr cos(φr − φi).

Planetary photometry's angles (incidence i, emission e, phase g) convert to and from
(θi, θr, Δφ) here too (:func:`photometric_to_local`, :func:`local_to_photometric`):
cos g = cos_io = cos θi cos θr + sin θi sin θr cos Δφ.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ._array import Array, asarray, concrete, namespace, result_dtype, safe_div, safe_sqrt
from ._validate import ParameterError

__all__ = [
    "angles_to_cosines",
    "check_angle",
    "check_cosines",
    "local_cosines",
    "local_to_photometric",
    "photometric_to_local",
    "spherical_to_vector",
    "unit_components",
    "vector_to_spherical",
    "world_cosines",
]


def spherical_to_vector(theta: Array, phi: Array = 0.0) -> Array:
    """Unit vector(s) in the local frame from polar angle θ and azimuth φ (radians).

    Returns an array of shape ``broadcast(theta, phi).shape + (3,)`` in the namespace of the
    inputs: (sin θ cos φ, sin θ sin φ, cos θ).

    Examples
    --------
    >>> spherical_to_vector(0.0).tolist()
    [0.0, 0.0, 1.0]
    """
    xp = namespace(theta, phi)
    dtype = result_dtype(xp, theta, phi)
    t = asarray(xp, theta, dtype)
    p = asarray(xp, phi, dtype)
    t, p = xp.broadcast_arrays(t, p)
    st = xp.sin(t)
    return xp.stack([st * xp.cos(p), st * xp.sin(p), xp.cos(t)], axis=-1)


def vector_to_spherical(w: Array) -> tuple[Array, Array]:
    """Polar angle θ and azimuth φ (radians) of direction(s) ``w`` of shape (..., 3)."""
    xp = namespace(w)
    x, y, z = unit_components(xp, w, "w")
    return xp.atan2(xp.sqrt(x * x + y * y), z), xp.atan2(y, x)


def _check_real(name: str, w: Any) -> None:
    """Refuse booleans, strings and objects as direction components (NumPy would cast them)."""
    np_dtype = np.asarray(w).dtype if isinstance(w, list | tuple) else getattr(w, "dtype", None)
    if getattr(np_dtype, "kind", "f") not in "iuf":
        raise ParameterError(f"{name} must hold real numbers (got dtype {np_dtype})")


def unit_components(xp: Any, w: Array, name: str, dtype: Any = None) -> tuple[Array, Array, Array]:
    """Split direction(s) ``w`` (shape (..., 3)) into normalised x, y, z components.

    Raises
    ------
    ValueError
        If the last axis is not 3, or a vector is zero-length or not finite.
    """
    _check_real(name, w)
    if dtype is None:
        dtype = result_dtype(xp, w)
    w = asarray(xp, w, dtype)
    if w.ndim < 1 or w.shape[-1] != 3:
        raise ParameterError(f"{name} must have shape (..., 3) (got shape {tuple(w.shape)})")
    x, y, z = w[..., 0], w[..., 1], w[..., 2]
    with np.errstate(over="ignore", under="ignore"):  # judged below, not warned about
        n2 = x * x + y * y + z * z
    c = concrete(n2)
    if c is not None and (not np.all(np.isfinite(c)) or np.any(c == 0)):
        # The squared length under- or overflowed, or a vector is zero or not finite. A
        # vector of finite components, not all zero, is scaled by its largest component
        # first ([1e-200, 0, 1e-200] is a direction); the others are refused.
        wc = np.asarray(concrete(w), dtype=np.float64)
        big = np.max(np.abs(wc), axis=-1)
        bad = ~np.all(np.isfinite(wc), axis=-1) | (big == 0)
        if np.any(bad):
            raise ParameterError(
                f"{name} must contain non-zero, finite direction vectors "
                f"({int(np.sum(bad))} are zero, NaN or infinite)"
            )
        w = w / asarray(xp, big[..., None], dtype)
        x, y, z = w[..., 0], w[..., 1], w[..., 2]
        n2 = x * x + y * y + z * z
    inv = 1.0 / xp.sqrt(n2)
    return x * inv, y * inv, z * inv


def _check_broadcast(names: tuple[str, ...], *arrays: Array) -> None:
    shapes = [tuple(a.shape)[:-1] if hasattr(a, "shape") else () for a in arrays]
    try:
        np.broadcast_shapes(*shapes)
    except ValueError:
        listed = ", ".join(f"{n} {tuple(a.shape)}" for n, a in zip(names, arrays, strict=True))
        raise ParameterError(f"direction arrays do not broadcast: {listed}") from None


def local_cosines(xp: Any, wi: Array, wo: Array, dtype: Any = None) -> tuple[Array, Array, Array]:
    """(mu_i, mu_o, cos_io) for local-frame directions ``wi`` and ``wo`` (normalised here)."""
    _check_real("wi", wi)
    _check_real("wo", wo)
    wi = asarray(xp, wi) if not hasattr(wi, "shape") else wi
    wo = asarray(xp, wo) if not hasattr(wo, "shape") else wo
    _check_broadcast(("wi", "wo"), wi, wo)
    if dtype is None:
        dtype = result_dtype(xp, wi, wo)
    xi, yi, zi = unit_components(xp, wi, "wi", dtype)
    xo, yo, zo = unit_components(xp, wo, "wo", dtype)
    return zi, zo, xi * xo + yi * yo + zi * zo


def world_cosines(
    xp: Any, n: Array, l: Array, v: Array, dtype: Any = None
) -> tuple[Array, Array, Array]:
    """(n·l, n·v, l·v) for world-space normal, light and view directions (normalised here)."""
    for name, w in (("n", n), ("l", l), ("v", v)):
        _check_real(name, w)
    n, l, v = (asarray(xp, a) if not hasattr(a, "shape") else a for a in (n, l, v))
    _check_broadcast(("n", "l", "v"), n, l, v)
    if dtype is None:
        dtype = result_dtype(xp, n, l, v)
    nx, ny, nz = unit_components(xp, n, "n", dtype)
    lx, ly, lz = unit_components(xp, l, "l", dtype)
    vx, vy, vz = unit_components(xp, v, "v", dtype)
    return (
        nx * lx + ny * ly + nz * lz,
        nx * vx + ny * vy + nz * vz,
        lx * vx + ly * vy + lz * vz,
    )


def angles_to_cosines(
    xp: Any, theta_i: Array, theta_r: Array, delta_phi: Array, dtype: Any = None
) -> tuple[Array, Array, Array]:
    """(mu_i, mu_o, cos_io) from the angles of the papers: θi, θr and φr − φi (radians)."""
    if dtype is None:
        dtype = result_dtype(xp, theta_i, theta_r, delta_phi)
    ti, tr, dp = (asarray(xp, a, dtype) for a in (theta_i, theta_r, delta_phi))
    ti, tr, dp = xp.broadcast_arrays(ti, tr, dp)
    mi, mo = xp.cos(ti), xp.cos(tr)
    return mi, mo, mi * mo + xp.sin(ti) * xp.sin(tr) * xp.cos(dp)


def check_cosines(mu_i: Any, mu_o: Any, cos_io: Any, *, pairs: bool = True) -> None:
    """Refuse local cosines that no pair of unit directions has (:class:`ParameterError`).

    With ``pairs=False`` only the range [−1, 1] of each cosine is checked: callers that clamp
    μ at the horizon (a renderer's shading cosines, max(n·ω, 0)) pass triples off the
    Gram condition on purpose, and every model takes them (its floors and clamps).

    mu_i and mu_o must lie in [−1, 1] (below 0: under the horizon, where a BRDF is 0), and
    cos_io = wi·wo = mu_i mu_o + sin θi sin θr cos Δφ within mu_i mu_o ± √((1 − mu_i²)(1 −
    mu_o²)): the Gram determinant of (n, wi, wo), 1 − mu_i² − mu_o² − cos_io² + 2 mu_i mu_o
    cos_io, is not negative. Each test allows the rounding of cosines computed in the inputs'
    precision (32 ulp, at least 1e-5: float32 cosines of float32-normalised vectors stray by
    up to about 1e-6, and the determinant's derivatives are at most 4). Values with no
    concrete value (inside ``jax.jit``, Dr.Jit, the fast path's symbols) and NaN (NoData)
    pass unchecked.

    >>> check_cosines(1.0, 1.0, 0.5)  # wi = wo = n, so wi·wo must be 1
    Traceback (most recent call last):
    ...
    roughdiffuse._validate.ParameterError: cos_io must be in [mu_i mu_o − s, ...
    """
    arrays = [concrete(a) for a in (mu_i, mu_o, cos_io)]
    if any(a is None or a.dtype.kind not in "iuf" for a in arrays):
        return
    tol = max([1e-5] + [32.0 * float(np.finfo(a.dtype).eps) for a in arrays if a.dtype.kind == "f"])
    # the range: two reductions an array in its own dtype (no copy; brdf_cosines's hot path)
    for name, a in zip(("mu_i", "mu_o", "cos_io"), arrays, strict=True):
        if a.size and not np.all(np.isnan(a)) and max(-np.nanmin(a), np.nanmax(a)) > 1.0 + tol:
            shown = float(a[np.abs(a) > 1.0 + tol].flat[0])
            raise ParameterError(f"{name} must be in [-1, 1], a cosine (got {shown:g})")
    if not pairs:
        return
    mi, mo, c = (a.astype(np.float64, copy=False) for a in arrays)
    mi, mo, c = np.broadcast_arrays(mi, mo, c)
    gram = 1.0 - mi * mi - mo * mo - c * c + 2.0 * mi * mo * c
    bad = gram < -tol
    if np.any(bad):
        k = np.flatnonzero(bad.ravel())[0]
        vi, vo, vc = (float(a.ravel()[k]) for a in (mi, mo, c))
        p, sk = vi * vo, math.sqrt(max(0.0, (1.0 - vi * vi) * (1.0 - vo * vo)))
        raise ParameterError(
            "cos_io must be in [mu_i mu_o − s, mu_i mu_o + s], s = √((1 − mu_i²)(1 − mu_o²)) "
            f"= [{p - sk:g}, {p + sk:g}] here: no pair of directions has these cosines "
            f"(got mu_i={vi:g}, mu_o={vo:g}, cos_io={vc:g})"
        )


def half_vector_cosines(xp: Any, mu_i: Array, mu_o: Array, cos_io: Array) -> tuple[Array, Array]:
    """(n·h, wi·h) of the half vector h = (wi + wo)/|wi + wo| from the three local cosines.

    |wi + wo| = √(2 (1 + wi·wo)), so wi·h = wo·h = √((1 + wi·wo)/2) (Burley's cos θd) and
    n·h = (μi + μo)/|wi + wo|; n·h is 0 where wi = −wo (h undefined, both on the horizon).
    """
    len_h = safe_sqrt(xp, 2.0 * (1.0 + cos_io))
    return safe_div(xp, mu_i + mu_o, len_h), 0.5 * len_h


# ---------------------------------------------------------------- photometric angles
_GEOMETRY_TOL = 1e-9  # radians: g this far outside [|i − e|, i + e] is rounding


def check_angle(name: str, value: Any, hi: float = math.pi) -> np.ndarray:
    """``value`` as a float64 array in [0, ``hi``] radians, else ``ValueError`` naming it.

    >>> check_angle("phase", 4.0)
    Traceback (most recent call last):
    ...
    roughdiffuse._validate.ParameterError: phase must be in [0, π] radians = [0°, 180°] ...
    """
    a = np.asarray(value, dtype=np.float64)
    bad = ~np.isfinite(a) | (a < 0.0) | (a > hi)
    if np.any(bad):
        shown = float(a[bad].flat[0]) if a.ndim else float(a)
        top = "π/2" if hi == math.pi / 2 else "π" if hi == math.pi else f"{hi:g}"
        raise ParameterError(
            f"{name} must be in [0, {top}] radians = [0°, {math.degrees(hi):g}°] "
            f"(got {shown:g} rad = {math.degrees(shown):g}°)"
        )
    return a


def photometric_to_local(
    incidence: Any, emission: Any, phase: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(θi, θr, Δφ) from the photometric angles (i, e, g), radians.

    Parameters
    ----------
    incidence, emission : array_like
        i and e in [0, π/2] (0 at the zenith).
    phase : array_like
        g in [0, π], within [|i − e|, i + e] (up to 1e-9 rad of rounding).

    Examples
    --------
    >>> ti, tr, dphi = photometric_to_local(*np.radians([30.0, 40.0, 70.0]))
    >>> round(float(np.degrees(dphi)), 6)  # sun and observer on opposite sides
    180.0
    """
    i = check_angle("incidence", incidence, math.pi / 2)
    e = check_angle("emission", emission, math.pi / 2)
    g = check_angle("phase", phase)
    i, e, g = np.broadcast_arrays(i, e, g)
    bad = (g < np.abs(i - e) - _GEOMETRY_TOL) | (g > i + e + _GEOMETRY_TOL)
    if np.any(bad):
        k = np.flatnonzero(bad.ravel())[0]
        gi, ii, ei = (math.degrees(float(a.ravel()[k])) for a in (g, i, e))
        raise ParameterError(
            f"phase must be in [|incidence − emission|, incidence + emission] "
            f"(got phase {gi:g}° with incidence {ii:g}°, emission {ei:g}°)"
        )
    s = np.sin(i) * np.sin(e)
    num = np.cos(g) - np.cos(i) * np.cos(e)
    cos_dphi = np.divide(num, s, out=np.ones_like(s), where=s > 1e-15)
    return i.copy(), e.copy(), np.arccos(np.clip(cos_dphi, -1.0, 1.0))


def local_to_photometric(
    theta_i: Any, theta_r: Any, delta_phi: Any
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(i, e, g) from (θi, θr, Δφ), radians: cos g = cos θi cos θr + sin θi sin θr cos Δφ.

    >>> i, e, g = local_to_photometric(*np.radians([30.0, 40.0, 0.0]))
    >>> round(float(np.degrees(g)), 6)  # same side: g = |i − e|
    10.0
    """
    ti = check_angle("theta_i", theta_i, math.pi / 2)
    tr = check_angle("theta_r", theta_r, math.pi / 2)
    dp = np.asarray(delta_phi, dtype=np.float64)
    if not np.all(np.isfinite(dp)):
        raise ParameterError("delta_phi must be finite")
    ti, tr, dp = np.broadcast_arrays(ti, tr, dp)
    cos_g = np.cos(ti) * np.cos(tr) + np.sin(ti) * np.sin(tr) * np.cos(dp)
    return ti.copy(), tr.copy(), np.arccos(np.clip(cos_g, -1.0, 1.0))
