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


def test_hapke_asymmetry_is_xi_and_the_old_name_g_warns():
    """Hapke's Henyey–Greenstein asymmetry is ``xi`` (``g`` is the phase angle in its
    formulas); ``g`` still works in the constructor, the registry and the command line, with
    a DeprecationWarning, and gives the same model."""
    from roughdiffuse import registry
    from roughdiffuse.models.hapke import Hapke, Hapke2012

    for cls, model_id in ((Hapke, "hapke"), (Hapke2012, "hapke-2012")):
        assert "xi" in {p.name for p in cls.params} and "g" not in {p.name for p in cls.params}
        with pytest.warns(DeprecationWarning, match=f"{cls.__name__}\\(\\): .*'g' is renamed 'xi'"):
            old = cls(0.3, g=-0.4)
        assert old == cls(0.3, xi=-0.4)
        with pytest.warns(DeprecationWarning, match=f"model '{model_id}'"):
            assert registry.get(model_id).create(g=-0.4) == registry.get(model_id).create(xi=-0.4)
        with pytest.raises(TypeError, match="both 'g' and its new name 'xi'"):
            cls(0.3, g=0.1, xi=0.2)
    # the value reaches the phase function: at g = 0, HG = (1 − ξ)/(1 + ξ)² is 3.9 for
    # ξ = −0.4 (backscattering) against 1 for ξ = 0
    wi = np.array([0.0, 0.0, 1.0])
    assert float(Hapke(0.3, h=0.0, xi=-0.4).brdf(wi, wi)) > float(Hapke(0.3, h=0.0).brdf(wi, wi))


def test_cli_takes_the_old_hapke_name_with_a_one_line_warning(capsys):
    from roughdiffuse.cli import main

    assert main(["eval", "--model", "hapke", "--param", "g=-0.4"]) == 0
    out, err = capsys.readouterr()
    assert "xi=-0.4" in out
    assert err.strip() == (
        "roughdiffuse eval: warning: --param g: the keyword 'g' is renamed 'xi' (since "
        "roughdiffuse 0.2); 'g' will be removed"
    )
    assert main(["eval", "--model", "hapke", "--xi", "-0.4", "--param", "g=0.1"]) == 2
    assert "give xi once" in capsys.readouterr().err
