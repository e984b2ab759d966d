"""The explorer's model parameters and the Python model each parameter set stands for.

The page (``static/js/models.js``) describes a model by a name and a flat set of parameters
(the page's sliders); its GLSL is printed from the model's own code
(:mod:`roughdiffuse.explorer.shaders`). :func:`model_from_params` builds the
:class:`roughdiffuse.models.Model` those parameters mean, so that the tests can compare the
GLSL with the Python formula and the server can render the same material with the Python
renderer.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from .. import registry
from .._validate import ParameterError
from ..models import Model

__all__ = [
    "DEFAULTS",
    "MODEL_STATE_KEYS",
    "STATE_KEYS",
    "explorer_entries",
    "flat_key",
    "model_from_params",
    "state_keys",
]

STATE_KEYS: dict[str, str] = {"limb_darkening": "limb"}
"""Declared parameter name -> the page's key for it, where the two differ (the key in the
page's state, its URLs and the vase's query; published as ``state_keys`` in ``/api/models``)."""

MODEL_STATE_KEYS: dict[str, dict[str, str]] = {"coated": {"roughness": "coat_roughness"}}
"""Registry id -> its parameters whose name other models use for another quantity, and the
page's key for each: a key of its own is a slider of its own, with the range, start and
words of this model's declaration (Coated's ``roughness`` is the coat's α, not a diffuse
base's r as EON's ``roughness`` is)."""


def explorer_entries() -> list[registry.Entry]:
    """The registry ids the explorer offers: every closed form (its GLSL is printed from its
    code, :mod:`.shaders`); the page leaves the simulations and tables out."""
    return [e for e in registry.entries() if e.cls.closed_form]


def flat_key(entry: registry.Entry, name: str) -> str:
    """The key of parameter ``name`` of ``entry`` in the flat record: the model's own
    (:data:`MODEL_STATE_KEYS`), else :data:`STATE_KEYS`, else the parameter's name."""
    own = MODEL_STATE_KEYS.get(entry.id, {})
    return own[name] if name in own else STATE_KEYS.get(name, name)


def state_keys(entry: registry.Entry) -> dict[str, str]:
    """The keys of ``entry``'s parameters that differ from their names (``state_keys`` in
    ``/api/models``)."""
    keys = {p.name: flat_key(entry, p.name) for p in entry.parameters}
    return {n: k for n, k in keys.items() if n != k}


def _flat_defaults() -> dict[str, Any]:
    out: dict[str, Any] = {"model": "oren-nayar"}
    for entry in explorer_entries():
        for p in entry.parameters:
            key = flat_key(entry, p.name)
            if key not in out:
                out[key] = [p.default] * 3 if p.channels else p.default
    out.setdefault("distribution", "gaussian")
    return out


DEFAULTS: dict[str, Any] = _flat_defaults()
"""Values of the parameters a parameter set leaves out: the declared defaults (σ in radians)."""


def model_from_params(params: Mapping[str, Any]) -> Model:
    """The Python model for one explorer parameter set (one flat record of the page's state).

    Parameters
    ----------
    params : mapping
        ``model`` (a registry id the page offers, :func:`explorer_entries`), then the model's
        declared parameters (see ``roughdiffuse models``) under their flat keys
        (:func:`flat_key`): ``albedo`` (three numbers in [0, 1]), ``sigma`` (radians),
        ``roughness``, ``eta``, ``weight`` (Mix), ``limb`` (Lunar-Lambert L), ``alpha``
        (Beckmann), ``distribution``, ``base``, ``base_roughness`` and ``coat_roughness``
        (Coated's α); an alias takes its own parameters (``sigma_deg`` for
        ``pbrt3-oren-nayar``). Keys the model does not take, or does not take with the
        menus' values (Coated over EON: ``sigma``), are ignored (the page sends every
        slider); missing keys take
        :data:`DEFAULTS` (a menu's value another model's menu set there: this model's own
        default).
        ``torrance-sparrow`` with ``distribution="beckmann"`` is the GLSL's reading of a σ
        for Beckmann: α = √2 σ.

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
    offered = [e.id for e in explorer_entries()]
    if name not in offered:
        raise ParameterError(f"model must be one of {', '.join(offered)} (got {name!r})")
    if name == "torrance-sparrow" and p.get("distribution") == "beckmann":
        name = "torrance-sparrow-beckmann"
        p = {**p, "alpha": math.sqrt(2.0) * float(p["sigma"])}
    entry = registry.get(name)
    kwargs: dict[str, Any] = {}
    for param in entry.parameters:  # the menus first: they say which sliders apply
        if not param.categorical:
            continue
        key = flat_key(entry, param.name)
        value = p[key]
        if value not in (param.choices or ()) and key not in params:
            value = param.default  # a menu shared with another model: this model's default
        kwargs[param.name] = value
    for param in entry.applicable(kwargs):  # e.g. Coated over EON: not Oren–Nayar's σ
        if param.categorical:
            continue
        value = p[flat_key(entry, param.name)]
        if param.channels:
            value = [float(a) for a in value]
            if len(value) != 3:
                raise ParameterError(f"{param.name} must have 3 values (got {len(value)})")
        else:
            value = float(value)
        kwargs[param.name] = value
    return entry.create(**kwargs)
