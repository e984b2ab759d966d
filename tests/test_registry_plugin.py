"""A model from another package, as the developer page "Adding a model" builds it, is
first-class.

The package is built in a temporary folder from that page's own code blocks (its module and
its ``pyproject.toml`` entry point) and made installed the way an installer would: the module
and a ``.dist-info`` folder with ``entry_points.txt`` on the ``PYTHONPATH`` of a subprocess
(nothing is installed into the shared environment). Then ``roughdiffuse models``,
``roughdiffuse eval --model minnaert-demo``, ``render``, the fit, ``compare_models`` and the fast
path run on it. Expected values come from Minnaert's closed form, f = ρ/π (μi μo)^(k − 1).
"""

from __future__ import annotations

import json
import math
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _readme_blocks() -> dict[str, str]:
    """The code blocks of ``docs/developer/adding-a-model.md``, by language."""
    section = (ROOT / "docs" / "developer" / "adding-a-model.md").read_text(encoding="utf-8")
    blocks: dict[str, str] = {}
    for lang, body in re.findall(r"```(\w+)\n(.*?)```", section, flags=re.S):
        blocks.setdefault(lang, body)
    return blocks


@pytest.fixture(scope="module")
def plugin_path(tmp_path_factory) -> Path:
    blocks = _readme_blocks()
    assert blocks["python"].startswith("# minnaert_model.py")
    site = tmp_path_factory.mktemp("site")
    (site / "minnaert_model.py").write_text(blocks["python"], encoding="utf-8")
    project = tomllib.loads(blocks["toml"])["project"]
    dist = site / f"{project['name'].replace('-', '_')}-{project['version']}.dist-info"
    dist.mkdir()
    (dist / "METADATA").write_text(
        f"Metadata-Version: 2.1\nName: {project['name']}\nVersion: {project['version']}\n"
    )
    eps = project["entry-points"]
    lines = []
    for group, entries in eps.items():
        lines.append(f"[{group}]")
        lines.extend(f"{k} = {v}" for k, v in entries.items())
    (dist / "entry_points.txt").write_text("\n".join(lines) + "\n")
    return site


def _run(site: Path, *args: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    env = dict(os.environ)
    src = str(ROOT / "src")
    env["PYTHONPATH"] = os.pathsep.join([str(site), src, env.get("PYTHONPATH", "")])
    return subprocess.run(
        [sys.executable, *args], capture_output=True, text=True, timeout=timeout, env=env
    )


def test_readme_module_runs_its_doctest(plugin_path):
    out = _run(plugin_path, "-m", "doctest", "-v", str(plugin_path / "minnaert_model.py"))
    assert out.returncode == 0, out.stdout + out.stderr
    assert "3 passed and 0 failed" in out.stdout


def test_models_lists_the_plugin(plugin_path):
    out = _run(plugin_path, "-m", "roughdiffuse", "models", "--json")
    assert out.returncode == 0, out.stderr
    rec = {r["id"]: r for r in json.loads(out.stdout)}["minnaert-demo"]
    assert rec["source"] == "minnaert-model" and rec["glsl"] is True  # printed from its code
    assert [(p["name"], p["min"], p["max"], p["default"]) for p in rec["parameters"]] == [
        ("albedo", 0.0, 1.0, 1.0),
        ("k", 0.5, 1.5, 1.0),
    ]
    out = _run(plugin_path, "-m", "roughdiffuse", "models")
    assert "minnaert-demo  Minnaert (demo)" in out.stdout and "[from minnaert-model]" in out.stdout


def test_eval_and_render_the_plugin(plugin_path, tmp_path):
    out = _run(
        plugin_path,
        *("-m", "roughdiffuse", "eval", "--model", "minnaert-demo", "--param", "k=0.8"),
        *("--albedo", "0.6", "--theta-i", "60", "--theta-r", "30"),
    )
    assert out.returncode == 0, out.stderr
    line = next(x for x in out.stdout.splitlines() if x.startswith("brdf"))
    expected = 0.6 / math.pi * (math.cos(math.radians(60)) * math.cos(math.radians(30))) ** -0.2
    assert float(line.split(":")[1]) == pytest.approx(expected, rel=1e-5)
    # a parameter Minnaert does not take is a usage error
    args = ("-m", "roughdiffuse", "eval", "--model", "minnaert-demo", "--sigma", "9")
    out = _run(plugin_path, *args)
    assert out.returncode == 2 and "has no parameter 'sigma'" in out.stderr
    img = tmp_path / "m.npy"
    args = ("--model", "minnaert-demo", "--param", "k=0.7", "--size", "24", "--spp", "1")
    out = _run(plugin_path, "-m", "roughdiffuse", "render", *args, "-o", str(img))
    assert out.returncode == 0, out.stderr
    a = np.load(img)
    assert a.shape[:2] == (24, 24) and np.all(np.isfinite(a)) and a.max() > 0


SCRIPT = """
import json, math, warnings
import numpy as np
import roughdiffuse as rd
from roughdiffuse import fastpath, registry
from roughdiffuse.fit import Measurements, compare_models, fit

m = registry.create("minnaert-demo", albedo=0.5, k=0.8)
rng = np.random.default_rng(3)
ti = rng.uniform(0.05, 1.4, 400); tr = rng.uniform(0.05, 1.4, 400); dp = rng.uniform(0, 6.28, 400)
wi = rd.spherical_to_vector(ti, 0.0); wo = rd.spherical_to_vector(tr, dp)
f = np.asarray(m.brdf(wi, wo))
data = Measurements.from_angles(ti, tr, dp, f)
r = fit(type(m), data, ("albedo", "k"))
cmp = compare_models(data, ["lambert", "minnaert-demo", "oren-nayar"])
n = np.tile([0.0, 0.0, 1.0], (400, 1))
fast = fastpath.evaluate(m, n, wi, wo)
ref = np.asarray(m.radiance(n, wi, wo))
print(json.dumps({"values": dict(zip(r.names, map(float, r.values))), "best": cmp.best,
                  "fast": float(np.max(np.abs(fast - ref) / ref))}))
"""


def test_fit_compare_and_fast_path_on_the_plugin(plugin_path):
    out = _run(plugin_path, "-c", SCRIPT)
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout.strip().splitlines()[-1])
    # exact, noise-free data: the fit recovers the parameters that made it
    assert res["values"]["albedo"] == pytest.approx(0.5, abs=1e-6)
    assert res["values"]["k"] == pytest.approx(0.8, abs=1e-6)
    assert res["best"] == "minnaert-demo"
    assert res["fast"] < 1e-9  # float64 input: the fast path agrees to rounding
