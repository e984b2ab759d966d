"""Mitsuba for the tests: libLLVM for the llvm variants, a variant, our plugins registered."""

from __future__ import annotations

import glob
import math
import os
from typing import Any

import numpy as np


def mitsuba_variant(variant: str) -> Any:
    """Import Mitsuba, set ``variant``, register roughdiffuse's plugins; return ``mitsuba``.

    Skips the calling test, with the reason, where Mitsuba or the variant is missing.

    The llvm variants need libLLVM 19, else the test skips (``make test`` installs Debian's
    libllvm19 and exports DRJIT_LIBLLVM_PATH; this finds it when the variable is not set).
    """
    if "DRJIT_LIBLLVM_PATH" not in os.environ:
        found = sorted(
            glob.glob("/usr/lib/*/libLLVM.so.1*") + glob.glob("/usr/lib/*/libLLVM-1*.so")
        )
        if found:
            os.environ["DRJIT_LIBLLVM_PATH"] = found[-1]
    import pytest

    mi = pytest.importorskip("mitsuba", reason="Mitsuba 3 is not installed (pip install mitsuba)")
    if variant.startswith("llvm"):
        from roughdiffuse.integrations.drjit_llvm import llvm_problem

        problem = llvm_problem()  # an old libLLVM would abort the test process
        if problem:
            pytest.skip(problem)
    try:
        mi.set_variant(variant)
    except (ImportError, RuntimeError, AttributeError) as exc:
        pytest.skip(f"Mitsuba variant {variant} is not available here: {exc}")
    from roughdiffuse.integrations.mitsuba import register

    register()
    return mi


def parameter_sets(entry: Any) -> list[dict[str, Any]]:
    """Two parameter sets of a registry model for the plugin tests: its defaults ({}) and a
    "rough" set (angles at 1 rad, numbers whose range lies inside [0, 10] at its middle,
    colour parameters at 0.7), so that every declared parameter is tried off its default."""
    rough: dict[str, Any] = {}
    for p in entry.applicable():  # those of the default choices (Coated: its default base)
        if p.categorical:
            continue
        if p.channels:
            rough[p.name] = 0.7
        elif p.unit == "radians" and (p.max is None or p.max >= 1.0):
            rough[p.name] = 1.0
        elif p.min is not None and p.max is not None and 0 <= p.min and p.max <= 10:
            rough[p.name] = 0.5 * (p.min + p.max)
    return [{}, rough]


def can_sample(model: Any) -> bool:
    """Whether ``model`` has anything to sample (not a mirror's Dirac delta, whose density is
    0 in every direction): its pdf at 64 cosine-distributed directions. The pdf, not a draw:
    this runs when the tests are collected, and a draw evaluates the BRDF (the V-cavity's
    exact solution costs seconds)."""
    import numpy as np

    u = np.random.default_rng(0).random((64, 2))
    cos_t, phi = np.sqrt(u[:, 0]), 2 * np.pi * u[:, 1]
    sin_t = np.sqrt(1 - cos_t**2)
    wo = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)
    wi = np.broadcast_to(np.array([0.3, 0.0, 0.95]) / np.hypot(0.3, 0.95), wo.shape)
    return bool(np.any(np.asarray(model.pdf(wi, wo)) > 0))


def random_geometries(
    n: int = 20, seed: int = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``n`` random (θi, θr, Δφ), θ below 83° (1.45 rad), seeded."""
    rng = np.random.default_rng(seed)
    return rng.uniform(0, 1.45, n), rng.uniform(0, 1.45, n), rng.uniform(0, np.pi, n)


def mitsuba_brdf(mi: Any, bsdf: Any, ti: Any, tr: Any, dp: Any) -> np.ndarray:
    """f = eval / cos θ_light of a loaded Mitsuba BSDF at each (θi, θr, Δφ): Mitsuba's
    ``si.wi`` is the viewer, the argument of ``eval`` the light."""
    out = []
    for a, b, c in zip(ti, tr, dp, strict=True):
        si = mi.SurfaceInteraction3f()
        si.wi = mi.Vector3f(math.sin(b) * math.cos(c), math.sin(b) * math.sin(c), math.cos(b))
        v = bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(math.sin(a), 0.0, math.cos(a)))
        out.append(float(v[0]) / math.cos(a))
    return np.array(out)
