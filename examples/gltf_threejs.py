"""The exported glTF file in three.js beside roughdiffuse's own render
(docs/images/gltf-threejs.png).

1. export EON (r = 0.8, ρ = (0.8, 0.5, 0.2)) as ``roughdiffuse export --to gltf`` writes it
   (a ``.glb``: a UV sphere of 64 × 32 segments, ``KHR_materials_diffuse_roughness``);
2. load it with three.js's ``GLTFLoader`` (a ``MeshPhysicalMaterial`` with
   ``diffuseRoughness``) and render it under a ``DirectionalLight``, seen by an orthographic
   camera, in headless Chromium into a float render target (tests/js/sphere.html);
3. render the same sphere, light and camera with :func:`roughdiffuse.render.render` and show
   the two and their difference; then split the difference into its two causes: three.js's
   EON (its polynomial E_F, tests/threejs_eon.py) at the sphere's exact normals, against
   roughdiffuse's; and the mesh's interpolated normals.

Run from the repository root: ``python examples/gltf_threejs.py [OUT.png]``. Needs Chromium
(/usr/bin/chromium), Playwright and three.js (``make install-js``: ``npm ci`` in tests/js).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from glsl_threejs import (
    CAMERA,
    LIGHT,
    MIN_COS_VIEW,
    SIZE,
    exported,
    interior,
    on_page,
    side_by_side,
)

import roughdiffuse as rd
from roughdiffuse.render import Sphere, pixel_coordinates, render

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from threejs_eon import three_eon  # noqa: E402
from threejs_sphere import threejs_gltf  # noqa: E402

RHO, R = np.array([0.8, 0.5, 0.2]), 0.8


def three_at_exact_normals() -> np.ndarray:
    """three.js's EON (transcribed) at the sphere's exact normal of each pixel centre."""
    right, up, view = CAMERA.basis()
    x, y = pixel_coordinates(Sphere(), CAMERA, SIZE)
    xx, yy = np.meshgrid(x, y)
    z = np.sqrt(np.clip(1.0 - xx**2 - yy**2, 0.0, None))
    n = xx[..., None] * right + yy[..., None] * up + z[..., None] * view
    light = LIGHT.direction
    nl = n @ light
    f = three_eon(nl[..., None], (n @ view)[..., None], float(light @ view), RHO, R)
    return f * np.asarray(LIGHT.irradiance) * np.clip(nl, 0.0, None)[..., None]


def main(out: str = "docs/images/gltf-threejs.png") -> None:
    model = rd.registry.create("eon", albedo=RHO.tolist(), roughness=R)
    data = exported(model, "gltf", "sphere.glb")
    theirs, covered, material = on_page(
        lambda page: threejs_gltf(page, data, light=LIGHT, camera=CAMERA, size=SIZE)
    )
    print(f"three.js loaded: {material}")
    ours, mask = render(model, Sphere(), LIGHT, CAMERA, size=SIZE, samples_per_pixel=1)
    diff = side_by_side(
        theirs, ours, covered, "three.js GLTFLoader, MeshPhysicalMaterial\n"
        "(export --to gltf, Chromium)", out,
    )  # fmt: skip
    inside = interior()
    top = float(ours.max())
    exact = three_at_exact_normals()
    lit = inside[..., None] & (ours > 0.05 * top)

    def said(a: np.ndarray, b: np.ndarray) -> str:
        gap = np.abs(a - b)
        return (f"{float(np.max(gap[inside[..., None].repeat(3, -1)])) / top:.2g} of the "
                f"brightest pixel, {float(np.max(gap[lit] / b[lit])):.2g} relative where "
                "lit above 5 %")  # fmt: skip

    print(f"sphere pixels: {int(covered.sum())} in three.js, {int((mask == 1).sum())} in "
          "roughdiffuse")  # fmt: skip
    print(f"three.js - roughdiffuse, inside n·v >= {MIN_COS_VIEW}: {np.nanmax(diff):.2g} of "
          f"the brightest pixel; mean {np.nanmean(diff):.2g}")  # fmt: skip
    print(f"  three.js's EON (polynomial E_F) at exact normals - roughdiffuse: {said(exact, ours)}")
    print(f"  three.js render - its EON at exact normals (the mesh): {said(theirs, exact)}")
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:])
