"""Photometric-stereo images rendered by Mitsuba 3: a truth outside roughdiffuse's renderer.

The object (a sphere, the clay vase of :func:`roughdiffuse.render.clay_vase_profile` as a
triangle mesh, or the lumpy blob of :func:`blob_mesh`, which shadows itself) is rendered by
Mitsuba's ``direct`` integrator (direct light and cast shadows, as photometric stereo models
them: one shadow ray towards the light per sample; no BSDF sampling, which can never reach a
distant light, a delta: the images are those of the ``path`` integrator with ``max_depth`` 2),
under each distant light in turn, seen by an orthographic camera along −z (x right, y up,
the frame of :mod:`.inputs`).

One scene serves every light: the light's transform is a scene parameter, changed by
``mi.traverse`` between images, so Dr.Jit compiles the render's kernel once and finds it in
its cache for the other lights. A BSDF written in Python (roughdiffuse's plugins) is traced
again by each ``mi.render`` call, and that tracing is most of an image's time for a large
model such as the coated one (``bench/RESULTS.md``, "Mitsuba renders of the coated plugin").

Its BSDF is any Mitsuba BSDF, roughdiffuse's plugins included
(``{"type": "roughdiffuse_oren_nayar", "variant": "full", "sigma": 0.3, "albedo": 0.7}``).
The true normals come from Mitsuba's own ``aov`` integrator (``sh_normal``), averaged over
each pixel.

Mitsuba is an optional dependency: ``pip install mitsuba``. Its ``llvm`` variants need libLLVM
(see :mod:`roughdiffuse.integrations.mitsuba`). The caller's variant is restored afterwards.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .._validate import ParameterError
from .inputs import StereoInput

__all__ = ["MATERIALS", "RENDER_BASE", "blob_mesh", "render_mitsuba", "vase_mesh"]

INTEGRATORS: dict[str, dict[str, Any]] = {
    "direct": {"type": "direct", "emitter_samples": 1, "bsdf_samples": 0},
    "path": {"type": "path", "max_depth": 2},
}
"""The Mitsuba integrators :func:`render_mitsuba` takes: both give the direct light of one
distant light with cast shadows."""

MARGIN = 0.04
"""Frame margin around the object, as :class:`roughdiffuse.render.OrthographicCamera`."""


RENDER_BASE = {"albedo": 0.6, "sigma": 0.4}
"""The matte material (full Oren–Nayar); the coats' and the metal's bases have its albedo."""

MATERIALS: dict[str, dict[str, Any]] = {
    "matte": {"type": "roughdiffuse_oren_nayar", "variant": "full", **RENDER_BASE},
    "coat01": {"type": "roughdiffuse_coated", "base": "oren-nayar-full", **RENDER_BASE,
               "eta": 1.5, "roughness": 0.1, "distribution": "ggx"},
    "coat03": {"type": "roughdiffuse_coated", "base": "oren-nayar-full", **RENDER_BASE,
               "eta": 1.5, "roughness": 0.3, "distribution": "ggx"},
    "metal": {
        "type": "blendbsdf",
        "weight": 0.25,
        "bsdf_0": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.6}},
        "bsdf_1": {"type": "roughconductor", "distribution": "ggx", "alpha": 0.2, "material": "Al"},
    },
}
"""The materials of ``scripts/stereo_renders.py`` (Mitsuba BSDF descriptions by name):
``matte`` the full Oren–Nayar plugin; ``coat01`` and ``coat03`` the coated plugin, a coat of
η 1.5 and GGX α 0.1 or 0.3 over the matte material; ``metal`` Mitsuba's blend of a
Lambertian ``diffuse`` (weight 0.75) and an aluminium GGX ``roughconductor`` (α 0.2)."""


def vase_mesh(heights: int = 96, around: int = 128) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The clay vase as a closed triangle mesh (y up, height 2): vertices (N, 3), smooth
    vertex normals (N, 3) from the profile's slope, and triangles (M, 3), counter-clockwise
    seen from outside. The foot and the lip are closed by flat caps."""
    from ..render import clay_vase_profile

    y = np.linspace(-1.0, 1.0, heights)
    r = np.asarray(clay_vase_profile(y), dtype=np.float64)
    h = 1e-5
    slope = (np.asarray(clay_vase_profile(y + h)) - np.asarray(clay_vase_profile(y - h))) / (2 * h)
    phi = np.linspace(0.0, 2 * math.pi, around, endpoint=False)
    c, s = np.cos(phi), np.sin(phi)
    verts = np.stack([r[:, None] * c, np.repeat(y[:, None], around, 1), r[:, None] * s], -1)
    norms = np.stack(
        [
            np.broadcast_to(c, (heights, around)),
            -slope[:, None] + 0 * c,
            np.broadcast_to(s, (heights, around)),
        ],
        -1,
    )
    verts, norms = verts.reshape(-1, 3), norms.reshape(-1, 3)
    norms /= np.linalg.norm(norms, axis=1, keepdims=True)
    i, j = np.meshgrid(np.arange(heights - 1), np.arange(around), indexing="ij")
    a = i * around + j
    b = i * around + (j + 1) % around
    tris = np.concatenate(
        [
            np.stack([a, b, a + around], -1).reshape(-1, 3),
            np.stack([b, b + around, a + around], -1).reshape(-1, 3),
        ]
    )
    # caps: a centre vertex each, with copies of the rim vertices carrying the cap's normal
    parts_v, parts_n, parts_t = [verts], [norms], [tris]
    base = len(verts)
    for ring, centre, normal, flip in ((0, -1.0, -1.0, False), (heights - 1, 1.0, 1.0, True)):
        rim = verts[ring * around : (ring + 1) * around]
        parts_v.append(np.vstack([[0.0, centre, 0.0], rim]))
        parts_n.append(np.tile([0.0, normal, 0.0], (around + 1, 1)))
        k = np.arange(around)
        tri = np.stack([np.full(around, base), base + 1 + k, base + 1 + (k + 1) % around], -1)
        parts_t.append(tri[:, ::-1] if flip else tri)
        base += around + 1
    return np.vstack(parts_v), np.vstack(parts_n), np.vstack(parts_t)


def blob_mesh(
    heights: int = 96, around: int = 192
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A lumpy closed blob (a bunny's size of bumps and hollows, made here, not a scan):
    the unit sphere with radius r(θ, φ) = 1 + 0.25 sin³θ cos 3φ + 0.15 cos 2θ
    + 0.2 e^{−8 ‖ω − ω₁‖²} + 0.2 e^{−8 ‖ω − ω₂‖²} (two lobes leaning towards the camera, one
    up-left and one right, that cast shadows on the body), scaled into the unit ball. Returns
    vertices (N, 3), smooth vertex normals (N, 3; the area-weighted mean of the faces'
    normals) and counter-clockwise triangles (M, 3), as :func:`vase_mesh`."""
    theta = np.linspace(0.0, math.pi, heights)
    phi = np.linspace(0.0, 2 * math.pi, around, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    u = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1)
    r = 1.0 + 0.25 * np.sin(t) ** 3 * np.cos(3 * p) + 0.15 * np.cos(2 * t)
    for lobe in ([-0.45, 0.55, 0.7], [0.7, -0.1, 0.7]):
        w = np.asarray(lobe) / np.linalg.norm(lobe)
        r = r + 0.2 * np.exp(-8.0 * np.sum((u - w) ** 2, axis=-1))
    verts = (u * r[..., None]).reshape(-1, 3)
    verts /= np.max(np.linalg.norm(verts, axis=1))
    i, j = np.meshgrid(np.arange(heights - 1), np.arange(around), indexing="ij")
    a = i * around + j
    b = i * around + (j + 1) % around
    # z = cos θ: θ grows downwards from the pole, so (a, a + around, b) turns outwards
    tris = np.concatenate(
        [
            np.stack([a, a + around, b], -1).reshape(-1, 3),
            np.stack([b, a + around, b + around], -1).reshape(-1, 3),
        ]
    )
    cross = np.cross(verts[tris[:, 1]] - verts[tris[:, 0]], verts[tris[:, 2]] - verts[tris[:, 0]])
    norms = np.zeros_like(verts)
    for k in range(3):
        np.add.at(norms, tris[:, k], cross)
    norms /= np.maximum(np.linalg.norm(norms, axis=1, keepdims=True), 1e-30)
    return verts, norms, tris


def _shape(mi: Any, shape: str, bsdf: Any) -> dict:
    if shape == "sphere":
        return {"type": "sphere", "bsdf": bsdf}
    meshes = {"vase": vase_mesh, "blob": blob_mesh}
    if shape not in meshes:
        raise ParameterError(f"shape must be 'sphere', 'vase' or 'blob' (got {shape!r})")
    v, n, t = meshes[shape]()
    mesh = mi.Mesh(shape, len(v), len(t), has_vertex_normals=True)
    params = mi.traverse(mesh)
    params["vertex_positions"] = mi.Float(v.astype(np.float32).ravel())
    params["vertex_normals"] = mi.Float(n.astype(np.float32).ravel())
    params["faces"] = mi.UInt32(t.astype(np.uint32).ravel())
    params.update()
    mesh.set_bsdf(mi.load_dict(bsdf) if isinstance(bsdf, dict) else bsdf)
    return mesh


def _sensor(mi: Any, size: int, spp: int) -> dict[str, Any]:
    """An orthographic camera on +z looking down at the origin, framing [−1, 1]² plus the
    margin, ``size`` × ``size`` pixels of ``spp`` independent samples each."""
    from .._mitsuba_scene import orthographic_sensor

    half = 1.0 + 2.0 * MARGIN
    to_world = mi.ScalarTransform4f().look_at(
        origin=[0, 0, 10], target=[0, 0, 0], up=[0, 1, 0]
    ) @ mi.ScalarTransform4f().scale([half, half, 1.0])
    return orthographic_sensor(to_world, size, spp)


def _light_frame(mi: Any, d: np.ndarray) -> Any:
    """The directional emitter's frame: its local +z along −d (light travels away from the
    direction towards the light), as Mitsuba builds it from ``direction``."""
    up = [0.0, 1.0, 0.0] if abs(d[1]) < 0.9 else [1.0, 0.0, 0.0]
    return mi.ScalarTransform4f().look_at(origin=[0, 0, 0], target=(-d).tolist(), up=up)


def render_mitsuba(
    bsdf: dict,
    directions: Any,
    *,
    shape: str = "sphere",
    size: int = 64,
    spp: int = 64,
    variant: str = "llvm_ad_rgb",
    seed: int = 0,
    progress: bool | None = None,
    integrator: str = "direct",
) -> tuple[StereoInput, np.ndarray]:
    """Render ``shape`` under each light of ``directions`` with Mitsuba 3.

    Parameters
    ----------
    bsdf : dict
        A Mitsuba BSDF description (roughdiffuse's plugins are registered first).
    directions : array (K, 3)
        Directions towards the lights (camera frame), irradiance 1 each.
    shape : {"sphere", "vase", "blob"}
        Unit sphere, the clay vase (height 2) seen from its side, or :func:`blob_mesh`.
    size : int
        Image side in pixels.
    spp : int
        Samples per pixel (Monte Carlo noise falls as 1/√spp).
    variant : str
        Mitsuba variant.
    seed : int
        Seed of the first image's samples (image k: ``seed + k``).
    progress : bool, optional
        A progress bar over the lights (default: when standard error is a terminal).
    integrator : {"direct", "path"}
        Mitsuba's ``direct`` integrator without BSDF sampling, or its ``path`` integrator
        with ``max_depth`` 2, which also samples the BSDF (it can never reach the light):
        the same images by other random numbers, the BSDF traced and run twice.

    Returns
    -------
    data : StereoInput
        Grey images (the mean of Mitsuba's RGB), mask of fully covered pixels facing the
        camera within 80°.
    normals : array (H, W, 3)
        Mitsuba's shading normals of each pixel (camera frame).
    """
    import mitsuba as mi

    from ..integrations.drjit_llvm import require_llvm
    from ..integrations.mitsuba import register
    from ..progress import progress as bar

    if integrator not in INTEGRATORS:
        raise ParameterError(
            f"integrator must be one of {', '.join(map(repr, INTEGRATORS))} (got {integrator!r})"
        )
    require_llvm(variant)  # before any kernel: an old libLLVM aborts the process there
    previous = mi.variant()
    mi.set_variant(variant)
    try:
        register()
        dirs = np.asarray(directions, dtype=np.float64)
        dirs = dirs / np.linalg.norm(dirs, axis=1, keepdims=True)
        sensor = _sensor(mi, size, spp)
        obj = _shape(mi, shape, bsdf)
        images = []
        scene = mi.load_dict(
            {
                "type": "scene",
                "integrator": INTEGRATORS[integrator],
                "sensor": sensor,
                "light": {"type": "directional", "direction": [0, 0, -1], "irradiance": 1.0},
                "object": obj,
            }
        )
        # one scene, its light turned for each image: Dr.Jit reuses the compiled kernels
        params = mi.traverse(scene)
        with bar(len(dirs), "Mitsuba renders", unit="image", enabled=progress) as b:
            for k, d in enumerate(dirs):
                params["light.to_world"] = _light_frame(mi, d)
                params.update()
                image = mi.render(scene, seed=seed + k)
                images.append(np.array(image, dtype=np.float64).mean(axis=-1))
                b.update(1)
        aov = mi.load_dict(
            {
                "type": "scene",
                "integrator": {"type": "aov", "aovs": "nn:sh_normal"},
                "sensor": sensor,
                "object": obj,
            }
        )
        out = np.array(mi.render(aov, seed=seed), dtype=np.float64)
    finally:
        if previous is not None:
            mi.set_variant(previous)
    normals = out[..., :3]
    length = np.linalg.norm(normals, axis=-1, keepdims=True)
    # covered pixels: the normal averages to about unit length where every sample hit (a
    # pixel's normals spread by ~0.05 rad shorten it by ~1e-4; a missed sample by 1/spp)
    mask = (length[..., 0] > 0.995) & (normals[..., 2] > math.cos(math.radians(80)))
    normals = np.where(length > 0, normals / np.maximum(length, 1e-30), 0.0)
    data = StereoInput.from_arrays(np.stack(images), dirs, 1.0, mask=mask)
    return data, normals
