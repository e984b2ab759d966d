"""Shared helpers of the test suite: random directions, an independent quadrature, and the
session-wide fixtures (one explorer server and one Chromium per worker, one docs build per run).

The suite runs under pytest-xdist (``make test``: ``-n`` workers, ``--dist loadfile``); see
``docs/developer/testing.md`` for what may be shared and what must stay per test.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import roughdiffuse as rd
from example_models import points_of
from explorer_browser import browser, explorer_url  # noqa: F401 - session fixtures for all modules
from roughdiffuse import registry

ROOT = Path(__file__).resolve().parent.parent


def pytest_configure(config: pytest.Config) -> None:
    """Compiled code cached in pytest's cache folder (``.pytest_cache``), shared by the xdist
    workers and by the CLI subprocesses the tests start, and kept from one run to the next:

    * the fast path's kernels and the compiled walks (``ROUGHDIFFUSE_CACHE_DIR``): one folder
      for every test file, so that a kernel two files need is compiled once; compiling every
      model's kernels costs minutes of CPU, loading them seconds. A
      kernel's file is named by the digest of its generated source, so a changed generator
      compiles afresh.
    * JAX's persistent compilation cache: the fits compile a few programs per model, and
      reading them back saves most of the fit tests' CPU time. JAX keys each
      entry by the program, its compile options and the JAX/XLA versions.

    Nothing is cached under ``-p no:cacheprovider`` (the kernels then go to the user's cache
    folder, as outside the tests)."""
    cache = getattr(config, "cache", None)
    if cache is None:
        return
    os.environ["ROUGHDIFFUSE_CACHE_DIR"] = str(cache.mkdir("compiled-kernels") / "cache")
    import jax

    jax.config.update("jax_compilation_cache_dir", str(cache.mkdir("jax-compilation")))
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)


# Test-seconds per file (2 workers, `make test SLOW=1` on 2 cores): the Makefile turns off
# xdist's ordering by test count (--no-loadscope-reorder) and the files are handed out
# heaviest first, so that no long file starts last and keeps one core busy alone at the end.
# Only the order depends on these numbers; a file not listed comes after the listed ones.
FILE_SECONDS = {
    "test_bench.py": 360, "test_docs.py": 450, "test_cli_help_examples.py": 300,
    "test_fastpath.py": 300, "test_fit_cli.py": 200, "test_fit_samples.py": 130,
    "test_sampling.py": 120, "test_explorer_page.py": 150, "test_explorer_sizes.py": 90,
    "test_explorer_views.py": 90, "test_simulate_cavity.py": 100, "test_models_backends.py": 70,
    "test_readme.py": 60, "test_render_cli.py": 55, "test_explorer_glsl.py": 70,
    "test_models_coated.py": 50, "test_explorer_data.py": 40, "test_stereo_cli.py": 40,
    "test_stereo.py": 35, "test_simulate_surface.py": 30, "test_sampling_strategies.py": 28,
    "test_doctests.py": 28, "test_simulate_layered.py": 25, "test_mitsuba_registry.py": 24,
    "test_c_baselines.py": 20,
    "test_export_glsl.py": 90,
}


def long_tests() -> frozenset[str]:
    """The node ids listed in ``tests/long_tests.txt`` (``tests/long_tests.py`` writes it from
    a warm run): the tests that take 4 s or more, which ``make test`` leaves to the full set."""
    lines = Path(__file__).with_name("long_tests.txt").read_text().splitlines()
    return frozenset(line.split(None, 1)[1] for line in lines if line and not line.startswith("#"))


@pytest.hookimpl(tryfirst=True)  # before -m selects by mark
def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark the long tests slow (:func:`long_tests`); hand out the heaviest files first
    (FILE_SECONDS), keeping the order within a file."""
    listed = long_tests()
    for item in items:
        if item.nodeid in listed:
            item.add_marker(pytest.mark.slow)
    items.sort(key=lambda item: -FILE_SECONDS.get(item.path.name, 0))


def pytest_report_header(config: pytest.Config) -> list[str]:
    """The CPU, C library and numerical packages at the top of the run, so that a failure seen
    only on another machine (CI's CPU differs from session to session) can be read from its log."""
    import platform
    from importlib.metadata import PackageNotFoundError, version

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as info:
            names = (ln.split(":", 1)[1].strip() for ln in info if ln.startswith("model name"))
            cpu = next(names)
    except (OSError, StopIteration):
        pass
    packages = []
    for name in ("numpy", "scipy", "numba", "llvmlite", "jax", "torch", "mitsuba"):
        try:
            packages.append(f"{name} {version(name)}")
        except PackageNotFoundError:
            packages.append(f"{name} absent")
    libc = " ".join(platform.libc_ver())
    try:  # a worker that reaches it crashes (scripts/system-deps.sh)
        with open("/proc/sys/vm/max_map_count", encoding="ascii") as limit:
            libc += f", vm.max_map_count {limit.read().strip()}"
    except OSError:
        pass
    return [f"roughdiffuse machine: {cpu}, {os.cpu_count()} cores, {libc}", ", ".join(packages)]


def random_hemisphere(rng: np.random.Generator, n: int) -> np.ndarray:
    """Uniform random unit vectors with z >= 0, shape (n, 3)."""
    v = rng.normal(size=(n, 3))
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2])
    return v


def midpoint_albedo(model: rd.Model, mu_o: float, n_mu: int = 600, n_phi: int = 600) -> np.ndarray:
    """∫ f cos θi dωi by the midpoint rule in (μi, φi): independent of the package's rules.

    Midpoint error is O(h²) even across the kinks of the Oren–Nayar family (about 1e-6 at
    this resolution).
    """
    mu = (np.arange(n_mu) + 0.5) / n_mu
    phi = (np.arange(n_phi) + 0.5) / n_phi * 2 * np.pi
    m, p = np.meshgrid(mu, phi, indexing="ij")
    s = np.sqrt(1 - m**2)
    wi = np.stack([s * np.cos(p), s * np.sin(p), m], axis=-1)
    wo = np.array([np.sqrt(1 - mu_o**2), 0.0, mu_o])
    f = np.asarray(model.brdf(wi, wo))
    weight = m * (1.0 / n_mu) * (2 * np.pi / n_phi)
    if f.ndim == 3:
        weight = weight[..., None]
    return (f * weight).sum(axis=(0, 1))


def all_models(rgb: bool = False) -> list[rd.Model]:
    """One instance per test point of every closed-form model of the package, for
    interface-wide tests: each registry id's declared ``example`` point and the points listed
    for it in ``tests/example_models.py`` (:func:`example_models.points_of`), with every
    colour parameter set to 0.7 (or three channels with ``rgb``)."""
    a = [0.9, 0.5, 0.2] if rgb else 0.7
    out = []
    for entry in registry.entries():
        if entry.source != "roughdiffuse" or not entry.cls.closed_form:
            continue
        channels = {p.name for p in entry.parameters if p.channels}
        for point in points_of(entry):
            out.append(entry.create(**{**point, **dict.fromkeys(channels, a)}))
    return out


CHANNEL_CLASSES = frozenset({"Lambert", "Mix", "Coated"})
"""Models whose colour channels are not handled by the generic ``Model.channel`` alone (Mix
passes them to its components, Coated has a per-channel absorption); Lambert stands for the
generic path. Three-channel cases of other models run only in the full set (marked slow)."""


COMPILE_HEAVY_CLASSES = frozenset({"Coated"})
"""Models whose every kernel (Numba, XLA) takes tens of CPU-seconds to compile: their first
test point runs in ``make test``, the others in the full set."""


def rgb_cases(models: list[rd.Model], rgb: list[rd.Model]) -> list:
    """pytest parameters for grey ``models`` and their three-channel twins ``rgb``: every grey
    case (of COMPILE_HEAVY_CLASSES the first test point only), and the three-channel case of
    the first test point of each class in CHANNEL_CLASSES; the other cases are marked slow."""
    grey = frozenset(type(m).__name__ for m in models) - COMPILE_HEAVY_CLASSES
    return representative_cases(models, COMPILE_HEAVY_CLASSES, every=grey) + (
        representative_cases(rgb, CHANNEL_CLASSES)
    )


def representative_cases(
    models: list[rd.Model], classes: frozenset[str], every: frozenset[str] = frozenset()
) -> list:
    """pytest parameters for ``models``: the first test point of each class named in
    ``classes`` (every test point of a class in ``every``) runs in ``make test``, every other
    case only in the full set (marked slow)."""
    out = []
    seen: set[str] = set()
    for m in models:
        name = type(m).__name__
        fast = name in every or (name in classes and name not in seen)
        seen.add(name)
        out.append(pytest.param(m, id=repr(m), marks=() if fast else (pytest.mark.slow,)))
    return out


@pytest.fixture
def rng() -> np.random.Generator:
    return np.random.default_rng(1994)


def shared_tmp(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder of this pytest run shared by all its xdist workers (each worker's own base
    temporary folder without xdist): for work done once per run under a file lock."""
    base = tmp_path_factory.getbasetemp()
    return base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base


@pytest.fixture(scope="session")
def docs_site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The documentation site, built once per test run (as ``make docs``: -W --keep-going)
    into a temporary folder; its HTML folder. Under xdist the first worker to ask builds it
    while the others wait on a file lock, then all read the same build (a failed build is
    reported to each of them, not rebuilt)."""
    pytest.importorskip("sphinx")
    from filelock import FileLock

    root = shared_tmp(tmp_path_factory)
    out = root / "docs-site"
    failed = root / "docs-site.failed"
    with FileLock(str(root / "docs-site.lock")):
        if failed.exists():
            pytest.fail(failed.read_text(encoding="utf-8"))
        if not (out / "html" / "index.html").is_file():
            path = os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")])
            env = {**os.environ, "PYTHONPATH": path}
            cmd = [sys.executable, "-m", "sphinx", "-b", "html", "-W", "--keep-going", "-q",
                   "-d", str(out / "doctrees"), str(ROOT / "docs"), str(out / "html")]
            proc = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=900)
            if proc.returncode != 0:
                failed.write_text(f"sphinx failed:\n{proc.stderr[-4000:]}", encoding="utf-8")
                pytest.fail(failed.read_text(encoding="utf-8"))
    return out / "html"
