"""scripts/coat_lobe_tables.py measures what it says: the rough coat's reflection by two or
more facet events.

Independent references: Walter et al.'s single-scattering lobe in closed form (with the
height-correlated masking of the Smith microsurface), which the walk's first facet event
estimates, and the layered walk over a black base (roughdiffuse.simulate.layered.brdf,
its own next-event estimator of the whole interface), which the lobe and the table's f_ms
add up to.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse.models.coated import coat_reflection
from roughdiffuse.simulate import layered

SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "coat_lobe_tables.py"


def _script():
    spec = importlib.util.spec_from_file_location("coat_lobe_tables", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("distribution", ["ggx", "beckmann"])
def test_first_event_is_the_single_lobe_and_the_rest_the_walks_remainder(distribution):
    tables = _script()
    ti = np.radians([0.0, 40.0, 60.0, 75.0, 75.0, 30.0])
    tr = np.radians([0.0, 40.0, 60.0, 75.0, 60.0, 70.0])
    dp = np.radians([180.0, 180.0, 170.0, 180.0, 180.0, 90.0])
    f_ms, se_ms, f_ss, se_ss = tables.lobe(distribution, 1.5, 0.3, 20_000, 5, (ti, tr, dp))
    mi, mo = np.cos(ti), np.cos(tr)
    cio = mi * mo + np.sin(ti) * np.sin(tr) * np.cos(dp)
    closed = coat_reflection(np, mi, mo, cio, 1.5, 0.3, distribution)
    # Beckmann's Λ in the closed form is Walter's rational fit (within 0.3 % of erfc's)
    assert np.all(np.abs(f_ss - closed) < 4 * se_ss + 0.003 * closed), (f_ss / closed, se_ss)
    walk, se = layered.brdf(ti, tr, dp, rd.Lambert(0.0), eta=1.5, roughness=0.3,
                            distribution=distribution, samples=20_000, seed=9,
                            return_stderr=True)
    assert np.all(np.abs(closed + f_ms - walk) < 4 * np.hypot(se, se_ms) + 0.003 * walk)


@pytest.mark.parametrize("distribution", ["ggx", "beckmann"])
def test_stored_coefficients_are_the_scripts_fit(distribution):
    """coat_lobe.npz's coefficients are what the script's fit makes of the file's own table
    (the data is current with the script): the lobes of both sets of coefficients agree
    within 1e-6 of the coat's reflection plus the fit's floor at the table's geometries."""
    from roughdiffuse.models import coated

    tables = _script()
    with np.load(coated._LOBE_TABLE) as t:
        table = {k: t[k] for k in t.files}
    d = tables.DISTRIBUTIONS.index(distribution)
    refit = tables.fit(distribution, table)
    nodes = tuple(float(a) for a in table["alphas"])
    e, a = (g[..., None] for g in np.meshgrid(table["etas"], nodes, indexing="ij"))
    ti, tr, dp = table["theta_i"], table["theta_r"], table["delta_phi"]
    mi, mo = np.cos(ti), np.cos(tr)
    cio = mi * mo + np.sin(ti) * np.sin(tr) * np.cos(dp)
    cols = tables._lobe_columns(mi + 0 * e, mo + 0 * e, cio + 0 * e, e + 0 * mi, a + 0 * mi,
                                distribution, nodes)
    scale = coat_reflection(np, mi, mo, cio, e, a, distribution) + tables.LOBE_FLOOR
    diff = (cols @ refit - cols @ table["coef"][d]) / scale
    assert np.max(np.abs(diff)) < 1e-6
