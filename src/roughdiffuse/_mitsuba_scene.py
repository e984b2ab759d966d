"""Pieces of the Mitsuba 3 scenes roughdiffuse builds, as plain dicts (no Mitsuba import).

One home for what every such scene shares: the exported scene
(:mod:`roughdiffuse.exporters.mitsuba`), the stereo renders
(:mod:`roughdiffuse.stereo.mitsuba_render`), the V-groove renders
(:mod:`roughdiffuse.simulate.grooves`), the render test and the vase example.
"""

from __future__ import annotations

from typing import Any

__all__ = ["orthographic_sensor"]


def orthographic_sensor(to_world: Any, size: int, spp: int) -> dict[str, Any]:
    """Mitsuba's ``orthographic`` sensor as a dict: placed by ``to_world`` (a 4×4 list, or
    a ``mi.ScalarTransform4f``), a ``size`` × ``size`` RGB film with a box filter (each
    pixel the mean over its own area, as roughdiffuse's renderer), ``spp`` independent
    samples per pixel."""
    return {
        "type": "orthographic",
        "to_world": to_world,
        "film": {
            "type": "hdrfilm",
            "width": size,
            "height": size,
            "rfilter": {"type": "box"},
            "pixel_format": "rgb",
        },
        "sampler": {"type": "independent", "sample_count": spp},
    }
