"""Array-namespace helpers shared by every model.

The models are written once against the Python array API standard; these helpers pick the
namespace of the caller's arrays (NumPy, JAX or PyTorch), convert parameters to it, and give
the branch-free "safe" primitives (the double-``where`` idiom) that keep values *and*
gradients finite where a square root or a division meets zero.
"""

from __future__ import annotations

import contextlib
import numbers
from typing import Any

import array_api_compat
import numpy as np

Array = Any
"""Any array of a supported namespace (NumPy, JAX, PyTorch)."""

FLOAT_TYPES = ("float32", "float64")


def _is_scalar(x: object) -> bool:
    return isinstance(x, numbers.Number) and not isinstance(x, np.generic)


def namespace(*xs: object) -> Any:
    """Return the array namespace for ``xs`` (Python scalars and ``None`` are ignored).

    JAX wins over the others (so ``jax.grad`` with respect to a model parameter works with
    NumPy directions), then PyTorch; NumPy is the default.
    """
    arrays = [x for x in xs if x is not None and not _is_scalar(x)]
    if any(array_api_compat.is_jax_array(x) for x in arrays):
        import jax.numpy as jnp

        return jnp
    if any(array_api_compat.is_torch_array(x) for x in arrays):
        return array_api_compat.array_namespace(
            *[x for x in arrays if array_api_compat.is_torch_array(x)]
        )
    for x in arrays:  # other array-API objects name their namespace (the fast path's tracer)
        if hasattr(x, "__array_namespace__") and not isinstance(x, np.ndarray | np.generic):
            return x.__array_namespace__()
    from array_api_compat import numpy as compat_numpy  # 0.1 s on first use (numpy.f2py...)

    return compat_numpy


def is_jax(xp: Any) -> bool:
    """True when ``xp`` is JAX's namespace."""
    return array_api_compat.is_jax_namespace(xp)


def is_numpy(xp: Any) -> bool:
    """True when ``xp`` is NumPy's namespace (as :func:`namespace` returns it)."""
    return xp is np or array_api_compat.is_numpy_namespace(xp)


def is_tracer(x: object) -> bool:
    """True for a JAX tracer (inside ``jit``, ``grad``, ``vmap``)."""
    if not array_api_compat.is_jax_array(x):
        return False
    import jax

    return isinstance(x, jax.core.Tracer)


def concrete(x: object, *, non_numbers: bool = False) -> np.ndarray | None:
    """Return ``x`` as a NumPy array when its value is known now, else ``None``.

    Values inside ``jax.jit`` (tracers), the fast path's symbolic values and placeholders
    that JAX's tree utilities pass through a dataclass constructor have no concrete value:
    validation skips them.

    Parameters
    ----------
    x : object
        The value.
    non_numbers : bool
        Return a value that is not an array-API object and that NumPy cannot read as numbers
        (``None``, an arbitrary object) as a 0-d object array, for a check to refuse, instead
        of ``None`` (skipped).
    """
    if is_tracer(x):
        return None
    if array_api_compat.is_torch_array(x):
        return x.detach().cpu().numpy()  # type: ignore[attr-defined]
    if (
        hasattr(x, "__array_namespace__")
        and not isinstance(x, np.ndarray | np.generic)
        and not array_api_compat.is_jax_array(x)
    ):
        return None  # Dr.Jit values, the fast path's symbolic values: no value here and now
    try:
        arr = np.asarray(x)
    except Exception:  # noqa: BLE001 - a value NumPy cannot read has no value as numbers
        arr = np.asarray(None)
    if arr.dtype != object or non_numbers:
        return arr
    return None


def result_dtype(xp: Any, *arrays: Array) -> Any:
    """Floating dtype of the result: the inputs' float dtype, float64 for integer input."""
    dtypes = [a.dtype for a in arrays if hasattr(a, "dtype")]
    for dt in dtypes:
        if dt == xp.float64:
            return xp.float64
    for dt in dtypes:
        if dt == xp.float32:
            return xp.float32
    return xp.float64 if _x64_enabled(xp) else xp.float32


def _x64_enabled(xp: Any) -> bool:
    if not is_jax(xp):
        return True
    import jax

    return bool(jax.config.read("jax_enable_x64"))


def asarray(xp: Any, x: object, dtype: Any = None) -> Array:
    """Convert ``x`` (a scalar, list or array of any namespace) to ``xp``."""
    if array_api_compat.is_torch_array(x) and not array_api_compat.is_torch_namespace(xp):
        x = x.detach().cpu().numpy()  # type: ignore[attr-defined]
    if isinstance(x, list | tuple):
        x = np.asarray(x, dtype=np.float64)
    if dtype is None:
        return xp.asarray(x)
    if array_api_compat.is_torch_namespace(xp) and array_api_compat.is_torch_array(x):
        return x.to(dtype)  # keeps the autograd graph
    return xp.asarray(x, dtype=dtype)


def safe_sqrt(xp: Any, x: Array) -> Array:
    """sqrt(max(x, 0)) with a finite (zero) gradient at 0."""
    pos = x > 0
    return xp.where(pos, xp.sqrt(xp.where(pos, x, 1.0)), 0.0)


def safe_div(xp: Any, num: Array, den: Array, default: float = 0.0) -> Array:
    """num / den where den != 0, else ``default``; gradients stay finite."""
    nz = den != 0
    return xp.where(nz, num / xp.where(nz, den, 1.0), default)


def clip(xp: Any, x: Array, lo: float, hi: float) -> Array:
    """Clip ``x`` to [lo, hi] with ``where`` (works in every namespace).

    NumPy gets ``np.clip`` (one pass instead of four; the same values, NaN stays NaN).
    """
    if is_numpy(xp):
        return np.clip(x, lo, hi)
    return xp.where(x < lo, lo, xp.where(x > hi, hi, x))


def maximum(xp: Any, a: Array, b: Array | float) -> Array:
    """Elementwise maximum (``where``-based, so it broadcasts scalars in every namespace).

    NumPy gets ``np.fmax`` (one pass; like the ``where`` form it returns ``b`` for a NaN ``a``).
    """
    if is_numpy(xp):
        return np.fmax(a, b)
    return xp.where(a >= b, a, b)


def minimum(xp: Any, a: Array, b: Array | float) -> Array:
    """Elementwise minimum (NumPy: ``np.fmin``, see :func:`maximum`)."""
    if is_numpy(xp):
        return np.fmin(a, b)
    return xp.where(a <= b, a, b)


def double_precision(xp: Any) -> contextlib.AbstractContextManager[None]:
    """Context in which ``xp`` computes in float64: JAX's ``enable_x64``, else nothing.

    For code that needs double precision whatever the caller's JAX setting (the V-cavity
    solver's crossed-strings differences lose digits in float32).
    """
    if is_jax(xp):
        import jax

        return jax.enable_x64(True)
    return contextlib.nullcontext()
