"""A sphere rendered by three.js with an exported GLSL function, or an exported glTF file
loaded by three.js's GLTFLoader, read back as float radiance.

The page ``tests/js/sphere.html`` puts the function in a ``THREE.ShaderMaterial`` (the user's
way: the exported text pasted above a ``main``; ``tests/js/material.js`` is the material the
documentation shows) on a sphere under a distant light, seen by a
``THREE.OrthographicCamera`` framed as :class:`roughdiffuse.render.OrthographicCamera` frames
the same sphere, so that pixel (row, column) sees the same point in both renderers. The
fragment shader writes f E0 max(n·l, 0) to an RGBA float32 render target; alpha is 1 where the
sphere is and 0 elsewhere.

three.js comes from ``tests/js/node_modules`` (``npm ci`` in ``tests/js``, a step of ``make
test``); nothing is downloaded at run time: the page's requests are answered from that folder
by Playwright (:meth:`Page.route`), under an address that is never resolved.
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any
from urllib.parse import urlparse

import numpy as np

from explorer_browser import PageWithLog
from roughdiffuse.render import DistantLight, OrthographicCamera, Sphere

JS_DIR = Path(__file__).resolve().parent / "js"
THREE = JS_DIR / "node_modules" / "three" / "build" / "three.module.js"
ORIGIN = "http://roughdiffuse-threejs.invalid"

__all__ = ["JS_DIR", "THREE", "open_sphere_page", "threejs_gltf", "threejs_sphere"]


def _serve(route: Any) -> None:
    """Answer a request of the page with a file of ``tests/js`` (404 for anything else)."""
    relative = urlparse(route.request.url).path.lstrip("/")
    f = (JS_DIR / relative).resolve()
    if JS_DIR in f.parents and f.is_file():
        route.fulfill(path=f)
    else:
        route.fulfill(status=404, body="not found")


def open_sphere_page(browser: Any) -> PageWithLog:
    """A new page of ``browser`` with three.js loaded and ``window.renderSphere`` defined.

    Raises
    ------
    FileNotFoundError
        If three.js is not installed (``npm ci`` in ``tests/js``).
    """
    if not THREE.is_file():
        raise FileNotFoundError(
            f"three.js not installed ({THREE} missing): run `make test`, or "
            "`npm ci --prefix tests/js`"
        )
    page = browser.new_page()
    page.route(f"{ORIGIN}/**", _serve)
    log = PageWithLog(page)
    page.goto(f"{ORIGIN}/sphere.html")
    page.wait_for_selector("body[data-ready='1']", state="attached", timeout=60_000)
    return log


def threejs_sphere(
    page: PageWithLog,
    glsl: str,
    *,
    name: str = "rd_brdf",
    uniforms: dict[str, Any] | None = None,
    light: DistantLight | None = None,
    camera: OrthographicCamera | None = None,
    size: int = 64,
    radius: float = 1.0,
    normals: str = "exact",
) -> tuple[np.ndarray, np.ndarray]:
    """Render a sphere of ``radius`` whose material calls ``name(wi, wo)`` of ``glsl``.

    Parameters
    ----------
    page : PageWithLog
        From :func:`open_sphere_page`.
    glsl : str
        The exported function (``roughdiffuse export --to glsl``).
    name : str
        The function's name.
    uniforms : dict or None
        The values of the function's uniforms (an export with uniforms): a float, or three
        floats for a ``vec3``.
    light, camera
        As for :func:`roughdiffuse.render.render` (defaults: light and camera along +z).
    size : int
        Image side in pixels.
    normals : {"exact", "mesh"}
        ``"exact"``: the sphere's normal where each pixel centre's ray meets it, as
        roughdiffuse's ray tracer finds it; ``"mesh"``: the user's material of
        ``tests/js/material.js``, the normals of a ``SphereGeometry`` (256 × 128 segments)
        interpolated across its triangles.

    Returns
    -------
    image : float32 array (size, size, 3)
        Radiance per channel, row 0 at the top.
    mask : bool array (size, size)
        Where the sphere is (the pixel centre's ray meets it).
    """
    spec = _frame(light, camera, size, radius)
    spec.update(brdf=glsl, name=name, uniforms=uniforms, normals=normals)
    got = page.page.evaluate("(spec) => window.renderSphere(spec)", spec)
    if "error" in got:
        raise RuntimeError(f"three.js could not compile the shader: {got['error']}")
    return _image(got, size)


def _frame(
    light: DistantLight | None, camera: OrthographicCamera | None, size: int, radius: float
) -> dict[str, Any]:
    """The page's light and camera: ``camera`` framing a sphere of ``radius`` in ``size`` ×
    ``size`` pixels as :func:`roughdiffuse.render.render` frames it."""
    light = DistantLight() if light is None else light
    camera = OrthographicCamera() if camera is None else camera
    right, up, view = camera.basis()
    centre, pixel = camera.frame(Sphere(radius), size, size)
    cx, cy, half = float(centre @ right), float(centre @ up), 0.5 * size * pixel
    e0 = np.broadcast_to(np.asarray(light.irradiance, dtype=np.float64), (3,))
    return {
        "width": size,
        "height": size,
        "light": light.direction.tolist(),
        "irradiance": e0.tolist(),
        "view": view.tolist(),
        "up": up.tolist(),
        "left": cx - half,
        "right": cx + half,
        "top": cy + half,
        "bottom": cy - half,
        "radius": float(radius),
    }


def _image(got: dict[str, Any], size: int) -> tuple[np.ndarray, np.ndarray]:
    rgba = np.asarray(got["pixels"], dtype=np.float32).reshape(size, size, 4)
    return rgba[..., :3], rgba[..., 3] > 0.5


def threejs_gltf(
    page: PageWithLog,
    data: bytes,
    *,
    light: DistantLight | None = None,
    camera: OrthographicCamera | None = None,
    size: int = 64,
) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Render a glTF file (``roughdiffuse export --to gltf``: a unit sphere) as three.js loads
    it (``GLTFLoader``), lit by a ``DirectionalLight`` of colour E0 and intensity 1 along
    ``light``, seen by ``camera`` framed as for :func:`threejs_sphere`.

    Returns
    -------
    image, mask
        As :func:`threejs_sphere`'s (the mask: where the mesh is).
    material : dict
        The loaded material's ``type`` (``MeshPhysicalMaterial``), ``color``,
        ``diffuseRoughness``, ``specularIntensity`` and ``metalness``.
    """
    spec = _frame(light, camera, size, 1.0)
    spec["data"] = base64.b64encode(data).decode("ascii")
    got = page.page.evaluate("(spec) => window.renderGltf(spec)", spec)
    if "error" in got:
        raise RuntimeError(f"three.js could not load or render the file: {got['error']}")
    image, mask = _image(got, size)
    return image, mask, got["material"]
