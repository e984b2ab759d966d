"""A polite library: importing roughdiffuse is light and changes no state its user owns.

Checked in fresh processes (``python -P``, so that nothing imported earlier by the test session
hides an import): ``import roughdiffuse`` imports none of the heavy optional dependencies;
importing every module and drawing figures leaves the matplotlib backend, the warnings
filters, NumPy's error state and JAX's configuration as they were; a call that computes in
float64 under JAX leaves ``jax_enable_x64`` as it found it. No timing here: start-up times are
in ``bench/RESULTS.md``.
"""

from __future__ import annotations

import json
import subprocess
import sys
import textwrap

import pytest

HEAVY = ("jax", "scipy", "matplotlib", "numba", "mitsuba", "drjit", "torch", "llvmlite")


def run_python(code: str) -> dict:
    """Run ``code`` in a new interpreter; it prints one JSON line last."""
    proc = subprocess.run(
        [sys.executable, "-P", "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_import_roughdiffuse_imports_no_heavy_dependency():
    got = run_python(
        f"""
        import json, sys
        import roughdiffuse as rd
        rd.OrenNayar(0.8, 0.3), rd.use_fastpath, rd.Mix  # the top-level names are there
        print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in {HEAVY!r})))
        """
    )
    assert got == []


def test_the_cli_parser_imports_no_heavy_dependency():
    """Every command's parser is built for ``roughdiffuse --help``: none may import them."""
    got = run_python(
        f"""
        import json, sys
        from roughdiffuse import cli
        cli.build_parser()
        print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in {HEAVY!r})))
        """
    )
    assert got == []


def test_modules_and_figures_leave_the_users_global_state_alone():
    pytest.importorskip("matplotlib")
    got = run_python(
        """
        import importlib, json, pkgutil, sys, warnings
        import matplotlib
        matplotlib.use("svg")                # the user's choice of backend
        import numpy as np
        np.seterr(all="warn", under="ignore")
        warnings.simplefilter("default")
        # the dependencies first: some add warnings filters of their own when imported
        # (SciPy does), which is theirs to answer for
        for name in ("scipy.optimize", "scipy.sparse", "scipy.special", "scipy.linalg",
                     "jax.numpy", "matplotlib.figure", "numba", "tqdm", "PIL.Image"):
            try:
                importlib.import_module(name)
            except ImportError:
                pass
        before = {
            "backend": matplotlib.get_backend(),
            "filters": len(warnings.filters),
            "err": np.geterr(),
        }
        try:
            import jax
            before["x64"] = bool(jax.config.read("jax_enable_x64"))
        except ImportError:
            jax = None

        import roughdiffuse
        skipped = ("roughdiffuse.integrations", "roughdiffuse.__main__", "roughdiffuse.bench._")
        for info in pkgutil.walk_packages(roughdiffuse.__path__, "roughdiffuse."):
            if not info.name.startswith(skipped):
                importlib.import_module(info.name)

        import roughdiffuse as rd
        from roughdiffuse import energy, plots
        fig = plots.plot_plane_of_incidence({"ON": rd.OrenNayar(0.8, 0.3)}, 0.5).figure
        fig.savefig("/dev/null", format="png")
        energy.plot_albedo({"ON": {"0.3": rd.OrenNayar(1.0, 0.3)}}, theta_o=np.radians([0.0, 60.0]))
        after = {
            "backend": matplotlib.get_backend(),
            "filters": len(warnings.filters),
            "err": np.geterr(),
        }
        if jax is not None:
            after["x64"] = bool(jax.config.read("jax_enable_x64"))
        after["pyplot"] = "matplotlib.pyplot" in sys.modules
        print(json.dumps({"before": before, "after": after}))
        """
    )
    before, after = got["before"], got["after"]
    # a plotting function makes its figure through pyplot, so plt.show() and Jupyter show it
    # (as seaborn and scikit-image do), and leaves the user's backend ("svg") as it was
    assert after.pop("pyplot") is True
    assert after == before


def test_a_float64_jax_call_does_not_leave_x64_switched_on():
    """The V-cavity solver computes in float64 under JAX (``_array.double_precision``); the
    caller's ``jax_enable_x64`` is unchanged afterwards, also after an error inside."""
    pytest.importorskip("jax")
    got = run_python(
        """
        import json
        import jax, jax.numpy as jnp
        import numpy as np
        from roughdiffuse._array import double_precision
        from roughdiffuse.simulate import cavity_radiance

        states = [bool(jax.config.read("jax_enable_x64"))]
        wi = jnp.asarray([0.3, 0.0, 0.95])
        wo = jnp.asarray([0.0, 0.2, 0.98])
        value = cavity_radiance(0.4, 0.0, wi, wo, bounces=1)
        states.append(bool(jax.config.read("jax_enable_x64")))
        try:
            with double_precision(jnp):
                raise RuntimeError("inside")
        except RuntimeError:
            pass
        states.append(bool(jax.config.read("jax_enable_x64")))
        states.append(str(jnp.zeros(1).dtype))
        print(json.dumps({"states": states, "finite": bool(np.isfinite(np.asarray(value)))}))
        """
    )
    assert got["states"] == [False, False, False, "float32"]
    assert got["finite"]
