"""scripts/coat_interface_tables.py's fit is what coat_interface.npz holds.

Reference: the script's own least squares, run again on the file's own table (the data
shipped is current with the script that makes it; the fit is not run by the model).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np
import pytest

from roughdiffuse.models import coated

SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "coat_interface_tables.py"


@pytest.mark.parametrize("distribution", coated.COAT_DISTRIBUTIONS)
def test_stored_ratio_coefficients_are_the_scripts_fit(distribution):
    spec = importlib.util.spec_from_file_location("coat_interface_tables", SCRIPT)
    tables = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tables)
    with np.load(coated._TABLE) as t:
        table = {k: t[k] for k in t.files}
    refit = tables.fit(distribution, table)
    stored = table["coef"][coated.COAT_DISTRIBUTIONS.index(distribution)]
    # compared as the ratio c they give over the table's own points
    e, a, m = (g.ravel() for g in np.meshgrid(table["etas"], table["alphas"], table["mu"],
                                              indexing="ij"))
    cols = np.stack([(1 - 1 / e) ** i * a**j * (1 - m) ** k
                     for i, j, k in coated._FIT_POWERS], axis=-1)
    np.testing.assert_allclose(cols @ refit, cols @ stored, atol=1e-9)
