"""``convert`` refuses what the user gave wrong before the solver sees it: one ParameterError
naming the argument, never SciPy's own message; the command line prints it in one line."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import cli
from roughdiffuse._validate import ParameterError
from roughdiffuse.fit.between_models import convert
from roughdiffuse.models.base import Model
from roughdiffuse.models.declaration import albedo_param


class _InfiniteAtGrazing(Model):
    """A source that is not finite for μi < 0.3 (as a model evaluated beyond its limits)."""

    albedo: Any = albedo_param("albedo")

    def _kernel(self, xp, mu_i, mu_o, cos_io, albedo):
        return xp.where(mu_i < 0.3, math.inf, albedo / math.pi + 0.0 * mu_o)


@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"n": 0}, "n must be in [1, 64]"),
        ({"n": 10**9}, "n must be in [1, 64]"),  # n³ pairs: memory, not a NumPy MemoryError
        ({"albedo_weight": math.nan}, "albedo_weight must be in [0, ∞)"),
        ({"albedo_weight": math.inf}, "albedo_weight must be in [0, ∞)"),
        ({"albedo_weight": -1.0}, "albedo_weight must be in [0, ∞)"),
    ],
)
def test_bad_arguments_are_named(kwargs, named):
    with pytest.raises(ParameterError) as info:
        convert(rd.OrenNayar(0.5, 0.3), "eon", **kwargs)
    assert str(info.value).startswith(named), info.value


def test_a_source_that_is_not_a_model_is_named():
    with pytest.raises(ParameterError, match="^source must be a roughdiffuse model"):
        convert("eon", "eon")


def test_a_source_with_values_that_are_not_finite_is_refused_before_the_solver():
    """SciPy's "Residuals are not finite in the initial point" would be the message."""
    with pytest.raises(ParameterError, match="BRDF is not finite at") as info:
        convert(_InfiniteAtGrazing(0.5), "eon", n=4)
    assert "Residuals" not in str(info.value)


def test_the_checks_keep_a_good_conversion():
    """Lambert in EON: EON at r = 0 is Lambert (Portsmouth et al. 2025), so the fit returns
    the albedo and a roughness near 0."""
    r = convert(rd.Lambert(0.6), "eon", n=6)
    assert r.params["albedo"] == pytest.approx(0.6, abs=1e-6)
    assert r.params["roughness"] == pytest.approx(0.0, abs=1e-4)
    assert np.isfinite(r.rms_f) and r.rms_f < 1e-6


def test_convert_on_the_command_line_is_one_line(capsys):
    argv = ["convert", "--model", "lunar-lambert", "--param", "limb_darkening=2e3", "--to", "eon"]
    status = cli.main(argv)
    out, err = capsys.readouterr()
    assert status == 2 and len(err.strip().splitlines()) == 1, err
    assert "limb_darkening" in err and "1000" in err


def test_a_coat_converts_to_itself():
    """A model converted to itself is itself (the exact answer): the target's albedo range is
    found with each colour parameter at either end, so a coat's absorption at its maximum
    (a black coat) does not make ``coated`` look unable to reach its own albedo."""
    source = rd.registry.create("coated", albedo=0.8, absorption=0.0)
    shape = {"base": "oren-nayar-full", "distribution": "ggx", "eta": 1.5, "roughness": 0.0,
             "sigma": source.base.sigma}  # fmt: skip
    got = convert(source, "coated", n=6, fixed=shape)
    assert got.params["albedo"] == pytest.approx(0.8, abs=1e-6)
    assert np.all(np.asarray(got.params["absorption"]) < 1e-6)
