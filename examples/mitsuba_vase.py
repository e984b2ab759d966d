"""Render the bundled clay vase in Mitsuba 3 with roughdiffuse's Oren–Nayar plugin.

Left: Lambert (``roughdiffuse_lambert``); right: Oren–Nayar, σ = 0.6 rad
(``roughdiffuse_oren_nayar``, qualitative model), same albedo. A directional light 35° to the
right of the viewer, an orthographic camera, a grey Lambertian floor and the ``path``
integrator with interreflections (max_depth 4). The rough vase is flatter: its limb stays
bright instead of darkening as cos θi, as the lecture explains.

Usage (llvm variants need libLLVM >= 15, see docs/developer/mitsuba.md)::

    python examples/mitsuba_vase.py [--variant llvm_ad_rgb] [--spp 128] [-o mitsuba_vase.png]
"""

from __future__ import annotations

import argparse
import math
import os
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ALBEDO = [0.72, 0.42, 0.26]  # terracotta


def scene(mi, bsdf: dict, size: int, spp: int) -> dict:
    """The scene as a Mitsuba dict: vase mesh, floor, light, orthographic camera (the
    sensor of roughdiffuse's own Mitsuba scenes)."""
    from roughdiffuse._mitsuba_scene import orthographic_sensor

    light = [math.sin(math.radians(35.0)), 0.3, math.cos(math.radians(35.0))]
    view = np.array([0.0, 0.35, 1.0])
    view /= np.linalg.norm(view)
    to_world = mi.ScalarTransform4f().look_at(
        origin=(10 * view).tolist(), target=[0, -0.05, 0], up=[0, 1, 0]
    ) @ mi.ScalarTransform4f().scale([1.2, 1.2, 1.0])
    return {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": 4},
        "sensor": orthographic_sensor(to_world, size, spp),
        "sun": {"type": "directional", "direction": [-x for x in light], "irradiance": 2.6},
        "sky": {"type": "constant", "radiance": 0.08},
        "vase": {"type": "obj", "filename": str(HERE / "vase.obj"), "bsdf": bsdf},
        "floor": {
            "type": "rectangle",
            "to_world": mi.ScalarTransform4f()
            .translate([0, -1.0, 0])
            .rotate([1, 0, 0], -90)
            .scale([4, 4, 1]),
            "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.5] * 3}},
        },
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--spp", type=int, default=128)
    parser.add_argument("--size", type=int, default=320)
    parser.add_argument("-o", "--output", default=str(HERE / "mitsuba_vase.png"))
    args = parser.parse_args()

    if args.variant.startswith("llvm") and "DRJIT_LIBLLVM_PATH" not in os.environ:
        debian = Path("/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
        if debian.exists():
            os.environ["DRJIT_LIBLLVM_PATH"] = str(debian)
    import mitsuba as mi

    mi.set_variant(args.variant)
    from roughdiffuse.integrations import mitsuba as rdmi

    rdmi.register()
    albedo = {"type": "rgb", "value": ALBEDO}
    images = []
    for bsdf in (
        {"type": "roughdiffuse_lambert", "albedo": albedo},
        {"type": "roughdiffuse_oren_nayar", "sigma": 0.6, "albedo": albedo},
    ):
        images.append(np.array(mi.render(mi.load_dict(scene(mi, bsdf, args.size, args.spp)))))
    gap = np.ones((args.size, 4, 3), dtype=np.float32)
    both = np.concatenate([images[0], gap, images[1]], axis=1)
    mi.util.write_bitmap(args.output, both)  # PNG: sRGB curve applied by Mitsuba
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
