"""Timing helpers shared by the benchmark scripts (``run.py``, ``fit_bench.py``,
``simulate_bench.py``): summary statistics, an interleaved timing loop, atomic writes, and
the relative difference by which each variant is checked against its reference.

The machine the benchmarks run on is shared and noisy, so variants are timed interleaved, run
by run, in a rotating order: the noise then hits every variant alike, and the ratios between
variants measured in one run are what the reports quote.
"""

from __future__ import annotations

import statistics
import time
from collections.abc import Callable, Collection, Iterable, Mapping
from pathlib import Path
from typing import Any

from .._validate import ParameterError


def summary(values: Iterable[float]) -> dict[str, float]:
    """Median, min and max of ``values`` (and how many there were).

    Parameters
    ----------
    values : iterable of float
        Timings (seconds) or rates; at least one.

    Returns
    -------
    dict
        ``{"median", "min", "max", "runs"}``.
    """
    vals = sorted(float(v) for v in values)
    if not vals:
        raise ParameterError("summary needs at least one value")
    return {
        "median": float(statistics.median(vals)),
        "min": vals[0],
        "max": vals[-1],
        "runs": len(vals),
    }


def rate_summary(times: Iterable[float], count: float, unit: float = 1e6) -> dict[str, float]:
    """:func:`summary` of the rates ``count / t / unit`` (e.g. million evaluations per second).

    Parameters
    ----------
    times : iterable of float
        Seconds per run.
    count : float
        Work done by one run (evaluations, samples, ...).
    unit : float
        Divisor of the rate (1e6: millions per second; 1: per second).
    """
    return summary(count / t / unit for t in times)


def block(result: Any) -> Any:
    """Wait for an asynchronous (JAX) result; other results are returned as they are."""
    wait = getattr(result, "block_until_ready", None)
    return wait() if callable(wait) else result


def interleaved(
    variants: Mapping[str, Callable[[], Any]],
    repeat: int,
    steady: Collection[str] = (),
) -> dict[str, list[float]]:
    """Seconds of ``repeat`` timed calls of each variant, interleaved in a rotating order.

    Run ``r`` times the variants in the order of ``variants`` rotated by ``r``, so that no
    variant always follows the same one. The variants named in ``steady`` get an untimed
    call right before each timed call, so that their timing is of a steady state (e.g. a
    multi-threaded loop timed right after a long single-threaded one starts slowly). JAX
    results are waited for inside the timed interval (:func:`block`). No warm-up here: call
    each variant once before (that is also where outputs are checked).

    Parameters
    ----------
    variants : mapping of str to callable
        The functions to time, without arguments.
    repeat : int
        Timed calls per variant (>= 1).
    steady : collection of str
        Variants that get an untimed call before each timed one.

    Returns
    -------
    dict of str to list of float
        Seconds of each timed call, per variant.
    """
    if repeat < 1:
        raise ParameterError(f"repeat must be >= 1 (got {repeat})")
    keys = list(variants)
    times: dict[str, list[float]] = {k: [] for k in keys}
    for r in range(repeat):
        shift = r % len(keys) if keys else 0
        for k in keys[shift:] + keys[:shift]:
            fn = variants[k]
            if k in steady:
                block(fn())
            t0 = time.perf_counter()
            block(fn())
            times[k].append(time.perf_counter() - t0)
    return times


def timed(fn: Callable[[], Any]) -> tuple[Any, float]:
    """(result, seconds) of one call of ``fn`` (JAX results waited for)."""
    t0 = time.perf_counter()
    result = block(fn())
    return result, time.perf_counter() - t0


def write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` whole or not at all (:func:`roughdiffuse.io.write_text`)."""
    from roughdiffuse.io import write_text

    write_text(path, text)


def with_write_target(argv: list[str], results: Path) -> list[str]:
    """``argv`` with ``results`` after a ``--write`` given without a file (the checkout's
    scripts in bench/ write there by default)."""
    argv = list(argv)
    if "--write" in argv:
        k = argv.index("--write")
        if k + 1 >= len(argv) or argv[k + 1].startswith("-"):
            argv.insert(k + 1, str(results))
    return argv


def write_section(path: Path, text: str, begin: str, end: str, heading: str | None = None) -> None:
    """Replace the section of ``path`` marked by ``begin`` ... ``end`` by ``text`` (which
    holds both markers); the first time, put it at the end of the section ``heading`` (a
    Markdown heading line), else at the end of the file. Whole or not at all."""
    old = path.read_text(encoding="utf-8") if path.exists() else ""
    if begin in old and end in old:
        new = old[: old.index(begin)] + text + old[old.index(end) + len(end) :]
    elif heading is not None and heading in old:
        at = old.index(heading) + len(heading)
        after = old.find("\n## ", at)
        at = len(old) if after < 0 else after + 1
        new = old[:at].rstrip("\n") + "\n\n" + text + "\n\n" + old[at:]
    else:
        new = old.rstrip("\n") + "\n\n" + (heading + "\n" if heading else "") + text + "\n"
    write_atomic(path, new)


def rel_error(a: Any, ref: Any) -> float:
    """Largest |a − ref| relative to the largest |ref| (any arrays NumPy can read)."""
    import numpy as np

    ref = np.asarray(ref, np.float64)
    scale = max(float(np.max(np.abs(ref))), 1e-300)
    return float(np.max(np.abs(np.asarray(a, np.float64) - ref)) / scale)
