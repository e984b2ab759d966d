"""The explorer's layered truth (/api/layeredtruth.json) for Coated.

Reference: at η = 1 with a smooth coat the layer is invisible, so the walk is exactly the
base (Oren–Nayar full, model A's green albedo) in the plane of incidence -- a closed form
independent of the walk.
"""

from __future__ import annotations

import json
import math
import urllib.request

import numpy as np
import pytest

import roughdiffuse as rd
from explorer_browser import explorer_url  # noqa: F401 - fixture
from roughdiffuse.explorer.backend import THETA_R_DEG
from roughdiffuse.explorer.layered_truth import layered_truth


def test_invisible_coat_is_the_base_in_the_plane_of_incidence(explorer_url) -> None:  # noqa: F811
    q = {"model": "coated", "albedo": "0.5,0.7,0.9", "sigma": "0.35", "eta": "1.0",
         "coat_roughness": "0", "distribution": "ggx", "theta_i": "30"}
    with urllib.request.urlopen(explorer_url.rstrip("/") + "/api/layeredtruth.json?" +
                                "&".join(f"{k}={v}" for k, v in q.items())) as r:
        out = json.loads(r.read())
    tr = np.radians(np.abs(THETA_R_DEG))
    dp = np.where(np.asarray(THETA_R_DEG) >= 0, 0.0, math.pi)
    ti = math.radians(30.0)
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], -1)
    ref = rd.OrenNayar(0.7, 0.35, "full").brdf(wi, wo)
    np.testing.assert_allclose(out["brdf"], ref, rtol=1e-9)
    np.testing.assert_allclose(out["radiance"], ref * math.pi * math.cos(ti), rtol=1e-9)
    assert out["theta_r"] == list(THETA_R_DEG)


@pytest.mark.parametrize(("key", "value"), [("eta", "-1"), ("theta_i", "95"),
                                            ("distribution", "phong"), ("model", "lambert")])
def test_bad_query_named(key: str, value: str) -> None:
    q = {"model": "coated", "theta_i": "10", "distribution": "ggx", key: value}
    with pytest.raises(ValueError, match=key):
        layered_truth(q)


@pytest.mark.slow  # the walk compiled for an EON base: about 25 s
def test_the_walk_runs_over_the_chosen_base() -> None:
    """Coated over EON (the page's base menu): the invisible coat's walk is EON itself."""
    q = {"model": "coated", "base": "eon", "albedo": "0.5,0.7,0.9", "base_roughness": "0.6",
         "eta": "1.0", "coat_roughness": "0", "distribution": "ggx", "theta_i": "30"}
    out = layered_truth(q)
    tr = np.radians(np.abs(THETA_R_DEG))
    dp = np.where(np.asarray(THETA_R_DEG) >= 0, 0.0, math.pi)
    ti = math.radians(30.0)
    wi = np.array([math.sin(ti), 0.0, math.cos(ti)])
    wo = np.stack([np.sin(tr) * np.cos(dp), np.sin(tr) * np.sin(dp), np.cos(tr)], -1)
    np.testing.assert_allclose(out["brdf"], rd.EON(0.7, 0.6).brdf(wi, wo), rtol=1e-9)
    assert "EON r = 0.6" in out["note"]


def test_a_base_the_coat_does_not_take_is_named() -> None:
    q = {"model": "coated", "theta_i": "10", "distribution": "ggx", "base": "coated"}
    with pytest.raises(ValueError, match="base 'coated'.*coat on a coat.*'eon'"):
        layered_truth(q)
