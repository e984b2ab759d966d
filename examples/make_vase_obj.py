"""Write ``vase.obj``: the clay vase of roughdiffuse.render as a triangle mesh (y up).

The surface of revolution r(y) of :func:`roughdiffuse.render.clay_vase_profile`, y in [−1, 1],
with smooth vertex normals from the profile's slope and flat caps at the foot and the lip.
Run once; the OBJ is bundled with the examples::

    python examples/make_vase_obj.py
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from roughdiffuse.io.atomic import atomic_write
from roughdiffuse.render import clay_vase_profile

HEIGHTS, AROUND = 48, 64


def vase_mesh() -> tuple[np.ndarray, np.ndarray, list[tuple[int, int, int]]]:
    """Vertices (N, 3), normals (N, 3) and triangles (1-based indices) of the vase."""
    y = np.linspace(-1.0, 1.0, HEIGHTS)
    r = clay_vase_profile(y)
    h = 1e-5
    slope = (clay_vase_profile(y + h) - clay_vase_profile(y - h)) / (2 * h)
    phi = np.linspace(0.0, 2 * math.pi, AROUND, endpoint=False)
    c, s = np.cos(phi), np.sin(phi)
    verts = np.stack(
        [r[:, None] * c[None], np.repeat(y[:, None], AROUND, 1), r[:, None] * s[None]], -1
    ).reshape(-1, 3)
    norms = np.stack(
        [
            np.broadcast_to(c, (HEIGHTS, AROUND)),
            -slope[:, None] + 0 * c,
            np.broadcast_to(s, (HEIGHTS, AROUND)),
        ],
        -1,
    ).reshape(-1, 3)
    norms /= np.linalg.norm(norms, axis=-1, keepdims=True)
    tris = []
    for i in range(HEIGHTS - 1):
        for j in range(AROUND):
            a, b = i * AROUND + j, i * AROUND + (j + 1) % AROUND
            c2, d = a + AROUND, b + AROUND
            tris += [(a + 1, c2 + 1, b + 1), (b + 1, c2 + 1, d + 1)]
    # caps: a centre vertex each, normal straight down / up
    base = len(verts)
    verts = np.vstack([verts, [[0, -1, 0]] + [list(v) for v in verts[:AROUND]]])
    verts = np.vstack(
        [verts, [[0, 1, 0]] + [list(v) for v in verts[(HEIGHTS - 1) * AROUND : HEIGHTS * AROUND]]]
    )
    norms = np.vstack(
        [norms, np.tile([0, -1, 0], (AROUND + 1, 1)), np.tile([0, 1, 0], (AROUND + 1, 1))]
    )
    foot, lip = base + 1, base + AROUND + 2
    for j in range(AROUND):
        k = (j + 1) % AROUND
        tris.append((foot, foot + 1 + j, foot + 1 + k))
        tris.append((lip, lip + 1 + k, lip + 1 + j))
    return verts, norms, tris


def main() -> None:
    verts, norms, tris = vase_mesh()
    lines = ["# clay vase of roughdiffuse (examples/make_vase_obj.py), y up, height 2"]
    lines += [f"v {x:.4f} {y:.4f} {z:.4f}" for x, y, z in verts]
    lines += [f"vn {x:.3f} {y:.3f} {z:.3f}" for x, y, z in norms]
    lines += [f"f {a}//{a} {b}//{b} {c}//{c}" for a, b, c in tris]
    out = Path(__file__).with_name("vase.obj")
    atomic_write(out, lambda tmp: tmp.write_text("\n".join(lines) + "\n", encoding="utf-8"))
    out.chmod(0o644)
    print(f"wrote {out} ({len(verts)} vertices, {len(tris)} triangles)")


if __name__ == "__main__":
    main()
