"""The Mitsuba example: the bundled vase mesh renders with the Oren–Nayar plugin."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from mitsuba_setup import mitsuba_variant

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def _example():
    spec = importlib.util.spec_from_file_location("mitsuba_vase", EXAMPLES / "mitsuba_vase.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_vase_obj_normals_point_outwards():
    v, n = [], []
    for line in (EXAMPLES / "vase.obj").read_text().splitlines():
        if line.startswith("v "):
            v.append([float(x) for x in line.split()[1:]])
        elif line.startswith("vn "):
            n.append([float(x) for x in line.split()[1:]])
    v, n = np.array(v), np.array(n)
    assert len(v) == len(n) > 1000
    side = np.abs(v[:, 1]) < 0.99
    radial = v[side] * np.array([1.0, 0.0, 1.0])
    assert np.all(np.sum(radial * n[side], axis=-1) > 0)
    np.testing.assert_allclose(np.linalg.norm(n, axis=-1), 1.0, atol=2e-3)


def test_rough_vase_is_flatter_than_lambert():
    """Oren–Nayar brightens the limb relative to the centre (the lecture's flattening)."""
    mi = mitsuba_variant("llvm_ad_rgb")
    ex = _example()
    albedo = {"type": "rgb", "value": ex.ALBEDO}
    images = [
        np.array(mi.render(mi.load_dict(ex.scene(mi, bsdf, 96, 64)), seed=1))[..., 0]
        for bsdf in (
            {"type": "roughdiffuse_lambert", "albedo": albedo},
            {"type": "roughdiffuse_oren_nayar", "sigma": 0.6, "albedo": albedo},
        )
    ]
    # row 52 crosses the body (columns ~22-74), lit from the right: limb (64-70) / middle
    row = [img[52] for img in images]
    assert row[0][30:66].min() > 0.15  # the row crosses the lit body
    ratios = [r[64:70].mean() / r[46:58].mean() for r in row]
    assert ratios[1] > ratios[0] * 1.05, ratios
