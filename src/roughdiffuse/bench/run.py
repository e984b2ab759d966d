"""Throughput of every model: roughdiffuse's fast path against a C reference and plain NumPy.

Part of the package (it runs nothing from the current directory)::

    roughdiffuse bench                  # 2^22 and 2^24 geometries, 7 runs each; all parts
    roughdiffuse bench --sizes 22 --repeat 9
    python -m roughdiffuse.bench --sizes 22              # the same without the CLI
    python bench/run.py --sizes 22      # from a checkout: writes bench/RESULTS.md
    roughdiffuse bench --no-render --no-fit --no-simulate     # the models only
    roughdiffuse bench --sizes 10 --repeat 1 --no-first-call --memory-log2 0 \
        --fit-size 64 --fit-repeat 1 --simulate-repeat 1 --simulate-cavities 400 \
        --simulate-geometries 1 --output-dir /tmp/bench          # a quick check of every part

For each model and size it builds float32 (N, 3) arrays of normals, light and view directions
(as a user would pass them) and times, interleaved run by run so that the machine's noise hits
all three alike:

* ``fast``  — :func:`roughdiffuse.engine.fastpath.evaluate` (compiled from the model's own code);
* ``numpy`` — ``model.radiance(n, l, v)`` on the NumPy arrays with the fast path switched
  off (``roughdiffuse.use_fastpath(False)``: the array-API reference path);
* ``c``     — the same formula in C (``roughdiffuse/bench/c/kernels.c``, shipped with the
  package), compiled in this run with ``gcc -O3 -march=native -fopenmp -ffast-math`` and
  called through ctypes.

Then the default call, ``model.brdf(wi, wo)`` on (N, 3) local-frame arrays (the compiled path
chosen automatically), against a C loop of the same BRDF on the same arrays, in float32 and
float64.

Each variant's output is checked against ``model.radiance`` first. Reported: million
evaluations per second, median of ``--repeat`` runs after one warm-up, with min and max, and
the ratios fast/C and fast/NumPy (the numbers that count on a noisy shared machine). Also
measured: the first call of the fast path in a new process (cold and warm disk cache) and the
peak memory of evaluating 2^26 geometries; the renderer (a 1024² sphere, 4 samples per pixel,
against NumPy shading); the fit of (ρ, σ) to a 1-megapixel image against a SciPy baseline
(:mod:`.fit_bench`); the V-cavity solver, NumPy and JAX paths (:mod:`.simulate_bench`, run in
a subprocess with single-threaded BLAS); start-up times (``import roughdiffuse``,
``roughdiffuse --help``, ``roughdiffuse eval``) against ``python -c pass``. Writes
``RESULTS.md`` and ``results.json`` (atomically) to ``--output-dir`` (default: the current
directory). Timing helpers: :mod:`.timing`. Subprocesses run with ``python -P`` (the current
directory is not put on ``sys.path``).
"""

from __future__ import annotations

import argparse
import ctypes
import datetime as dt
import json
import math
import os
import platform
import shlex
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from .._validate import ParameterError
from ..programs import PYTHON, find_program
from ..programs import run as run_program
from .options import parser
from .timing import interleaved, rate_summary, rel_error, summary, write_atomic

HERE = Path(__file__).resolve().parent
C_SOURCE = HERE / "c" / "kernels.c"
"""The C reference, package data (``roughdiffuse/bench/c/kernels.c``)."""
CFLAGS = ["-O3", "-march=native", "-fopenmp", "-ffast-math", "-shared", "-fPIC"]

TARGET_C = 0.5
TARGET_C_QUALITATIVE = 0.8
TARGET_NUMPY = 10.0


# ------------------------------------------------------------------ models and C bindings
class BenchCase(NamedTuple):
    """One benchmarked model: its registry id, its label in the tables, the instance, and the
    C reference kernel of ``kernels.c`` with its arguments (``None``: no C kernel; the model
    is then measured against NumPy, and the tables say so)."""

    id: str
    label: str
    model: Any
    c_name: str | None
    c_params: tuple[Any, ...]


def _c_torrance_sparrow(model: Any) -> tuple[str, tuple[float, ...]]:
    from roughdiffuse.models import microfacet

    """The Gaussian Torrance–Sparrow kernel: η, σ and the distribution's normalisation at
    σ floored as the model floors it (the C zeroes σ = 0 itself)."""
    s = max(float(model.sigma), microfacet.SIGMA_FLOOR)
    norm = float(microfacet.gaussian_norm(np, np.float64(s), np.float64))
    return "rd_torrance_sparrow", (float(model.eta), float(model.sigma), norm)


def _c_coated(model: Any) -> tuple[str | None, tuple[Any, ...]]:
    """The registry's ``coated`` over the full Oren–Nayar model (its default base) or over
    Lambert (σ passed as 0, unused); the C file has no other base. The last argument is the
    array of the fitted coefficients of the coat's multiple scattering: its ratio's
    (:func:`~roughdiffuse.models.coated.ms_fit`), the lobes' widths
    (:data:`~roughdiffuse.models.coated.LOBE_WIDTHS`), the number of α nodes, the nodes and
    the lobes' coefficients (:func:`~roughdiffuse.models.coated.lobe_fit`)."""
    from roughdiffuse import registry

    base, base_id = model.base, registry.id_of(model.base)
    if base_id not in ("oren-nayar-full", "lambert"):
        return None, ()
    from roughdiffuse.models.coated import LOBE_WIDTHS, lobe_fit, ms_fit

    sigma = base.sigma if base_id == "oren-nayar-full" else 0.0
    args = (base.albedo, sigma, model.eta, model.roughness, model.absorption)
    name = "rd_coated_" + ("lambert_" if base_id == "lambert" else "") + model.distribution
    # the fitted coefficients of the coat's multiple scattering: data, not formula
    nodes, lobe = lobe_fit(model.distribution)
    coef = np.asarray([*ms_fit(model.distribution), *LOBE_WIDTHS, len(nodes), *nodes, *lobe],
                      np.float64)
    return name, (*(float(a) for a in args), coef)


def _c_args(*names: str) -> Callable[[Any], tuple[float, ...]]:
    return lambda m: tuple(float(getattr(m, n)) for n in names)


C_KERNELS: dict[str, Callable[[Any], tuple[str, tuple[float, ...]]]] = {
    "lambert": lambda m: ("rd_lambert", _c_args("albedo")(m)),
    "oren-nayar": lambda m: ("rd_oren_nayar_qualitative", _c_args("albedo", "sigma")(m)),
    "oren-nayar-full": lambda m: ("rd_oren_nayar_full", _c_args("albedo", "sigma")(m)),
    "fujii": lambda m: ("rd_fujii", _c_args("albedo", "roughness")(m)),
    "eon": lambda m: ("rd_eon", _c_args("albedo", "roughness")(m)),
    "torrance-sparrow": _c_torrance_sparrow,
    "burley": lambda m: ("rd_burley", _c_args("albedo", "roughness")(m)),
    "frostbite": lambda m: ("rd_frostbite", _c_args("albedo", "roughness")(m)),
    "burley-2015": lambda m: ("rd_burley_2015", _c_args("albedo", "roughness")(m)),
    "hammon": lambda m: ("rd_hammon", _c_args("albedo", "alpha")(m)),
    "chan": lambda m: ("rd_chan", _c_args("albedo", "alpha")(m)),
    "minnaert": lambda m: ("rd_minnaert", _c_args("albedo", "k")(m)),
    "lambert-sphere": lambda m: (f"rd_lambert_sphere_{m.variant}", _c_args("albedo")(m)),
    "hapke": lambda m: ("rd_hapke", _c_args("albedo", "b0", "h", "xi", "theta_bar", "hg2")(m)),
    "coated": _c_coated,
}
"""Registry id -> (C function of ``kernels.c``, its arguments) for a model instance: the C
references are this benchmark's business, not the models'."""


def bench_models() -> list[BenchCase]:
    """Every closed-form model of the package, from the registry: each id at its declared
    example point, once per choice of a categorical parameter the id leaves free."""
    from roughdiffuse import registry

    cases = []
    for entry in registry.entries():
        if entry.source != "roughdiffuse" or not entry.cls.closed_form:
            continue
        point = entry.example()
        # a free choice of formula (not one that changes the parameters: Coated's base)
        names = {k for p in entry.parameters for k in (p.when or {})}
        free = [p for p in entry.parameters if p.categorical and p.name not in names]
        choices = [(None, point)]
        if free:  # each choice with the parameters it takes (Coated's base: σ or r)
            choices = [(c, _point_for(entry, {**point, free[0].name: c}))
                       for c in free[0].choices or ()]
        for choice, params in choices:
            model = entry.create(**params)
            label = entry.label + (f" ({choice})" if choice is not None else "")
            c_name, c_params = C_KERNELS[entry.id](model) if entry.id in C_KERNELS else (None, ())
            if c_name is None:
                label += " [no C kernel: against NumPy]"
            cases.append(BenchCase(entry.id, label, model, c_name, c_params))
    return cases


def _point_for(entry: Any, values: dict[str, Any]) -> dict[str, Any]:
    """``values`` restricted to the parameters that exist for its categorical values, those
    missing at their declared example (else default)."""
    return {
        p.name: values.get(p.name, p.default if p.example is None else p.example)
        for p in entry.applicable(values)
    }


def build_c(workdir: Path) -> tuple[ctypes.CDLL | None, str]:
    """Compile roughdiffuse/bench/c/kernels.c into ``workdir``; return (library or None, a
    line saying what happened)."""
    gcc = find_program("gcc")
    if gcc is None:
        return None, "gcc not found: no C reference in this run"
    lib, obj = workdir / "kernels.so", workdir / "kernels.o"
    # compiled with -ffast-math, linked without it: gcc < 13 links crtfastmath.o into a
    # shared library built with -ffast-math, whose constructor turns on flush-to-zero for the
    # whole process that loads it (every later NumPy and Python computation in it)
    link_flags = [f for f in CFLAGS if f != "-ffast-math"]
    for cmd in (
        [gcc, *CFLAGS, "-c", "-o", str(obj), str(C_SOURCE)],
        [gcc, *link_flags, "-o", str(lib), str(obj), "-lm"],
    ):
        proc = run_program(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            return None, f"gcc failed: {proc.stderr.strip().splitlines()[-1:]}"
    # Idle OpenMP threads spin (libgomp's default), and spinning after each C call took a
    # core from the variant timed next (bench/RESULTS.md). Passive waiting cost C itself
    # nothing measurable.
    os.environ.setdefault("OMP_WAIT_POLICY", "passive")
    version = run_program([gcc, "--version"], capture_output=True, text=True).stdout
    line = version.splitlines()[0] if version else "gcc"
    cmd_text = " ".join(["gcc", *CFLAGS, "-c", "roughdiffuse/bench/c/kernels.c"]) + "; " + " ".join(
        ["gcc", *link_flags, "-o", "kernels.so", "kernels.o"]
    )
    policy = os.environ["OMP_WAIT_POLICY"]
    return ctypes.CDLL(str(lib)), f"{line}; `{cmd_text}`; OMP_WAIT_POLICY={policy}"


def _param_types(params: tuple[Any, ...], ctype: Any) -> list[Any]:
    """The ctypes of a kernel's parameters: ``ctype`` for a number, a pointer to double for a
    float64 array (Coated's fitted coefficients)."""
    double_ptr = ctypes.POINTER(ctypes.c_double)
    return [double_ptr if isinstance(p, np.ndarray) else ctype for p in params]


def _param_values(params: tuple[Any, ...]) -> tuple[Any, ...]:
    """The parameters as passed: numbers as they are, a float64 array by a pointer to its
    C-contiguous data (the pointer keeps the array alive)."""
    double_ptr = ctypes.POINTER(ctypes.c_double)
    return tuple(
        np.ascontiguousarray(p, np.float64).ctypes.data_as(double_ptr)  # keeps the array
        if isinstance(p, np.ndarray) else p
        for p in params
    )


def c_caller(lib: ctypes.CDLL, name: str, params: tuple[float, ...]) -> Callable[..., None]:
    fn = getattr(lib, name)
    ptr = ctypes.POINTER(ctypes.c_float)
    fn.argtypes = [ptr, ptr, ptr, ptr, ctypes.c_long, ctypes.c_float] + _param_types(
        params, ctypes.c_float)
    fn.restype = None
    params = _param_values(params)

    def call(n: np.ndarray, l: np.ndarray, v: np.ndarray, out: np.ndarray) -> None:
        for a in (n, l, v, out):
            assert a.dtype == np.float32 and a.flags.c_contiguous
        fn(
            n.ctypes.data_as(ptr),
            l.ctypes.data_as(ptr),
            v.ctypes.data_as(ptr),
            out.ctypes.data_as(ptr),
            out.shape[0],
            1.0,
            *params,
        )

    return call


# ------------------------------------------------------------------ data
def geometries(rows: int, seed: int = 1994) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """float32 (rows, 3) normals and light/view directions, not normalised.

    Normals are uniform on the sphere; light and view directions are random, flipped into the
    normal's hemisphere for 7 rows in 8 (so that most rows are lit and seen, some are not).
    Made in chunks, in float32, so that making 2^26 rows needs no float64 copy.
    """
    rng = np.random.default_rng(seed)
    out = [np.empty((rows, 3), np.float32) for _ in range(3)]
    step = 1 << 20
    for a in range(0, rows, step):
        b = min(a + step, rows)
        n = rng.standard_normal((b - a, 3), dtype=np.float32)
        n += np.float32(1e-3)
        out[0][a:b] = n
        for k in (1, 2):
            d = rng.standard_normal((b - a, 3), dtype=np.float32)
            flip = (np.einsum("ij,ij->i", d, n) < 0) & (rng.random(b - a) < 0.875)
            d[flip] *= -1
            d += np.float32(1e-3)
            out[k][a:b] = d
    return out[0], out[1], out[2]


def local_directions(rows: int, dtype: Any, seed: int = 2024) -> tuple[np.ndarray, np.ndarray]:
    """(rows, 3) wi and wo in the local frame, not normalised, 7 rows in 8 above the horizon."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(2):
        d = rng.standard_normal((rows, 3), dtype=np.float32).astype(dtype, copy=False)
        d[:, 2] = np.where(rng.random(rows) < 0.875, np.abs(d[:, 2]), d[:, 2]) + 1e-3
        out.append(d)
    return out[0], out[1]


def reference(method: Callable[..., Any], *args: Any) -> Any:
    """``method(*args)`` on the array-API reference path (the fast path switched off)."""
    import roughdiffuse as rd

    with rd.use_fastpath(False):
        return method(*args)


def c_brdf_caller(
    lib: ctypes.CDLL, name: str, params: tuple[float, ...], dtype: Any
) -> Callable[..., None]:
    """The C BRDF loop ``<name>_brdf_f32`` or ``_f64`` on (N, 3) wi, wo."""
    double = np.dtype(dtype) == np.float64
    fn = getattr(lib, f"{name}_brdf_{'f64' if double else 'f32'}")
    ctype = ctypes.c_double if double else ctypes.c_float
    ptr = ctypes.POINTER(ctype)
    fn.argtypes = [ptr, ptr, ptr, ctypes.c_long] + _param_types(params, ctype)
    fn.restype = None
    params = _param_values(params)

    def call(wi: np.ndarray, wo: np.ndarray, out: np.ndarray) -> None:
        for a in (wi, wo, out):
            assert a.dtype == dtype and a.flags.c_contiguous
        fn(wi.ctypes.data_as(ptr), wo.ctypes.data_as(ptr), out.ctypes.data_as(ptr),
           out.shape[0], *params)  # fmt: skip

    return call


def bench_brdf(
    log_rows: int,
    repeat: int,
    lib: ctypes.CDLL | None,
    models: list[BenchCase],
    dtype: Any,
) -> list[dict[str, Any]]:
    """The default call ``model.brdf(wi, wo)`` (compiled automatically) against a C loop of the
    same BRDF on the same (N, 3) arrays, interleaved; each checked against the reference path."""
    rows = 1 << log_rows
    wi, wo = local_directions(rows, dtype)
    out_c = np.empty(rows, dtype)
    check = slice(0, min(rows, 1 << 16))
    results = []
    for case in models:
        label, model, c_name, c_params = case.label, case.model, case.c_name, case.c_params
        variants: dict[str, Callable[[], Any]] = {"default": lambda m=model: m.brdf(wi, wo)}
        if lib is not None and c_name is not None:
            c_call = c_brdf_caller(lib, c_name, c_params, dtype)
            variants["c"] = lambda c_call=c_call: c_call(wi, wo, out_c)
        ref = np.asarray(reference(model.brdf, wi[check], wo[check]))
        errors = {}
        from roughdiffuse.engine.dispatch import BUILD_ROWS, MIN_ROWS

        warm = -(-BUILD_ROWS // rows) if rows >= MIN_ROWS else 0
        for _ in range(warm):  # the calls after which the kernel is built
            variants["default"]()
        for k, fn in variants.items():  # warm-up and the agreement check
            res = fn()
            got = out_c if k == "c" else res
            errors[k] = rel_error(np.asarray(got)[check], ref)
        times = interleaved(variants, repeat, steady=list(variants))
        entry: dict[str, Any] = {
            "model": label,
            "id": case.id,
            "dtype": np.dtype(dtype).name,
            "log2_rows": log_rows,
            "rows": rows,
            "max_rel_error_vs_reference": errors,
        }
        for k in variants:
            entry[k] = rate_summary(times[k], rows)
        if "c" in entry:
            entry["default_over_c"] = entry["default"]["median"] / entry["c"]["median"]
        results.append(entry)
        ratio = entry.get("default_over_c")
        print(
            f"brdf {entry['dtype']} 2^{log_rows} {label:<28} default "
            f"{entry['default']['median']:7.1f} M/s"
            + ("" if ratio is None else f"  C {entry['c']['median']:7.1f} M/s  /C {ratio:.2f}"),
            flush=True,
        )
    return results


# ------------------------------------------------------------------ agreement
def bench_size(
    log_rows: int,
    repeat: int,
    lib: ctypes.CDLL | None,
    models: list[BenchCase],
    with_numpy: bool,
) -> list[dict[str, Any]]:
    from roughdiffuse import fastpath

    rows = 1 << log_rows
    n, l, v = geometries(rows)
    out_fast = np.empty(rows, np.float32)
    out_c = np.empty(rows, np.float32)
    check = slice(0, min(rows, 1 << 16))
    results = []
    for case in models:
        label, model, c_name, c_params = case.label, case.model, case.c_name, case.c_params
        variants: dict[str, Callable[[], Any]] = {
            "fast": lambda m=model: fastpath.evaluate(m, n, l, v, out=out_fast),
        }
        if lib is not None and c_name is not None:
            c_call = c_caller(lib, c_name, c_params)
            variants["c"] = lambda c_call=c_call: c_call(n, l, v, out_c)
        if with_numpy or c_name is None:  # no C kernel: measured against NumPy
            variants["numpy"] = lambda m=model: reference(m.radiance, n, l, v)
        ref = np.asarray(reference(model.radiance, n[check], l[check], v[check]))
        errors = {}
        for k, fn in variants.items():  # warm-up (compiles) and the agreement check
            res = fn()
            got = {"fast": out_fast, "c": out_c}.get(k, res)
            errors[k] = rel_error(np.asarray(got)[check], ref)
        # rotate the order, and run the short variants once untimed right before their
        # timed run: after the long single-threaded NumPy run, the first few ms of a
        # two-thread run were slow (fast/C 0.64 interleaved with NumPy, 0.81 without it,
        # qualitative Oren-Nayar at 2^22), so each timing is of a steady state
        times = interleaved(variants, repeat, steady=[k for k in variants if k != "numpy"])
        entry: dict[str, Any] = {
            "model": label,
            "id": case.id,
            "repr": repr(model),
            "log2_rows": log_rows,
            "rows": rows,
            "max_rel_error_vs_reference": errors,
        }
        for k in variants:
            entry[k] = rate_summary(times[k], rows)
        if "c" in entry:
            entry["fast_over_c"] = entry["fast"]["median"] / entry["c"]["median"]
        if "numpy" in entry:
            entry["fast_over_numpy"] = entry["fast"]["median"] / entry["numpy"]["median"]
        results.append(entry)
        print(_line(entry), flush=True)
    return results


def _line(e: dict[str, Any]) -> str:
    parts = [f"2^{e['log2_rows']} {e['model']:<28}"]
    for k in ("fast", "c", "numpy"):
        if k in e:
            parts.append(f"{k} {e[k]['median']:7.1f} M/s")
    if "fast_over_c" in e:
        parts.append(f"fast/C {e['fast_over_c']:.2f}")
    if "fast_over_numpy" in e:
        parts.append(f"fast/NumPy {e['fast_over_numpy']:.1f}")
    return "  ".join(parts)


# ------------------------------------------------------------------ renderer
def sphere_samples(size: int, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Normals (float32, (size² k², 3)) and hit mask of a unit sphere framed as ``render``
    frames it (``render.pixel_coordinates``), k × k stratified samples per pixel."""
    from roughdiffuse.render import Sphere, pixel_coordinates

    xc, yc = pixel_coordinates(Sphere(), None, size)
    step = float(xc[1] - xc[0])
    off = ((np.arange(k) + 0.5) / k - 0.5) * step
    x = (xc[:, None] + off[None, :]).reshape(-1)
    y = (yc[:, None] - off[None, :]).reshape(-1)
    xx, yy = np.meshgrid(x, y)
    r2 = xx * xx + yy * yy
    hit = r2 < 1.0
    z = np.sqrt(np.maximum(1.0 - r2, 0.0))
    n = np.stack([np.where(hit, xx, 0.0), np.where(hit, yy, 0.0), np.where(hit, z, 1.0)], -1)
    return n.reshape(-1, 3).astype(np.float32), hit.reshape(-1)


def bench_render(repeat: int, size: int = 1024, spp: int = 4) -> dict[str, Any]:
    """A size² sphere, spp samples per pixel: ``render`` against NumPy and fast-path loops.

    The baselines shade the same samples with ``model.radiance`` (NumPy) or
    ``fastpath.evaluate`` on analytic sphere normals (no ray intersection), then average the
    samples of each pixel: the simplest honest loop for this one image.
    """
    import roughdiffuse as rd
    from roughdiffuse import fastpath

    try:
        from roughdiffuse.render import DistantLight, Sphere, render
    except ImportError as exc:  # pragma: no cover - the renderer is another part
        return {"error": f"renderer not available: {exc}"}
    k = int(round(math.sqrt(spp)))
    model = rd.OrenNayar(0.8, 0.3)
    theta = 0.5
    l_dir = np.array([math.sin(theta), 0.0, math.cos(theta)], np.float32)
    v_dir = np.array([0.0, 0.0, 1.0], np.float32)
    n, hit = sphere_samples(size, k)

    def average(radiance: np.ndarray) -> np.ndarray:
        img = np.where(hit, radiance, 0.0).reshape(size, k, size, k)
        return img.mean(axis=(1, 3))

    variants = {
        "render": lambda: render(
            model, Sphere(), DistantLight(theta), size=size, samples_per_pixel=spp
        )[0],
        "numpy": lambda: average(np.asarray(model.radiance(n, l_dir, v_dir))),
        "fast": lambda: average(fastpath.evaluate(model, n, l_dir, v_dir)),
    }
    images = {key: np.asarray(fn()) for key, fn in variants.items()}  # warm-up (jit)
    times = interleaved(variants, repeat)
    samples = size * size * spp
    res: dict[str, Any] = {"size": size, "spp": spp, "samples": samples}
    for key in variants:
        res[key] = rate_summary(times[key], samples)
    res["max_abs_difference_vs_render"] = {
        key: float(np.max(np.abs(images[key] - images["render"]))) for key in ("numpy", "fast")
    }
    res["render_over_numpy"] = res["render"]["median"] / res["numpy"]["median"]
    res["fast_over_numpy"] = res["fast"]["median"] / res["numpy"]["median"]
    return res


# ------------------------------------------------------------------ fit and solver
def bench_fit(repeat: int, size: int) -> dict[str, Any]:
    """:mod:`.fit_bench`: our fit against the SciPy baseline, every case."""
    from . import fit_bench

    return {"image_size": size, "repeat": repeat, "rows": fit_bench.bench_fit(repeat, size=size)}


SOLVER_ENV = {"OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "MKL_NUM_THREADS": "1"}
"""Environment of the solver's subprocess: single-threaded BLAS (its matrices are small)."""


def bench_simulate(repeat: int, cavities: int, geometries: int, cases: str) -> dict[str, Any]:
    """:mod:`.simulate_bench` in a subprocess with :data:`SOLVER_ENV`; its JSON rows.

    This process has imported NumPy (and its BLAS threads) already, so the solver runs in a
    new one, where BLAS starts single-threaded.
    """
    cmd = [
        *PYTHON,
        "-m",
        "roughdiffuse.bench.simulate_bench",
        "--repeat", str(repeat),
        "--cavities", str(cavities),
        "--geometries", str(geometries),
        "--json", "-",
    ]  # fmt: skip
    if cases:
        cmd += ["--cases", cases]
    res: dict[str, Any] = {
        "repeat": repeat,
        "cavities": cavities,
        "geometries": geometries,
        "environment": SOLVER_ENV,
    }
    out = run_program(cmd, env=SOLVER_ENV, capture_output=True, text=True)
    if out.returncode != 0:
        res["error"] = (out.stderr.strip().splitlines() or ["failed"])[-1]
        return res
    res["rows"] = json.loads(out.stdout.strip().splitlines()[-1])
    return res


# ------------------------------------------------------------------ first call and memory
_FIRST_CALL = """
import time, json, sys
t0 = time.perf_counter()
import numpy as np
import roughdiffuse as rd
from roughdiffuse.bench.run import local_directions
t1 = time.perf_counter()
wi, wo = local_directions(1 << 22, np.float32)
t2 = time.perf_counter()
rd.OrenNayar(0.8, 0.3).brdf(wi, wo)
t3 = time.perf_counter()
rd.OrenNayar(0.8, 0.5).brdf(wi, wo)
t4 = time.perf_counter()
print(json.dumps({"import_s": t1 - t0, "first_call_s": t3 - t2, "second_call_s": t4 - t3,
                  "compiled": "numba" in sys.modules}))
"""


def first_call() -> dict[str, Any]:
    """First default call ``OrenNayar(0.8, 0.3).brdf(wi, wo)`` on 2^22 float32 rows in a new
    process (import and data excluded): with an empty kernel cache, then with the cache; and
    a second call with a new σ (the same kernel)."""
    res: dict[str, Any] = {}
    with tempfile.TemporaryDirectory() as tmp:
        env = {"ROUGHDIFFUSE_CACHE_DIR": tmp}
        for label in ("cold_cache", "warm_cache"):
            out = run_program([*PYTHON, "-c", _FIRST_CALL], env=env, capture_output=True, text=True)
            if out.returncode != 0:
                res[label] = {"error": out.stderr.strip().splitlines()[-1:]}
            else:
                res[label] = json.loads(out.stdout.strip().splitlines()[-1])
    return res


_MEMORY = """
import json, sys
import numpy as np
import roughdiffuse as rd
from roughdiffuse import fastpath
from roughdiffuse.bench.run import geometries

def status(key):
    for line in open("/proc/self/status"):
        if line.startswith(key):
            return int(line.split()[1]) * 1024
rows = 1 << {log_rows}
model = rd.OrenNayar(0.8, 0.3)
z = np.ones((4, 3), np.float32)
fastpath.evaluate(model, z, z, z)          # compile before measuring
n, l, v = geometries(rows)
rss0 = status("VmRSS:")
open("/proc/self/clear_refs", "w").write("5")   # reset the peak (VmHWM)
out = fastpath.evaluate(model, n, l, v)
peak = status("VmHWM:")
inputs = n.nbytes + l.nbytes + v.nbytes
print(json.dumps({{"rows": rows, "inputs_bytes": inputs, "output_bytes": out.nbytes,
                  "rss_before_bytes": rss0, "peak_bytes": peak,
                  "extra_bytes": peak - rss0}}))
"""


def memory(log_rows: int) -> dict[str, Any]:
    """Peak memory of one fast-path evaluation of 2^log_rows rows, in a fresh process."""
    code = _MEMORY.format(log_rows=log_rows)
    out = run_program([*PYTHON, "-c", code], capture_output=True, text=True)
    if out.returncode != 0:
        return {"error": out.stderr.strip().splitlines()[-1:]}
    res = json.loads(out.stdout.strip().splitlines()[-1])
    # memory used while evaluating: everything resident at the peak (inputs included) minus
    # what the process held before the inputs were made is not measurable here; we report
    # the peak over the inputs + output, and the growth during the call
    res["ratio_peak_over_inputs_output"] = (res["rss_before_bytes"] + res["extra_bytes"]) / (
        res["inputs_bytes"] + res["output_bytes"]
    )
    res["ratio_extra_over_output"] = res["extra_bytes"] / res["output_bytes"]
    return res


# ------------------------------------------------------------------ start-up
STARTUP = {
    "python -c pass": ["-c", "pass"],
    "import numpy": ["-c", "import numpy"],
    "import roughdiffuse": ["-c", "import roughdiffuse"],
    "roughdiffuse --help": ["-m", "roughdiffuse", "--help"],
    "roughdiffuse eval": [
        "-m", "roughdiffuse", "eval", "--model", "oren-nayar", "--sigma", "20",
        "--albedo", "0.8", "--theta-i", "30", "--theta-r", "60",
    ],
}  # fmt: skip
"""The commands timed by :func:`startup` (``python -P`` + these arguments)."""

STARTUP_TARGETS = {"import roughdiffuse": 0.3, "roughdiffuse --help": 0.5, "roughdiffuse eval": 1.0}
"""Targets in seconds: above the bare interpreter for the import, wall time for the CLI."""


def startup(repeat: int) -> dict[str, Any]:
    """Wall time of each :data:`STARTUP` command in a new process, interleaved, ``repeat`` runs
    each after one warm-up (the OS's file cache); medians against ``python -c pass``."""
    import time

    times: dict[str, list[float]] = {k: [] for k in STARTUP}
    for run_ in range(repeat + 1):
        for label, args in STARTUP.items():
            t0 = time.perf_counter()
            proc = run_program([*PYTHON, *args], capture_output=True, text=True)
            elapsed = time.perf_counter() - t0
            if proc.returncode != 0:
                return {"error": f"{label}: {(proc.stderr.strip().splitlines() or ['?'])[-1]}"}
            if run_:
                times[label].append(elapsed)
    res: dict[str, Any] = {"repeat": repeat}
    base = summary(times["python -c pass"])["median"]
    for label, values in times.items():
        stats = summary(values)
        res[label] = {**stats, "above_python": stats["median"] - base}
    return res


# ------------------------------------------------------------------ report
def _fmt(s: dict[str, float] | None) -> str:
    if not s:
        return "–"
    return f"{s['median']:.0f} ({s['min']:.0f}–{s['max']:.0f})"


def _fast_path_section(meta: dict[str, Any], results: list[dict[str, Any]]) -> list[str]:
    """The title, the machine, and the fast path against C and NumPy (``results``)."""
    lines = [
        "# Benchmark results",
        "",
        f"Produced by `{meta['command']}` on {meta['date']} — {meta['cores']} cores "
        f"({meta['cpu']}), Python {meta['python']}, NumPy {meta['numpy']}, "
        f"Numba {meta['numba']}, JAX {meta.get('jax', '–')}, SciPy {meta.get('scipy', '–')}.",
        f"C reference: {meta['c_compiler']}.",
        "",
        "Radiance of each model on float32 (N, 3) arrays of n, l, v, in million evaluations "
        f"per second: median of {meta['repeat']} runs after a warm-up, (min–max); the "
        "variants take turns in a rotating order, and each timed run of `fast` and `C` "
        "follows an untimed run of itself (steady state). "
        "`fast` is `roughdiffuse.engine.fastpath.evaluate`, `NumPy` is `model.radiance` on the "
        "same NumPy arrays (fast path off), `C` is `roughdiffuse/bench/c/kernels.c`. The ratios "
        "are what counts: this machine "
        "is shared and noisy. Targets: fast/C ≥ 0.5 (≥ 0.8 for the qualitative Oren–Nayar "
        "model), fast/NumPy ≥ 10.",
        "",
        "| N | model | fast | C | NumPy | fast/C | fast/NumPy | max rel. error (fast, C) |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for e in results:
        err = e["max_rel_error_vs_reference"]
        fc = e.get("fast_over_c")
        fn = e.get("fast_over_numpy")
        target = TARGET_C_QUALITATIVE if "qualitative" in e["model"] else TARGET_C
        fc_txt = "–" if fc is None else f"{fc:.3f}" + ("" if fc >= target else " ✗")
        fn_txt = "–" if fn is None else f"{fn:.1f}" + ("" if fn >= TARGET_NUMPY else " ✗")
        err_txt = ", ".join(f"{err[k]:.1e}" for k in ("fast", "c") if k in err)
        lines.append(
            f"| 2^{e['log2_rows']} | {e['model']} | {_fmt(e.get('fast'))} | "
            f"{_fmt(e.get('c'))} | {_fmt(e.get('numpy'))} | {fc_txt} | {fn_txt} | {err_txt} |"
        )
    return lines


def _brdf_section(br: Any, meta: dict[str, Any]) -> list[str]:
    """``model.brdf(wi, wo)``, the call a user makes, against the C loop of the same BRDF."""
    lines: list[str] = []
    lines += ["", "## The default call: `model.brdf(wi, wo)` against C", ""]
    lines.append(
        "`model.brdf(wi, wo)` on (N, 3) local-frame NumPy arrays, called as a user calls it "
        "(the compiled path is chosen automatically; the result is allocated by the call), "
        "against a C loop of the same BRDF on the same arrays writing into a ready buffer "
        "(`rd_<model>_brdf_f32`/`_f64` in `roughdiffuse/bench/c/kernels.c`), interleaved, "
        "million evaluations per second, median (min–max). float32: 24 bytes in and 4 out "
        "per evaluation; float64: 48 and 8. Targets: default/C ≥ 0.8 for the qualitative "
        "Oren–Nayar model in float32, ≥ 0.5 for every model and for float64."
    )
    lines += [
        "",
        "| N | dtype | model | default | C | default/C | max rel. error (default, C) |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for e in br:
        err = e["max_rel_error_vs_reference"]
        r = e.get("default_over_c")
        target = (
            TARGET_C_QUALITATIVE
            if "qualitative" in e["model"] and e["dtype"] == "float32"
            else TARGET_C
        )
        r_txt = "–" if r is None else f"{r:.3f}" + ("" if r >= target else " ✗")
        err_txt = ", ".join(f"{err[k]:.1e}" for k in ("default", "c") if k in err)
        lines.append(
            f"| 2^{e['log2_rows']} | {e['dtype']} | {e['model']} | {_fmt(e.get('default'))} |"
            f" {_fmt(e.get('c'))} | {r_txt} | {err_txt} |"
        )
    return lines


def _startup_section(su: Any, meta: dict[str, Any]) -> list[str]:
    """Wall time of a new process: import, ``--help``, ``eval``."""
    lines: list[str] = []
    lines += ["", "## Start-up", ""]
    if "error" in su:
        lines.append(f"error: {su['error']}")
    else:
        lines.append(
            f"Wall time of a new process (`python -P …`), median of {su['repeat']} runs "
            "(min–max), the commands interleaved, after one warm-up run each. Targets: "
            "`import roughdiffuse` under 0.3 s above `python -c pass`, `roughdiffuse --help` "
            "under 0.5 s, `roughdiffuse eval …` under 1 s. `import numpy` is shown for scale: "
            "roughdiffuse imports NumPy, and nothing else heavy."
        )
        lines += ["", "| command | median | min–max | above `python -c pass` |"]
        lines.append("| --- | --- | --- | --- |")
        for label in STARTUP:
            r = su[label]
            target = STARTUP_TARGETS.get(label)
            value = r["above_python"] if label == "import roughdiffuse" else r["median"]
            mark = "" if target is None or value < target else " ✗"
            lines.append(
                f"| `{label}` | {r['median']:.3f} s{mark} | {r['min']:.3f}–{r['max']:.3f} s |"
                f" {r['above_python']:+.3f} s |"
            )
    return lines


def _first_call_section(fc: Any, meta: dict[str, Any]) -> list[str]:
    """The first ``brdf`` call in a fresh process, with a cold and a warm kernel cache."""
    lines: list[str] = []
    lines += ["", "## First call in a new process", ""]
    lines.append(
        "`rd.OrenNayar(0.8, 0.3).brdf(wi, wo)` on 2^22 float32 rows in a fresh process: "
        "the first call (Numba's import, the kernel's compilation or its load from the disk "
        "cache, and the evaluation), then a call with σ = 0.5 (same kernel). Target: first "
        "call with a warm cache under 1 s."
    )
    lines += ["", "| kernel cache | import roughdiffuse | first call | second call, new σ |"]
    lines.append("| --- | --- | --- | --- |")
    for k, r in fc.items():
        if "error" in r:
            lines.append(f"| {k} | error: {r['error']} | | |")
        else:
            lines.append(
                f"| {k.replace('_', ' ')} | {r['import_s']:.2f} s | {r['first_call_s']:.2f} s"
                f" | {r['second_call_s'] * 1e3:.1f} ms |"
            )
    lines.append("")
    lines.append(
        "The cache lives in `$ROUGHDIFFUSE_CACHE_DIR`, else "
        "`$XDG_CACHE_HOME/roughdiffuse/fastpath` (`~/.cache/roughdiffuse/fastpath`)."
    )
    return lines


def _render_section(ren: Any, meta: dict[str, Any]) -> list[str]:
    """The renderer against shading the same samples with NumPy and the fast path."""
    lines: list[str] = []
    lines += ["", "## Renderer", ""]
    if "error" in ren:
        lines.append(f"error: {ren['error']}")
    else:
        lines.append(
            f"A {ren['size']} × {ren['size']} Oren–Nayar sphere, {ren['spp']} samples per "
            "pixel, in million samples per second: `render` (ray intersection and shading "
            "under `jax.jit`) against the same samples shaded on analytic normals with "
            "`model.radiance` on NumPy and with `fastpath.evaluate`."
        )
        lines += ["", "| variant | M samples/s | vs NumPy |", "| --- | --- | --- |"]
        for key, ratio in (("render", "render_over_numpy"), ("fast", "fast_over_numpy")):
            lines.append(f"| {key} | {_fmt(ren[key])} | {ren[ratio]:.1f} |")
        lines.append(f"| numpy | {_fmt(ren['numpy'])} | 1 |")
        diff = ren["max_abs_difference_vs_render"]
        lines.append("")
        lines.append(
            f"Largest pixel difference from `render`: NumPy {diff['numpy']:.1e}, fast "
            f"{diff['fast']:.1e}."
        )
    return lines


def _fit_section(fit: Any, meta: dict[str, Any]) -> list[str]:
    """The fit of (ρ, σ) to a sphere image against plain SciPy least squares."""
    lines: list[str] = []
    from . import fit_bench

    size = fit["image_size"]
    lines += ["", f"## Fit of (ρ, σ) to a {size} × {size} image", ""]
    lines.append(
        f"`roughdiffuse.fit.fit` of an Oren–Nayar model to a {size} × {size} sphere image "
        "(ρ = 0.7, σ = 0.4, 1% noise; `roughdiffuse.bench.fit_bench`), against the simplest "
        "honest baseline, timed interleaved with it: `scipy.optimize.least_squares` on the "
        "same "
        "pixels, residuals from `model.radiance` on NumPy arrays, its default "
        "finite-difference Jacobian, from the centre of the same bounds (fit's first start)."
        f" Warm runs: median of {fit['repeat']} (min–max); the first fit in a process adds "
        f"JAX compilation. Target: under {fit_bench.TARGET_S:g} s. "
        f"Command: `{meta['command']}`."
    )
    lines += ["", fit_bench.table(fit["rows"])]
    return lines


def _simulate_section(sim: Any, meta: dict[str, Any]) -> list[str]:
    """The V-cavity solver on NumPy and on JAX (its table rows from ``simulate_bench``)."""
    lines: list[str] = []
    from . import simulate_bench

    lines += ["", "## V-cavity solver", ""]
    env = " ".join(f"{k}={v}" for k, v in sim["environment"].items())
    lines.append(
        "`roughdiffuse.simulate`: evaluations per second, median of "
        f"{sim['repeat']} runs after a warm-up (min–max), of the NumPy path (the baseline) "
        "and of the same call with `jax.numpy` arrays (float64, after a warm-up call that "
        "compiles), interleaved. Surface BRDF rows use the default `Settings()` (1e-4 "
        "accuracy, docs/accuracy.md); the table time is extrapolated from the median "
        "rate: NumPy in two single-core worker processes, JAX in the one process measured "
        "(XLA already runs it on every core). Cavities of all-different slopes run op by "
        "op on JAX, one radiosity operator per slope. Run by "
        f"`roughdiffuse.bench.simulate_bench` in a subprocess with {env}. "
        f"Command: `{meta['command']}`."
    )
    lines.append("")
    if "error" in sim:
        lines.append(f"error: {sim['error']}")
    else:
        lines.append(simulate_bench.markdown(sim["rows"]))
    return lines


def _memory_section(mem: Any, meta: dict[str, Any]) -> list[str]:
    """The fast path's memory on a large call."""
    lines: list[str] = []
    lines += ["", "## Memory", ""]
    if "error" in mem:
        lines.append(f"error: {mem['error']}")
    else:
        gib = 1 << 30
        lines.append(
            f"Fast path, qualitative Oren–Nayar, {mem['rows']:,} rows: inputs "
            f"{mem['inputs_bytes'] / gib:.2f} GiB, output {mem['output_bytes'] / gib:.2f} "
            f"GiB; the process grew by {mem['extra_bytes'] / gib:.2f} GiB during the call "
            f"(peak resident {mem['peak_bytes'] / gib:.2f} GiB = "
            f"{mem['ratio_peak_over_inputs_output']:.2f} × inputs + output, Python and "
            "libraries included)."
        )
    return lines


SECTIONS = (
    ("brdf", _brdf_section),
    ("startup", _startup_section),
    ("first_call", _first_call_section),
    ("render", _render_section),
    ("fit", _fit_section),
    ("simulate", _simulate_section),
    ("memory", _memory_section),
)
"""The report's sections after the fast-path table: key in ``extra`` -> its writer."""


def markdown(meta: dict[str, Any], results: list[dict[str, Any]], extra: dict[str, Any]) -> str:
    """``bench/RESULTS.md``: the fast-path table, then one section for each part of ``extra``
    that was run (:data:`SECTIONS`).

    Parameters
    ----------
    meta : dict
        The machine and the command (``command``, ``date``, ``cores``, versions, ``repeat``).
    results : list of dict
        The fast-path rows (:func:`run`).
    extra : dict
        The other parts' results, by key; a part that was not run is absent.
    """
    lines = _fast_path_section(meta, results)
    for key, writer in SECTIONS:
        if extra.get(key):
            lines += writer(extra[key], meta)
    lines.append("")
    return "\n".join(lines)


def _versions(*names: str) -> dict[str, str]:
    """Installed versions of these distributions (without importing them)."""
    from importlib import metadata

    out = {}
    for name in names:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def main(
    argv: list[str] | None = None,
    prog: str = "python -m roughdiffuse.bench",
    shown: list[str] | None = None,
) -> int:
    """``python -m roughdiffuse.bench [options]``; returns the exit status (2 for bad options).
    ``shown``: the arguments recorded in RESULTS.md (default ``argv``)."""
    args = parser().parse_args(argv)
    words = shown if shown is not None else argv if argv is not None else sys.argv[1:]
    try:
        return run(args, " ".join([prog, *(shlex.quote(a) for a in words)]))
    except ValueError as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 2


def check_output_dir(folder: Path) -> None:
    """Refuse an --output-dir that cannot take RESULTS.md and results.json, before any
    benchmark runs: a file, a path under a file, a folder that cannot be written, or one
    where either file's name is taken by something not a regular file (a folder, a FIFO:
    :func:`roughdiffuse.io.atomic.check_output_path`, the writer's own check)."""
    from ..io.atomic import check_output_path

    folder = Path(folder)
    if folder.is_dir():
        for name in ("RESULTS.md", "results.json"):
            check_output_path(folder / name, "--output-dir: the file")
    for parent in (folder, *folder.parents):
        if parent.exists():
            if not parent.is_dir():
                raise ParameterError(
                    f"--output-dir {str(folder)!r}: {str(parent)!r} is not a folder"
                )
            if not os.access(parent, os.W_OK | os.X_OK):
                raise ParameterError(
                    f"--output-dir {str(folder)!r}: {str(parent)!r} is not writable"
                )
            return


def _check_options(args: argparse.Namespace) -> tuple[list[int], list[int]]:
    """Refuse out-of-range options (:class:`ParameterError`); the fast-path and ``brdf`` sizes
    (log2 row counts)."""
    try:
        sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    except ValueError:
        raise ParameterError(
            f"--sizes must be comma-separated integers (got {args.sizes!r})"
        ) from None
    if not sizes or any(not 4 <= s <= 28 for s in sizes):
        raise ParameterError(f"--sizes must be log2 sizes in [4, 28] (got {args.sizes!r})")
    try:
        brdf_sizes = [int(s) for s in args.brdf_sizes.split(",") if s.strip()]
    except ValueError:
        raise ParameterError(
            f"--brdf-sizes must be comma-separated integers (got {args.brdf_sizes!r})"
        ) from None
    if any(not 4 <= s <= 28 for s in brdf_sizes):
        raise ParameterError(
            f"--brdf-sizes must be log2 sizes in [4, 28] (got {args.brdf_sizes!r})"
        )
    if args.startup_repeat < 0:
        raise ParameterError(f"--startup-repeat must be >= 0 (got {args.startup_repeat})")
    if args.repeat < 1:
        raise ParameterError(f"--repeat must be >= 1 (got {args.repeat})")
    for name in ("fit_repeat", "simulate_repeat", "simulate_geometries"):
        if getattr(args, name) < 1:
            raise ParameterError(
                f"--{name.replace('_', '-')} must be >= 1 (got {getattr(args, name)})"
            )
    if args.fit_size < 16:
        raise ParameterError(f"--fit-size must be >= 16 pixels (got {args.fit_size})")
    if args.simulate_cavities < 100:
        raise ParameterError(f"--simulate-cavities must be >= 100 (got {args.simulate_cavities})")
    if args.memory_log2 and not 10 <= args.memory_log2 <= 28:
        raise ParameterError(f"--memory-log2 must be 0 or in [10, 28] (got {args.memory_log2})")
    check_output_dir(args.output_dir)
    return sizes, brdf_sizes


def _run_parts(args: argparse.Namespace, bar: Any) -> dict[str, Any]:
    """The parts after the fast-path tables that the options leave on, by report key (each one
    step of ``bar``)."""
    stages: list[tuple[str, bool, Callable[[], dict[str, Any]]]] = [
        ("startup", bool(args.startup_repeat), lambda: startup(args.startup_repeat)),
        ("first_call", not args.no_first_call, first_call),
        ("render", not args.no_render, lambda: bench_render(args.repeat)),
        ("fit", not args.no_fit, lambda: bench_fit(args.fit_repeat, args.fit_size)),
        (
            "simulate",
            not args.no_simulate,
            lambda: bench_simulate(
                args.simulate_repeat,
                args.simulate_cavities,
                args.simulate_geometries,
                args.simulate_cases,
            ),
        ),
        ("memory", bool(args.memory_log2), lambda: memory(args.memory_log2)),
    ]
    said = {"startup": "start-up", "first_call": "first call"}
    extra: dict[str, Any] = {}
    for key, wanted, job in stages:
        if not wanted:
            continue
        bar.set_postfix_str(said.get(key, key))
        extra[key] = job()
        if key != "fit":
            print(f"{said.get(key, key)}: {json.dumps(extra[key])}", flush=True)
        bar.update(1)
    return extra


def _machine(command: str, c_note: str, repeat: int) -> dict[str, Any]:
    """The report's header record: command, date, cores, CPU name and versions."""
    import numba

    from roughdiffuse.engine.fastpath import cpu_count

    meta = {
        "command": command,
        "date": dt.datetime.now(dt.UTC).strftime("%Y-%m-%d %H:%M UTC"),
        "cores": cpu_count(),
        "cpu": platform.processor() or platform.machine(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "numba": numba.__version__,
        **_versions("jax", "scipy"),
        "c_compiler": c_note,
        "repeat": repeat,
    }
    try:
        with open("/proc/cpuinfo") as f:
            names = [ln.split(":", 1)[1].strip() for ln in f if ln.startswith("model name")]
        if names:
            meta["cpu"] = names[0]
    except OSError:
        pass
    return meta


def run(args: argparse.Namespace, command: str) -> int:
    """Run the benchmarks the parsed options ask for; ``command`` is recorded in RESULTS.md."""
    sizes, brdf_sizes = _check_options(args)
    wanted = args.models.lower()
    models = [m for m in bench_models() if wanted in m.label.lower() or wanted in m.id]
    if not models:
        raise ParameterError(f"--models {args.models!r} matches no model")
    from roughdiffuse.progress import progress, progress_enabled

    later = [
        bool(args.startup_repeat),
        not args.no_first_call,
        not args.no_render,
        not args.no_fit,
        not args.no_simulate,
        bool(args.memory_log2),
    ]
    stages = len(sizes) + 2 * len(brdf_sizes) + sum(later)
    bar = progress(stages, "bench", unit="stage", enabled=progress_enabled())
    with tempfile.TemporaryDirectory() as tmp:
        lib, c_note = (None, "skipped (--no-c)") if args.no_c else build_c(Path(tmp))
        print(f"C reference: {c_note}", flush=True)
        results = []
        for s in sizes:
            bar.set_postfix_str(f"models, 2^{s} rows")
            results += bench_size(s, args.repeat, lib, models, not args.no_numpy)
            bar.update(1)
        brdf_rows = []
        for s in brdf_sizes:
            for dtype in (np.float32, np.float64):
                bar.set_postfix_str(f"brdf, 2^{s} {np.dtype(dtype).name}")
                brdf_rows += bench_brdf(s, args.repeat, lib, models, dtype)
                bar.update(1)
    extra: dict[str, Any] = {"brdf": brdf_rows} if brdf_rows else {}
    extra.update(_run_parts(args, bar))
    bar.close()
    meta = _machine(command, c_note, args.repeat)
    out_dir = args.output_dir
    out_dir.mkdir(parents=True, exist_ok=True)
    payload = {"meta": meta, "results": results, **extra}
    from roughdiffuse.io import deferred
    from roughdiffuse.io.jsonfile import dumps

    with deferred(out_dir):  # both files or neither
        write_atomic(out_dir / "results.json", dumps(payload, indent=1) + "\n")
        write_atomic(out_dir / "RESULTS.md", markdown(meta, results, extra))
    print(f"wrote {out_dir / 'RESULTS.md'} and {out_dir / 'results.json'}")
    return 0
