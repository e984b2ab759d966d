"""three.js's EON, transcribed: what a glTF file with ``KHR_materials_diffuse_roughness``
renders as in three.js 0.187 (``MeshPhysicalMaterial.diffuseRoughness``).

From ``src/renderers/shaders/ShaderChunk/lights_physical_pars_fragment.glsl.js`` of three.js
0.187.0 (npm ``three``, read in tests/js/node_modules): ``BRDF_EON`` and
``FON_DirectionalAlbedo``. EON (J. Portsmouth, P. Kutz, S. Hill, JCGT 2025) with FON's
directional albedo E_F(μ) taken from the paper's polynomial fit (``E_FON_approx`` of its
Listing 1) instead of its closed form (paper Eq. 8, roughdiffuse's ``eon``).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["fon_poly", "three_eon"]


def fon_poly(mu: np.ndarray, r: float) -> np.ndarray:
    """three.js ``FON_DirectionalAlbedo`` (lights_physical_pars_fragment.glsl.js) at ρ = 1."""
    a = 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * math.pi)) * r)
    m = 1.0 - mu
    g = m * (0.0571085289 + m * (0.491881867 + m * (-0.332181442 + m * 0.0714429953)))
    return a * (1.0 + r * g)


def three_eon(nl, nv, lv, rho, r):
    """three.js 0.187 ``BRDF_EON`` (src/renderers/shaders/ShaderChunk/
    lights_physical_pars_fragment.glsl.js), transcribed: the cosines n·l, n·v, l·v; ρ per
    channel (last axis)."""
    eps = 1e-7
    rho = np.clip(rho, 0.0, 1.0)
    if r <= eps:
        return np.broadcast_to(rho / math.pi, np.shape(nl)[:-1] + rho.shape).copy()
    nl, nv = np.clip(nl, 0.0, 1.0), np.clip(nv, 0.0, 1.0)
    s = lv - nl * nv
    s_over_t = np.where(s > 0.0, s / np.maximum(np.maximum(nl, nv), eps), s)
    a = 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * math.pi)) * r)
    single = rho / math.pi * a * (1.0 + r * s_over_t)
    e_avg = a * (1.0 + (2.0 / 3.0 - 28.0 / (15.0 * math.pi)) * r)
    rho_ms = rho * rho * e_avg / np.maximum(eps, 1.0 - rho * (1.0 - e_avg))
    lobe = np.maximum(eps, 1.0 - fon_poly(nv, r)) * np.maximum(eps, 1.0 - fon_poly(nl, r))
    return single + rho_ms / math.pi * lobe / max(eps, 1.0 - e_avg)
