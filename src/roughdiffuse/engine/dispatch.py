"""When ``brdf``, ``brdf_cosines`` and ``radiance`` run compiled: the fast path by default.

:class:`~roughdiffuse.models.base.Model` asks :func:`compiled` first; it answers with the
compiled result (:mod:`roughdiffuse.engine.fastpath`) or ``None`` for the array-API path.
This module imports nothing heavy: Numba is imported only when a kernel is first needed.

The rule (the measurements behind the two thresholds are in their docstrings):

* only NumPy float32/float64 arrays (``numpy.ndarray`` or ``numpy.memmap``; no subclass
  such as a masked array, no integers) with concrete parameters (no JAX, no PyTorch, no
  tracers), shaped as the reference path accepts them;
* at least :data:`MIN_ROWS` rows: below that, the compiled call's fixed cost (laying out the
  call, looking up the kernel) outweighs the gain;
* a kernel that is not yet loaded in this process is built (loaded from the disk cache, or
  compiled on a cold cache) once the rows evaluated with it on the reference path reach
  :data:`BUILD_ROWS`, so that a few small calls never pay a compilation; a single call of
  that many rows builds it at once;
* a model the fast path cannot compile (a Python branch on values, say) stays on the
  reference path, silently.

Switch: ``ROUGHDIFFUSE_FASTPATH=0`` in the environment, or :func:`use_fastpath` (``False``
for the process, or as a context manager).
"""

from __future__ import annotations

import dataclasses
import threading
from types import TracebackType
from typing import Any

import numpy as np

from .._env import env_flag

__all__ = ["BUILD_ROWS", "MIN_ROWS", "compiled", "fastpath_enabled", "use_fastpath"]

MIN_ROWS = 1 << 10
"""Fewest rows a call must have to run compiled: the compiled call has a fixed cost (laying
out the call, looking up the kernel; one thread below 2^16 rows, see
``fastpath.ROWS_PER_THREAD``) that the reference path's per-row cost outweighs from about
this many rows on (measurements: bench/RESULTS.md, "Thresholds of the compiled engine")."""

BUILD_ROWS = 1 << 20
"""Rows evaluated on the reference path after which a kernel is built (one call of this many
rows builds it at once): NumPy work of the order of a kernel load from the disk cache (a cold
compilation is far longer, once per machine; bench/RESULTS.md)."""

_ENABLED: bool | None = None
"""The switch; ``None`` until the first call reads ``ROUGHDIFFUSE_FASTPATH`` (a value
:func:`~roughdiffuse._env.env_flag` cannot read is a ``ValueError`` naming the variable)."""
_LOCK = threading.Lock()
_SEEN_ROWS: dict[Any, int] = {}
_FAILED: set[Any] = set()
_PLAIN = (float, int, np.ndarray, np.floating, np.integer)


def fastpath_enabled() -> bool:
    """Whether large NumPy calls run compiled (see :func:`use_fastpath`).

    Raises
    ------
    ValueError
        If ``ROUGHDIFFUSE_FASTPATH`` decides (no :func:`use_fastpath` has) and is set to
        something other than the words :func:`~roughdiffuse._env.env_flag` reads.
    """
    global _ENABLED
    if _ENABLED is None:
        _ENABLED = env_flag("ROUGHDIFFUSE_FASTPATH", default=True)
    return _ENABLED


class use_fastpath:  # noqa: N801 - used as a function
    """Turn the automatic compiled path on or off, for the process or within a ``with`` block.

    Parameters
    ----------
    enabled : bool
        ``False``: every call takes the array-API reference path (as
        ``ROUGHDIFFUSE_FASTPATH=0`` does). :func:`roughdiffuse.engine.fastpath.evaluate` stays
        available either way.

    Examples
    --------
    >>> import roughdiffuse as rd
    >>> with rd.use_fastpath(False):
    ...     rd.fastpath_enabled()
    False
    >>> rd.fastpath_enabled()
    True
    """

    def __init__(self, enabled: bool = True) -> None:
        global _ENABLED
        self._previous = _ENABLED
        _ENABLED = bool(enabled)

    def __enter__(self) -> use_fastpath:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        global _ENABLED
        _ENABLED = self._previous


def _rows(entry: str, arrays: tuple[Any, ...]) -> int:
    """Rows of a well-formed call (0 if the reference path should judge the input)."""
    dtype = None
    shapes = []
    for a in arrays:
        if type(a) is not np.ndarray and type(a) is not np.memmap:  # no masked arrays...
            if isinstance(a, float | int) and entry == "brdf_cosines":
                continue
            return 0
        if a.dtype != np.float32 and a.dtype != np.float64:
            return 0
        dtype = a.dtype if dtype is None or a.dtype == np.float64 else dtype
        if entry == "brdf_cosines":
            shapes.append(a.shape)
        elif a.ndim == 0 or a.shape[-1] != 3:
            return 0
        else:
            shapes.append(a.shape[:-1])
    try:
        shape = np.broadcast_shapes(*shapes)
    except ValueError:
        return 0
    rows = 1
    for s in shape:
        rows *= s
    return rows


def _plain_parameters(x: Any) -> bool:
    """Whether a model's numeric parameters are all concrete NumPy or Python values (no JAX
    array or tracer, no tensor); a Mix's components are looked into."""
    fields = getattr(type(x), "array_fields", None)
    if fields is not None and dataclasses.is_dataclass(x):
        return all(_plain_parameters(getattr(x, f)) for f in fields)
    if isinstance(x, list | tuple):
        return all(_plain_parameters(v) for v in x)
    return x is None or isinstance(x, _PLAIN)


def compiled(model: Any, entry: str, *arrays: Any, irradiance: Any = 1.0) -> Any:
    """The compiled result of ``model.<entry>(*arrays)``, or ``None`` for the reference path.

    ``entry`` is ``"brdf"``, ``"brdf_cosines"`` or ``"radiance"``.
    """
    if not fastpath_enabled() or not type(model).traceable:  # a simulation runs as it is
        return None
    rows = _rows(entry, arrays)
    if rows < MIN_ROWS or not _plain_parameters(model):
        return None
    if entry == "radiance" and not (
        isinstance(irradiance, _PLAIN) or isinstance(irradiance, list | tuple)
    ):
        return None
    from . import fastpath

    try:
        call = fastpath.kernel_key(model, entry, arrays, irradiance)
    except Exception:  # noqa: BLE001 - anything the fast path does not take: reference path
        return None
    if call.key in _FAILED:
        return None
    if not fastpath.is_loaded(call):
        with _LOCK:
            seen = _SEEN_ROWS.get(call.key, 0) + rows
            _SEEN_ROWS[call.key] = seen
        if seen < BUILD_ROWS:
            return None
    try:
        fastpath.build(model, call)  # a dictionary look-up once built
    except Exception:  # noqa: BLE001 - no compiled code for this model: reference path
        with _LOCK:
            _FAILED.add(call.key)
        return None
    return fastpath.run_entry(model, call)
