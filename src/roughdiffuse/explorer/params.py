"""The explorer's model parameters and the Python model each parameter set stands for.

The page (``static/js/models.js``) and the GLSL (``static/glsl/brdf.glsl``) describe a model
by a name and a flat set of parameters (the page's sliders). :func:`model_from_params` builds
the :class:`roughdiffuse.models.Model` those parameters mean, so that the tests can compare the
GLSL with the Python formula and the server can render the same material with the Python
renderer.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from ..models import (
    EON,
    Burley,
    Burley2015,
    BurleyRenormalized,
    Chan,
    Fujii,
    Hammon,
    Hapke,
    Lambert,
    LambertSphere,
    LommelSeeliger,
    LunarLambert,
    Minnaert,
    Mix,
    Model,
    OrenNayar,
    TorranceSparrow,
)

__all__ = ["MODEL_IDS", "DEFAULTS", "model_from_params"]

MODEL_IDS: dict[str, int] = {
    "lambert": 0,
    "oren-nayar": 1,
    "oren-nayar-full": 2,
    "fujii": 3,
    "eon": 4,
    "torrance-sparrow": 5,
    "mix": 6,
    "lommel-seeliger": 7,
    "lunar-lambert": 8,
    "burley": 9,
    "frostbite": 10,
    "burley-2015": 11,
    "hammon": 12,
    "chan": 13,
    "lambert-sphere": 14,
    "hapke": 15,
    "minnaert": 16,
}
"""Model names and the ids ``brdf.glsl`` dispatches on (the same numbers there)."""

DEFAULTS: dict[str, Any] = {
    "model": "oren-nayar",
    "albedo": (0.8, 0.8, 0.8),
    "sigma": 0.0,
    "roughness": 0.0,
    "eta": 1.5,
    "weight": 0.0,
    "limb": 0.5,
    "distribution": "gaussian",
    "alpha": 0.3,
    "variant": "full",
    "k": 1.0,
    "b0": 0.0,
    "h": 0.1,
    "g": 0.0,
    "theta_bar": 0.0,
}
"""Values of the parameters a parameter set leaves out (σ in radians)."""


def model_from_params(params: Mapping[str, Any]) -> Model:
    """The Python model for one explorer parameter set.

    Parameters
    ----------
    params : mapping
        ``model`` (a key of :data:`MODEL_IDS`), ``albedo`` (three numbers in [0, 1]),
        ``sigma`` (radians, [0, π/2]), ``roughness`` (r in [0, 1]), ``eta`` (> 0), ``weight``
        (Mix: weight of the specular lobe, [0, 1]), ``limb`` (Lunar-Lambert L, [0, 1]),
        ``distribution`` (``"gaussian"`` or ``"beckmann"``); issue 17's models: ``alpha``
        (Hammon, Chan), ``variant`` (Lambert spheres), ``k`` (Minnaert), ``b0``, ``h``, ``g``,
        ``theta_bar`` (Hapke, radians); Burley, Frostbite and Burley 2015 take ``roughness``.
        Missing keys take :data:`DEFAULTS`.

    Returns
    -------
    Model
        ``"mix"`` is ``Mix([(1 − w, OrenNayar(ρ, σ, "full")), (w, TorranceSparrow(η, σ))])``:
        the lecture's rough surface with diffuse and surface reflection, one σ for both.

    Raises
    ------
    ValueError
        For an unknown model name or a parameter out of its range (from the model).
    """
    p = {**DEFAULTS, **params}
    name = p["model"]
    if name not in MODEL_IDS:
        raise ValueError(f"model must be one of {', '.join(MODEL_IDS)} (got {name!r})")
    albedo = [float(a) for a in p["albedo"]]
    if len(albedo) != 3:
        raise ValueError(f"albedo must have 3 values (got {len(albedo)})")
    sigma, r, eta = float(p["sigma"]), float(p["roughness"]), float(p["eta"])
    weight, limb = float(p["weight"]), float(p["limb"])
    if not 0.0 <= weight <= 1.0 or math.isnan(weight):
        raise ValueError(f"weight must be in [0, 1] (got {weight})")
    dist = p["distribution"]
    if name == "lambert":
        return Lambert(albedo)
    if name == "oren-nayar":
        return OrenNayar(albedo, sigma, "qualitative")
    if name == "oren-nayar-full":
        return OrenNayar(albedo, sigma, "full")
    if name == "fujii":
        return Fujii(albedo, r)
    if name == "eon":
        return EON(albedo, r)
    if name == "torrance-sparrow":
        return TorranceSparrow(eta, sigma, dist)
    if name == "mix":
        return Mix(
            [
                (1.0 - weight, OrenNayar(albedo, sigma, "full")),
                (weight, TorranceSparrow(eta, sigma, dist)),
            ]
        )
    if name == "lommel-seeliger":
        return LommelSeeliger(albedo)
    if name in ("burley", "frostbite", "burley-2015"):
        cls = {"burley": Burley, "frostbite": BurleyRenormalized, "burley-2015": Burley2015}[name]
        return cls(albedo, r)
    if name == "hammon":
        return Hammon(albedo, float(p["alpha"]))
    if name == "chan":
        return Chan(albedo, float(p["alpha"]))
    if name == "lambert-sphere":
        return LambertSphere(albedo, str(p["variant"]))
    if name == "hapke":
        b0, h, g, tb = (float(p[k]) for k in ("b0", "h", "g", "theta_bar"))
        return Hapke(albedo, b0, h, g, tb)
    if name == "minnaert":
        return Minnaert(albedo, float(p["k"]))
    return LunarLambert(albedo, limb)
