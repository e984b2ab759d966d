"""The benchmark's C baselines (roughdiffuse/bench/c/kernels.c) against the Python models.

The C kernels are a second, hand-written transcription of each formula: the yardstick the
benchmark times the package against. Each is compiled here exactly as the benchmark compiles
it (``roughdiffuse.bench.run.build_c``: ``-O3 -march=native -fopenmp -ffast-math``) and
evaluated at the corners of its model's domain:

* geometries: θ from 0° to exactly 90° (grazing: 89°, 89.9°, 90°) on both sides, Δφ = 0°
  (backscatter when θi = θr), 180° (forward scatter), 90° and between, plus interior points;
* parameters: the declared example, then each numeric parameter alone at each end of its
  declared range (roughness 0 and its maximum, albedo 0 and 1; an unbounded or open end at
  the end of its fit box), then all at their lower ends and all at their upper ends; each
  choice of a categorical parameter the C file has a kernel for.

Reference: the model's ``brdf`` on the array-API path in float64, at the inputs the C
receives (float32 inputs rounded first). Allowed difference at each direction, from the
precision of the arithmetic (ε = 2.2e-16 in float64, 1.2e-7 in float32):

    rtol |Python| + atol + ε/ε32 (4 |Python32 − Python| + max |Python(moved) − Python|)

* rtol, atol: 1e-9 and 1e-12 sr⁻¹ in float64 (a few dozen operations of ε each, which
  ``-ffast-math`` reassociates and glibc's vector ``libmvec`` functions compute within 4 ulp:
  the transcriptions here agree to 5e-16 relative at the median point, 5e-13 at the worst
  (Hapke near grazing); a wrong term misses by far more);
  2e-4 and 1e-6 sr⁻¹ in float32 (the same operations at 1.2e-7; the absolute term matters
  only where a value cancels to nearly 0, and is 3e-6 of 1/π). Where both directions are
  exactly grazing (μi + μo under the models' 1e-6 floors) rtol is 1e-7 in float64: d'Eon's
  Lambert sphere cancels terms in 1/(μi + μo) a million-fold there (Python's float32 keeps
  no digit of it).
* The formula's own rounding: Python's float32 result's distance from its float64 one.
* Its inputs' rounding: the largest change of the Python value when μi, μo (relative) and
  cos ψ (absolute) move by 4 ε32, as the C's normalisations and dot products move them. It
  is what remains at the ill-conditioned corners: the tangent of half the phase angle at
  backscatter (Hapke's shadow-hiding surge), the mirror peak of Torrance–Sparrow at grazing
  forward scatter.

Both are measured at float32's precision and scaled by ε/ε32 to the loop's.
"""

from __future__ import annotations

import ctypes
import hashlib
import itertools
import math
import os
import platform
import shutil
import subprocess
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from roughdiffuse import registry
from roughdiffuse.bench import run as bench

pytestmark = pytest.mark.skipif(
    shutil.which("gcc") is None, reason="gcc not found: the C baselines cannot be compiled"
)

RTOL64, ATOL64 = 1e-9, 1e-12
RTOL64_GRAZING = 1e-7
RTOL32, ATOL32 = 2e-4, 1e-6
COND = 4.0


@pytest.fixture(scope="module")
def lib(tmp_path_factory):
    """The benchmark's build of kernels.c, kept in the kernel cache (``ROUGHDIFFUSE_CACHE_DIR``,
    which the test session points at pytest's cache) under a hash of the source, the flags,
    the compiler and the CPU's features (``-march=native``), so that a warm run does not
    compile it again."""
    gcc = shutil.which("gcc")
    version = subprocess.run([gcc, "--version"], capture_output=True, text=True).stdout
    cpuinfo = Path("/proc/cpuinfo")
    cpu = cpuinfo.read_text() if cpuinfo.is_file() else platform.processor()
    flags = sorted({line for line in cpu.splitlines() if line.startswith(("flags", "Features"))})
    key = hashlib.sha256(
        "\0".join(
            [bench.C_SOURCE.read_text(), *bench.CFLAGS, "linked-apart", version, *flags]
        ).encode()
    ).hexdigest()[:16]
    cache = os.environ.get("ROUGHDIFFUSE_CACHE_DIR")
    kept = Path(cache) / "c-baselines" / f"{key}.so" if cache else None
    if kept is not None and kept.is_file():
        return ctypes.CDLL(str(kept))
    folder = tmp_path_factory.mktemp("c-baselines")
    library, note = bench.build_c(folder)
    assert library is not None, note  # gcc is there (skipif above): it must compile
    if kept is not None:  # whole or not at all: renamed into the cache once written
        kept.parent.mkdir(parents=True, exist_ok=True)
        part = kept.with_name(f"{key}.{os.getpid()}.part")  # beside it: same file system
        shutil.copyfile(folder / "kernels.so", part)
        part.rename(kept)
    return library


def _directions() -> tuple[np.ndarray, np.ndarray]:
    """(N, 3) float64 local wi, wo: a grid with grazing, normal, backscatter and forward
    scatter, then interior points."""
    theta = np.radians([0.0, 30.0, 60.0, 85.0, 89.0, 89.9, 90.0])
    dphi = np.radians([0.0, 45.0, 90.0, 135.0, 180.0])
    ti, to, dp = (a.ravel() for a in np.meshgrid(theta, theta, dphi, indexing="ij"))
    rng = np.random.default_rng(34)
    ti = np.concatenate([ti, rng.uniform(0.05, 1.5, 40)])
    to = np.concatenate([to, rng.uniform(0.05, 1.5, 40)])
    dp = np.concatenate([dp, rng.uniform(0.0, np.pi, 40)])
    wi = np.stack([np.sin(ti), np.zeros_like(ti), np.cos(ti)], axis=-1)
    wo = np.stack([np.sin(to) * np.cos(dp), np.sin(to) * np.sin(dp), np.cos(to)], axis=-1)
    return wi, wo


WI, WO = _directions()


def test_directions_cover_the_corners():
    """The grid holds exact grazing, normal incidence, backscatter and forward scatter."""
    assert (WI[:, 2] == np.cos(np.pi / 2)).any() and (WI[:, 2] == 1.0).any()
    cos_io = np.einsum("ij,ij->i", WI, WO)
    grazing = WI[:, 2] < 0.02
    assert (np.isclose(cos_io, 1.0) & grazing).any()  # backscatter at grazing
    assert (np.isclose(cos_io, -1.0, atol=1e-6) & grazing).any()  # forward at grazing


def _end(p: Any, which: int) -> float:
    """The lower (0) or upper (1) end of ``p``'s declared range; an open or unbounded end
    at the end of its fit box."""
    end = (p.min, p.max)[which]
    if end is None or (which == 0 and p.min_open):
        end = p.bounds[which]
    return float(end)


def _points(entry: registry.Entry) -> list[dict[str, Any]]:
    """Parameter sets of ``entry`` (see the module docstring), each choice of its free
    categorical parameters."""
    categorical = [p for p in entry.parameters if p.categorical]
    out = []
    for combo in itertools.product(*[p.choices for p in categorical]):
        chosen = dict(zip([p.name for p in categorical], combo, strict=True))
        params = [p for p in entry.applicable(chosen) if not p.categorical]
        start = {p.name: p.default if p.example is None else p.example for p in params}
        sets = [start]
        sets += [{**start, p.name: _end(p, k)} for p in params for k in (0, 1)]
        sets += [{p.name: _end(p, k) for p in params} for k in (0, 1)]
        for values in sets:
            point = {**chosen, **values}
            if point not in out:
                out.append(point)
    return out


def _cases() -> list[Any]:
    """(id, parameter set) for every set whose model the C file has a kernel for (Coated's
    kernels are over the full Oren–Nayar and the Lambert bases only)."""
    cases = []
    for entry in registry.entries():
        if entry.id not in bench.C_KERNELS:
            continue
        points = [p for p in _points(entry) if bench.C_KERNELS[entry.id](entry.create(**p))[0]]
        cases += [
            pytest.param(entry.id, p, id=f"{entry.id}-{k}", marks=_known(entry.id, p))
            for k, p in enumerate(points)
        ]
    return cases


def _known(model_id: str, point: dict[str, Any]) -> list[Any]:
    """The one known C deviation, kept visible (strict: it fails once fixed): Coated's
    float32 loop over the full Oren–Nayar (σ > 0) at η = 1, smooth, is 0.09 % high at θ = 89.9°
    (38.023 against 37.990), where the Oren–Nayar kernel alone is exact; Python's float32 is
    exact there since its refraction is √(μ² + η² − 1)/η."""
    if (model_id == "coated" and point.get("base") == "oren-nayar-full"
            and point.get("sigma", 0.0) > 0.0
            and point.get("eta") == 1.0 and point.get("roughness") == 0.0):  # fmt: skip
        return [pytest.mark.xfail(strict=True, reason="Coated's float32 C loop, η = 1, θ = 89.9°")]
    return []


CASES = _cases()


def _failures(got: np.ndarray, ref: np.ndarray, band: np.ndarray, what: str) -> list[str]:
    bad = ~(np.abs(got - ref) <= band)
    return [
        f"{what} at wi={WI[k].round(6).tolist()} wo={WO[k].round(6).tolist()}: "
        f"C {got[k]!r} Python {ref[k]!r} (allowed difference {band[k]:.3g})"
        for k in np.flatnonzero(bad)[:4]
    ]


WI32, WO32 = WI.astype(np.float32), WO.astype(np.float32)


def _cosines(wi: np.ndarray, wo: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """μi, μo and cos ψ of (N, 3) directions, in float64."""
    wi, wo = wi.astype(np.float64), wo.astype(np.float64)
    len_i, len_o = np.linalg.norm(wi, axis=1), np.linalg.norm(wo, axis=1)
    return wi[:, 2] / len_i, wo[:, 2] / len_o, np.einsum("ij,ij->i", wi, wo) / (len_i * len_o)


COSINES32 = _cosines(WI32, WO32)


def _rounding(model: Any, ref: np.ndarray) -> np.ndarray:
    """What float32 rounding alone moves the value by at each direction (``ref``: Python in
    float64 at the float32 inputs): the formula's own (Python's float32 result's distance
    from ``ref``, times ``COND``) plus the inputs' (the largest change of the Python value
    when μi, μo (relative) and cos ψ (absolute) move by ``COND`` ulp, as the C's
    normalisations and dot products move them)."""
    py32 = np.asarray(bench.reference(model.brdf, WI32, WO32), np.float64)
    mu_i, mu_o, cos_io = COSINES32
    d = COND * float(np.finfo(np.float32).eps)
    spread = np.zeros_like(ref)
    for si, so, sc in itertools.product((-1, 1), repeat=3):
        moved = bench.reference(
            model.brdf_cosines,
            np.clip(mu_i * (1 + si * d), 0.0, 1.0),
            np.clip(mu_o * (1 + so * d), 0.0, 1.0),
            np.clip(cos_io + sc * d, -1.0, 1.0),
        )
        spread = np.maximum(spread, np.abs(np.asarray(moved, np.float64).reshape(ref.shape) - ref))
    return COND * np.abs(py32 - ref) + spread


@pytest.mark.parametrize(("model_id", "point"), CASES)
def test_c_kernel_matches_python(lib, model_id, point):
    """float64 and float32 BRDF loops and the float32 radiance loop of the model's C
    kernel: within the stated tolerance of Python at every direction."""
    model = registry.get(model_id).create(**point)
    name, params = bench.C_KERNELS[model_id](model)
    ref32 = np.asarray(bench.reference(model.brdf, *(w.astype(np.float64) for w in (WI32, WO32))))
    rounding32 = _rounding(model, ref32)
    failures = []
    for dtype, rtol, atol in ((np.float64, RTOL64, ATOL64), (np.float32, RTOL32, ATOL32)):
        wi, wo = (WI, WO) if dtype is np.float64 else (WI32, WO32)
        ref = np.asarray(bench.reference(model.brdf, WI, WO)) if dtype is np.float64 else ref32
        assert np.all(np.isfinite(ref)), f"{model_id} {point}: Python not finite"
        if dtype is np.float64:  # both directions exactly grazing (module docstring)
            rtol = np.where(wi[:, 2] + wo[:, 2] < 1e-6, RTOL64_GRAZING, rtol)
        scale = float(np.finfo(dtype).eps / np.finfo(np.float32).eps)
        band = rtol * np.abs(ref) + atol + scale * rounding32
        out = np.empty(len(wi), dtype)
        bench.c_brdf_caller(lib, name, params, dtype)(wi, wo, out)
        failures += _failures(out.astype(np.float64), ref, band, f"brdf {dtype.__name__}")
        if dtype is np.float32:  # the radiance loop: n = z, E0 = 1, so L = f μi
            n = np.broadcast_to(np.float32([0, 0, 1]), wi.shape).copy()
            bench.c_caller(lib, name, params)(n, wi, wo, out)
            mu_i = np.clip(wi[:, 2].astype(np.float64), 0.0, 1.0)
            failures += _failures(out.astype(np.float64), ref * mu_i, band * mu_i, "radiance")
    assert not failures, f"C and Python differ for {model_id} {point}:\n" + "\n".join(failures)


def test_every_c_kernel_is_checked():
    """Each registry id with a C kernel has parameter sets here, with both ends of each
    numeric parameter."""
    ids = {c.values[0] for c in CASES}
    assert ids == set(bench.C_KERNELS) & set(registry.ids())
    on = [c.values[1] for c in CASES if c.values[0] == "oren-nayar-full"]
    assert {p["sigma"] for p in on} >= {0.0, math.pi / 2}
    assert {p["albedo"] for p in on} >= {0.0, 1.0}
