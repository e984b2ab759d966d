"""Fit, convert, export, render: the shipped samples in roughdiffuse, Cycles' and MaterialX's
diffuse, and Mitsuba 3 loading the exported scene (docs/images/renderers-side-by-side.png).

1. fit the full Oren–Nayar model to the BRDF samples that ship with the package;
2. convert the fit to Blender Cycles' Diffuse BSDF and to MaterialX's node (least squares);
3. export the Mitsuba 3 scenes (XML) of the fit and of the Cycles variant, load them with
   ``mi.load_file`` and render them;
4. export the fit to Blender (converted to the Diffuse BSDF) and render the script in Cycles,
   where Blender's Python is found (``make install-blender``);
5. show them beside roughdiffuse's own renders of the same models.

Run: ``python examples/renderers_side_by_side.py [OUT.png]`` (needs Mitsuba 3 and libLLVM
for its llvm variant: ``DRJIT_LIBLLVM_PATH``).
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import roughdiffuse as rd  # noqa: E402
from roughdiffuse.data import path  # noqa: E402
from roughdiffuse.exporters.mitsuba import LIGHT, MARGIN, SIZE  # noqa: E402
from roughdiffuse.fit import fit, read_csv  # noqa: E402
from roughdiffuse.io.atomic import atomic_write  # noqa: E402
from roughdiffuse.render import DistantLight, OrthographicCamera, Sphere, render  # noqa: E402


def ours(model: rd.Model) -> np.ndarray:
    image, _ = render(
        model,
        Sphere(),
        DistantLight(*np.radians(LIGHT)),
        OrthographicCamera(0.0, 0.0, margin=MARGIN),
        size=SIZE,
        samples_per_pixel=16,
    )
    return np.asarray(image)


def mitsuba(model: rd.Model, folder: Path) -> np.ndarray:
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    from roughdiffuse.integrations.mitsuba import register

    register()
    rd.export(model, "mitsuba", folder / "scene.xml")
    return np.array(mi.render(mi.load_file(str(folder / "scene.xml")), seed=7))[..., 0]


def blender(model: rd.Model, folder: Path) -> np.ndarray | None:
    """Cycles' render of the exported script: the sphere of the Blender check (a sun, an
    orthographic camera), averaged over each pixel as roughdiffuse's 16 samples are;
    ``None`` without Blender."""
    from roughdiffuse.exporters.blender_run import blender_command, run_scene

    if blender_command() is None:
        print("no Blender interpreter (make install-blender): its panel is left out")
        return None
    rd.export(model, "blender", folder / "material.py", blend=False)
    theta, phi = np.radians(LIGHT)
    light = [np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)]
    job = {"kind": "render", "shape": "sphere", "light": light, "view": [0.0, 0.0, 1.0],
           "size": SIZE, "scale": 2.0 * (1.0 + 2.0 * MARGIN), "samples": 64, "pixel_filter": "box",
           "output": str(folder / "cycles.npy")}  # fmt: skip
    run_scene(folder / "material.py", [job])
    return np.load(folder / "cycles.npy")[..., 0]


def main(out: str = "docs/images/renderers-side-by-side.png") -> None:
    fitted = fit(rd.OrenNayar, read_csv(path("samples.csv")), fixed={"variant": "full"}).model
    cycles = rd.convert(fitted, target="cycles-diffuse")
    mtlx = rd.convert(fitted, target="materialx-eon")
    with tempfile.TemporaryDirectory() as tmp:
        mi_fit = mitsuba(fitted, Path(tmp))
        mi_cycles = mitsuba(cycles.model, Path(tmp))
        bl_cycles = blender(fitted, Path(tmp))
    panels = [
        ("fit: Oren–Nayar full\nroughdiffuse", ours(fitted)),
        ("fit: Oren–Nayar full\nMitsuba 3, exported XML", mi_fit),
        (
            f"Cycles Diffuse BSDF, r = {cycles.params['roughness']:.3f}\nroughdiffuse",
            ours(cycles.model),
        ),
        ("Cycles Diffuse BSDF\nMitsuba 3, exported XML", mi_cycles),
        *(
            [("Cycles Diffuse BSDF\nBlender Cycles, exported .py", bl_cycles)]
            if bl_cycles is not None
            else []
        ),
        (f"MaterialX EON node, r = {mtlx.params['roughness']:.3f}\nroughdiffuse", ours(mtlx.model)),
    ]
    top = max(float(np.max(p)) for _, p in panels)
    fig, axes = plt.subplots(1, len(panels) + 1, figsize=(3.0 * (len(panels) + 1), 3.4))
    for ax, (title, img) in zip(axes, panels, strict=False):
        ax.imshow(np.clip(img / top, 0, 1) ** (1 / 2.2), cmap="gray", vmin=0, vmax=1)
        ax.set_title(title, fontsize=8)
    diff = panels[2][1] - panels[0][1]
    lim = float(np.max(np.abs(diff))) or 1.0
    im = axes[-1].imshow(diff / top, cmap="RdBu_r", vmin=-lim / top, vmax=lim / top)
    axes[-1].set_title("Cycles variant − fit\n(relative to the brightest pixel)", fontsize=8)
    fig.colorbar(im, ax=axes[-1], fraction=0.046)
    for ax in axes:
        ax.set_axis_off()
    fig.tight_layout()
    atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=100, format="png"))
    print(f"fit: {fitted}")
    print(cycles.summary())
    print(mtlx.summary())
    pairs = [
        ("Mitsuba", "fit", panels[0][1], mi_fit),
        ("Mitsuba", "cycles", panels[2][1], mi_cycles),
    ]
    if bl_cycles is not None:
        pairs.append(("Blender", "cycles", panels[2][1], bl_cycles))
    for who, name, a, b in pairs:
        lit = a > 0.02 * a.max()
        rel = np.abs(a - b)[lit].mean() / a[lit].mean()
        print(f"{who} vs roughdiffuse ({name}): mean |diff| {rel:.2%}")


if __name__ == "__main__":
    main(*sys.argv[1:])
