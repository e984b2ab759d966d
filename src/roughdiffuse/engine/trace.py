"""Trace a model's array-API code into straight-line scalar code (for :mod:`.fastpath`).

The formulas of roughdiffuse are written once, against the array API standard, and evaluated
on whole arrays. The fast path compiles them instead: it calls the *same* Python code
(``Model.radiance`` or ``Model.brdf``) with a special namespace whose "arrays" are symbols for
one element. Every operation on a symbol records a node of an expression graph (with
common-subexpression sharing); operations whose operands are all concrete (the model's
parameters, constants) are evaluated at once with NumPy, exactly as the reference path
evaluates them. The graph is then printed as the body of a scalar loop (see
:func:`scalar_source`), which Numba compiles.

Parameter values do not appear in the generated text: every concrete NumPy value that meets a
symbol becomes a run-time argument, so a new σ or albedo reuses the compiled loop. Python
number literals of the formula (0.33, π, ...) are compile-time constants.

Supported: + − × ÷, integer and real powers, comparisons, & | ~, ``where``, ``sqrt``, ``exp``,
``log``, ``log1p``, ``sin``, ``cos``, ``tan``, ``asin``, ``acos``, ``atan``, ``atan2``,
``abs``, ``minimum``, ``maximum`` and the array constructors used on symbols (``asarray``,
``zeros_like``, ``ones_like``, ``broadcast_arrays``); a Python ``if`` on a symbol raises
(kernels are branch-free by the project's rules).

Node axes: a quadrature written as arrays with a trailing node axis (``mu[..., None]`` times a
concrete 1-D array of nodes, then ``xp.sum(..., axis=-1)``) is traced as a loop, not unrolled:
a concrete array of n > 1 values that meets a symbol becomes a run-time array argument read at
the loop index, every operation that depends on it is a per-node symbol, and ``xp.sum`` over
the node axis prints as ``for j in range(n)`` accumulating them. So the generated code (and
Numba's compile time) grows with the quadrature's formula, not with its number of nodes. One
node axis at a time: a per-node symbol meets no array of another length.
"""

from __future__ import annotations

import math
from typing import Any

import array_api_compat.numpy as anp
import numpy as np

__all__ = ["Graph", "Sym", "SymVec", "TraceNamespace", "TraceError"]


class TraceError(TypeError):
    """The traced code did something a scalar kernel cannot express."""


_UNARY_MATH = {
    "sqrt": "math.sqrt",
    "exp": "math.exp",
    "log": "math.log",
    "log1p": "math.log1p",
    "expm1": "math.expm1",
    "sin": "math.sin",
    "cos": "math.cos",
    "tan": "math.tan",
    "asin": "math.asin",
    "acos": "math.acos",
    "atan": "math.atan",
    "abs": "abs",
    "floor": "np.floor",
    "exp2i": "exp2i",
    "exp2i_f64": "exp2i_f64",
}
_BINARY = {
    "add": "+",
    "sub": "-",
    "mul": "*",
    "div": "/",
    "lt": "<",
    "le": "<=",
    "gt": ">",
    "ge": ">=",
    "eq": "==",
    "ne": "!=",
    "and": "&",
    "or": "|",
}
_BOOL_OPS = {"lt", "le", "gt", "ge", "eq", "ne", "and", "or", "not"}


class Graph:
    """Expression graph of one traced evaluation.

    Operand references are tuples: ``("node", k)``, ``("lit", value)`` (a Python number of
    the formula), ``("par", k)`` (a concrete NumPy value: a run-time argument), ``("vec",
    k)`` (a concrete 1-D array of nodes: a run-time array argument read at the loop index) and
    ``("in", name)`` (an input component). ``loops[k]`` is the number of nodes node ``k``
    runs over (0: one value per row).

    Equal concrete values are one parameter (``share_scalars``), so that the operations on
    them are shared; with ``share_scalars=False`` each concrete number met is a parameter of
    its own (node arrays are still shared), so that the graph does not depend on which
    values happen to be equal (the GLSL printer's uniforms, :mod:`roughdiffuse.engine.glsl`).
    """

    def __init__(self, dtype: np.dtype, share_scalars: bool = True) -> None:
        self.dtype = np.dtype(dtype)
        self.share_scalars = share_scalars
        self.nodes: list[tuple[Any, ...]] = []
        self._index: dict[tuple[Any, ...], int] = {}
        self.params: list[np.ndarray] = []
        self._param_ids: dict[int, int] = {}
        self._param_values: dict[tuple[int, bytes], int] = {}
        self._keep: list[Any] = []  # keeps traced NumPy values alive (ids stay unique)
        self.inputs: list[str] = []
        self.loops: list[int] = []

    # -------------------------------------------------------------- operands
    def ref(self, x: Any) -> tuple[Any, ...]:
        if isinstance(x, Sym):
            if x.graph is not self:
                raise TraceError("symbols of two traces were mixed")
            return x.ref
        if isinstance(x, bool | np.bool_):
            return ("lit", bool(x))
        if isinstance(x, int | float) and not isinstance(x, np.generic):
            return ("lit", float(x))
        arr = np.asarray(x)
        if arr.size != 1 and max(arr.shape) != arr.size:
            raise TraceError(
                f"a concrete array of shape {arr.shape} meets a traced value: the fast path "
                "handles scalar parameters, per-channel albedo (split before tracing) and one "
                "node axis (a 1-D array of nodes)"
            )
        k = self._param_ids.get(id(x))
        if k is None:
            if arr.size == 1:
                value: Any = self.dtype.type(arr.reshape(()))
            else:
                value = np.ascontiguousarray(arr.reshape(-1), dtype=self.dtype)
            # one argument per distinct value: a parameter converted twice (each channel of
            # an RGB model converts its own copy) is one operand, so the operations on it
            # are shared (common subexpressions across channels)
            key = (np.ndim(value), np.asarray(value).tobytes())
            k = self._param_values.get(key) if self.share_scalars or key[0] else None
            if k is None:
                k = len(self.params)
                self._param_values[key] = k
                self.params.append(value)
            self._param_ids[id(x)] = k
            self._keep.append(x)
        return ("par", k) if arr.size == 1 else ("vec", k)

    def loop_of(self, ref: tuple[Any, ...]) -> int:
        """The number of nodes ``ref`` runs over (0: none)."""
        if ref[0] == "vec":
            return int(self.params[ref[1]].size)
        if ref[0] == "node":
            return self.loops[ref[1]]
        return 0

    def input(self, name: str) -> Sym:
        self.inputs.append(name)
        return Sym(self, ("in", name), bool_=False)

    def op(self, name: str, *args: Any) -> Sym:
        refs = tuple(self.ref(a) for a in args)
        key = (name, *refs)
        k = self._index.get(key)
        if k is None:
            lengths = {self.loop_of(r) for r in refs} - {0}
            if len(lengths) > 1:
                raise TraceError(f"node axes of lengths {sorted(lengths)} meet in one operation")
            loop = lengths.pop() if lengths else 0
            if name == "sum":
                if not loop:
                    raise TraceError("xp.sum over a node axis that the traced value does not have")
                loop = 0
            k = len(self.nodes)
            self.nodes.append(key)
            self.loops.append(loop)
            self._index[key] = k
        is_bool = name in _BOOL_OPS or (
            name == "where" and all(_is_bool_ref(self, r) for r in refs[1:])
        )
        return Sym(self, ("node", k), bool_=is_bool)

    def is_bool(self, ref: tuple[Any, ...]) -> bool:
        return _is_bool_ref(self, ref)


def _is_bool_ref(g: Graph, ref: tuple[Any, ...]) -> bool:
    if ref[0] == "lit":
        return isinstance(ref[1], bool)
    if ref[0] == "node":
        node = g.nodes[ref[1]]
        if node[0] in _BOOL_OPS:
            return True
        if node[0] == "where":
            return all(_is_bool_ref(g, r) for r in node[2:])
    return False


def _binop(name: str, swap: bool = False):  # noqa: ANN202 - operator factory
    def f(self: Sym, other: Any) -> Any:
        if isinstance(other, np.ndarray) and other.size != 1 and max(other.shape) != other.size:
            return NotImplemented
        return self.graph.op(name, other, self) if swap else self.graph.op(name, self, other)

    return f


class Sym:
    """A traced scalar: one element of an array the kernel computes with."""

    __array_ufunc__ = None  # NumPy defers to our reflected operators
    __array_priority__ = 1000
    ndim = 0
    shape: tuple[int, ...] = ()
    size = 1

    def __init__(self, graph: Graph, ref: tuple[Any, ...], bool_: bool) -> None:
        self.graph = graph
        self.ref = ref
        self._bool = bool_

    @property
    def dtype(self) -> np.dtype:
        return np.dtype(bool) if self._bool else self.graph.dtype

    def __array_namespace__(self, api_version: str | None = None) -> TraceNamespace:
        return TraceNamespace(self.graph)

    def __array__(self, *args: Any, **kwargs: Any) -> np.ndarray:
        raise TraceError("a traced value has no concrete value")

    def __bool__(self) -> bool:
        raise TraceError("Python `if` on a traced value: kernels must be branch-free (use where)")

    def __float__(self) -> float:
        raise TraceError("float() of a traced value")

    def __repr__(self) -> str:
        return f"Sym({self.ref})"

    def __getitem__(self, key: Any) -> Sym:
        if key is Ellipsis or key == (Ellipsis,) or key == ():
            return self
        if isinstance(key, tuple) and key[:1] == (Ellipsis,) and all(k is None for k in key[1:]):
            return self  # x[..., None]: a node axis to broadcast along (the loop's)
        raise TraceError(f"indexing a traced scalar with {key!r} (channel axes are split first)")

    __add__ = _binop("add")
    __radd__ = _binop("add", swap=True)
    __sub__ = _binop("sub")
    __rsub__ = _binop("sub", swap=True)
    __mul__ = _binop("mul")
    __rmul__ = _binop("mul", swap=True)
    __truediv__ = _binop("div")
    __rtruediv__ = _binop("div", swap=True)
    __lt__ = _binop("lt")
    __le__ = _binop("le")
    __gt__ = _binop("gt")
    __ge__ = _binop("ge")
    __and__ = _binop("and")
    __rand__ = _binop("and", swap=True)
    __or__ = _binop("or")
    __ror__ = _binop("or", swap=True)

    def __eq__(self, other: Any) -> Sym:  # type: ignore[override]
        return self.graph.op("eq", self, other)

    def __ne__(self, other: Any) -> Sym:  # type: ignore[override]
        return self.graph.op("ne", self, other)

    __hash__ = object.__hash__

    def __pow__(self, other: Any) -> Sym:
        return self.graph.op("pow", self, other)

    def __rpow__(self, other: Any) -> Sym:
        return self.graph.op("pow", other, self)

    def __neg__(self) -> Sym:
        return self.graph.op("neg", self)

    def __pos__(self) -> Sym:
        return self

    def __abs__(self) -> Sym:
        return self.graph.op("abs", self)

    def __invert__(self) -> Sym:
        return self.graph.op("not", self)


class SymVec:
    """A traced direction: one row (3,) of an (N, 3) input; indexing gives its components."""

    __array_ufunc__ = None
    ndim = 1
    shape = (3,)
    size = 3

    def __init__(self, graph: Graph, name: str) -> None:
        self.graph = graph
        self.components = tuple(graph.input(f"{name}{k}") for k in range(3))

    @property
    def dtype(self) -> np.dtype:
        return self.graph.dtype

    def __array_namespace__(self, api_version: str | None = None) -> TraceNamespace:
        return TraceNamespace(self.graph)

    def __array__(self, *args: Any, **kwargs: Any) -> np.ndarray:
        raise TraceError("a traced value has no concrete value")

    def __getitem__(self, key: Any) -> Sym:
        if isinstance(key, tuple) and len(key) == 2 and key[0] is Ellipsis:
            key = key[1]
        if isinstance(key, int) and -3 <= key < 3:
            return self.components[key]
        raise TraceError(f"unsupported index {key!r} of a traced direction")


def _traced(*xs: Any) -> bool:
    return any(isinstance(x, Sym | SymVec) for x in xs)


class TraceNamespace:
    """The array namespace of traced values: records symbolic operations, evaluates the rest."""

    __name__ = "roughdiffuse.engine.trace"
    float32 = np.dtype("float32")
    float64 = np.dtype("float64")
    bool = np.dtype("bool")
    pi = math.pi
    e = math.e

    def __init__(self, graph: Graph) -> None:
        self.graph = graph

    def __getattr__(self, name: str) -> Any:
        target = getattr(anp, name)
        if not callable(target):
            return target

        def concrete_only(*args: Any, **kwargs: Any) -> Any:
            if _traced(*args, *kwargs.values()):
                raise TraceError(f"xp.{name} on a traced value is not supported by the fast path")
            return target(*args, **kwargs)

        return concrete_only

    # constructors ------------------------------------------------------------
    def asarray(self, x: Any, dtype: Any = None, copy: Any = None) -> Any:
        if _traced(x):
            return x
        return anp.asarray(x, dtype=dtype)

    def astype(self, x: Any, dtype: Any, copy: bool = True) -> Any:
        return x if _traced(x) else anp.astype(x, dtype)

    def zeros_like(self, x: Any, dtype: Any = None) -> Any:
        return 0.0 if _traced(x) else anp.zeros_like(x, dtype=dtype)

    def ones_like(self, x: Any, dtype: Any = None) -> Any:
        return 1.0 if _traced(x) else anp.ones_like(x, dtype=dtype)

    def full_like(self, x: Any, fill_value: float, dtype: Any = None) -> Any:
        return float(fill_value) if _traced(x) else anp.full_like(x, fill_value, dtype=dtype)

    def broadcast_arrays(self, *xs: Any) -> list[Any]:
        if _traced(*xs):
            for x in xs:
                if not _traced(x) and np.ndim(x) != 0:
                    raise TraceError("broadcasting a traced scalar against a concrete array")
            return list(xs)
        return anp.broadcast_arrays(*xs)

    # elementwise -------------------------------------------------------------
    def where(self, cond: Any, a: Any, b: Any) -> Any:
        if not _traced(cond, a, b):
            return anp.where(cond, a, b)
        if not _traced(cond):
            c = np.asarray(cond)
            if c.size == 1:
                return a if bool(c) else b
        return self.graph.op("where", cond, a, b)

    def sum(self, x: Any, axis: Any = None, dtype: Any = None, keepdims: bool = False) -> Any:
        """``xp.sum`` of concrete arrays; over the node axis (``axis=-1``) of a per-node
        symbol, the loop that adds its nodes up."""
        if not _traced(x):
            return anp.sum(x, axis=axis, dtype=dtype, keepdims=keepdims)
        if axis not in (-1, (-1,)) or keepdims:
            raise TraceError(f"xp.sum(axis={axis!r}) of a traced value: only the node axis, -1")
        return self.graph.op("sum", x)

    def atan2(self, y: Any, x: Any) -> Any:
        if not _traced(y, x):
            return anp.atan2(y, x)
        if self.graph.dtype == np.float32:
            return _atan2_polynomial(self, y, x)
        if self.graph.dtype == np.float64:
            return _atan2_polynomial_f64(self, y, x)
        return self.graph.op("atan2", y, x)

    def pow(self, a: Any, b: Any) -> Any:
        if not _traced(a, b):
            return anp.pow(a, b)
        return self.graph.op("pow", a, b)

    def maximum(self, a: Any, b: Any) -> Any:
        if not _traced(a, b):
            return anp.maximum(a, b)
        return self.where(a >= b, a, b)

    def minimum(self, a: Any, b: Any) -> Any:
        if not _traced(a, b):
            return anp.minimum(a, b)
        return self.where(a <= b, a, b)

    def logical_and(self, a: Any, b: Any) -> Any:
        return a & b

    def logical_or(self, a: Any, b: Any) -> Any:
        return a | b

    def logical_not(self, a: Any) -> Any:
        return ~a if _traced(a) else anp.logical_not(a)


def _atan2_polynomial(xp: TraceNamespace, y: Any, x: Any) -> Any:
    """atan2 for float32 kernels, branch-free so that the compiled loop vectorises.

    libm's atan2f is a call the loop vectoriser cannot widen (Numba has no vector math
    library here), which keeps a kernel with atan2 scalar where C is vectorised (gcc uses
    glibc's vector ``_ZGVdN8vv_atan2f``; bench/RESULTS.md, "Thresholds"). This is Cephes'
    ``atanf`` (S. Moshier): reduction to |t| <= tan(π/8) and a degree-9 odd polynomial,
    maximum relative error about 1e-7 (float32 rounding); quadrants as in C's atan2;
    atan2(0, 0) = 0 like NumPy's.
    """
    ax, ay = abs(x), abs(y)
    big = xp.where(ay > ax, ay, ax)
    small = xp.where(ay > ax, ax, ay)
    red = small > 0.4142135623730950 * big  # t = small/big > tan(π/8)
    u = _reduced_ratio(xp, small, big, red)
    z = u * u
    p = (
        ((8.05374449538e-2 * z - 1.38776856032e-1) * z + 1.99777106478e-1) * z - 3.33329491539e-1
    ) * z * u + u
    a = xp.where(red, p + math.pi / 4, p)  # atan(small/big) in [0, π/4]
    a = xp.where(ay > ax, math.pi / 2 - a, a)
    a = xp.where(x < 0.0, math.pi - a, a)
    return xp.where(y < 0.0, -a, a)


def _reduced_ratio(xp: TraceNamespace, small: Any, big: Any, red: Any) -> Any:
    """t = small/big (0 ≤ small ≤ big), or (t − 1)/(t + 1) where ``red``, in one division:
    (small − big)/(small + big) (no division waits for another; 0 for 0/0)."""
    num = xp.where(red, small - big, small)
    return num / xp.where(red, small + big, xp.where(big > 0.0, big, 1.0))


def _round(xp: TraceNamespace, x: Any) -> Any:
    return xp.graph.op("floor", x + 0.5)


def _sin_cos_polynomial(xp: TraceNamespace, x: Any, want_sin: bool) -> Any:
    """sin or cos for float32 kernels, branch-free (Cephes ``sinf``/``cosf`` polynomials).

    x = k π/2 + r with |r| <= π/4 (π/2 in three parts, exact for |x| up to about 1e4);
    the quadrant k mod 4 picks ±sin r or ±cos r. Maximum error about 1e-7 (float32 rounding).
    """
    k = _round(xp, x * (2.0 / math.pi))
    r = ((x - k * 1.5703125) - k * 4.837512969970703125e-4) - k * 7.549789954891205e-8
    z = r * r
    sin_r = r + r * z * (-1.6666654611e-1 + z * (8.3321608736e-3 + z * -1.9515295891e-4))
    cos_r = (
        1.0
        - 0.5 * z
        + z * z * (4.166664568298827e-2 + z * (-1.388731625493765e-3 + z * 2.443315711809948e-5))
    )
    q = k - 4.0 * xp.graph.op("floor", k * 0.25)  # k mod 4, in {0, 1, 2, 3}
    if not want_sin:
        q = q + 1.0  # cos x = sin(x + π/2)
        q = xp.where(q > 3.5, q - 4.0, q)
    odd = ((q > 0.5) & (q < 1.5)) | (q > 2.5)
    val = xp.where(odd, cos_r, sin_r)
    return xp.where(q > 1.5, -val, val)


def _exp_polynomial(xp: TraceNamespace, x: Any) -> Any:
    """exp for float32 kernels, branch-free (Cephes ``expf``): x = k ln 2 + r, |r| <= ln2/2,
    a degree-7 polynomial for e^r and 2^k from the exponent bits. Arguments are clamped to
    [−87.3, 88.7] (e^−87.3 ≈ 1.2e−38, the smallest normal float32), and 0 is returned below
    it (NumPy gives subnormals there). Maximum relative error about 1e-7 elsewhere.
    """
    tiny = x < -87.3
    x = xp.where(x > 88.7, 88.7, xp.where(tiny, -87.3, x))
    k = _round(xp, x * 1.4426950408889634)
    r = (x - k * 0.693359375) - k * -2.12194440e-4
    z = r * r
    p = (
        (
            (
                (
                    ((1.9875691500e-4 * r + 1.3981999507e-3) * r + 8.3334519073e-3) * r
                    + 4.1665795894e-2
                )
                * r
                + 1.6666665459e-1
            )
            * r
            + 5.0000001201e-1
        )
        * z
        + r
        + 1.0
    )
    return xp.where(tiny, 0.0, p * xp.graph.op("exp2i", k))


def _acos_polynomial(xp: TraceNamespace, x: Any) -> Any:
    """acos for float32 kernels: atan2(√(1 − x²), x) through :func:`_atan2_polynomial`.

    libm's acosf is a call the loop vectoriser cannot widen, as atan2f is, which would keep
    the Lambert-sphere models (acos in the phase function and the azimuth) scalar. Same
    accuracy as the atan2 polynomial (about 1e-7 relative); √(1 − x²) is clamped at 0 so
    |x| slightly above 1 from rounding gives 0 or π as NumPy's clipped inputs do.
    """
    s = 1.0 - x * x
    return _atan2_polynomial(xp, xp.graph.op("sqrt", xp.where(s > 0.0, s, 0.0)), x)


_POLYNOMIAL = {
    "sin": lambda xp, x: _sin_cos_polynomial(xp, x, want_sin=True),
    "cos": lambda xp, x: _sin_cos_polynomial(xp, x, want_sin=False),
    "exp": _exp_polynomial,
    "acos": _acos_polynomial,
}


# ------------------------------------------------------------------ float64 polynomials
# The same idea in double precision: libm's atan2, sin, cos and exp are calls the loop
# vectoriser cannot widen, which kept the float64 kernels of the models that use them at about
# 0.2 of a C loop (gcc calls glibc's vector math library). Cephes' double-precision
# rational and polynomial approximations (S. Moshier, atan.c, sin.c, exp.c), written
# branch-free; maximum relative error about 2e-16 plus the reduction's rounding.
def _atan2_polynomial_f64(xp: TraceNamespace, y: Any, x: Any) -> Any:
    """atan2 for float64 kernels (Cephes ``atan``: for t in [0, 1], t > 0.66 reduced by
    (t − 1)/(t + 1) and π/4; a rational P(z)/Q(z) of degree 4/5 in z = u²)."""
    ax, ay = abs(x), abs(y)
    big = xp.where(ay > ax, ay, ax)
    small = xp.where(ay > ax, ax, ay)
    red = small > 0.66 * big  # t = small/big > 0.66
    u = _reduced_ratio(xp, small, big, red)
    z = u * u
    p = (
        (((-8.750608600031904122785e-1 * z - 1.615753718733365076637e1) * z
          - 7.500855792314704667340e1) * z - 1.228866684490136173410e2) * z
        - 6.485021904942025371773e1
    )  # fmt: skip
    q = (
        ((((z + 2.485846490142306297962e1) * z + 1.650270098316988542046e2) * z
          + 4.328810604912902668951e2) * z + 4.853903996359136964868e2) * z
        + 1.945506571482613964425e2
    )  # fmt: skip
    r = u + u * (z * p / q)
    # π/4 and the bits of π/4 that a double misses (Cephes' MOREBITS / 2)
    a = xp.where(red, (r + 3.061616997868382943065e-17) + math.pi / 4, r)
    a = xp.where(ay > ax, math.pi / 2 - a, a)
    a = xp.where(x < 0.0, math.pi - a, a)
    return xp.where(y < 0.0, -a, a)


def _sin_cos_polynomial_f64(xp: TraceNamespace, x: Any, want_sin: bool) -> Any:
    """sin or cos for float64 kernels: x = k π/2 + r, |r| <= π/4, π/2 in three parts
    (fdlibm's pio2_1, pio2_2, pio2_3: exact for |k| below about 2^20), Cephes' degree-13 and
    degree-14 polynomials for sin r and cos r, the quadrant k mod 4."""
    k = _round(xp, x * (2.0 / math.pi))
    r = (
        (x - k * 1.57079632673412561417e00) - k * 6.07710050630396597660e-11
    ) - k * 2.02226624871116645580e-21
    z = r * r
    sin_r = r + r * z * (
        (((((1.58962301576546568060e-10 * z - 2.50507477628578072866e-8) * z
            + 2.75573136213857245213e-6) * z - 1.98412698295895385996e-4) * z
          + 8.33333333332211858878e-3) * z) - 1.66666666666666307295e-1
    )  # fmt: skip
    cos_r = (1.0 - 0.5 * z) + z * z * (
        (((((-1.13585365213876817300e-11 * z + 2.08757008419747316778e-9) * z
            - 2.75573141792967388112e-7) * z + 2.48015872888517045348e-5) * z
          - 1.38888888888730564116e-3) * z) + 4.16666666666665929218e-2
    )  # fmt: skip
    q = k - 4.0 * xp.graph.op("floor", k * 0.25)  # k mod 4, in {0, 1, 2, 3}
    if not want_sin:
        q = q + 1.0  # cos x = sin(x + π/2)
        q = xp.where(q > 3.5, q - 4.0, q)
    odd = ((q > 0.5) & (q < 1.5)) | (q > 2.5)
    val = xp.where(odd, cos_r, sin_r)
    return xp.where(q > 1.5, -val, val)


def _exp_polynomial_f64(xp: TraceNamespace, x: Any) -> Any:
    """exp for float64 kernels (Cephes ``exp``): x = k ln 2 + r, e^r = 1 + 2 r P(r²)/(Q(r²) −
    r P(r²)), 2^k from the exponent bits. Arguments are clamped to [−708.39, 709] (e^−708.39 is
    about the smallest normal double) and 0 is returned below (NumPy gives subnormals there)."""
    tiny = x < -708.39
    x = xp.where(x > 709.0, 709.0, xp.where(tiny, -708.39, x))
    k = _round(xp, x * 1.4426950408889634)
    r = (x - k * 6.93145751953125e-1) - k * 1.42860682030941723212e-6
    z = r * r
    p = r * ((1.26177193074810590878e-4 * z + 3.02994407707441961300e-2) * z
             + 9.99999999999999999910e-1)  # fmt: skip
    q = ((3.00198505138664455042e-6 * z + 2.52448340349684104192e-3) * z
         + 2.27265548208155028766e-1) * z + 2.00000000000000000009e0  # fmt: skip
    e = 1.0 + 2.0 * (p / (q - p))
    return xp.where(tiny, 0.0, e * xp.graph.op("exp2i_f64", k))


_POLYNOMIAL_F64 = {
    "sin": lambda xp, x: _sin_cos_polynomial_f64(xp, x, want_sin=True),
    "cos": lambda xp, x: _sin_cos_polynomial_f64(xp, x, want_sin=False),
    "exp": _exp_polynomial_f64,
}


def _make_unary(name: str):  # noqa: ANN202 - method factory
    def f(self: TraceNamespace, x: Any) -> Any:
        if not _traced(x):
            return getattr(anp, name)(x)
        if name in _POLYNOMIAL and self.graph.dtype == np.float32:
            return _POLYNOMIAL[name](self, x)
        if name in _POLYNOMIAL_F64 and self.graph.dtype == np.float64:
            return _POLYNOMIAL_F64[name](self, x)
        return self.graph.op(name, x)

    f.__name__ = name
    return f


for _name in _UNARY_MATH:
    if _name in ("floor", "exp2i", "exp2i_f64"):
        continue
    setattr(TraceNamespace, _name, _make_unary(_name))


# ------------------------------------------------------------------ code generation
def scalar_source(
    graph: Graph, outputs: list[Any], literal_name: str = "_L"
) -> tuple[list[str], list[str]]:
    """Print the graph as Python statements computing ``outputs`` (dead nodes dropped).

    Returns ``(constants, body)``: module-level constant definitions (each literal as a
    value of the graph's dtype, so float32 code stays float32 under Numba) and the loop
    body, whose last ``len(outputs)`` lines assign ``r0, r1, ...``. Inputs are referred to by
    their names, parameters as ``p0, p1, ...``.
    """
    live: set[int] = set()
    stack = [graph.ref(o)[1] for o in outputs if graph.ref(o)[0] == "node"]
    if any(graph.loop_of(graph.ref(o)) for o in outputs):
        raise TraceError("a result keeps a node axis (add it up with xp.sum(..., axis=-1))")
    while stack:
        k = stack.pop()
        if k in live:
            continue
        live.add(k)
        stack.extend(r[1] for r in graph.nodes[k][1:] if r[0] == "node")

    lits: dict[Any, str] = {}
    constants: list[str] = []
    fcast = "np.float32" if graph.dtype == np.float32 else "np.float64"

    def name(r: tuple[Any, ...]) -> str:
        kind, val = r
        if kind == "node":
            return f"t{val}"
        if kind == "par":
            return f"p{val}"
        if kind == "vec":
            return f"p{val}[j]"
        if kind == "in":
            return str(val)
        if isinstance(val, bool):
            return repr(val)
        key = ("lit", float(val))
        if key not in lits:
            lits[key] = f"{literal_name}{len(lits)}"
            constants.append(f"{lits[key]} = {fcast}({float(val)!r})")
        return lits[key]

    # A conditional expression is a branch in Python's bytecode: Numba makes a block and a
    # merged (phi) variable of each, and its SSA pass costs blocks x such variables, which
    # is quadratic in a long kernel (those with node loops hold hundreds of wheres); reading
    # a pair at the condition's index is one block. Kernels without node loops keep the
    # conditional expression.
    indexed = any(node[0] == "sum" for node in graph.nodes)

    def expression(node: tuple[Any, ...]) -> str:
        op, args = node[0], node[1:]
        a = [name(r) for r in args]
        if op in _BINARY:
            expr = f"{a[0]} {_BINARY[op]} {a[1]}"
        elif op == "neg":
            expr = f"-{a[0]}"
        elif op == "not":
            expr = f"not {a[0]}"
        elif op == "where" and indexed:
            expr = f"({a[2]}, {a[1]})[int({a[0]})]"
        elif op == "where":
            expr = f"{a[1]} if {a[0]} else {a[2]}"
        elif op == "atan2":
            expr = f"math.atan2({a[0]}, {a[1]})"
        elif op == "pow":
            expr = _power(a[0], args[1], a[1])
        elif op in _UNARY_MATH:
            expr = f"{_UNARY_MATH[op]}({a[0]})"
        else:  # pragma: no cover - every recorded op is listed above
            raise TraceError(f"no code for operation {op!r}")
        return expr

    body: list[str] = []
    for k, node in enumerate(graph.nodes):
        if k not in live or graph.loops[k]:
            continue  # per-node values are computed in the loop of the sum that needs them
        if node[0] == "sum":
            body.extend(_sum_loop(graph, k, expression, name(("lit", 0.0))))
        else:
            body.append(f"t{k} = {expression(node)}")
    for j, o in enumerate(outputs):
        body.append(f"r{j} = {name(graph.ref(o))}")
    return constants, body


def loop_body(graph: Graph, operand: tuple[Any, ...]) -> set[int]:
    """The per-node values the operand of a node sum reads, itself included: what the loop
    of the sum computes at each node."""
    inner: set[int] = set()
    stack = [operand[1]] if operand[0] == "node" else []
    while stack:
        m = stack.pop()
        if m in inner or not graph.loops[m]:
            continue
        inner.add(m)
        stack.extend(r[1] for r in graph.nodes[m][1:] if r[0] == "node")
    return inner


def _sum_loop(graph: Graph, k: int, expression: Any, zero: str) -> list[str]:
    """The statements of sum node ``k``: a loop over its nodes computing the per-node values
    it depends on (in graph order) and adding up its operand."""
    operand = graph.nodes[k][1]
    inner = loop_body(graph, operand)
    lines = [f"t{k} = {zero}", f"for j in range({graph.loop_of(operand)}):"]
    lines += [f"    t{m} = {expression(graph.nodes[m])}" for m in sorted(inner)]
    lines.append(f"    t{k} = t{k} + t{operand[1]}")
    return lines


def _power(base: str, exp_ref: tuple[Any, ...], exp_name: str) -> str:
    if exp_ref[0] == "lit" and float(exp_ref[1]).is_integer() and 0 <= exp_ref[1] <= 8:
        n = int(exp_ref[1])
        return " * ".join([base] * n) if n else f"{base} * 0 + 1"
    if exp_ref[0] == "lit" and exp_ref[1] == 0.5:
        return f"math.sqrt({base})"
    return f"{base} ** {exp_name}"
