"""Adding a model to the package is writing its module: nothing else lists it.

The package is copied to a temporary folder, the module of docs/developer/adding-a-model.md
(Minnaert's law under the id ``minnaert-demo``) is written into the copy's ``models/``
folder, and a subprocess running the copy finds the model everywhere: ``roughdiffuse.models``
and ``rd.<Name>``, the registry (source ``roughdiffuse``), the command line (``models``,
``eval --model``), a fit, the explorer's ``/api/models`` record (``registry.to_json``, what
the server sends), the interface-wide test matrix (``tests/conftest.py`` ``all_models``) and,
if Mitsuba is installed, its plugin. Expected values come from Minnaert's closed form,
f = ρ/π (μi μo)^(k − 1).
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def package_copy(tmp_path_factory) -> Path:
    page = (ROOT / "docs" / "developer" / "adding-a-model.md").read_text(encoding="utf-8")
    module = re.findall(r"```python\n(.*?)```", page, flags=re.S)[0]
    assert "class MinnaertDemo(Model)" in module
    site = tmp_path_factory.mktemp("copy")
    shutil.copytree(
        ROOT / "src" / "roughdiffuse",
        site / "roughdiffuse",
        ignore=shutil.ignore_patterns("__pycache__"),
    )
    (site / "roughdiffuse" / "models" / "minnaert_demo.py").write_text(module, encoding="utf-8")
    return site


def _run(site: Path, *args: str) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(site), str(ROOT / "tests")])
    env["ROUGHDIFFUSE_CACHE_DIR"] = str(site / "cache")
    return subprocess.run(
        [sys.executable, "-P", *args], capture_output=True, text=True, timeout=600, env=env
    )


SCRIPT = """
import json
import numpy as np
import roughdiffuse as rd
from roughdiffuse import models, registry
from roughdiffuse.fit import Measurements, fit
from conftest import all_models

out = {"file": rd.__file__, "in_all": "MinnaertDemo" in models.__all__}
out["same_class"] = rd.MinnaertDemo is models.MinnaertDemo is registry.get("minnaert-demo").cls
out["source"] = registry.get("minnaert-demo").source
out["last"] = registry.ids()[-1]
out["api"] = {r["id"]: r for r in registry.to_json()}["minnaert-demo"]
out["matrix"] = sorted(repr(m) for m in all_models() if type(m).__name__ == "MinnaertDemo")
m = registry.create("minnaert-demo", albedo=0.5, k=0.8)
rng = np.random.default_rng(3)
ti = rng.uniform(0.05, 1.4, 300); tr = rng.uniform(0.05, 1.4, 300); dp = rng.uniform(0, 6.28, 300)
f = np.asarray(m.brdf(rd.spherical_to_vector(ti, 0.0), rd.spherical_to_vector(tr, dp)))
r = fit(type(m), Measurements.from_angles(ti, tr, dp, f), ("albedo", "k"))
out["fit"] = dict(zip(r.names, map(float, r.values)))
try:
    import mitsuba as mi
except ImportError:
    out["mitsuba"] = None
else:
    mi.set_variant("scalar_rgb")
    from roughdiffuse.integrations.mitsuba import register
    out["mitsuba"] = "roughdiffuse_minnaert_demo" in register()
    mi.load_dict({"type": "roughdiffuse_minnaert_demo", "k": 0.8})
print(json.dumps(out))
"""


def test_a_new_model_module_is_found_everywhere(package_copy):
    out = _run(package_copy, "-c", SCRIPT)
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout.strip().splitlines()[-1])
    assert res["file"].startswith(str(package_copy))  # the copy ran, not the checkout
    assert res["in_all"] and res["same_class"]
    assert res["source"] == "roughdiffuse" and res["last"] == "minnaert-demo"  # order 1000
    api = res["api"]
    assert api["glsl"] is True  # a closed form: the explorer prints its GLSL from its code
    assert [p["name"] for p in api["parameters"]] == ["albedo", "k"]
    assert res["matrix"], "the test matrix does not hold the new model"
    # exact, noise-free data: the fit recovers the parameters that made it
    assert res["fit"]["albedo"] == pytest.approx(0.5, abs=1e-6)
    assert res["fit"]["k"] == pytest.approx(0.8, abs=1e-6)
    if res["mitsuba"] is not None:
        assert res["mitsuba"] is True


def test_the_command_line_knows_the_new_model(package_copy):
    out = _run(package_copy, "-m", "roughdiffuse", "models")
    assert out.returncode == 0, out.stderr
    assert "minnaert-demo  Minnaert (demo)" in out.stdout
    out = _run(
        package_copy,
        *("-m", "roughdiffuse", "eval", "--model", "minnaert-demo", "--param", "k=0.8"),
        *("--albedo", "0.6", "--theta-i", "60", "--theta-r", "30"),
    )
    assert out.returncode == 0, out.stderr
    line = next(x for x in out.stdout.splitlines() if x.startswith("brdf"))
    expected = 0.6 / math.pi * (math.cos(math.radians(60)) * math.cos(math.radians(30))) ** -0.2
    assert float(line.split(":")[1]) == pytest.approx(expected, rel=1e-5)


def test_the_package_serves_every_model_class_from_the_scan():
    import roughdiffuse as rd
    from roughdiffuse import models, registry

    classes = {e.cls for e in registry.entries() if e.source == "roughdiffuse"}
    assert classes == set(models.builtin_classes())
    for cls in classes:  # rd.<Name> and roughdiffuse.models.<Name> are the registry's class
        assert getattr(rd, cls.__name__) is cls is getattr(models, cls.__name__)
        assert cls.__name__ in rd.__all__ and cls.__name__ in dir(rd)
    for name in rd.__all__:  # every listed name resolves ("from roughdiffuse import *")
        getattr(rd, name)
    assert callable(rd.oren_nayar) and rd.fastpath.evaluate is not None


EXPLORER_SCRIPT = """
import json, math
from explorer_browser import CHROMIUM, CHROMIUM_ARGS, frames, open_page
from playwright.sync_api import sync_playwright
from roughdiffuse.explorer import make_server, serve_in_thread, url_of

server = make_server("127.0.0.1", None)
serve_in_thread(server)
out = {}
with sync_playwright() as p:
    browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
    log = open_page(browser, url_of(server), 800, 600)
    page = log.page
    out["menu"] = page.eval_on_selector_all("#a-model option", "os => os.map(o => o.value)")
    page.select_option("#a-model", "minnaert-demo")
    frames(page)
    out["sliders"] = [k for k in ("albedo-r", "k", "sigma")
                      if page.evaluate(f"() => !document.getElementById('a-{k}-row').hidden")]
    out["sphere"] = page.evaluate(
        "() => { const c = document.getElementById('sphere'); const g = c.getContext('webgl2');"
        " const px = new Uint8Array(4); g.readPixels(c.width >> 1, c.height >> 1, 1, 1, g.RGBA,"
        " g.UNSIGNED_BYTE, px); return Array.from(px); }")
    cos = [0.5, 0.8, 0.3, 0.9, 0.2, 0.1]
    out["glsl"] = page.evaluate(
        "(c) => window.rdExplorer.evaluate({model: 'minnaert-demo', albedo: [0.5, 0.4, 0.3],"
        " k: 0.8}, c)", cos)
    out["errors"] = log.errors
    browser.close()
server.shutdown()
print(json.dumps(out))
"""


@pytest.mark.slow  # a Chromium and a server of the copy: about 15 s
def test_the_explorer_draws_the_new_model(package_copy):
    """The copy's explorer offers the new model in its menus, with its declared sliders, and
    draws it in Chromium: its GLSL, printed from the module's code, gives Minnaert's closed
    form f = ρ/π (μi μo)^(k − 1)."""
    pytest.importorskip("playwright")
    out = _run(package_copy, "-c", EXPLORER_SCRIPT)
    assert out.returncode == 0, out.stderr[-3000:]
    res = json.loads(out.stdout.strip().splitlines()[-1])
    assert "minnaert-demo" in res["menu"] and not res["errors"], res
    assert res["sliders"] == ["albedo-r", "k"]  # its own, not Oren–Nayar's σ
    r, g, b, _ = res["sphere"]
    assert r == g == b > 0  # the sphere's lit centre, grey (the declared albedo, 1)
    glsl = [res["glsl"][:3], res["glsl"][3:]]
    for (mu_i, mu_o, _), f in zip([(0.5, 0.8, 0.3), (0.9, 0.2, 0.1)], glsl, strict=True):
        want = [a / math.pi * (mu_i * mu_o) ** -0.2 for a in (0.5, 0.4, 0.3)]
        assert f == pytest.approx(want, rel=1e-5)
