"""A small array namespace over Dr.Jit, so the models' kernels run inside Mitsuba 3 as they are.

The models' formulas (:meth:`roughdiffuse.models.base.Model.kernel`) and samplers
(:mod:`roughdiffuse.models.sampling`) are written once against an array namespace ``xp``:
``xp.where``, ``xp.sqrt``, ``xp.atan2``, ``xp.sin``, ``xp.cos``, ``xp.exp``, ``xp.log``,
``xp.abs``, ``xp.sum`` and Python operators; a tabulated model (``VCavity``) also reads its
table with ``xp.floor``, ``xp.astype(..., xp.int32)`` and ``xp.take`` (a gather).
This module gives that handful of functions for Dr.Jit values (``mi.Float``, ``mi.Color3f``
in every Mitsuba variant: plain Python floats in ``scalar_rgb``, traced JIT arrays with
automatic differentiation in ``llvm_ad_rgb``), so a Mitsuba plugin calls the same code as
NumPy and JAX do, not a second copy of each formula.

Two wrappers carry the values:

* :class:`DrArray` wraps one Dr.Jit value (one number per lane, any Dr.Jit type). It has
  ``ndim == 0`` (a kernel sees one lane) and ``x[..., None]`` returns ``x`` unchanged.
* :class:`Nodes` is a short trailing axis of constants, e.g. the Gauss–Legendre nodes the
  Gaussian facet distribution integrates over (``xp.asarray(numpy_array)``); operations map
  over it elementwise and ``xp.sum(..., axis=-1)`` adds it up. ``x[..., None]`` of a
  :class:`Nodes` adds an axis of length 1 (Nodes of Nodes), which broadcasts against another
  node axis as NumPy's trailing axes do (a rule of rules, as ``Coated``'s internal sums).
  ``xp.take(nodes, index)`` reads it as a table instead: one entry per lane, chosen by a
  Dr.Jit integer ``index`` (``dr.gather`` from a Dr.Jit array of the constants, built once
  per :class:`Nodes`).

Wrap every input with :func:`wrap` (Dr.Jit's operators reject foreign types, so a raw Dr.Jit
value must never meet a wrapper) and take results back with :func:`unwrap`.
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from typing import Any

import drjit as dr
import numpy as np

from .._validate import ParameterError

__all__ = ["DrArray", "Nodes", "drjit_namespace", "unwrap", "wrap"]


def _raw(x: Any) -> Any:
    if isinstance(x, DrArray):
        return x.v
    if isinstance(x, np.generic):
        return x.item()
    return x


def _binary(op: Callable[[Any, Any], Any], reflected: bool = False) -> Callable[..., Any]:
    def f(self: Any, other: Any) -> Any:
        if isinstance(other, Nodes):
            return other._map2(self, op, swap=not reflected)
        a, b = (_raw(other), self.v) if reflected else (self.v, _raw(other))
        return DrArray(op(a, b))

    return f


class DrArray:
    """One Dr.Jit value seen by a kernel as a 0-d array (see module docstring)."""

    __slots__ = ("v",)
    __array_ufunc__ = None  # NumPy scalars defer to our reflected operators
    __hash__ = None  # type: ignore[assignment]
    ndim = 0
    shape: tuple[int, ...] = ()
    dtype = "drjit"

    def __init__(self, v: Any) -> None:
        self.v = v

    def __getitem__(self, key: Any) -> DrArray:
        return self  # x[..., None] on a per-lane value: nothing to add

    def __array_namespace__(self, api_version: str | None = None) -> Any:
        """The namespace of this value (so ``roughdiffuse._array.namespace`` finds it and
        parameter checks, which need a concrete value, let it pass)."""
        return drjit_namespace

    def __repr__(self) -> str:
        return f"DrArray({self.v!r})"

    __add__ = _binary(operator.add)
    __radd__ = _binary(operator.add, True)
    __sub__ = _binary(operator.sub)
    __rsub__ = _binary(operator.sub, True)
    __mul__ = _binary(operator.mul)
    __rmul__ = _binary(operator.mul, True)
    __truediv__ = _binary(operator.truediv)
    __rtruediv__ = _binary(operator.truediv, True)
    __pow__ = _binary(operator.pow)
    __rpow__ = _binary(operator.pow, True)
    __lt__ = _binary(operator.lt)
    __le__ = _binary(operator.le)
    __gt__ = _binary(operator.gt)
    __ge__ = _binary(operator.ge)
    __eq__ = _binary(operator.eq)  # type: ignore[assignment]
    __ne__ = _binary(operator.ne)  # type: ignore[assignment]
    __and__ = _binary(operator.and_)
    __rand__ = _binary(operator.and_, True)
    __or__ = _binary(operator.or_)
    __ror__ = _binary(operator.or_, True)

    def __neg__(self) -> DrArray:
        return DrArray(-self.v)

    def __invert__(self) -> DrArray:
        v = self.v
        return DrArray((not v) if isinstance(v, bool) else ~v)


class Nodes:
    """A short trailing axis (a Python list of floats or :class:`DrArray`), or a table of
    constants that :meth:`_DrJitNamespace.take` gathers from (see module docstring)."""

    __slots__ = ("items", "_buffers")
    __array_ufunc__ = None
    __hash__ = None  # type: ignore[assignment]
    ndim = 1
    dtype = "drjit"

    def __init__(self, items: list[Any]) -> None:
        self.items = items
        self._buffers: dict[type, Any] = {}

    def buffer(self, array_type: type) -> Any:
        """The constants as a Dr.Jit array of ``array_type`` (cached), for ``dr.gather``."""
        buf = self._buffers.get(array_type)
        if buf is None:
            if not all(isinstance(v, float) for v in self.items):
                raise TypeError("take reads a table of constants, not of Dr.Jit values")
            buf = array_type(np.asarray(self.items, dtype=np.float32))
            self._buffers[array_type] = buf
        return buf

    @property
    def shape(self) -> tuple[int]:
        return (len(self.items),)

    @property
    def depth(self) -> int:
        """The number of node axes (1, or more for Nodes of Nodes)."""
        first = self.items[0] if self.items else None
        return 1 + (first.depth if isinstance(first, Nodes) else 0)

    def __getitem__(self, key: Any) -> Nodes:
        if isinstance(key, tuple) and key[:1] == (Ellipsis,) and key[1:] == (None,):
            return _expand(self)
        return self

    def _map2(self, other: Any, op: Callable[[Any, Any], Any], swap: bool = False) -> Nodes:
        if isinstance(other, Nodes) and other.depth >= self.depth:
            if other.depth > self.depth:  # self broadcasts against each of other's items
                return Nodes([_apply(op, b, self) if swap else _apply(op, self, b)
                              for b in other.items])  # fmt: skip
            a_items, b_items = _broadcast(self.items, other.items)
            pairs = zip(b_items, a_items, strict=True) if swap else zip(a_items, b_items,
                                                                        strict=True)
            return Nodes([_apply(op, a, b) for a, b in pairs])
        if swap:
            return Nodes([_apply(op, other, a) for a in self.items])
        return Nodes([_apply(op, a, other) for a in self.items])

    def _map(self, fn: Callable[[Any], Any]) -> Nodes:
        return Nodes([fn(a) for a in self.items])


def _expand(x: Any) -> Nodes:
    """``x[..., None]``: a trailing axis of length 1."""
    if isinstance(x, Nodes):
        return Nodes([_expand(v) for v in x.items])
    return Nodes([x])


def _broadcast(a: list[Any], b: list[Any]) -> tuple[list[Any], list[Any]]:
    """Two node axes of one depth, an axis of length 1 repeated to the other's length."""
    if len(a) == 1 and len(b) != 1:
        a = a * len(b)
    elif len(b) == 1 and len(a) != 1:
        b = b * len(a)
    if len(a) != len(b):
        raise ParameterError(f"node axes of lengths {len(a)} and {len(b)} do not broadcast")
    return a, b


def _items(x: Any, depth: int, n: int) -> list[Any]:
    """The ``n`` items of ``x`` along the outer of ``depth`` node axes (``x`` whole if it has
    fewer axes; an axis of length 1 repeated)."""
    if isinstance(x, Nodes) and x.depth == depth:
        return _broadcast(x.items, [None] * n)[0]
    return [x] * n


def _elementwise(fn: Callable[..., Any], *xs: Any) -> Any:
    """``fn`` over the node axes of ``xs`` (broadcast as NumPy does), or ``fn(*xs)``."""
    nodes = [x for x in xs if isinstance(x, Nodes)]
    if not nodes:
        return fn(*xs)
    depth = max(x.depth for x in nodes)
    n = max(len(x.items) for x in nodes if x.depth == depth)
    columns = [_items(x, depth, n) for x in xs]
    return Nodes([_elementwise(fn, *row) for row in zip(*columns, strict=True)])


def _apply(op: Callable[[Any, Any], Any], a: Any, b: Any) -> Any:
    if isinstance(a, DrArray | Nodes) or isinstance(b, DrArray | Nodes):
        if isinstance(a, DrArray | Nodes):
            return op(a, b)
        return op(DrArray(a), b)
    return op(a, b)


def _nodes_binary(op: Callable[[Any, Any], Any], reflected: bool = False) -> Callable[..., Any]:
    def f(self: Nodes, other: Any) -> Nodes:
        return self._map2(other, op, swap=reflected)

    return f


for _name, _op in [
    ("add", operator.add),
    ("sub", operator.sub),
    ("mul", operator.mul),
    ("truediv", operator.truediv),
    ("pow", operator.pow),
]:
    setattr(Nodes, f"__{_name}__", _nodes_binary(_op))
    setattr(Nodes, f"__r{_name}__", _nodes_binary(_op, True))
for _name, _op in [("lt", operator.lt), ("le", operator.le), ("gt", operator.gt)]:
    setattr(Nodes, f"__{_name}__", _nodes_binary(_op))
Nodes.__ge__ = _nodes_binary(operator.ge)  # type: ignore[method-assign]
Nodes.__eq__ = _nodes_binary(operator.eq)  # type: ignore[method-assign,assignment]
Nodes.__ne__ = _nodes_binary(operator.ne)  # type: ignore[method-assign,assignment]
for _name, _op in [("and", operator.and_), ("or", operator.or_)]:
    setattr(Nodes, f"__{_name}__", _nodes_binary(_op))
    setattr(Nodes, f"__r{_name}__", _nodes_binary(_op, True))
Nodes.__neg__ = lambda self: self._map(operator.neg)  # type: ignore[attr-defined]
Nodes.__invert__ = lambda self: self._map(operator.invert)  # type: ignore[attr-defined]


def wrap(x: Any) -> DrArray:
    """Wrap a Dr.Jit value (or a Python number) for the kernels."""
    return x if isinstance(x, DrArray) else DrArray(x)


def unwrap(x: Any) -> Any:
    """The Dr.Jit value inside a :class:`DrArray` (a plain number is returned as is)."""
    return x.v if isinstance(x, DrArray) else x


def _unary(fn: Callable[[Any], Any]) -> Callable[[Any], Any]:
    def f(x: Any) -> Any:
        if isinstance(x, Nodes):
            return x._map(f)
        if isinstance(x, DrArray):
            return DrArray(fn(x.v))
        return fn(x)

    return f


class _DrJitNamespace:
    """The array functions the models use, over :class:`DrArray` and :class:`Nodes`."""

    __name__ = "roughdiffuse.integrations.drjit_namespace"
    float32 = "float32"
    float64 = "float64"
    pi = math.pi

    sqrt = staticmethod(_unary(dr.sqrt))
    sin = staticmethod(_unary(dr.sin))
    cos = staticmethod(_unary(dr.cos))
    exp = staticmethod(_unary(dr.exp))
    log = staticmethod(_unary(dr.log))
    abs = staticmethod(_unary(dr.abs))
    atan = staticmethod(_unary(dr.atan))
    acos = staticmethod(_unary(dr.acos))
    log1p = staticmethod(_unary(lambda v: dr.log(1.0 + v)))
    asin = staticmethod(_unary(dr.asin))
    floor = staticmethod(_unary(dr.floor))
    int32 = "int32"

    @staticmethod
    def astype(x: Any, dtype: Any) -> Any:
        """``xp.astype(x, xp.int32)``: a Dr.Jit float to the integer of its variant (a
        Python ``int`` in the scalar variants), rounding towards zero."""
        if dtype != "int32":
            raise TypeError(f"the Dr.Jit namespace casts to int32 only (got {dtype!r})")
        if isinstance(x, Nodes):
            return x._map(lambda a: _DrJitNamespace.astype(a, dtype))
        v = _raw(x)
        return DrArray(dr.int32_array_t(type(v))(v))

    @staticmethod
    def take(x: Any, indices: Any, axis: int = 0) -> DrArray:
        """``x[indices]`` per lane: the entry of the constants ``x`` (:class:`Nodes`, from
        ``xp.asarray`` of a 1-D NumPy array) at each lane's Dr.Jit integer index, by
        ``dr.gather`` (a list lookup in the scalar variants). Out-of-range indices are a bug
        of the caller (Dr.Jit reads 0 there)."""
        if axis != 0 or not isinstance(x, Nodes):
            raise TypeError("take reads a 1-D table of constants (xp.asarray) along axis 0")
        i = _raw(indices)
        if isinstance(i, int):  # scalar variants: one lane, a Python int
            return DrArray(x.items[i])
        value_type = dr.float32_array_t(type(i))  # Mitsuba's Float of the variant
        return DrArray(dr.gather(value_type, x.buffer(value_type), dr.uint32_array_t(type(i))(i)))

    @staticmethod
    def broadcast_arrays(*xs: Any) -> list[Any]:
        """Per-lane values broadcast already (one number per lane each)."""
        return list(xs)

    @staticmethod
    def reshape(x: Any, shape: Any) -> Any:
        """A per-lane value has no axes to reshape: returned as it is."""
        if isinstance(x, Nodes):
            raise TypeError("the Dr.Jit namespace cannot reshape a Nodes axis")
        return x

    @staticmethod
    def atan2(y: Any, x: Any) -> Any:
        return _elementwise(lambda b, a: DrArray(dr.atan2(_raw(b), _raw(a))), y, x)

    @staticmethod
    def where(cond: Any, a: Any, b: Any) -> Any:
        return _elementwise(lambda c, u, v: DrArray(dr.select(_raw(c), _raw(u), _raw(v))),
                            cond, a, b)  # fmt: skip

    @staticmethod
    def sum(x: Any, axis: int = -1) -> Any:
        """The sum over node axis ``axis`` (-1: the innermost, -2: the one outside it)."""
        if not isinstance(x, Nodes):
            return x
        if x.depth + axis > 0:  # an inner axis: the sum of each item
            return Nodes([_DrJitNamespace.sum(v, axis) for v in x.items])
        total = x.items[0]
        for item in x.items[1:]:
            total = total + item
        return total

    @staticmethod
    def asarray(x: Any, dtype: Any = None) -> Any:
        if isinstance(x, DrArray | Nodes):
            return x
        arr = np.asarray(x, dtype=np.float64)
        if arr.ndim == 0:
            return float(arr)
        if arr.ndim != 1:
            raise ParameterError(f"the Dr.Jit namespace holds 1-D constants only (got {arr.shape})")
        return Nodes(arr.tolist())

    @staticmethod
    def zeros_like(x: Any) -> Any:
        return 0.0 * x


drjit_namespace = _DrJitNamespace()
"""The namespace object to pass as ``xp`` to a kernel."""
