"""A model's formula printed as GLSL ES 3.00 (WebGL2) from its traced expression graph.

The models' formulas are written once, against the array API standard. :mod:`.trace` records
one evaluation of a model as an expression graph (the Numba printers :mod:`.fastpath` and
:mod:`.scalar` print it as Python); this module prints the same graph as GLSL, for the
explorer's shaders and for a user's own shader (``roughdiffuse export --to glsl``). No
formula is written by hand in GLSL: the floors, clamps and horizon test are the Python
code's, and so are the float32 polynomial substitutes of the trace (sin, cos, exp, atan2 and
acos are traced as Cephes polynomials; ``exp2i``, 2^k from the exponent bits, is printed
with ``intBitsToFloat``).

Public API
----------
:func:`glsl_source` ``(model, *, name="rd_brdf", bake=True) -> str``
    Self-contained GLSL ES 3.00 code defining ``vec3 NAME(vec3 wi, vec3 wo)``: the BRDF in
    1/sr, without the cosine, 0 below the horizon, RGB always (a grey model gives three
    equal channels). ``wi`` (towards the light) and ``wo`` (towards the viewer) are in the
    local frame, z the normal; they need not be unit vectors. It also defines
    ``vec3 NAME_cosines(float mu_i, float mu_o, float cos_io)`` (the same BRDF from the three
    local cosines) and helpers whose names start with ``NAME_``, so that two exported
    models can live in one shader.

    * ``bake=True``: the parameter values of ``model`` are constants of the code. Any
      closed-form model (``model.closed_form``) can be baked.
    * ``bake=False``: the parameters are uniforms named after the model's declared
      parameters (``uniform vec3 albedo;`` for a colour parameter, ``uniform float sigma;``
      in radians), so one compiled shader serves every value; categorical parameters
      (``variant``, ``distribution``...) are fixed by ``model``. The uniform names and types
      are listed in a comment at the top of the code and by :func:`glsl_uniforms`. A model
      whose parameter math cannot be traced with symbolic parameters (``Coated``: its
      internal sums are a quadrature over two node axes) or that is not one registry id
      with its parameters as fields (a hand-made ``Mix``) raises
      :class:`~roughdiffuse._validate.ParameterError`. The code computes the
      parameter-only part of the formula first in the function (a driver may or may not
      hoist it; the explorer does, below).

:func:`glsl_uniforms` ``(model) -> dict[str, str]``
    The uniforms of ``glsl_source(model, bake=False)``: name -> GLSL type.

How (design)
------------
Tracing with symbolic parameters (:func:`trace_entry`): the registry entry's ``create`` is
called with a :class:`~.trace.Sym` for each numeric parameter (and channel: a colour
parameter is traced as one scalar per channel, three times), so every node of the graph is
classed as *per pixel* (it depends on the cosines) or *parameter-only*. The per-pixel part is
printed as a GLSL function of the cosines and of the parameter-only values it reads
(``h0, h1, ...``); the parameter-only part is printed as a *prepass* that computes those
values from the parameters: in GLSL (:func:`glsl_source` with ``bake=False``, at the top of
the function) or in JavaScript (:func:`javascript_prepass`: the explorer computes them once
per frame on the CPU and sends them as uniforms). Concrete 1-D arrays the trace meets (the
quadrature nodes and weights of a node loop) are ``const float[]`` arrays, and a node loop
(``xp.sum`` over the node axis) is a ``for`` loop with a constant bound.

Baking (``bake=True``) and models whose parameter math cannot be traced symbolically use a
trace with concrete parameters instead (:func:`trace_model`, as the fast path does): the
parameter math runs in NumPy, and its results, the graph's ``params``, are either printed as
constants or read from a uniform array whose values the explorer's Python server sends
(:func:`uniform_function`: ``Coated``, whose internal sums are a quadrature over two node
axes, which the tracer does not follow with symbols).

The trace is float32 (WebGL's highp float): the polynomial substitutes of the float32 trace
have a maximum relative error of about 1e-7 (:mod:`.trace`), and GLSL's own sqrt, log, tan,
asin, atan are those of the GPU (a few float32 ulps).
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import re
from collections.abc import Callable, Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import ParameterError
from .trace import Graph, Sym, TraceError, loop_body

__all__ = [
    "Printed",
    "Traced",
    "expression_text",
    "expression_tree",
    "glsl_source",
    "glsl_uniforms",
    "javascript_prepass",
    "javascript_values",
    "print_function",
    "trace_entry",
    "trace_model",
    "uniform_function",
]

COSINES = ("mu_i", "mu_o", "cos_io")
"""The per-pixel inputs of a traced model: n·wi, n·wo, wi·wo."""

_CHANNELS = 3
_SWIZZLE = "rgb"


@dataclasses.dataclass
class Traced:
    """One model traced for printing.

    Attributes
    ----------
    graph : Graph
        The float32 expression graph.
    outputs : list
        The three channels' results (symbols, or numbers for a constant channel).
    params : dict
        Parameter name -> GLSL type (``"float"`` or ``"vec3"``) of the symbolic inputs
        (empty for a trace with concrete parameters). A ``vec3`` parameter's channels are
        the inputs ``name.0``, ``name.1``, ``name.2``.
    symbolic : bool
        Whether the parameters are inputs (:func:`trace_entry`) or concrete values
        (:func:`trace_model`, whose ``graph.params`` hold the values the parameter math gave).
    """

    graph: Graph
    outputs: list[Any]
    params: dict[str, str]
    symbolic: bool


def _cosine_inputs(graph: Graph) -> list[Sym]:
    return [graph.input(name) for name in COSINES]


def trace_entry(entry: Any, choices: Mapping[str, Any] | None = None) -> Traced:
    """Trace registry entry ``entry`` with its numeric parameters as symbolic inputs.

    Parameters
    ----------
    entry : roughdiffuse.registry.Entry
        The model id.
    choices : mapping, optional
        Values of its free categorical parameters (others at their defaults).

    Raises
    ------
    TraceError
        When the model's parameter math cannot run on symbols (it needs concrete values).
    """
    choices = dict(choices or {})
    for p in entry.parameters:
        if p.categorical and p.name not in choices:
            choices[p.name] = p.default
    numeric = [p for p in entry.applicable(choices) if not p.categorical]
    graph = Graph(np.dtype(np.float32))
    cosines = _cosine_inputs(graph)
    symbols: dict[str, Sym] = {}
    outputs = []
    for c in range(_CHANNELS):
        kwargs: dict[str, Any] = dict(choices)
        for p in numeric:
            key = f"{p.name}.{c}" if p.channels else p.name
            if key not in symbols:
                symbols[key] = graph.input(key)
            kwargs[p.name] = symbols[key]
        try:
            model = entry.create(**kwargs)
            outputs.append(model.brdf_cosines(*cosines))
        except TraceError:
            raise
        except (TypeError, ValueError, AttributeError, IndexError) as exc:
            raise TraceError(f"{entry.id}: parameters not traceable as symbols ({exc})") from exc
    params = {p.name: "vec3" if p.channels else "float" for p in numeric}
    return Traced(graph, outputs, params, symbolic=True)


def trace_model(model: Any, *, share_equal_values: bool = True) -> Traced:
    """Trace ``model`` with its parameter values concrete (as the fast path does): the
    parameter math runs in NumPy; its results are ``graph.params``. With
    ``share_equal_values=False`` two equal values stay two parameters (the graph is the same
    for other values of the same structure: :func:`uniform_function`)."""
    if not getattr(model, "closed_form", False):
        raise ParameterError(
            f"{type(model).__name__} is not a closed form (a simulation or a table): it has "
            "no GLSL code"
        )
    graph = Graph(np.dtype(np.float32), share_scalars=share_equal_values)
    cosines = _cosine_inputs(graph)
    outputs = []
    for c in range(_CHANNELS):
        m = model.channel(c) if model.channels else model
        outputs.append(m.brdf_cosines(*cosines))
    return Traced(graph, outputs, {}, symbolic=False)


# ------------------------------------------------------------------ graph analysis
def _deps(graph: Graph, ref: tuple[Any, ...]) -> list[tuple[Any, ...]]:
    return list(graph.nodes[ref[1]][1:]) if ref[0] == "node" else []


def _reached(
    graph: Graph, roots: Iterable[tuple[Any, ...]], stop: Callable[[tuple[Any, ...]], bool]
) -> set[tuple[Any, ...]]:
    """The refs for which ``stop`` holds among those ``roots`` read, directly or through
    other nodes (not looking past them)."""
    found: set[tuple[Any, ...]] = set()
    stack, seen = list(roots), set()
    while stack:
        r = stack.pop()
        if r in seen:
            continue
        seen.add(r)
        if stop(r):
            found.add(r)
        else:
            stack.extend(_deps(graph, r))
    return found


def _pixel_nodes(graph: Graph) -> set[int]:
    """The nodes that depend on a cosine (per pixel); the others depend on parameters and
    constants alone."""
    out: set[int] = set()
    for k, node in enumerate(graph.nodes):
        for r in node[1:]:
            if (r[0] == "in" and r[1] in COSINES) or (r[0] == "node" and r[1] in out):
                out.add(k)
                break
    return out


def _is_parameter_only(graph: Graph, ref: tuple[Any, ...], pixel: set[int]) -> bool:
    """A value worth hoisting: a parameter-only node without a node axis, or a parameter
    input (literals and constants are printed in place)."""
    if ref[0] == "node":
        return ref[1] not in pixel and not graph.loops[ref[1]]
    return ref[0] == "in" and ref[1] not in COSINES


# ------------------------------------------------------------------ languages
def _float_literal(v: float, lang: str) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    v = float(v)
    if math.isnan(v):
        return "(0.0 / 0.0)" if lang == "glsl" else "NaN"
    if math.isinf(v):
        text = "uintBitsToFloat(0x7f800000u)" if lang == "glsl" else "Infinity"
        return text if v > 0 else f"(-{text})"
    if lang == "glsl":
        v = float(np.float32(v))  # the value the float32 trace computes with
    text = repr(v)
    if lang == "glsl" and "." not in text and "e" not in text:
        text += ".0"
    return f"({text})" if math.copysign(1.0, v) < 0 else text


def _power(base: str, exp_ref: tuple[Any, ...], exp: str, lang: str) -> str:
    if exp_ref[0] == "lit" and float(exp_ref[1]).is_integer() and abs(exp_ref[1]) <= 8:
        n = int(exp_ref[1])
        if n == 0:
            return "1.0" if lang == "glsl" else "1"
        prod = "(" + " * ".join([base] * abs(n)) + ")"
        return prod if n > 0 else f"(1.0 / {prod})"
    if exp_ref[0] == "lit" and exp_ref[1] == 0.5:
        return f"sqrt({base})" if lang == "glsl" else f"Math.sqrt({base})"
    return f"pow({base}, {exp})" if lang == "glsl" else f"({base} ** {exp})"


_GLSL_UNARY = {
    "sqrt": "sqrt",
    "exp": "exp",
    "log": "log",
    "sin": "sin",
    "cos": "cos",
    "tan": "tan",
    "asin": "asin",
    "acos": "acos",
    "atan": "atan",
    "abs": "abs",
    "floor": "floor",
}
_JS_UNARY = {
    "sqrt": "Math.sqrt",
    "exp": "Math.exp",
    "log": "Math.log",
    "log1p": "Math.log1p",
    "expm1": "Math.expm1",
    "sin": "Math.sin",
    "cos": "Math.cos",
    "tan": "Math.tan",
    "asin": "Math.asin",
    "acos": "Math.acos",
    "atan": "Math.atan",
    "abs": "Math.abs",
    "floor": "Math.floor",
}
_GLSL_HELPERS = {
    # 2^k for an integer-valued k in [-126, 127], from the exponent bits (numba_math.exp2i);
    # highp: a fragment shader's ints are mediump (maybe 16 bits) unless said otherwise
    "exp2i": (
        "float {p}_exp2i(float k) {{\n"
        "  highp int bits = (int(k) + 127) << 23;\n"
        "  return intBitsToFloat(bits);\n"
        "}}"
    ),
    # log(1 + x) accurate for small x (Goldberg, "What every computer scientist should know
    # about floating-point arithmetic", 1991, theorem 4)
    "log1p": (
        "float {p}_log1p(float x) {{\n"
        "  float u = 1.0 + x;\n"
        "  return u == 1.0 ? x : log(u) * (x / (u - 1.0));\n"
        "}}"
    ),
    # exp(x) - 1 accurate for small x (Kahan's trick)
    "expm1": (
        "float {p}_expm1(float x) {{\n"
        "  float u = exp(x);\n"
        "  if (u == 1.0) return x;\n"
        "  float um = u - 1.0;\n"
        "  return um == -1.0 ? -1.0 : um * x / log(u);\n"
        "}}"
    ),
}
_BINARY = {"add": "+", "sub": "-", "mul": "*", "div": "/", "lt": "<", "le": "<=", "gt": ">",
           "ge": ">=", "eq": "==", "ne": "!=", "and": "&&", "or": "||"}


@dataclasses.dataclass
class _Context:
    """What printing one graph needs: the language, how each operand kind is named, the
    helpers and constant arrays used (printed once, before the functions)."""

    lang: str
    prefix: str
    input_name: Any  # input name -> expression
    hoisted: dict[tuple[Any, ...], str]  # parameter-only refs read by name
    par_name: Any  # ("par", k) -> expression
    helpers: dict[str, str]
    arrays: dict[str, str]

    def name(self, graph: Graph, r: tuple[Any, ...]) -> str:
        if r in self.hoisted:
            return self.hoisted[r]
        kind, val = r
        if kind == "node":
            return f"t{val}"
        if kind == "in":
            return self.input_name(val)
        if kind == "lit":
            return _float_literal(val, self.lang)
        if kind == "par":
            return self.par_name(val)
        return f"{self.array(graph.params[val])}[j]"  # "vec": the loop's node

    def array(self, values: np.ndarray) -> str:
        data = np.asarray(values, dtype=np.float32)
        digest = hashlib.sha1(data.tobytes()).hexdigest()[:10]
        name = f"{self.prefix}_q{digest}"
        if name not in self.arrays:
            items = ", ".join(_float_literal(float(v), self.lang) for v in data)
            if self.lang == "glsl":
                n = data.size
                self.arrays[name] = f"const float {name}[{n}] = float[{n}]({items});"
            else:
                self.arrays[name] = f"const {name} = [{items}];"
        return name

    def expression(self, graph: Graph, node: tuple[Any, ...]) -> str:
        op, args = node[0], node[1:]
        a = [self.name(graph, r) for r in args]
        glsl = self.lang == "glsl"
        if op in _BINARY:
            return f"({a[0]} {_BINARY[op]} {a[1]})"
        if op == "neg":
            return f"(-{a[0]})"
        if op == "not":
            return f"(!{a[0]})"
        if op == "where":
            return f"({a[0]} ? {a[1]} : {a[2]})"
        if op == "pow":
            return _power(a[0], args[1], a[1], self.lang)
        if op == "atan2":
            return f"atan({a[0]}, {a[1]})" if glsl else f"Math.atan2({a[0]}, {a[1]})"
        if op in ("exp2i", "exp2i_f64"):
            if not glsl:
                return f"(2 ** {a[0]})"
            return f"{self.helper('exp2i')}({a[0]})"
        if glsl and op in ("log1p", "expm1"):
            return f"{self.helper(op)}({a[0]})"
        table = _GLSL_UNARY if glsl else _JS_UNARY
        if op in table:
            return f"{table[op]}({a[0]})"
        raise TraceError(f"no {self.lang} code for operation {op!r}")  # pragma: no cover

    def helper(self, op: str) -> str:
        name = f"{self.prefix}_{op}"
        self.helpers.setdefault(name, _GLSL_HELPERS[op].format(p=self.prefix))
        return name


def _statements(
    graph: Graph, roots: Iterable[tuple[Any, ...]], ctx: _Context, stop: set[tuple[Any, ...]]
) -> list[str]:
    """Declarations computing ``roots`` (in graph order), reading the refs in ``stop`` by
    their names; node loops (``xp.sum``) as ``for`` loops."""
    live: set[int] = set()
    stack = [r[1] for r in roots if r[0] == "node" and r not in stop]
    while stack:
        k = stack.pop()
        if k in live:
            continue
        live.add(k)
        stack.extend(r[1] for r in graph.nodes[k][1:] if r[0] == "node" and r not in stop)
    glsl = ctx.lang == "glsl"

    def declare(k: int) -> str:
        if glsl:
            kind = "bool" if graph.is_bool(("node", k)) else "float"
            return f"{kind} t{k} = {ctx.expression(graph, graph.nodes[k])};"
        return f"const t{k} = {ctx.expression(graph, graph.nodes[k])};"

    lines: list[str] = []
    for k in sorted(live):
        if graph.loops[k]:
            continue  # computed in the loop of the sum that needs it
        node = graph.nodes[k]
        if node[0] != "sum":
            lines.append(declare(k))
            continue
        operand = node[1]
        inner = sorted(loop_body(graph, operand) & live)
        n = graph.loop_of(operand)
        zero = "0.0" if glsl else "0"
        lines.append(f"float t{k} = {zero};" if glsl else f"let t{k} = 0;")
        head = f"for (int j = 0; j < {n}; j++) {{" if glsl else f"for (let j = 0; j < {n}; j++) {{"
        lines.append(head)
        lines += ["  " + declare(m) for m in inner]
        lines.append(f"  t{k} += {ctx.name(graph, operand)};")
        lines.append("}")
    return lines


# ------------------------------------------------------------------ printing
def _literal_par(graph: Graph, lang: str) -> Any:
    """Concrete scalars of the graph (``("par", k)``) printed as literals."""
    return lambda k: _float_literal(float(graph.params[k]), lang)


@dataclasses.dataclass
class Printed:
    """One model printed for a shader with a prepass (:func:`print_function`).

    Attributes
    ----------
    function : str
        ``vec3 NAME(float mu_i, float mu_o, float cos_io, float h0, float h1, ...)``.
    hoisted : list
        The refs of the parameter-only values ``h0, h1, ...`` (their order).
    arity : int
        The number of ``h`` arguments.
    helpers, arrays : dict
        Helper functions and constant arrays the function uses (name -> code).
    """

    function: str
    hoisted: list[tuple[Any, ...]]
    arity: int
    helpers: dict[str, str]
    arrays: dict[str, str]


def _outputs(traced: Traced) -> list[tuple[Any, ...]]:
    refs = [traced.graph.ref(o) for o in traced.outputs]
    if any(traced.graph.loop_of(r) for r in refs):
        raise TraceError("a result keeps a node axis (add it up with xp.sum(..., axis=-1))")
    return refs


def _hoist(traced: Traced, pars_as_values: bool) -> list[tuple[Any, ...]]:
    """The parameter-only refs the per-pixel code reads (in graph order), and, with
    ``pars_as_values``, the concrete parameters it reads (uniform values from the server)."""
    g = traced.graph
    pixel = _pixel_nodes(g)

    def hoisted(r: tuple[Any, ...]) -> bool:
        if pars_as_values and r[0] == "par":
            return True
        return _is_parameter_only(g, r, pixel) and not g.is_bool(r)  # uniforms are floats

    found = _reached(g, _outputs(traced), hoisted)

    def order(r: tuple[Any, ...]) -> tuple[int, Any]:
        return ({"in": 0, "par": 1, "node": 2}[r[0]], r[1])

    return sorted(found, key=order)


def print_function(
    traced: Traced, name: str, prefix: str = "rd", helpers: dict[str, str] | None = None,
    arrays: dict[str, str] | None = None,
) -> Printed:
    """Print the per-pixel part of ``traced`` as a GLSL function of the cosines and of its
    parameter-only values (``h0, h1, ...``: :func:`javascript_prepass` computes them from
    the parameters; for a concrete trace, its ``graph.params`` it reads).

    Helpers and constant arrays are added to ``helpers`` and ``arrays`` (shared between the
    models of one shader)."""
    hoisted = _hoist(traced, pars_as_values=not traced.symbolic)
    names = {r: f"h{k}" for k, r in enumerate(hoisted)}
    ctx = _Context("glsl", prefix, str, names, _literal_par(traced.graph, "glsl"),
                   {} if helpers is None else helpers, {} if arrays is None else arrays)
    outputs = _outputs(traced)
    body = _statements(traced.graph, outputs, ctx, set(names))
    args = ", ".join(["float mu_i", "float mu_o", "float cos_io",
                      *(f"float h{k}" for k in range(len(hoisted)))])
    result = ", ".join(ctx.name(traced.graph, r) for r in outputs)
    lines = [f"vec3 {name}({args}) {{", *("  " + s for s in body),
             f"  return vec3({result});", "}"]
    return Printed("\n".join(lines), hoisted, len(hoisted), ctx.helpers, ctx.arrays)


def javascript_prepass(traced: Traced, printed: Printed, prefix: str = "rd") -> str:
    """The body of a JavaScript function ``(p) => [h0, h1, ...]``: the parameter-only values
    of ``printed`` from the parameter values ``p`` (``p.sigma``, ``p.albedo[0]`` ...), in
    float64. Constant arrays are defined inside the body."""
    if not traced.symbolic:
        raise TraceError("a trace with concrete parameters has no prepass (uniform_function)")

    def input_name(key: str) -> str:
        base, _, channel = key.partition(".")
        return f"p[{base!r}][{channel}]" if channel else f"p[{base!r}]"

    ctx = _Context("js", prefix, input_name, {}, _literal_par(traced.graph, "js"), {}, {})
    body = _statements(traced.graph, printed.hoisted, ctx, set())
    values = ", ".join(ctx.name(traced.graph, r) for r in printed.hoisted)
    return "\n".join([*ctx.arrays.values(), *body, f"return [{values}];"])


def javascript_values(graph: Graph, outputs: Mapping[str, Any]) -> str:
    """The body of a JavaScript function ``(p) => ({name: value, ...})`` computing
    ``outputs`` (name -> traced value or number) from the graph's inputs ``p[name]``, in
    float64 (an Alias's conversion, :meth:`~roughdiffuse.models.alias.Alias.conversion`)."""
    refs = {k: graph.ref(v) for k, v in outputs.items()}
    ctx = _Context("js", "rd", lambda key: f"p[{key!r}]", {}, _literal_par(graph, "js"), {}, {})
    body = _statements(graph, refs.values(), ctx, set())
    values = ", ".join(f"{k!r}: {ctx.name(graph, r)}" for k, r in refs.items())
    return "\n".join([*ctx.arrays.values(), *body, f"return {{{values}}};"])


_PRECEDENCE = {"add": 1, "sub": 1, "mul": 2, "div": 2, "neg": 3, "pow": 4}
_TEXT_OPS = {"add": "+", "sub": "-", "mul": "*", "div": "/", "pow": "**"}


def expression_text(graph: Graph, value: Any, digits: int = 6) -> str:
    """A traced value as one infix expression to show (``sigma_deg * 0.0174533``): inputs by
    name, numbers to ``digits`` significant digits, functions as ``sqrt(x)``."""

    def text(r: tuple[Any, ...]) -> tuple[str, int]:
        kind, val = r
        if kind == "in":
            return str(val), 9
        if kind in ("lit", "par"):
            v = float(val if kind == "lit" else graph.params[val])
            out = f"{v:.{digits}g}"
            return (f"({out})", 9) if v < 0 else (out, 9)
        if kind == "vec":
            return "[…]", 9
        op, args = graph.nodes[val][0], graph.nodes[val][1:]
        parts = [text(a) for a in args]
        if op in _TEXT_OPS:
            prec = _PRECEDENCE[op]
            (a, pa), (b, pb) = parts
            a = a if pa >= prec and not (op == "pow" and pa == prec) else f"({a})"
            right_tight = op in ("sub", "div", "pow")
            b = b if pb > prec or (pb == prec and not right_tight) else f"({b})"
            return f"{a} {_TEXT_OPS[op]} {b}", prec
        if op == "neg":
            a, pa = parts[0]
            return (f"-{a}" if pa >= 3 else f"-({a})"), 3
        return f"{op}({', '.join(p for p, _ in parts)})", 9

    return text(graph.ref(value))[0]


_TREE_OPS = {"add": "+", "sub": "-", "mul": "*", "div": "/", "pow": "**"}


def expression_tree(graph: Graph, value: Any) -> Any:
    """A traced value as a JSON expression tree: an input's name (a string), a number, or
    ``[op, operand, ...]``, op one of ``"+" "-" "*" "/" "**"`` (two operands), ``"neg"``
    (one), or a function's name (``"sqrt"``, ``"exp"``...) with its operands.

    The form ``roughdiffuse models --json`` has given an alias's ``to_base`` since the
    explorer first offered aliases.
    """

    def tree(r: tuple[Any, ...]) -> Any:
        kind, val = r
        if kind == "in":
            return str(val)
        if kind in ("lit", "par"):
            return float(val if kind == "lit" else graph.params[val])
        if kind == "vec":
            raise TraceError("an array of values has no expression tree")
        op, args = graph.nodes[val][0], graph.nodes[val][1:]
        return [_TREE_OPS.get(op, op), *(tree(a) for a in args)]

    return tree(graph.ref(value))


def uniform_function(
    model: Any, name: str, *, share_equal_values: bool = True
) -> tuple[str, list[float]]:
    """``model`` traced with concrete parameters as ``vec3 NAME(float mu_i, float mu_o,
    float cos_io)`` reading every value the parameter math gave (scalars and node arrays)
    from ``uniform float NAME_u[n]``; and those n values.

    The code depends on the model's structure (its class, categorical values, which
    parameters are per channel, the Python branches its parameter math takes) and, with
    ``share_equal_values`` (one parameter for equal values: shorter code, e.g. one
    evaluation for three equal channels), on which of its values are equal; not on the
    values themselves: the explorer compiles it once and sends new values as uniforms.
    """
    traced = trace_model(model, share_equal_values=share_equal_values)
    g = traced.graph
    outputs = _outputs(traced)
    used = _reached(g, outputs, lambda r: r[0] in ("par", "vec"))
    offsets: dict[int, int] = {}
    values: list[float] = []
    for k in sorted(r[1] for r in used):
        offsets[k] = len(values)
        values.extend(float(v) for v in np.asarray(g.params[k], dtype=np.float64).reshape(-1))
    values = values or [0.0]

    class _Uniforms(_Context):
        def name(self, graph: Graph, r: tuple[Any, ...]) -> str:
            if r[0] == "par":
                return f"{name}_u[{offsets[r[1]]}]"
            if r[0] == "vec":
                return f"{name}_u[{offsets[r[1]]} + j]"
            return super().name(graph, r)

    ctx = _Uniforms("glsl", name, str, {}, None, {}, {})
    body = _statements(g, outputs, ctx, set())
    result = ", ".join(ctx.name(g, r) for r in outputs)
    lines = [
        f"uniform float {name}_u[{len(values)}];",
        *ctx.arrays.values(),
        *ctx.helpers.values(),
        f"vec3 {name}(float mu_i, float mu_o, float cos_io) {{",
        *("  " + line for line in body),
        f"  return vec3({result});",
        "}",
        "",
    ]
    return "\n".join(lines), values


# ------------------------------------------------------------------ the user's function
_NAME = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")


def _check_name(name: str) -> None:
    if not _NAME.match(name) or name.startswith("gl_") or "__" in name:
        raise ParameterError(
            f"name must be a GLSL identifier (a letter, then letters, digits or _; no gl_ "
            f"prefix, no __) (got {name!r})"
        )


def _entry_and_values(model: Any) -> tuple[Any, dict[str, Any], dict[str, Any]]:
    """The registry entry of ``model``, its categorical choices and its numeric values
    (read from its fields); a ParameterError when ``model`` is not such a model."""
    from .. import registry
    from .fastpath import _value_key

    entry = registry.id_of(model)
    if entry is None:
        raise ParameterError(
            f"bake=False needs a model of one registry id ({type(model).__name__} matches "
            "none); use bake=True"
        )
    entry = registry.get(entry)
    choices: dict[str, Any] = {}
    values: dict[str, Any] = {}
    try:
        for p in entry.parameters:
            if p.categorical:
                choices[p.name] = getattr(model, p.name)
        for p in entry.applicable(choices):
            if not p.categorical:
                values[p.name] = getattr(model, p.name)
        same = _value_key(entry.create(**choices, **values)) == _value_key(model)
    except (AttributeError, ValueError, TypeError):
        same = False
    if not same:
        raise ParameterError(
            f"bake=False needs a model whose declared parameters are its fields (a "
            f"{type(model).__name__} is not); use bake=True"
        )
    return entry, choices, values


def glsl_uniforms(model: Any) -> dict[str, str]:
    """The uniforms of ``glsl_source(model, bake=False)``: parameter name -> GLSL type
    (``"float"``, or ``"vec3"`` for a colour parameter); angles in radians."""
    entry, choices, _ = _entry_and_values(model)
    return {p.name: "vec3" if p.channels else "float"
            for p in entry.applicable(choices) if not p.categorical}


def _header(model: Any, name: str, lines: Sequence[str]) -> list[str]:
    from .. import __version__

    return [
        f"// {name}: {type(model).__name__} printed by roughdiffuse {__version__} from the",
        "// model's own code (roughdiffuse.engine.glsl); GLSL ES 3.00 (WebGL2).",
        f"// vec3 {name}(vec3 wi, vec3 wo): the BRDF in 1/sr without the cosine, local frame",
        "// (z = normal), wi towards the light, wo towards the viewer; 0 below the horizon.",
        *lines,
    ]


def glsl_source(model: Any, *, name: str = "rd_brdf", bake: bool = True) -> str:
    """Self-contained GLSL ES 3.00 code of ``model``'s BRDF (see the module docstring).

    Parameters
    ----------
    model : Model
        A closed-form model (``model.closed_form``).
    name : str
        The function's name; helpers are named ``NAME_...``.
    bake : bool
        True: the parameter values are constants. False: they are uniforms named after the
        model's declared parameters (:func:`glsl_uniforms`).

    Returns
    -------
    str
        Code defining ``vec3 NAME(vec3 wi, vec3 wo)`` and
        ``vec3 NAME_cosines(float mu_i, float mu_o, float cos_io)``; no ``#version`` or
        precision line (the shader's own come first: ``precision highp float;`` is needed).

    Raises
    ------
    ParameterError
        A model that is not a closed form; with ``bake=False``, a model whose parameters
        cannot be uniforms (see the module docstring); a bad ``name``.
    """
    _check_name(name)
    helpers: dict[str, str] = {}
    arrays: dict[str, str] = {}
    if bake:
        traced = trace_model(model)
        ctx = _Context("glsl", name, str, {}, _literal_par(traced.graph, "glsl"), helpers, arrays)
        outputs = _outputs(traced)
        body = _statements(traced.graph, outputs, ctx, set())
        top: list[str] = ["// Parameter values baked in: " + repr(model)]
        uniforms: list[str] = []
    else:
        if not getattr(model, "closed_form", False):
            trace_model(model)  # raises the closed-form message
        entry, choices, _ = _entry_and_values(model)
        try:
            traced = trace_entry(entry, choices)
        except TraceError as exc:
            raise ParameterError(
                f"{entry.id}: its parameters cannot be uniforms (its parameter math needs "
                f"concrete values: {exc}); use bake=True"
            ) from None

        def input_name(key: str) -> str:
            base, _, channel = key.partition(".")
            return f"{base}.{_SWIZZLE[int(channel)]}" if channel else base

        ctx = _Context("glsl", name, input_name, {}, _literal_par(traced.graph, "glsl"), helpers,
                       arrays)
        outputs = _outputs(traced)
        body = _statements(traced.graph, outputs, ctx, set())
        listed = ", ".join(f"{t} {n}" for n, t in traced.params.items())
        top = [f"// Uniforms (the model's parameters; angles in radians): {listed}",
               "// Categorical parameters fixed: " + (repr(choices) if choices else "none")]
        uniforms = [f"uniform {t} {n};" for n, t in traced.params.items()]
    result = ", ".join(ctx.name(traced.graph, r) for r in outputs)
    lines = [
        *_header(model, name, top),
        *uniforms,
        *arrays.values(),
        *helpers.values(),
        f"vec3 {name}_cosines(float mu_i, float mu_o, float cos_io) {{",
        *("  " + s for s in body),
        f"  return vec3({result});",
        "}",
        f"vec3 {name}(vec3 wi, vec3 wo) {{",
        "  vec3 a = normalize(wi);",
        "  vec3 b = normalize(wo);",
        f"  return {name}_cosines(a.z, b.z, dot(a, b));",
        "}",
        "",
    ]
    return "\n".join(lines)
