"""The parameter sets the interface-wide tests run each model at, one table for every model
(as astropy's ``modeling/tests/example_models.py``).

Each registry id is run at its declared ``example`` point (each parameter's ``example``, else
its default: :meth:`roughdiffuse.registry.Entry.example`) and at the points listed here,
keyword arguments of ``registry.get(id).create``: the ends of a roughness range, a second
variant, the corners where a formula changes branch. A new model needs no line here: its
example point is tested.
"""

from __future__ import annotations

import math
from typing import Any

from roughdiffuse.registry import Entry

EXAMPLES: dict[str, tuple[dict[str, Any], ...]] = {
    "oren-nayar": ({"sigma": 0.0}, {"sigma": 0.4}),
    "oren-nayar-full": ({"sigma": 0.4}, {"sigma": math.pi / 2}),
    "eon": ({"roughness": 0.0}, {"roughness": 1.0}),
    "fujii": ({"roughness": 0.6},),
    "torrance-sparrow": ({"eta": 1.5, "sigma": 0.3}, {"eta": 0.7, "sigma": 0.2}),
    "torrance-sparrow-beckmann": ({"eta": 1.5, "alpha": math.sqrt(2.0) * 0.3},),
    "mix": ({"sigma": 0.3, "weight": 0.1, "eta": 1.5},),
    "burley": ({"roughness": 0.5},),
    "frostbite": ({"roughness": 0.7},),
    "burley-2015": ({"roughness": 0.3},),
    "chan": ({"alpha": 0.4},),
    "hammon": ({"alpha": 0.5},),
    "lunar-lambert": ({"limb_darkening": 0.6},),
    "minnaert": ({"k": 0.7},),
    "lambert-sphere": ({"variant": "full"}, {"variant": "fast"}),
    "hapke": (
        {"b0": 0.8, "h": 0.1, "xi": -0.3, "theta_bar": 0.35},
        {"b0": 0.0, "h": 0.0, "xi": 0.2, "theta_bar": 0.0},
        {"b0": 2.5, "h": 0.05, "xi": 0.4, "theta_bar": 0.3, "hg2": 0.7},
    ),
    "hapke-legendre": ({"b0": 1.5, "h": 0.06, "bh": -0.4, "ch": 0.3, "theta_bar": 0.3},),
    "hapke-2012": (
        {
            "bs0": 1.2,
            "h_s": 0.06,
            "bc0": 0.5,
            "h_c": 0.02,
            "porosity": 1.4,
            "xi": -0.3,
            "hg2": 0.2,
            "theta_bar": 0.35,
        },
    ),
    "coated": (
        {"sigma": 0.3, "eta": 1.5},
        {"sigma": 0.0, "eta": 1.5, "roughness": 0.3, "distribution": "beckmann",
         "absorption": 0.2},
        # one other base (each interface-wide test compiles every point: one is enough to
        # check that a base's own parameter reaches it; tests/test_coated_bases.py checks
        # every base)
        {"base": "eon", "base_roughness": 0.7, "eta": 1.5, "roughness": 0.2,
         "absorption": 0.1},
    ),
    "cycles-diffuse": ({"roughness": 0.0}, {"roughness": 1.0, "albedo": 0.5}),
    "materialx-eon": ({"roughness": 0.0}, {"roughness": 1.0}),
}
"""Registry id -> parameter sets run besides the id's example point."""


def points_of(entry: Entry) -> list[dict[str, Any]]:
    """The parameter sets of ``entry``: its example point, then those of :data:`EXAMPLES`
    (duplicates dropped)."""
    points = [entry.example()]
    for point in EXAMPLES.get(entry.id, ()):
        if point not in points:
            points.append(dict(point))
    return points
