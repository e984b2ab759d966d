"""The compiled layered walk: Numba, one thread per range of paths, deterministic.

The same walk as the NumPy one (:mod:`.layered`, engine ``"numpy"``), path by path in a
compiled loop, with the Smith walk's machinery (:mod:`.smith_walk_numba`): blocks of
:data:`~.smith_walk_numba.BLOCK` paths of one geometry per thread (``numba.prange``), each
adding its scores in its own slot, summed in block order afterwards; random numbers from the
counter-based generator keyed by (seed, path index, draw index)
(:mod:`roughdiffuse.engine.numba_random`), so the values do not depend on the thread count.
The formulas are shared with the NumPy walk: the interface's (:mod:`.layered_formulas`),
Smith's Λ and the visible normals (:mod:`.smith_formulas`, through
:func:`.smith_walk_numba.visible_normal`).

The base enters as scalar functions traced from the model's own code
(:func:`roughdiffuse.engine.scalar.scalar_sources`): its ``brdf_cosines`` and its sampling
strategy's ``sample``. f is taken in parts (``base_f_o``, ``base_f_i``, ``base_f_io``): the
next events, all at one ωo per path, compute the part that depends on μo alone once per path;
the continuation computes its part at μo = u_z while the sampler runs, and the next event of
the same arrival, whose μi is that u_z, takes its μi part from it (``base_f_i_as_o``) when the
base's f treats μi and μo alike. The kernel is
compiled once per base *structure* (the printed source of those functions: a new albedo or
roughness reuses it) and cached on disk like the Smith
walk, in a folder named by a hash of the sources it is compiled from, in the fast path's
private cache folder (:func:`roughdiffuse.engine.cache.private_cache_dir`); without one it is
compiled in memory. A base the trace cannot express raises :class:`~roughdiffuse.engine.trace.
TraceError` (the NumPy walk serves it).
"""

from __future__ import annotations

import hashlib
import math
import threading
import types
from pathlib import Path
from typing import Any

import numba
import numpy as np
from numba import prange

from ..engine.cache import Compiled, private_cache_dir
from ..engine.numba_random import path_key, uniform
from ..engine.scalar import PRELUDE, scalar_sources
from .layered_formulas import MS_MAX_EVENTS
from .layered_formulas import build as build_interface
from .smith_walk_numba import BLOCK, FORMULAS, PRIMITIVES, visible_normal

__all__ = ["interface_sums", "run"]

_LOCK = threading.Lock()
_CALL_LOCK = threading.Lock()
_KERNELS: dict[str, Any] = {}
_JIT = PRIMITIVES.jit
_I = build_interface(PRIMITIVES, FORMULAS.smith_lambda)
_fresnel = _I.fresnel
_refract_in = _I.refract_in
_phase_out = _I.phase_out
_smith_g1 = FORMULAS.smith_g1
_smith_lambda = FORMULAS.smith_lambda
_height_step = FORMULAS.height_step
_PI = math.pi
_TWO_PI = 2.0 * math.pi
_FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}


def base_f_o(mu_o, p):  # pragma: no cover - replaced per base
    """Placeholder of the traced base BRDF's part that depends on μo alone."""
    raise NotImplementedError


def base_f_i(mu_i, p):  # pragma: no cover - replaced per base
    """Placeholder of the traced base BRDF's part that depends on μi alone."""
    raise NotImplementedError


def base_f_i_as_o(mu, ho, p):  # pragma: no cover - replaced per base
    """Placeholder of ``base_f_i(mu, p)`` given ``ho = base_f_o(mu, p)``."""
    raise NotImplementedError


def base_f_io(mu_i, mu_o, cos_io, hi, ho, out, p):  # pragma: no cover - replaced per base
    """Placeholder of the traced base BRDF given its parts ``hi`` and ``ho``."""
    raise NotImplementedError


def base_sample(u1, u2, wo0, wo1, wo2, p):  # pragma: no cover - replaced per base
    """Placeholder of the traced base sampler."""
    raise NotImplementedError


@_JIT
def _g1(ggx, z, alpha):  # pragma: no cover - compiled by Numba
    """Smith's G1 = 1 / (1 + Λ(|z|)) (1 for a smooth interface)."""
    if alpha == 0.0:
        return 1.0
    z = min(max(abs(z), 1e-12), 1.0)
    if not ggx and z * z > 36.0 * alpha * alpha * (1.0 - z * z):
        # Beckmann's a = cot θ / α > 6: Λ < 1.5e-19, 1/(1 + Λ) is 1 in float64 (no erfc)
        return 1.0
    return _smith_g1(ggx, z, alpha)


@_JIT
def _unit(x, y, z):  # pragma: no cover - compiled by Numba
    r = 1.0 / math.sqrt(x * x + y * y + z * z)
    return x * r, y * r, z * r


@_JIT
def _enter(wx, wy, wz, eta, alpha, ggx, key, c):  # pragma: no cover - compiled by Numba
    """The direction into the layer from ω (above) and its weight (1 − F) G1; the next draw."""
    mx, my, mz = 0.0, 0.0, 1.0
    if alpha > 0.0:
        mx, my, mz, c = visible_normal(ggx, wx, wy, wz, alpha, key, c)
    tx, ty, tz, trans = _refract_in(wx, wy, wz, mx, my, mz, eta)
    weight = trans * _g1(ggx, tz, alpha) if tz < 0.0 else 0.0
    tx, ty, tz = _unit(tx, ty, min(tz, -1e-12))
    return tx, ty, tz, weight, c


@_JIT
def _reflect_inside(wx, wy, wz, eta, alpha, ggx, key, c):  # pragma: no cover - compiled
    """Light going up (ω) reflected down at the interface's underside: the direction (a
    mirror image of the unit ω, unit but for rounding), the weight F(·, 1/η) (× G1 when rough;
    0 if it goes up again) and the next draw."""
    if alpha == 0.0:
        return wx, wy, -wz, _fresnel(wz, 1.0 / eta), c
    mx, my, mz, c = visible_normal(ggx, -wx, -wy, wz, alpha, key, c)
    mz = -mz
    d = wx * mx + wy * my + wz * mz  # < 0: the facet faces the ray
    rx, ry, rz = wx - 2.0 * d * mx, wy - 2.0 * d * my, wz - 2.0 * d * mz
    weight = 0.0  # reflected up again: lost
    if rz < 0.0:
        weight = _fresnel(min(max(-d, 0.0), 1.0), 1.0 / eta) * _g1(ggx, rz, alpha)
    return rx, ry, min(rz, -1e-12), weight, c


@_JIT
def _hg(cos_t, g):  # pragma: no cover - compiled by Numba
    """The Henyey–Greenstein phase function (1 − g²) / (4π (1 + g² − 2 g cos θ)^{3/2}),
    θ between the directions of travel before and after the scattering (Henyey and
    Greenstein 1941, ApJ 93, eq. 3, normalised to 1 over the sphere): g > 0 scatters
    forwards."""
    den = 1.0 + g * g - 2.0 * g * cos_t
    return (1.0 - g * g) / (4.0 * _PI * den * math.sqrt(den))


@_JIT
def _hg_sample(dx, dy, dz, g, u1, u2):  # pragma: no cover - compiled by Numba
    """A direction of travel after a Henyey–Greenstein scattering of light travelling along
    the unit (dx, dy, dz): cos θ by inversion of its distribution,
    (1 + g² − ((1 − g²) / (1 − g + 2 g u))²) / (2 g) (uniform for |g| < 1e-3), the azimuth
    2π u2 in the frame of Duff et al. 2017 ("Building an orthonormal basis, revisited")."""
    if abs(g) < 1e-3:
        ct = 1.0 - 2.0 * u1
    else:
        q = (1.0 - g * g) / (1.0 - g + 2.0 * g * u1)
        ct = (1.0 + g * g - q * q) / (2.0 * g)
    ct = min(max(ct, -1.0), 1.0)
    st = math.sqrt(max(1.0 - ct * ct, 0.0))
    phi = _TWO_PI * u2
    sign = 1.0 if dz >= 0.0 else -1.0
    a = -1.0 / (sign + dz)
    b = dx * dy * a
    t1x, t1y, t1z = 1.0 + sign * dx * dx * a, sign * b, -sign * dx
    t2x, t2y, t2z = b, sign + dy * dy * a, -dy
    cp, sp = st * math.cos(phi), st * math.sin(phi)
    return _unit(cp * t1x + sp * t2x + ct * dx, cp * t1y + sp * t2y + ct * dy,
                 cp * t1z + sp * t2z + ct * dz)


@_JIT
def _ms_walk(wx, wy, wz, outside, eta, alpha, ggx, key, c, nee, ox, oy, oz,
             lam_o):  # pragma: no cover - compiled by Numba
    """The random walk on the dielectric microsurface of Heitz, Hanika, d'Eon and
    Dachsbacher 2016 ("Multiple-scattering microfacet BSDFs with the Smith model", SIGGRAPH,
    Sec. 5) of a ray travelling along ω = (wx, wy, wz) that arrives from the air side
    (``outside``) or from the dielectric: (the direction it leaves along, whether it leaves on
    the air side, whether it is lost (still on the surface after :data:`MS_MAX_EVENTS`
    events), the next-event sum, the facet events, the next draw).

    Heights are those of a uniform height distribution, carried as h = ln C1 on the side
    the ray is on (the dielectric side sees the surface turned upside down, C1 ↦ 1 − C1;
    the walk does not depend on the height distribution, Heitz et al. Sec. 3). At each facet
    event the ray meets a facet drawn from the visible normals of −ω on its side (the
    normal negated on the dielectric side), reflects with probability F(·, η) (η' = 1/η
    from the dielectric) and refracts otherwise: every ray leaves with weight 1. With
    ``nee`` each event adds p(−ω → ωo) G1(ωo, h) (:func:`~.layered_formulas` ``phase_out``,
    G1(ωo, h) = C1^Λ(ωo) on the air side): the sum is an unbiased estimate of the
    interface's f(ωi, ωo) cos θo for ωo = (ox, oy, oz) above it (Heitz et al.'s eval)."""
    h = 0.0
    total = 0.0
    events = 0
    while events < MS_MAX_EVENTS:
        sz = wz if outside else -wz
        escape, h = _height_step(h, _smith_lambda(ggx, sz, alpha), sz, uniform(key, c))
        c += 1
        if escape:
            return wx, wy, wz, outside, False, total, events, c
        events += 1
        if outside:
            nx, ny, nz, c = visible_normal(ggx, -wx, -wy, -wz, alpha, key, c)
        else:
            nx, ny, nz, c = visible_normal(ggx, wx, wy, wz, alpha, key, c)
            nx, ny, nz = -nx, -ny, -nz
        if nee:
            h_air = h if outside else max(math.log1p(-math.exp(h)), -700.0)
            g1 = math.exp(lam_o * h_air) if h_air < 0.0 else 1.0
            total += _phase_out(ggx, outside, -wx, -wy, -wz, ox, oy, oz, eta, alpha) * g1
        rel = eta if outside else 1.0 / eta
        tx, ty, tz, trans = _refract_in(-wx, -wy, -wz, nx, ny, nz, rel)
        if uniform(key, c) < trans:
            wx, wy, wz = _unit(tx, ty, tz)
            outside = not outside
            h = max(math.log1p(-math.exp(h)), -700.0)  # the other side's ln C1
        else:
            d = 2.0 * (wx * nx + wy * ny + wz * nz)
            wx, wy, wz = _unit(wx - d * nx, wy - d * ny, wz - d * nz)
        c += 1
    return wx, wy, wz, outside, True, total, events, c


MEDIUM_MAX_EVENTS = 100_000
"""Scatterings in the medium one path traces at most (its weight is then dropped: a
conservative medium of optical thickness 10 scatters about a hundred times per path)."""


def _medium_path(dx, dy, dz, w_in, tx, ty, tz, w_exit, h_exit, spec, tau, tau_s, tau_bar,
                 g_hg, eta, alpha, ggx, ms, max_k, key, c, cut, pf, ps, n_f, ox, oy, oz, beta,
                 tot, fb):  # pragma: no cover - compiled by Numba
    """One path through a coat whose medium scatters (the slab of pbrt-v4's
    ``LayeredBxDF``: depth z from 0 under the interface to 1 on the base): ``tot`` gets its
    score per channel; returns (the next draw, the segments traced). Free paths are drawn
    with the channels' mean scattering thickness τ̄s (a path of length ℓ, in thicknesses,
    is a scattering with density τ̄s e^{−τ̄s ℓ}); each channel's weight takes the ratio of its
    own, τs e^{−τ ℓ} / (τ̄s e^{−τ̄s ℓ}) at a scattering, e^{−τ L} / e^{−τ̄s L} on reaching a
    boundary (absorption in e^{−τ ℓ}, τ the extinction). Next events towards the exit
    direction t (drawn once per path, as the base's): from a scattering at depth z,
    p(d · (−t)) e^{−τ z/|t_z|} / |t_z| (the source of radiance of a collision density, per
    unit optical path along −t); from the base, f e^{−τ/|t_z|}, as the walk without a
    medium. At the base: its sampler; at the interface from below: its reflection (single
    or multiple scattering), as the walk without a medium."""
    n_c = tot.shape[0]
    n_t = tau.size
    z = 0.0
    nseg = 0
    arrivals = 0
    events = 0
    inv_tz = 1.0 / max(-tz, 1e-12)
    live = False
    for ch in range(n_c):
        beta[ch] = w_in
        tot[ch] = spec
        live |= beta[ch] > cut
    while live and arrivals < max_k and events < MEDIUM_MAX_EVENTS:
        if dz < 0.0:
            dist = (1.0 - z) / max(-dz, 1e-12)
        else:
            dist = z / max(dz, 1e-12)
        ell = -math.log(1.0 - uniform(key, c)) / tau_bar
        c += 1
        if ell < dist:  # a scattering at z − ℓ d_z
            events += 1
            nseg += 1
            z = min(max(z - ell * dz, 0.0), 1.0)
            ph = _hg(-(dx * tx + dy * ty + dz * tz), g_hg) * inv_tz * w_exit
            live = False
            for ch in range(n_c):
                t = tau[min(ch, n_t - 1)]
                beta[ch] *= tau_s[ch] / tau_bar * math.exp(-(t - tau_bar) * ell)
                tot[ch] += beta[ch] * ph * math.exp(-t * z * inv_tz)
                live |= beta[ch] > cut
            dx, dy, dz = _hg_sample(dx, dy, dz, g_hg, uniform(key, c), uniform(key, c + 1))
            c += 2
            continue
        for ch in range(n_c):
            beta[ch] *= math.exp(-(tau[min(ch, n_t - 1)] - tau_bar) * dist)
        if dz < 0.0:  # on the base: its next event, then its sampler
            arrivals += 1
            nseg += 1
            z = 1.0
            ux, uy, uz = -dx, -dy, -dz
            h_u = base_f_o(uz, pf)
            base_f_io(uz, -tz, -(ux * tx + uy * ty + uz * tz), base_f_i_as_o(uz, h_u, pf),
                      h_exit, fb, pf)
            for ch in range(n_c):
                att = math.exp(-tau[min(ch, n_t - 1)] * inv_tz)
                tot[ch] += beta[ch] * w_exit * fb[min(ch, n_f - 1)] * att
            sx, sy, sz, pdf = base_sample(uniform(key, c), uniform(key, c + 1), ux, uy, uz, ps)
            c += 2
            if not (pdf > 0.0 and sz > 0.0):
                break
            base_f_io(sz, uz, sx * ux + sy * uy + sz * uz, base_f_i(sz, pf), h_u, fb, pf)
            live = False
            for ch in range(n_c):
                beta[ch] *= fb[min(ch, n_f - 1)] * sz / pdf
                live |= beta[ch] > cut
            dx, dy, dz = sx, sy, sz
        else:  # under the interface: reflected down, or out (its light is in the next events)
            z = 0.0
            if not ms:
                dx, dy, dz, refl, c = _reflect_inside(dx, dy, dz, eta, alpha, ggx, key, c)
            else:
                dx, dy, dz, up, lost, _nee, ev, c = _ms_walk(
                    dx, dy, dz, False, eta, alpha, ggx, key, c, False, ox, oy, oz, 0.0)
                nseg += ev
                refl = 0.0 if up or lost else 1.0
            if refl == 0.0:
                break
            live = False
            for ch in range(n_c):
                beta[ch] *= refl
                live |= beta[ch] > cut
    return c, nseg


def _walk_blocks(
    wi, wo, uniform_wo, samples, first, count, eta, alpha, ggx, ms, tau, omega, g_hg, max_k,
    seed, cut, pf, ps, n_f, sum1, sum2, segments,
):  # pragma: no cover - compiled by Numba
    """Trace blocks ``first`` .. ``first + count − 1``; block b holds paths
    (b mod n) · BLOCK ... of geometry b // n, n = ⌈samples / BLOCK⌉. Row j of ``sum1``,
    ``sum2`` (count, C) gets the sums of each path's score and of its square, ``segments[j]``
    the arrivals on the base (and scatterings in the medium) traced. With ``uniform_wo`` each
    path draws ωo cosine-distributed and scores π f (the directional albedo). ``omega`` (per
    channel) and ``g_hg``: the medium's single-scattering albedo and Henyey–Greenstein g; a
    medium that scatters takes :func:`_medium_path`."""
    per_group = (samples + BLOCK - 1) // BLOCK
    n_c = sum1.shape[1]
    n_t = tau.size
    absorbs = np.any(tau > 0.0)  # else no exponentials per crossing
    n_w = omega.size
    tau_s = np.empty(n_c)  # the scattering optical thickness of each channel, ω τ
    for ch in range(n_c):
        tau_s[ch] = omega[min(ch, n_w - 1)] * tau[min(ch, n_t - 1)]
    tau_bar = np.mean(tau_s)  # free paths are drawn with the channels' mean
    inv_eta2 = 1.0 / (eta * eta)
    for j in prange(count):
        b = first + j
        g = b // per_group
        s0 = (b % per_group) * BLOCK
        s1 = min(s0 + BLOCK, samples)
        beta = np.empty(n_c)
        tot = np.empty(n_c)
        fb = np.empty(n_f)
        nseg = 0
        for s in range(s0, s1):
            key = path_key(seed, g * samples + s)
            c = 0
            wgt = 1.0
            ox, oy, oz = wo[g, 0], wo[g, 1], wo[g, 2]
            if uniform_wo:
                u0, phi = uniform(key, 0), _TWO_PI * uniform(key, 1)
                c = 2
                r = math.sqrt(u0)
                ox, oy, oz = r * math.cos(phi), r * math.sin(phi), math.sqrt(max(1.0 - u0, 1e-24))
                wgt = _PI
            spec = 0.0
            if ms:
                dx, dy, dz, up, lost, nee, ev, c = _ms_walk(
                    -wi[g, 0], -wi[g, 1], -wi[g, 2], True, eta, alpha, ggx, key, c,
                    not uniform_wo, ox, oy, oz, _smith_lambda(ggx, oz, alpha))
                nseg += ev
                w_in = 0.0 if up or lost else 1.0
                spec = (1.0 if up and not lost else 0.0) if uniform_wo else nee / oz
                if w_in == 0.0:
                    dx, dy, dz = 0.0, 0.0, -1.0
                # the next events' exit: ω' (down, inside) of a walk from ωo, one per path
                tx, ty, tz, up, lost, nee, ev, c = _ms_walk(
                    -ox, -oy, -oz, True, eta, alpha, ggx, key, c, False, ox, oy, oz, 0.0)
                nseg += ev
                w_exit = 0.0 if up or lost else 1.0
                if w_exit == 0.0:
                    tx, ty, tz = 0.0, 0.0, -1.0
            else:
                dx, dy, dz, w_in, c = _enter(wi[g, 0], wi[g, 1], wi[g, 2], eta, alpha, ggx,
                                             key, c)
                # the next events' exit: ω' (up, inside) for the view ωo, one facet per path
                tx, ty, tz, w_exit, c = _enter(ox, oy, oz, eta, alpha, ggx, key, c)
            w_exit *= inv_eta2 * wgt
            h_exit = base_f_o(-tz, pf)  # the next events' f: its part at μo = −t_z
            if tau_bar > 0.0:
                c, ns = _medium_path(dx, dy, dz, w_in, tx, ty, tz, w_exit, h_exit, spec, tau,
                                     tau_s, tau_bar, g_hg, eta, alpha, ggx, ms, max_k, key, c,
                                     cut, pf, ps, n_f, ox, oy, oz, beta, tot, fb)
                nseg += ns
                for ch in range(n_c):
                    sum1[j, ch] += tot[ch]
                    sum2[j, ch] += tot[ch] * tot[ch]
                continue
            live = False
            for ch in range(n_c):
                beta[ch] = w_in * (math.exp(-tau[min(ch, n_t - 1)] / abs(dz)) if absorbs else 1.0)
                tot[ch] = spec
                live |= beta[ch] > cut
            for _ in range(max_k):
                if not live:
                    break
                nseg += 1
                ux, uy, uz = -dx, -dy, -dz  # the base's light direction
                # f's part at μo = u_z (the continuation's) and at μi = u_z (the next event's)
                h_u = base_f_o(uz, pf)
                base_f_io(uz, -tz, -(ux * tx + uy * ty + uz * tz), base_f_i_as_o(uz, h_u, pf),
                          h_exit, fb, pf)  # next event
                for ch in range(n_c):
                    att = math.exp(tau[min(ch, n_t - 1)] / tz) if absorbs else 1.0
                    tot[ch] += beta[ch] * w_exit * fb[min(ch, n_f - 1)] * att
                # continue: the base's own sampler, up, reflected inside, down
                sx, sy, sz, pdf = base_sample(uniform(key, c), uniform(key, c + 1), ux, uy, uz, ps)
                c += 2
                ratio = 0.0
                valid = pdf > 0.0 and sz > 0.0
                if not valid:  # the path ends (β = 0); the normal, for the interface below
                    sx, sy, sz = 0.0, 0.0, 1.0
                else:  # a unit vector (the strategy's), up
                    ratio = sz / pdf
                    base_f_io(sz, uz, sx * ux + sy * uy + sz * uz, base_f_i(sz, pf), h_u, fb, pf)
                if not ms:
                    dx, dy, dz, refl, c = _reflect_inside(sx, sy, sz, eta, alpha, ggx, key, c)
                elif valid:
                    dx, dy, dz, up, lost, nee, ev, c = _ms_walk(
                        sx, sy, sz, False, eta, alpha, ggx, key, c, False, ox, oy, oz, 0.0)
                    nseg += ev
                    refl = 0.0 if up or lost else 1.0
                    if refl == 0.0:
                        dx, dy, dz = 0.0, 0.0, -1.0
                else:
                    dx, dy, dz, refl = 0.0, 0.0, -1.0, 0.0
                live = False
                for ch in range(n_c):
                    t = tau[min(ch, n_t - 1)]
                    att = math.exp(-t / sz - t / abs(dz)) if absorbs else 1.0
                    beta[ch] *= (fb[min(ch, n_f - 1)] * ratio if valid else 0.0) * refl * att
                    live |= beta[ch] > cut
            for ch in range(n_c):
                sum1[j, ch] += tot[ch]
                sum2[j, ch] += tot[ch] * tot[ch]
        segments[j] = nseg


def _interface_blocks(mu, above, samples, eta, alpha, ggx, seed,
                      sums):  # pragma: no cover - compiled by Numba
    """For each cosine ``mu[g]``: ``samples`` walks on the microsurface (:func:`_ms_walk`) of
    light arriving from above (``above``) or from the dielectric at θ = arccos μ; ``sums[g]``
    gets (walks that leave on the side they came from, facet events, lost walks)."""
    for g in prange(mu.size):
        m = mu[g]
        sn = math.sqrt(max(1.0 - m * m, 0.0))
        wz = -m if above else m
        back = 0
        ev_all = 0
        lost_all = 0
        for s in range(samples):
            key = path_key(seed, g * samples + s)
            _x, _y, _z, up, lost, _t, ev, _c = _ms_walk(
                sn, 0.0, wz, above, eta, alpha, ggx, key, 0, False, 0.0, 0.0, 1.0, 0.0)
            ev_all += ev
            if lost:
                lost_all += 1
            elif up == above:
                back += 1
        sums[g, 0] = back
        sums[g, 1] = ev_all
        sums[g, 2] = lost_all


_INTERFACE_KERNEL: list[Any] = []


def interface_sums(mu: np.ndarray, above: bool, samples: int, eta: float, alpha: float,
                   ggx: bool, seed: int) -> np.ndarray:
    """(G, 3) int64 counts of :func:`_interface_blocks` for the cosines ``mu`` (G,)."""
    with _LOCK:
        if not _INTERFACE_KERNEL:
            _INTERFACE_KERNEL.append(_compiled(_interface_blocks,
                                               f"layered_interface_{_digest('')}"))
    kernel = _INTERFACE_KERNEL[0]
    mu = np.ascontiguousarray(mu, np.float64)
    sums = np.zeros((mu.size, 3), dtype=np.int64)
    with _CALL_LOCK:
        kernel(mu, bool(above), int(samples), float(eta), float(alpha), bool(ggx),
               np.uint64(int(seed) % (1 << 64)), sums)
    return sums


def _digest(source: str) -> str:
    here = Path(__file__).resolve()
    engine = here.parent.parent / "engine"
    files = (
        here,
        here.with_name("layered_formulas.py"),
        here.with_name("smith_formulas.py"),
        here.with_name("smith_walk_numba.py"),
        engine / "numba_math.py",
        engine / "numba_random.py",
    )
    h = hashlib.sha1(numba.__version__.encode())
    for f in files:
        h.update(f.read_bytes())
    h.update(source.encode())
    return h.hexdigest()[:16]


def _kernel(source: str) -> Any:
    """The walk compiled with the base functions printed in ``source`` (built or loaded once
    per process)."""
    digest = _digest(source)
    with _LOCK:
        kernel = _KERNELS.get(digest)
        if kernel is not None:
            return kernel
        namespace: dict[str, Any] = {}
        exec(compile(PRELUDE + source, f"<layered base {digest}>", "exec"), namespace)  # noqa: S102
        scope = dict(globals())
        scope.update({name: namespace[name]
                      for name in ("base_f_o", "base_f_i", "base_f_i_as_o", "base_f_io",
                                   "base_sample")})
        # the medium's path calls the same base functions: compiled in the same scope
        medium = types.FunctionType(_medium_path.__code__, scope, "_medium_path")
        scope["_medium_path"] = numba.njit(nogil=True, error_model="numpy",
                                           fastmath=_FASTMATH)(medium)
        fn = types.FunctionType(_walk_blocks.__code__, scope, "_walk_blocks")
        kernel = _compiled(fn, f"layered_walk_{digest}")
        _KERNELS[digest] = kernel
        return kernel


def _compiled(fn: Any, folder: str) -> Compiled:
    """``fn`` compiled (parallel) and cached on disk in the fast path's private cache folder
    ``folder`` (in memory without one); a new signature is compiled under the cache's lock."""
    flags = dict(parallel=True, nogil=True, error_model="numpy", fastmath=_FASTMATH)
    directory = private_cache_dir()
    if directory is None:
        return Compiled(numba.njit(**flags)(fn))
    old = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(directory / folder)
    try:  # Numba reads the folder when the dispatcher is made
        return Compiled(numba.njit(cache=True, **flags)(fn))
    finally:
        numba.config.CACHE_DIR = old


def run(base: Any, wi: np.ndarray, wo: np.ndarray, uniform_wo: bool, samples: int, eta: float,
        alpha: float, ggx: bool, tau: np.ndarray, max_k: int, seed: int, cut: float,
        channels: int, ms: bool = False, omega: np.ndarray | None = None,
        hg_g: float = 0.0) -> tuple[np.ndarray, np.ndarray, int]:
    """Per-geometry sums of the path scores and of their squares (G, C), and the number of
    path segments, for directions ``wi``, ``wo`` (G, 3) (``wo`` unused with ``uniform_wo``);
    ``ms``: a rough interface scatters multiply (:func:`_ms_walk`), its reflection included;
    ``omega`` (per channel, default 0) and ``hg_g``: the single-scattering albedo and the
    Henyey–Greenstein g of the medium whose optical thickness is ``tau``.
    Raises :class:`~roughdiffuse.engine.trace.TraceError` if the base cannot be traced."""
    traced = scalar_sources(base)
    kernel = _kernel(traced.source)
    g = wi.shape[0]
    per_group = -(-samples // BLOCK)
    n = g * per_group
    sum1, sum2 = np.zeros((n, channels)), np.zeros((n, channels))
    segments = np.zeros(n, dtype=np.int64)
    key = np.uint64(int(seed) % (1 << 64))  # the generator's key is 64 bits
    args = (np.ascontiguousarray(wi, np.float64), np.ascontiguousarray(wo, np.float64),
            bool(uniform_wo), int(samples), 0, n, float(eta), float(alpha), bool(ggx),
            bool(ms and alpha > 0.0), np.ascontiguousarray(tau, np.float64),
            np.ascontiguousarray(np.zeros(1) if omega is None else omega, np.float64),
            float(hg_g), int(max_k), key,
            float(cut),
            traced.f_params, traced.sample_params, traced.channels, sum1, sum2, segments)
    with _CALL_LOCK:
        kernel(*args)
    s1 = sum1.reshape(g, per_group, channels).sum(axis=1)
    s2 = sum2.reshape(g, per_group, channels).sum(axis=1)
    return s1, s2, int(segments.sum())
