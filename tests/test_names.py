"""One name per quantity: the view angle is ``theta_r`` in every public signature; the old
keyword ``theta_o`` still works with a DeprecationWarning."""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import energy
from roughdiffuse.models.sampling import weight_variance


def _public_callables():
    for info in pkgutil.walk_packages(rd.__path__, prefix="roughdiffuse."):
        if info.name.endswith("__main__") or "mitsuba" in info.name or "drjit" in info.name:
            continue
        module = importlib.import_module(info.name)
        for name in getattr(module, "__all__", []):
            obj = getattr(module, name)
            if callable(obj):
                yield f"{info.name}.{name}", obj


def test_no_public_signature_names_the_view_angle_theta_o():
    offenders = []
    for qualname, obj in _public_callables():
        try:
            params = inspect.signature(obj).parameters
        except (TypeError, ValueError):
            continue
        offenders += [f"{qualname}({p})" for p in params if p.startswith("theta_o")]
    assert offenders == []


def test_old_keyword_warns_and_gives_the_same_result():
    models = {"lambert": rd.Lambert(1.0)}
    th = np.radians([0.0, 60.0])
    with pytest.warns(DeprecationWarning, match="'theta_o' is renamed 'theta_r'"):
        old = energy.albedo_curves(models, theta_o=th)
    # Lambert with ρ = 1 reflects everything: albedo 1 at every view (closed form)
    np.testing.assert_allclose(old["lambert"], [1.0, 1.0], atol=1e-6)
    np.testing.assert_array_equal(
        old["lambert"], energy.albedo_curves(models, theta_r=th)["lambert"]
    )
    with pytest.warns(DeprecationWarning):
        assert weight_variance(rd.Lambert(1.0), theta_o=0.3, n=1000)[0] == pytest.approx(1.0)
    with pytest.raises(TypeError, match="both 'theta_o' and its new name 'theta_r'"):
        energy.albedo_curves(models, theta_o=th, theta_r=th)
