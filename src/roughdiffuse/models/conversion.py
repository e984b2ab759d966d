"""An :class:`~roughdiffuse.models.alias.Alias`'s conversion, recorded as data for the explorer.

An Alias declares its conversion once, in Python (``to_base``, elementwise arithmetic). The
browser explorer evaluates the base model's GLSL, so it needs the same conversion without a
second copy of it: :func:`record` calls ``to_base`` on :class:`Symbol` objects, which record
the arithmetic applied to them (``+ - * / **``, unary minus, numbers) as an expression tree.
The page evaluates the tree (``static/js/models.js``, ``evaluate``), and :func:`evaluate` here
is checked against the numeric ``to_base`` (:func:`recorded_conversion`) before a tree is
published, so a recorder that followed the conversion wrongly is refused, not shipped.

A tree is JSON: a parameter's name (a string), a number, or ``[op, operand, ...]`` with op one
of ``"+" "-" "*" "/" "**"`` (two operands) or ``"neg"`` (one).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from numbers import Real
from typing import Any

import numpy as np

__all__ = [
    "NotRecordable",
    "Symbol",
    "evaluate",
    "record",
    "recorded_conversion",
    "text",
]

Tree = str | float | list[Any]

_BINARY: dict[str, Callable[[Any, Any], Any]] = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "**": lambda a, b: a**b,
}


class NotRecordable(TypeError):
    """``to_base`` did something other than arithmetic on its parameters (a function call
    such as ``math.sqrt``, a comparison, a branch): it cannot be recorded as a tree."""


def _tree(x: Any) -> Tree:
    if isinstance(x, Symbol):
        return x.tree
    if isinstance(x, Real) and not isinstance(x, bool):
        return float(x)
    raise NotRecordable(f"to_base combined a parameter with {type(x).__name__} {x!r}")


def _binop(op: str, swap: bool = False) -> Callable[[Symbol, Any], Symbol]:
    """The method recording ``self op other`` (``other op self`` with ``swap``), as
    :mod:`roughdiffuse.engine.trace` declares its operators."""

    def method(self: Symbol, other: Any) -> Symbol:
        return self._op(op, other, swap)

    return method


class Symbol:
    """A parameter (or an expression of parameters) whose arithmetic is recorded."""

    __slots__ = ("tree",)
    __array_ufunc__ = None  # NumPy functions refuse a Symbol (TypeError) instead of iterating

    def __init__(self, tree: Tree) -> None:
        self.tree = tree

    def _op(self, op: str, other: Any, swap: bool = False) -> Symbol:
        if not isinstance(other, (Symbol, Real)) or isinstance(other, bool):
            return NotImplemented
        a, b = (_tree(other), self.tree) if swap else (self.tree, _tree(other))
        return Symbol([op, a, b])

    __add__, __radd__ = _binop("+"), _binop("+", swap=True)
    __sub__, __rsub__ = _binop("-"), _binop("-", swap=True)
    __mul__, __rmul__ = _binop("*"), _binop("*", swap=True)
    __truediv__, __rtruediv__ = _binop("/"), _binop("/", swap=True)
    __pow__, __rpow__ = _binop("**"), _binop("**", swap=True)

    def __neg__(self) -> Symbol:
        return Symbol(["neg", self.tree])

    def __pos__(self) -> Symbol:
        return self

    def _refuse(self, *_: Any) -> Any:
        raise NotRecordable(
            f"to_base used {text(self.tree)} as a number (a function call or a comparison); "
            "only + - * / ** and numbers can be recorded"
        )

    __float__ = __int__ = __index__ = __bool__ = __lt__ = __le__ = __gt__ = __ge__ = _refuse
    __abs__ = __round__ = __floor__ = __ceil__ = _refuse


def record(to_base: Callable[..., Mapping[str, Any]], names: Sequence[str]) -> dict[str, Tree]:
    """``to_base`` recorded: the tree of each base parameter in the parameters ``names``.

    Raises
    ------
    NotRecordable
        If ``to_base`` does anything but arithmetic on its parameters.
    """
    out = to_base(**{n: Symbol(n) for n in names})
    return {k: _tree(v) for k, v in out.items()}


def evaluate(tree: Tree, values: Mapping[str, Any]) -> Any:
    """The value of ``tree`` for the parameter ``values`` (numbers or arrays, elementwise)."""
    if isinstance(tree, str):
        return values[tree]
    if isinstance(tree, float | int):
        return tree
    op, *args = tree
    if op == "neg":
        return -evaluate(args[0], values)
    return _BINARY[op](evaluate(args[0], values), evaluate(args[1], values))


def text(tree: Tree, digits: int | None = None) -> str:
    """The tree as an infix expression, e.g. ``(sigma_deg * 0.017453292519943295)``; numbers
    to ``digits`` significant digits (default: all, ``repr``)."""
    if isinstance(tree, str):
        return tree
    if isinstance(tree, float | int):
        return repr(float(tree)) if digits is None else f"{tree:.{digits}g}"
    op, *args = tree
    if op == "neg":
        return f"(-{text(args[0], digits)})"
    return f"({text(args[0], digits)} {op} {text(args[1], digits)})"


def recorded_conversion(
    to_base: Callable[..., Mapping[str, Any]], ranges: Mapping[str, tuple[float, float]]
) -> dict[str, Tree]:
    """:func:`record`, checked: each tree equals ``to_base`` at points over ``ranges``.

    Parameters
    ----------
    to_base : callable
        The conversion (keyword arguments: the parameters named in ``ranges``).
    ranges : mapping
        Parameter name -> (low, high), the values the check spans (five points per
        parameter, the ends included, each parameter's sequence in another order).

    Raises
    ------
    NotRecordable
        If ``to_base`` cannot be recorded, or a recorded tree differs from the numeric
        ``to_base`` by more than 1e-12 relative (the recorder missed something).
    """
    trees = record(to_base, list(ranges))
    fractions = np.array([0.0, 0.25, 0.5, 0.8, 1.0])
    values = {
        n: lo + (hi - lo) * np.roll(fractions, k) for k, (n, (lo, hi)) in enumerate(ranges.items())
    }
    numeric = to_base(**values)
    if set(numeric) != set(trees):
        raise NotRecordable(f"to_base returned {sorted(numeric)}, recorded {sorted(trees)}")
    for name, tree in trees.items():
        got = np.broadcast_to(evaluate(tree, values), fractions.shape)
        want = np.broadcast_to(np.asarray(numeric[name], dtype=float), fractions.shape)
        if not np.allclose(got, want, rtol=1e-12, atol=1e-300):
            raise NotRecordable(
                f"the recorded {name} = {text(tree)} gives {got.tolist()}, "
                f"to_base {want.tolist()}"
            )
    return trees
