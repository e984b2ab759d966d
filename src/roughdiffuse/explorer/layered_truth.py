"""The explorer's layered truth: a coat's BRDF in the plane of incidence by the layered walk.

As the server's V-cavity curve is the truth of the Oren–Nayar models, the position-free walk
(:func:`roughdiffuse.simulate.layered.brdf`) is the truth of ``Coated``: the same dielectric
coat (η, roughness, distribution, absorption) over the same base (the ``base`` menu's model,
ρ and σ or r),
traced by Monte Carlo with a standard error on every value, at the V-cavity curve's viewing
angles. Computed on demand (about a second), cached.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from .._validate import ParameterError
from .backend import THETA_R_DEG, channel_values, number, params_from_query
from .params import DEFAULTS, MODEL_STATE_KEYS, model_from_params

_ALPHA = MODEL_STATE_KEYS["coated"]["roughness"]
"""The flat key of the coat's α (its own slider on the page)."""

__all__ = [
    "CHUNKS",
    "DEADLINE_SECONDS",
    "MAX_ARRIVALS",
    "SAMPLES",
    "Stopped",
    "arrivals",
    "check_cost",
    "layered_truth",
]

SAMPLES = 20_000
"""Paths per viewing angle (the standard error is about 1 % of the value)."""

_LOCK = threading.Lock()  # one walk at a time: the machine may have 2 cores

MAX_ARRIVALS = 1000.0
"""The cost budget of one request: the expected base arrivals per path (:func:`arrivals`)
above which the walk is refused before it starts. Typical coats need 1 to 20; η = 10 with
ρ = 1 about 300; η = 1000 with ρ = 1 would run every path to the walk's bounce limit."""


def arrivals(eta: float, albedo: float) -> float:
    """Expected arrivals on the base of one path of the layered walk, an upper estimate:
    each arrival is reflected (albedo ρ) and leaves through the coat with probability
    ``e = (1 - r0) / η²`` (Lambertian light inside escaping the escape cone, r0 the normal
    Fresnel reflectance ((η - 1)/(η + 1))²; ``1 - r0`` for η <= 1), so arrivals are
    geometric: 1 / (1 - ρ (1 - e)). Absorption in the coat only lowers the count.

    >>> round(arrivals(1.5, 0.8), 2)
    1.85
    >>> arrivals(1000.0, 1.0) > 1e8
    True
    """
    r0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    escape = (1.0 - r0) / (eta * eta) if eta > 1.0 else 1.0 - r0
    keep = albedo * (1.0 - escape)
    return math.inf if keep >= 1.0 else 1.0 / (1.0 - keep)


def check_cost(eta: float, albedo: float) -> None:
    """Refuse a walk whose expected cost is beyond :data:`MAX_ARRIVALS` (a ``ValueError``:
    the server answers 400 before any work), naming η, ρ and what to lower."""
    n = arrivals(eta, albedo)
    if n > MAX_ARRIVALS:
        raise ParameterError(
            f"the layered truth of η = {eta:g} with albedo {albedo:g} needs about {n:.3g} base "
            f"bounces per path (at most {MAX_ARRIVALS:g}): lower η or the albedo"
        )


DEADLINE_SECONDS = 120.0
"""Wall-clock deadline of one request's walk (queueing for the walk included)."""

CHUNKS = 10
"""The walk runs in this many parts of ``SAMPLES / CHUNKS`` paths (seeds 1, 2, ...); between
parts the deadline and the client are checked, so an abandoned request stops."""

_CACHE: dict[tuple, tuple[tuple[float, ...], tuple[float, ...]]] = {}
_CACHE_SIZE = 64


class Stopped(ConnectionError):
    """The client went away: the walk was stopped (the server logs one line)."""


def _plane_of_incidence(
    key: tuple, still_wanted: Callable[[], bool] | None = None
) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """The walk of ``key`` (cached): the mean over :data:`CHUNKS` parts and its standard
    error (the parts' errors combined: sqrt(Σ se²) / K). Before each part, the deadline
    (``ValueError``) and ``still_wanted`` (:class:`Stopped` when it returns False)."""
    if key in _CACHE:
        return _CACHE[key]
    from ..simulate import layered

    deadline = time.monotonic() + DEADLINE_SECONDS
    base_id, albedo, sigma, base_r, eta, roughness, distribution, absorption, theta_i_deg = key
    model = model_from_params({"model": "coated", "base": base_id, "albedo": [albedo] * 3,
                               "sigma": sigma, "base_roughness": base_r, "eta": eta,
                               _ALPHA: roughness, "distribution": distribution,
                               "absorption": [absorption] * 3})
    base = model.base.channel(1) if model.base.channels else model.base
    tr = np.radians(np.abs(THETA_R_DEG))
    delta_phi = np.where(np.asarray(THETA_R_DEG) >= 0, 0.0, math.pi)
    fs, ses = [], []
    with _LOCK:
        for part in range(CHUNKS):
            if time.monotonic() > deadline:
                raise ParameterError(
                    f"the layered truth took more than {DEADLINE_SECONDS:g} s; stopped "
                    "(lower η or the albedo, or try again when the server is less busy)"
                )
            if still_wanted is not None and not still_wanted():
                raise Stopped("the client went away; the layered walk was stopped")
            f, se = layered.brdf(math.radians(theta_i_deg), tr, delta_phi, base, eta=eta,
                                 roughness=roughness, distribution=distribution,
                                 absorption=absorption, samples=SAMPLES // CHUNKS,
                                 seed=1 + part, return_stderr=True)
            fs.append(np.asarray(f, dtype=float))
            ses.append(np.asarray(se, dtype=float))
    mean = np.mean(fs, axis=0)
    stderr = np.sqrt(np.sum(np.square(ses), axis=0)) / CHUNKS
    out = tuple(float(v) for v in mean), tuple(float(v) for v in stderr)
    if len(_CACHE) >= _CACHE_SIZE:
        _CACHE.pop(next(iter(_CACHE)))
    _CACHE[key] = out
    return out


def layered_truth(
    q: dict[str, str], still_wanted: Callable[[], bool] | None = None
) -> dict[str, Any]:
    """The layered walk for the ``coated`` parameters of the query (as ``/api/vase.png``
    takes them, ``absorption`` added: one number or three) and ``theta_i`` (degrees,
    [0, 90)); model A's green albedo and green absorption, as the V-cavity curve. The values are
    rounded to a grid (1e-3, θi to 0.1°) so that small slider moves hit the cache.

    Bounded: a coat beyond the cost budget is refused before the walk (:func:`check_cost`),
    a walk past :data:`DEADLINE_SECONDS` is stopped (``ValueError``), and one whose
    ``still_wanted()`` turns False (the client left) is stopped (:class:`Stopped`).

    Returns
    -------
    dict
        ``theta_r`` (degrees), ``brdf`` and its ``stderr`` (1/sr), ``radiance`` (f E0 cos θi
        with E0 = π, as on the page), the parameters and a ``note`` for the page.
    """
    params = {**DEFAULTS, **params_from_query(q)}  # the coat's α: absent means its default
    if params["model"] != "coated":
        raise ParameterError(f"model must be 'coated' for the layered truth (got "
                             f"{params['model']!r})")
    theta_i = number(q, "theta_i", 0.0)
    if not 0.0 <= theta_i < 90.0:
        raise ParameterError(f"theta_i must be in [0, 90) degrees (got {theta_i!r})")
    params["absorption"] = channel_values(q, "absorption", 0.0)
    params["distribution"] = q.get("distribution", "ggx")
    model_from_params(params)  # every parameter checked by name before the walk runs
    check_cost(params["eta"], params["albedo"][1])  # before the walk: η = 1000 runs for hours
    key = (params["base"], round(params["albedo"][1], 3), round(params["sigma"], 3),
           round(params["base_roughness"], 3), round(params["eta"], 3),
           round(params[_ALPHA], 3), params["distribution"],
           round(params["absorption"][1], 3), min(round(theta_i, 1), 89.9))
    f, se = _plane_of_incidence(key, still_wanted)
    base = {"lambert": "Lambert", "fujii": f"Fujii r = {key[3]:g}", "eon": f"EON r = {key[3]:g}"}
    base_text = base.get(key[0], f"{key[0]} σ = {math.degrees(key[2]):.1f}°")
    e_cos = math.pi * math.cos(math.radians(key[-1]))
    return {
        "theta_r": list(THETA_R_DEG),
        "brdf": list(f),
        "stderr": list(se),
        "radiance": [v * e_cos for v in f],
        "theta_i": key[-1],
        "albedo": key[1],
        "note": (
            f"Layered truth (roughdiffuse.simulate.layered, {SAMPLES:,} paths per angle, "
            f"largest standard error {max(se) * e_cos:.2g} in radiance): ρ = {key[1]:.3f} "
            f"(model A's green albedo), base {base_text}, η = {key[4]:g}, "
            f"{key[6]} α = {key[5]:g}, τ = {key[7]:g}, θi = {key[-1]:.1f}°."
        ),
    }
