"""The exported GLSL function in three.js beside roughdiffuse's own render
(docs/images/glsl-threejs.png).

1. export Oren–Nayar (full, σ = 30°, ρ = (0.8, 0.5, 0.2)) as a GLSL function, as
   ``roughdiffuse export --to glsl`` writes it;
2. paste it into a three.js ``ShaderMaterial`` on a sphere under a distant light, seen by an
   orthographic camera, render it in headless Chromium into a float render target
   (tests/js/sphere.html, the page of the test tests/test_export_glsl.py);
3. render the same sphere, light and camera with :func:`roughdiffuse.render.render` (one
   sample at each pixel's centre, as the shader) and show the two and their difference.

Run from the repository root: ``python examples/glsl_threejs.py [OUT.png]``. Needs Chromium
(/usr/bin/chromium), Playwright and three.js (``make install-js``: ``npm ci`` in tests/js).
"""

from __future__ import annotations

import math
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from playwright.sync_api import sync_playwright  # noqa: E402

import roughdiffuse as rd  # noqa: E402
from roughdiffuse.io.atomic import atomic_write  # noqa: E402
from roughdiffuse.render import (  # noqa: E402
    DistantLight,
    OrthographicCamera,
    Sphere,
    pixel_coordinates,
    render,
)

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
from explorer_browser import CHROMIUM, CHROMIUM_ARGS  # noqa: E402
from threejs_sphere import open_sphere_page, threejs_sphere  # noqa: E402

SIZE = 256
LIGHT = DistantLight(math.radians(50.0), math.radians(30.0), (1.0, 0.9, 0.8))
CAMERA = OrthographicCamera(math.radians(20.0), math.radians(100.0))
MIN_COS_VIEW = 0.1  # the rim left out of the comparison (see tests/test_export_glsl.py)


def main(out: str = "docs/images/glsl-threejs.png") -> None:
    model = rd.OrenNayar([0.8, 0.5, 0.2], math.radians(30.0), "full")
    glsl = exported(model, "glsl", "brdf.glsl").decode("utf-8")
    theirs, covered = on_page(
        lambda page: threejs_sphere(page, glsl, light=LIGHT, camera=CAMERA, size=SIZE)
    )
    ours, mask = render(model, Sphere(), LIGHT, CAMERA, size=SIZE, samples_per_pixel=1)
    inside = interior()
    top = float(ours.max())
    diff = side_by_side(theirs, ours, covered, "three.js ShaderMaterial\n(export --to glsl, "
                        "Chromium)", out)  # fmt: skip
    lit = inside[..., None] & (ours > 0.05 * top)
    same = np.array_equal(covered, mask == 1)
    print(f"sphere pixels: {int(covered.sum())} in three.js, {int((mask == 1).sum())} in "
          f"roughdiffuse ({'the same' if same else 'not the same'})")  # fmt: skip
    print(f"largest difference inside n·v >= {MIN_COS_VIEW}: {np.nanmax(diff):.2g} of the "
          f"brightest pixel; relative, where the radiance is > 5 % of it: "
          f"{float(np.max(np.abs(theirs - ours)[lit] / ours[lit])):.2g}")  # fmt: skip
    print(f"wrote {out}")


def exported(model: rd.Model, target: str, name: str) -> bytes:
    """The bytes of ``model`` exported to ``target`` as a file ``name`` (its summary
    printed)."""
    with tempfile.TemporaryDirectory() as tmp:
        result = rd.export(model, target, Path(tmp) / name)
        print(result.summary())
        return result.paths[0].read_bytes()


def on_page(draw: Callable[[Any], Any]) -> Any:
    """``draw(page)`` on the three.js page (tests/js/sphere.html) in headless Chromium."""
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            return draw(open_sphere_page(browser))
        finally:
            browser.close()


def interior() -> np.ndarray:
    """The pixels compared: the sphere where n·v ≥ MIN_COS_VIEW."""
    x, y = pixel_coordinates(Sphere(), CAMERA, SIZE)
    cos_view = np.sqrt(np.clip(1.0 - x[None, :] ** 2 - y[:, None] ** 2, 0.0, None))
    return cos_view >= MIN_COS_VIEW


def side_by_side(
    theirs: np.ndarray, ours: np.ndarray, covered: np.ndarray, label: str, out: str
) -> np.ndarray:
    """Save three.js's render (``label``), roughdiffuse's and their difference (largest
    channel, ÷ the brightest pixel, NaN on the rim) to ``out``; returns that difference."""
    inside = interior()
    top = float(ours.max())
    diff = np.where(inside, np.nanmax(np.abs(theirs - ours), axis=-1), np.nan) / top
    fig, axes = plt.subplots(1, 3, figsize=(10.5, 3.6))
    for ax, (title, img) in zip(
        axes,
        [(label, theirs), ("roughdiffuse.render\n(the model's own code, JAX)", ours)],
        strict=False,
    ):
        shown = np.clip(img / top, 0, 1) ** (1 / 2.2)
        ax.imshow(np.where(covered[..., None], shown, 0.25))  # the background grey
        ax.set_title(title, fontsize=9)
    cmap = plt.get_cmap("magma").copy()
    cmap.set_bad("0.85")
    im = axes[2].imshow(diff, cmap=cmap, vmin=0.0, vmax=float(np.nanmax(diff)))
    axes[2].set_title(
        "|three.js − roughdiffuse|, largest channel\n"
        f"(÷ brightest pixel; grey: rim, n·v < {MIN_COS_VIEW})",
        fontsize=9,
    )
    fig.colorbar(im, ax=axes[2], fraction=0.046, format="%.1e")
    for ax in axes:
        ax.set_axis_off()
    fig.tight_layout()
    atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=100, format="png", bbox_inches="tight"))
    plt.close(fig)
    return diff


if __name__ == "__main__":
    main(*sys.argv[1:])
