"""Render the photometric-stereo test objects with Mitsuba 3, in DiLiGenT's folder layout.

Three shapes (a sphere, the lumpy blob of :func:`roughdiffuse.stereo.mitsuba_render.blob_mesh`
which shadows itself, the clay vase) in four materials, each under the 96 lights of
:func:`roughdiffuse.stereo.diligent.diligent_lights` (DiLiGenT's pattern, approximated),
1 % signal-relative noise and 12-bit quantisation (:func:`roughdiffuse.stereo.diligent.
write_diligent`), one ``pmsData/<shape>-<material>PNG/`` folder each, the materials of
:data:`roughdiffuse.stereo.mitsuba_render.MATERIALS`:

* ``matte``: full Oren–Nayar, ρ = 0.6, σ = 0.4 (roughdiffuse's Mitsuba plugin);
* ``coat01`` and ``coat03``: the coated Oren–Nayar of ``--model coated`` itself
  (roughdiffuse's ``roughdiffuse_coated`` plugin): a dielectric coat of η = 1.5 and GGX
  α = 0.1 or 0.3 over the matte material (full Oren–Nayar, ρ = 0.6, σ = 0.4), so the fit's
  σ and α have a truth (its speed: ``bench/RESULTS.md``, "Mitsuba renders of the coated
  plugin");
* ``metal``: Mitsuba's own ``blendbsdf`` of a Lambertian ``diffuse`` (ρ = 0.6, weight 0.75)
  and a GGX ``roughconductor`` (aluminium, α = 0.2, weight 0.25): a specular lobe that no
  roughdiffuse model is, for every fit.

Mitsuba's ``llvm_ad_rgb`` variant on the CPU (its ``scalar_rgb`` cannot build the meshes from
arrays), its ``direct`` integrator (:func:`roughdiffuse.stereo.mitsuba_render.render_mitsuba`);
4 samples per pixel (a directional light is sampled exactly: the samples only average over
a pixel's footprint). The renders are generated, never committed::

    python scripts/stereo_renders.py OUT [--size 128] [--only sphere-coat03,...]

then ``roughdiffuse stereo --diligent OUT/pmsData/sphere-coat03PNG --model coated -o res/``
or ``python bench/stereo_coated.py --renders OUT``.
"""

from __future__ import annotations

import argparse
import time
import zlib
from pathlib import Path

SHAPES = ("sphere", "blob", "vase")

def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="folder to write pmsData/ into")
    parser.add_argument("--size", type=int, default=128, help="image side (default 128)")
    parser.add_argument("--spp", type=int, default=4, help="samples per pixel (default 4)")
    parser.add_argument("--only", help="comma-separated <shape>-<material> names")
    args = parser.parse_args(argv)
    from roughdiffuse.stereo.diligent import diligent_lights, write_diligent
    from roughdiffuse.stereo.mitsuba_render import MATERIALS, render_mitsuba

    wanted = set(args.only.split(",")) if args.only else None
    lights = diligent_lights()
    root = Path(args.out) / "pmsData"
    root.mkdir(parents=True, exist_ok=True)
    for shape in SHAPES:
        for material, bsdf in MATERIALS.items():
            name = f"{shape}-{material}"
            folder = root / f"{name}PNG"
            if (wanted and name not in wanted) or folder.exists():
                continue
            t = time.perf_counter()
            data, normals = render_mitsuba(
                bsdf, lights, shape=shape, size=args.size, spp=args.spp, seed=1
            )
            write_diligent(folder, data, normals, seed=zlib.crc32(name.encode()))
            print(
                f"{name}: {int(data.mask.sum())} pixels, {time.perf_counter() - t:.0f} s",
                flush=True,
            )


if __name__ == "__main__":
    main()
