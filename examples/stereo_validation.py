"""Lambertian against rough photometric stereo, on images the fit's model did not make.

1. A sphere and the clay vase, made of roughdiffuse's full Oren–Nayar plugin (albedo 0.7),
   rendered by Mitsuba's path tracer under 8 lights on a 35° ring; Mitsuba's ``aov``
   integrator gives the true normals.
2. A sphere of the exact V-cavity surface (``VCavity``, all bounces, albedo 0.7) rendered by
   roughdiffuse's renderer: a reflectance the full Oren–Nayar model only approximates.

Prints the Markdown tables of the README's photometric-stereo section::

    export DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1  # Mitsuba's llvm
    python examples/stereo_validation.py
"""

from __future__ import annotations

import argparse

import numpy as np

import roughdiffuse as rd
from roughdiffuse import stereo
from roughdiffuse.render import Sphere
from roughdiffuse.stereo.mitsuba_render import render_mitsuba


def row(label: str, sigma: float, data: stereo.StereoInput, normals: np.ndarray) -> str:
    """One table row: Lambertian and rough (full Oren–Nayar) errors and the fitted σ."""
    truth = normals[data.mask]
    lam = stereo.lambertian(data)
    res = stereo.rough(data, rd.OrenNayar(variant="full"), start=lam)
    e_lam = np.nanmean(stereo.angular_error(lam.normals, truth))
    e_rough = np.nanmean(stereo.angular_error(res.normals, truth))
    return (
        f"| {label} | {sigma} | {int(data.mask.sum())} | {e_lam:.2f}° | {e_rough:.2f}° | "
        f"{res.roughness:.4f} ± {res.roughness_se:.1g} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--spp", type=int, default=256)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args()
    header = (
        "| object | σ | pixels | Lambertian: mean angular error | rough (full Oren–Nayar): "
        "mean angular error | fitted σ |\n| --- | ---: | ---: | ---: | ---: | ---: |"
    )
    print(f"Mitsuba 3: {args.size}² pixels, {args.spp} samples per pixel, 8 lights at 35°\n")
    print(header)
    for shape in ("sphere", "vase"):
        for sigma in (0.3, 0.6):
            bsdf = {"type": "roughdiffuse_oren_nayar", "variant": "full", "sigma": sigma}
            bsdf["albedo"] = 0.7
            data, normals = render_mitsuba(
                bsdf,
                stereo.default_lights(8),
                shape=shape,
                size=args.size,
                spp=args.spp,
                variant=args.variant,
            )
            print(row(shape, sigma, data, normals), flush=True)
    print(f"\nThe exact V-cavity surface (VCavity), roughdiffuse's renderer, {args.size}² pixels\n")
    print(header)
    for sigma in (0.3, 0.6):
        data, normals = stereo.render_stereo(
            rd.VCavity(0.7, sigma), Sphere(), stereo.default_lights(8), args.size
        )
        print(row("sphere", sigma, data, normals), flush=True)


if __name__ == "__main__":
    main()
