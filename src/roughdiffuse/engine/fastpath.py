"""The fast path: compiled ``radiance``, ``brdf`` and ``brdf_cosines`` of any model on NumPy
arrays, in place, on every core.

The array-API reference path makes one pass over memory per operation (about 25 million
evaluations per second for Oren–Nayar); the compiled kernel computes the same values in one
pass: it compiles the model's own code, not a second copy of its formula. The models' own
methods run it by default on large NumPy arrays (:mod:`roughdiffuse.engine.dispatch`, switched off
by ``roughdiffuse.use_fastpath(False)`` or ``ROUGHDIFFUSE_FASTPATH=0``); :func:`evaluate`,
:func:`brdf` and :func:`brdf_cosines` are the explicit forms (``out``, ``chunk``, ``threads``).

How: the model's method, e.g. :meth:`~roughdiffuse.models.base.Model.radiance` (with its
``_kernel``, the frame normalisation and the horizon test of ``models/base.py``) is run once
on *symbols* for one row of the inputs (see :mod:`roughdiffuse.engine.trace`); the recorded
operations are printed as the body of a scalar loop over the rows, and Numba compiles that loop
(float32 code for float32 input, ``fastmath`` without the no-NaN/no-Inf assumptions,
vectors no wider than the CPU's tuning prefers: see ``numba_math.tuned_vector_width``). The
model's parameters are run-time arguments, so a new σ or albedo does not recompile.

Threads: the rows are cut into chunks (by default one contiguous part per core, like
OpenMP's static schedule) that a thread pool of ``os.sched_getaffinity`` size (all usable
cores) evaluates with the GIL released. Memory: nothing but the output is
allocated when the inputs are C-contiguous arrays of the output's dtype; otherwise each chunk
is converted on its own, so the peak stays near inputs + output. For inputs larger than
memory, pass ``numpy.memmap`` arrays, a memmap ``out`` and a ``chunk``: chunks are read
and written as they are computed. :func:`evaluate_batches` streams an iterable of batches instead.

Compiled code is cached on disk: the generated modules and Numba's cache files live in
``$ROUGHDIFFUSE_CACHE_DIR`` or else ``$XDG_CACHE_HOME/roughdiffuse/fastpath`` (default
``~/.cache/roughdiffuse/fastpath``, created with mode 0700); a new process loads them instead
of compiling. The folder is used only if it is private (:func:`private_cache_dir`), and so
are the folders above it (none writable by another user, unless sticky like ``/tmp``): Numba
unpickles its index files, so a folder another user can write to could run their code here.
Otherwise kernels are compiled in memory.
"""

from __future__ import annotations

import dataclasses
import hashlib
import importlib.util
import os
import sys
import threading
import types
from collections.abc import Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..io.atomic import write_text
from .cache import Compiled, cache_dir, private_cache_dir
from .protocol import CompilableModel as Model
from .protocol import is_model
from .trace import Graph, SymVec, TraceError, scalar_source

__all__ = [
    "DEFAULT_CHUNK",
    "TraceError",
    "brdf",
    "brdf_cosines",
    "cache_dir",
    "cpu_count",
    "evaluate",
    "evaluate_batches",
    "private_cache_dir",
]

DEFAULT_CHUNK = 1 << 18
"""Rows per unit of work when inputs must be converted (another dtype, not contiguous): one
chunk of buffers per thread (about 10 MB in float32). Inputs read in place are split in one
contiguous part per thread instead, like OpenMP's static schedule: each chunk costs Python
overhead and a GIL hand-over, so fewer, larger chunks run faster (bench/RESULTS.md)."""

ROWS_PER_THREAD = 1 << 15
"""Fewest rows worth a thread of their own (by default): below it, handing rows over to a
pool thread costs about as much as computing them on one core (bench/RESULTS.md)."""

_FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}
_LOCK = threading.Lock()
_COMPILED: dict[str, Any] = {}
_TRACES: dict[Any, tuple[Any, tuple[np.ndarray, ...], int]] = {}
_STRUCTURES: set[Any] = set()
_POOL: ThreadPoolExecutor | None = None
_POOL_SIZE = 0


def cpu_count() -> int:
    """Cores this process may run on (``os.sched_getaffinity``; ``os.cpu_count`` elsewhere)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


# ------------------------------------------------------------------ entry points
_ENTRIES: dict[str, tuple[tuple[str, int], ...]] = {
    "radiance": (("n", 3), ("l", 3), ("v", 3)),
    "brdf": (("wi", 3), ("wo", 3)),
    "brdf_cosines": (("mu_i", 1), ("mu_o", 1), ("cos_io", 1)),
}
"""The model methods the fast path compiles, with their inputs' names and widths (a direction
(..., 3) or a cosine (...))."""


# ------------------------------------------------------------------ tracing
def _value_key(x: Any) -> Any:
    """A hashable key of a model's (or a value's) type and every value it holds."""
    if is_model(x):
        fields = tuple((f.name, _value_key(getattr(x, f.name))) for f in dataclasses.fields(x))
        return (type(x).__module__, type(x).__qualname__, fields)
    if isinstance(x, str | bool | int | float | type(None)):
        return x
    if isinstance(x, list | tuple):  # a Mix's components
        return ("seq", tuple(_value_key(v) for v in x))
    a = np.asarray(x)
    return (a.dtype.str, a.shape, a.tobytes())


def _structure_key(x: Any) -> Any:
    """What the generated code depends on besides parameter values: the class, its static
    fields and the shapes of its parameters (a new σ or albedo reuses the kernel)."""
    if is_model(x):
        fields = []
        for f in dataclasses.fields(x):
            value = getattr(x, f.name)
            if f.name in x.array_fields:
                fields.append((f.name, _structure_key(value)))
            else:
                fields.append((f.name, _value_key(value)))
        return (type(x).__module__, type(x).__qualname__, tuple(fields))
    if isinstance(x, list | tuple):
        return ("seq", tuple(_structure_key(v) for v in x))
    return None if x is None else np.shape(x)


def _source(
    graph: Graph,
    outputs: list[Any],
    inputs: tuple[tuple[str, int], ...],
    pattern: tuple[bool, ...],
    channels: int,
) -> str:
    constants, body = scalar_source(graph, outputs)
    n_out = max(channels, 1)
    params = "".join(f", p{k}" for k in range(len(graph.params)))
    loads = []
    for (name, width), const in zip(inputs, pattern, strict=True):
        for k in range(width):
            idx = f"{k}" if const else (f"{width} * i + {k}" if width > 1 else "i")
            loads.append(f"        {name}{k} = {name}[{idx}]")
    stores = [
        f"        out[{n_out} * i + {c}] = r{c}" if n_out > 1 else "        out[i] = r0"
        for c in range(n_out)
    ]
    # the reference path's validation (non-zero, finite direction vectors), cheaply: the
    # product of the squared norms is positive and finite unless one of them is 0,
    # infinite or NaN -- or unless the product under/overflows, a false alarm that
    # _check_directions sorts out exactly on the rare chunk where it happens. LLVM reuses the
    # squared norms of the normalisation; the test cost about 6% in cache (2^16 rows, one
    # thread) and nothing measurable at 2^22 rows (memory-bound), qualitative Oren-Nayar.
    # Cosines (brdf_cosines) are not validated, as on the reference path.
    norms = [
        f"({name}0 * {name}0 + {name}1 * {name}1 + {name}2 * {name}2)"
        for name, width in inputs
        if width == 3
    ]
    checks = []
    if norms:
        checks = [
            "        q = " + " * ".join(norms),
            "        bad |= not ((q > 0) & (q < _INF))",
        ]
    names = ", ".join(name for name, _ in inputs)
    lines = [
        "# Generated by roughdiffuse.fastpath from a model's array-API code; do not edit.",
        f"# helpers: roughdiffuse.engine.numba_math {_helpers_digest()}",
        "import math",
        "",
        "import numba",
        "import numpy as np",
        "",
        "from roughdiffuse.engine.numba_math import exp2i, exp2i_f64, tuned_vector_width",
        "",
        *constants,
        f"_INF = np.{graph.dtype.name}(np.inf)",
        "",
        "",
        "@numba.njit(nogil=True, fastmath={" + ", ".join(map(repr, sorted(_FASTMATH))) + "},",
        "            error_model='numpy',",
        "            boundscheck=False, cache=_CACHE)",
        f"def kernel({names}, out{params}):",
        "    tuned_vector_width()",
        "    bad = False",
        f"    for i in range(out.shape[0] // {n_out}):",
        *loads,
        *checks,
        *("        " + line for line in body),
        *stores,
        "    return bad",
        "",
    ]
    return "\n".join(lines)


def _helpers_digest() -> str:
    """Hash of the helpers the kernels call: Numba's cache does not track such dependencies,
    so a change to them must change the generated source (and so the cache entry)."""
    global _HELPERS
    if _HELPERS is None:
        path = Path(__file__).with_name("numba_math.py")
        _HELPERS = hashlib.sha1(path.read_bytes()).hexdigest()[:12]
    return _HELPERS


_HELPERS: str | None = None


def _load(source: str) -> Any:
    """Compile (or load from the disk cache) the generated module; return its kernel."""
    digest = hashlib.sha1(source.encode()).hexdigest()[:20]
    fn = _COMPILED.get(digest)
    if fn is not None:
        return fn
    name = f"roughdiffuse_fastpath_{digest}"
    directory = private_cache_dir()
    path = None
    if directory is not None:
        try:
            path = directory / f"rdk_{digest}.py"
            if not path.exists() or path.read_text() != source:
                write_text(path, source)
        except (OSError, ValueError):  # ValueError: check_output_path found it unwritable
            path = None
    if path is not None:
        spec = importlib.util.spec_from_file_location(name, path)
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        module._CACHE = True  # type: ignore[attr-defined]
        sys.modules[name] = module
        spec.loader.exec_module(module)
    else:  # no safe cache folder: compile in memory, every process anew
        module = types.ModuleType(name)
        module._CACHE = False  # type: ignore[attr-defined]
        sys.modules[name] = module
        exec(compile(source, f"<{name}>", "exec"), module.__dict__)  # noqa: S102 - our code
    _COMPILED[digest] = module.kernel
    return module.kernel


def _trace(
    model: Model, entry: str, dtype: np.dtype, pattern: tuple[bool, ...], e0: np.ndarray
) -> tuple[Any, tuple[np.ndarray, ...], int]:
    channels = max(model.channels, e0.shape[0] if e0.ndim else 0)
    graph = Graph(dtype)
    inputs = _ENTRIES[entry]
    symbols = [SymVec(graph, name) if w == 3 else graph.input(f"{name}0") for name, w in inputs]
    outputs = []
    for c in range(max(channels, 1)):
        m = model.channel(c) if channels else model
        if entry == "radiance":
            e = e0[c] if e0.ndim else e0
            outputs.append(m.radiance(*symbols, e.astype(dtype)))
        else:
            outputs.append(getattr(m, entry)(*symbols))
    source = _source(graph, outputs, inputs, pattern, channels)
    return _load(source), tuple(graph.params), channels


def _kernel_for(
    model: Model,
    dtype: np.dtype,
    pattern: tuple[bool, ...],
    e0: np.ndarray,
    entry: str = "radiance",
) -> tuple[Any, tuple[np.ndarray, ...], int]:
    key = (entry, _value_key(model), dtype.str, pattern, _value_key(e0))
    hit = _TRACES.get(key)
    if hit is None:
        hit = _trace(model, entry, dtype, pattern, e0)
        with _LOCK:
            if len(_TRACES) > 512:
                _TRACES.clear()
            _TRACES[key] = hit
            _STRUCTURES.add((entry, _structure_key(model), dtype.str, pattern, e0.shape))
    return hit


# ------------------------------------------------------------------ evaluation
def _pool(threads: int) -> ThreadPoolExecutor:
    global _POOL, _POOL_SIZE
    with _LOCK:
        if _POOL is None or _POOL_SIZE != threads:
            if _POOL is not None:
                _POOL.shutdown(wait=False)
            _POOL = ThreadPoolExecutor(threads, thread_name_prefix="roughdiffuse-fastpath")
            _POOL_SIZE = threads
        return _POOL


def _as_numpy(entry: str, name: str, x: Any, width: int) -> np.ndarray:
    mod = type(x).__module__
    if mod.startswith(("jax", "torch")):
        raise ParameterError(
            f"{name}: the fast path takes NumPy arrays; call model.{entry} for JAX or PyTorch"
        )
    a = np.asarray(x)
    if width == 3 and (a.ndim < 1 or a.shape[-1] != 3):
        raise ParameterError(f"{name} must have shape (..., 3) (got shape {a.shape})")
    if not (np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.integer)):
        raise ParameterError(f"{name} must hold real numbers (got dtype {a.dtype})")
    return a


def _result_dtype(*arrays: np.ndarray) -> np.dtype:
    """As the reference path: float64 if any input is, else float32 if any is, else float64."""
    if any(a.dtype == np.float64 for a in arrays):
        return np.dtype(np.float64)
    if any(a.dtype == np.float32 for a in arrays):
        return np.dtype(np.float32)
    return np.dtype(np.float64)


@dataclasses.dataclass
class _Call:
    """One call, checked and laid out: what :func:`_run` needs besides the kernel."""

    entry: str
    arrays: list[np.ndarray]
    flats: list[np.ndarray]
    pattern: tuple[bool, ...]
    shape: tuple[int, ...]
    rows: int
    dtype: np.dtype
    e0: np.ndarray
    key: Any = None


def _prepare(
    entry: str, args: tuple[Any, ...], irradiance: Any, dtype: np.dtype | None = None
) -> _Call:
    inputs = _ENTRIES[entry]
    arrays = [_as_numpy(entry, name, x, w) for (name, w), x in zip(inputs, args, strict=True)]
    widths = [w for _, w in inputs]
    try:
        shape = np.broadcast_shapes(
            *(a.shape[:-1] if w == 3 else a.shape for a, w in zip(arrays, widths, strict=True))
        )
    except ValueError:
        listed = ", ".join(f"{k} {a.shape}" for (k, _), a in zip(inputs, arrays, strict=True))
        kind = "direction" if widths[0] == 3 else "cosine"
        raise ParameterError(f"{kind} arrays do not broadcast: {listed}") from None
    if dtype is None:
        dtype = _result_dtype(*arrays)
    e0 = np.asarray(irradiance, dtype=np.float64)
    if e0.ndim > 1 or not np.all(np.isfinite(e0)):
        raise ParameterError("irradiance must be a finite number or a 1-D array of channel values")
    rows = int(np.prod(shape, dtype=np.int64))
    pattern = []
    flats = []
    for a, w in zip(arrays, widths, strict=True):
        if a.size == w:  # one direction (or cosine) for every row
            pattern.append(True)
            flats.append(np.ascontiguousarray(a.reshape(w), dtype=dtype))
            continue
        full = (*shape, w) if w == 3 else shape
        if a.shape != full:  # partial broadcast: materialise (rare)
            a = np.broadcast_to(a, full)
        pattern.append(False)
        flats.append(a.reshape(rows, w) if a.flags.c_contiguous else a)
    return _Call(entry, arrays, flats, tuple(pattern), shape, rows, np.dtype(dtype), e0)


def _run(
    model: Model,
    call: _Call,
    out: np.ndarray | None,
    chunk: int | None,
    threads: int | None,
) -> np.ndarray:
    if chunk is not None and chunk < 1:
        raise ParameterError(f"chunk must be a positive number of rows (got {chunk})")
    if threads is None:  # every core, but no thread with less than ROWS_PER_THREAD rows
        threads = max(1, min(cpu_count(), call.rows // ROWS_PER_THREAD))
    threads = int(threads)
    if threads < 1:
        raise ParameterError(f"threads must be >= 1 (got {threads})")
    dtype, rows, shape = call.dtype, call.rows, call.shape
    kernel, params, channels = _kernel_for(model, dtype, call.pattern, call.e0, call.entry)
    kernel = Compiled(kernel)  # a new signature is compiled under the cache's lock
    out_shape = (*shape, channels) if channels else shape
    if out is None:
        out = np.empty(out_shape, dtype=dtype)
    elif out.shape != out_shape or out.dtype != dtype or not out.flags.c_contiguous:
        raise ParameterError(
            f"out must be a C-contiguous {dtype} array of shape {out_shape} "
            f"(got {out.dtype} {out.shape})"
        )
    flat_out = out.reshape(-1)
    width = max(channels, 1)
    widths = [w for _, w in _ENTRIES[call.entry]]
    flats, pattern = call.flats, call.pattern

    if chunk is None:
        in_place = all(
            const or (a.ndim == 2 and a.dtype == dtype and a.flags.c_contiguous)
            for a, const in zip(flats, pattern, strict=True)
        )
        chunk = max(1, -(-rows // threads)) if in_place else DEFAULT_CHUNK

    def rows_of(a: np.ndarray, const: bool, w: int, start: int, stop: int) -> np.ndarray:
        if const:
            return a
        if a.ndim == 2:
            part = a[start:stop]
        else:  # not C-contiguous: take the rows through a flat index
            part = a.reshape(-1, w)[start:stop] if a.flags.c_contiguous else None
            if part is None:
                idx = np.unravel_index(np.arange(start, stop), shape)
                part = a[idx]
        return np.ascontiguousarray(part, dtype=dtype).reshape(-1)

    def work(start: int) -> int:
        stop = min(start + chunk, rows)
        args = [
            rows_of(a, c, w, start, stop) for a, c, w in zip(flats, pattern, widths, strict=True)
        ]
        o = flat_out[start * width : stop * width]
        return start if kernel(*args, o, *params) else -1

    starts = range(0, rows, chunk)
    if threads == 1 or len(starts) <= 1:
        bad = [work(s) for s in starts]
    elif len(starts) <= threads:
        # one chunk per thread: the calling thread computes the first itself, a hand-over
        # less
        futures = [_pool(threads).submit(work, s) for s in starts[1:]]
        try:
            first = work(starts[0])
        finally:
            rest = [f.result() for f in futures]
        bad = [first, *rest]
    else:
        bad = list(_pool(threads).map(work, starts))
    names = [name for name, _ in _ENTRIES[call.entry]]
    for start in bad:
        if start >= 0:
            _check_directions(names, call.arrays, shape, start, min(start + chunk, rows), dtype)
    return out


def evaluate(
    model: Model,
    n: Any,
    l: Any,
    v: Any,
    irradiance: Any = 1.0,
    *,
    out: np.ndarray | None = None,
    chunk: int | None = None,
    threads: int | None = None,
) -> np.ndarray:
    """Radiance L = f_r E0 cos θi of ``model``, compiled, on NumPy arrays.

    The same values as ``model.radiance(n, l, v, irradiance)`` (the same code is compiled),
    to float rounding: float32 input is computed in float32, float64 input in float64.
    ``model.radiance`` itself runs this on large NumPy arrays (see
    :mod:`roughdiffuse.engine.dispatch`); this is the explicit form, with control of ``out``,
    ``chunk`` and ``threads``.

    Parameters
    ----------
    model : Model
        Any roughdiffuse model with scalar parameters (an RGB albedo, a trailing axis of C
        values, is supported).
    n, l, v : array_like (..., 3)
        Normal, direction to the light and to the viewer (normalised here). Leading shapes
        broadcast; a single (3,) direction (a distant light, an orthographic camera) is read
        once, not copied. Zero, NaN or infinite vectors raise ``ValueError``.
    irradiance : float or array (C,)
        E0, the irradiance on a plane facing the source (per channel if an array).
    out : ndarray, optional
        Where to write the result (C-contiguous, the right shape and dtype; may be a
        ``numpy.memmap``).
    chunk : int, optional
        Rows per unit of work. Default: one contiguous part per thread when the inputs are
        read in place, else :data:`DEFAULT_CHUNK` rows (converted chunk by chunk). With
        ``numpy.memmap`` inputs, give a chunk to bound the pages touched at once.
    threads : int, optional
        Threads to use (default: every core this process may run on, :func:`cpu_count`, but
        no more than one per :data:`ROWS_PER_THREAD` rows).

    Returns
    -------
    ndarray (...) or (..., C)
        float32 if the inputs are float32 (and none is float64), else float64.

    Examples
    --------
    >>> import numpy as np, roughdiffuse as rd
    >>> z = np.array([[0.0, 0.0, 1.0]], dtype=np.float32)
    >>> round(float(evaluate(rd.Lambert(1.0), z, z, z)[0] * np.pi), 6)  # float32 in, float32 out
    1.0
    """
    _check_model(model)
    return _run(model, _prepare("radiance", (n, l, v), irradiance), out, chunk, threads)


def brdf(
    model: Model,
    wi: Any,
    wo: Any,
    *,
    out: np.ndarray | None = None,
    chunk: int | None = None,
    threads: int | None = None,
) -> np.ndarray:
    """``model.brdf(wi, wo)``, compiled, on NumPy arrays (as :func:`evaluate` for radiance).

    Parameters
    ----------
    model : Model
        Any roughdiffuse model with scalar (or per-channel) parameters.
    wi, wo : array_like (..., 3)
        Directions to the light and the viewer in the local frame (z = normal), normalised
        here; they broadcast. Zero, NaN or infinite vectors raise ``ValueError``.
    out, chunk, threads
        As for :func:`evaluate`.

    Returns
    -------
    ndarray (...) or (..., C)
        The BRDF in 1/sr, in the inputs' float dtype.

    Examples
    --------
    >>> import numpy as np, roughdiffuse as rd
    >>> z = np.array([[0.0, 0.0, 1.0]])
    >>> float(brdf(rd.Lambert(1.0), z, z)[0] * np.pi)
    1.0
    """
    _check_model(model)
    return _run(model, _prepare("brdf", (wi, wo), 1.0), out, chunk, threads)


def brdf_cosines(
    model: Model,
    mu_i: Any,
    mu_o: Any,
    cos_io: Any,
    *,
    out: np.ndarray | None = None,
    chunk: int | None = None,
    threads: int | None = None,
) -> np.ndarray:
    """``model.brdf_cosines(mu_i, mu_o, cos_io)``, compiled, on NumPy arrays.

    Parameters
    ----------
    model : Model
        Any roughdiffuse model with scalar (or per-channel) parameters.
    mu_i, mu_o, cos_io : array_like (...)
        n·wi, n·wo and wi·wo (not normalised or validated, as on the reference path).
    out, chunk, threads
        As for :func:`evaluate`.

    Returns
    -------
    ndarray (...) or (..., C)

    Examples
    --------
    >>> import numpy as np, roughdiffuse as rd
    >>> float(brdf_cosines(rd.Lambert(1.0), np.ones(2), np.ones(2), np.ones(2))[0] * np.pi)
    1.0
    """
    _check_model(model)
    return _run(model, _prepare("brdf_cosines", (mu_i, mu_o, cos_io), 1.0), out, chunk, threads)


def _check_model(model: Any) -> None:
    if not is_model(model):
        raise ParameterError(f"model must be a roughdiffuse Model (got {type(model).__name__})")
    if not type(model).closed_form:
        raise ParameterError(
            f"{type(model).__name__} is not a closed form (a simulation or a table): the fast "
            "path compiles closed forms only; call model.radiance (NumPy) instead"
        )


# ------------------------------------------------------------------ automatic dispatch
def kernel_key(model: Model, entry: str, args: tuple[Any, ...], irradiance: Any) -> _Call:
    """The laid-out call ``model.<entry>(*args)`` (used by :mod:`roughdiffuse.engine.dispatch`),
    with the reference path's dtype rule (Python numbers do not count)."""
    dtype = _result_dtype(*(a for a in args if isinstance(a, np.ndarray)))
    call = _prepare(entry, args, irradiance, dtype)
    call.key = (entry, _structure_key(model), dtype.str, call.pattern, call.e0.shape)
    return call


def is_loaded(call: _Call) -> bool:
    """Whether a kernel of this call's structure is loaded in this process."""
    return call.key in _STRUCTURES


def build(model: Model, call: _Call) -> None:
    """Trace and compile (or load) the kernel of a call laid out by :func:`kernel_key`."""
    _kernel_for(model, call.dtype, call.pattern, call.e0, call.entry)


def run_entry(model: Model, call: _Call) -> np.ndarray:
    """Run a call laid out by :func:`kernel_key` whose kernel is built."""
    return _run(model, call, None, None, None)


def _check_directions(
    names: list[str],
    arrays: list[np.ndarray],
    shape: tuple[int, ...],
    start: int,
    stop: int,
    dtype: np.dtype,
) -> None:
    """Raise ValueError where the reference path does (``frames.unit_components``: a squared
    norm, in the evaluation dtype, that is 0, infinite or NaN) for rows [start, stop), which
    the kernel's quick test flagged."""
    for name, a in zip(names, arrays, strict=True):
        if name in ("mu_i", "mu_o", "cos_io"):  # cosines are not validated
            continue
        part = np.broadcast_to(a, (*shape, 3)).reshape(-1, 3)[start:stop].astype(dtype)
        with np.errstate(over="ignore", under="ignore", invalid="ignore"):
            x, y, z = part[:, 0], part[:, 1], part[:, 2]
            n2 = x * x + y * y + z * z
        if np.any(~np.isfinite(n2) | (n2 == 0)):
            raise ParameterError(f"{name} must contain non-zero, finite direction vectors")


def evaluate_batches(
    model: Model,
    batches: Iterable[tuple[Any, Any, Any]],
    irradiance: Any = 1.0,
    **kwargs: Any,
) -> Iterator[np.ndarray]:
    """Stream :func:`evaluate` over an iterable of ``(n, l, v)`` batches.

    For inputs that do not fit in memory at once (read from files, generated on the fly):
    each batch is evaluated and yielded before the next is read.

    Examples
    --------
    >>> import numpy as np, roughdiffuse as rd
    >>> z = np.array([[0.0, 0.0, 1.0]])
    >>> [float(r[0] * np.pi) for r in evaluate_batches(rd.Lambert(1.0), [(z, z, z)] * 2)]
    [1.0, 1.0]
    """
    for n, l, v in batches:
        yield evaluate(model, n, l, v, irradiance, **kwargs)
