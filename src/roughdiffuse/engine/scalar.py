"""A model's BRDF and its sampler as scalar functions of one direction pair, for Numba loops.

The fast path (:mod:`.fastpath`) compiles a loop over rows of a model's traced code; a Monte
Carlo walk that meets the model once per path vertex needs the same code as a *function* it
can call from its own compiled loop. :func:`scalar_sources` traces (:mod:`.trace`) the model's
``brdf_cosines`` (each colour channel, as :mod:`.fastpath` does) and its sampling strategy's
``sample`` (:mod:`roughdiffuse.models.sampling`: branch-free code on vector components) and
prints them as functions:

* ``base_f(mu_i, mu_o, cos_io, out, p)``: writes f into ``out[0 .. C−1]``;
* ``base_sample(u1, u2, wox, woy, woz, p)``: returns ``(x, y, z, pdf)``, the sampled direction
  towards the light and its density per solid angle;
* ``base_f`` in parts, for a caller that evaluates f many times at one direction (a walk's
  next events towards the view; a walk's continuation, whose μo is the μi of its next
  event): ``ho = base_f_o(mu_o, p)`` and ``hi = base_f_i(mu_i, p)`` hold the values that
  depend on μo alone and on μi alone (tuples), and
  ``base_f_io(mu_i, mu_o, cos_io, hi, ho, out, p)`` writes what ``base_f`` writes from them.
  ``base_f_i_as_o(mu, ho, p)`` is ``base_f_i(mu, p)`` given ``ho = base_f_o(mu, p)`` at the
  same cosine: ``ho`` itself when the two parts are the same code (a base whose f treats μi
  and μo alike, as a reciprocal model written symmetrically does: the values are
  bit-for-bit those ``base_f_i`` computes), else a call of ``base_f_i``.

``p`` is a tuple of float64 values, the parameters met while tracing (:func:`scalar_sources`
returns them): a new albedo or roughness needs no new code. The code is float64, without
``fastmath``; each function asks LLVM to inline it into its compiled caller
(:func:`.numba_math.inline_in_callers`), so that a walk's compiled loop interleaves the
base's independent computations (its f at one cosine while its sampler runs). A model or
strategy the trace cannot express raises :class:`.trace.TraceError`.
"""

from __future__ import annotations

import re
from typing import Any, NamedTuple

import numpy as np

from .trace import Graph, SymVec, TraceNamespace, scalar_source

__all__ = ["PRELUDE", "ScalarBase", "scalar_sources"]

PRELUDE = "\n".join([
    "import math",
    "",
    "import numba",
    "import numpy as np",
    "",
    "from roughdiffuse.engine.numba_math import exp2i, exp2i_f64, inline_in_callers",
    "",
])
"""The imports the printed functions need (a module that ``exec``\\ s them starts with it)."""

_JIT = "@numba.njit(error_model='numpy')"


class ScalarBase(NamedTuple):
    """The printed functions (to run after :data:`PRELUDE`), the parameter tuples of
    ``base_f`` and ``base_sample``, and the number of values ``base_f`` writes."""

    source: str
    f_params: tuple[float, ...]
    sample_params: tuple[float, ...]
    channels: int


def _unpack(graph: Graph) -> list[str]:
    return ["    inline_in_callers()", *(f"    p{k} = p[{k}]" for k in range(len(graph.params)))]


def _params(graph: Graph) -> tuple[float, ...]:
    return tuple(float(v) for v in graph.params)


_ASSIGN = re.compile(r"^([tr]\d+) = (.*)$")
_NAME = re.compile(r"\b(t\d+|mu_i|mu_o|cos_io)\b")
_T = re.compile(r"\bt\d+\b")


class _Split(NamedTuple):
    """``body`` split by the inputs its statements depend on (:func:`_split`)."""

    common: list[str]  # on no input: at the start of every part
    i_part: list[str]  # on mu_i alone
    o_part: list[str]  # on mu_o alone
    rest: list[str]
    i_held: list[str]  # the names of i_part that ``base_f_i`` returns
    o_held: list[str]  # the names of o_part that ``base_f_o`` returns, in the same order
    symmetric: bool  # i_part is o_part with mu_i for mu_o (and its own names)


def _canonical(part: list[str], cosine: str) -> tuple[list[str], dict[str, int]]:
    """The statements of ``part`` with ``cosine`` written ``mu`` and the names it assigns
    numbered in order, and those numbers."""
    index = {_ASSIGN.match(line).group(1): k for k, line in enumerate(part)}
    text = [re.sub(rf"\b{cosine}\b", "mu", line) for line in part]
    return [_T.sub(lambda m: f"v{index[m.group(0)]}" if m.group(0) in index else m.group(0),
                   line) for line in text], index


def _split(body: list[str]) -> _Split:
    """``body`` (straight-line ``name = expression`` statements) split into the statements
    that depend on no input, on ``mu_i`` alone, on ``mu_o`` alone, and the rest. A body with a
    loop (a node sum) is not split."""
    if not all(_ASSIGN.match(line) for line in body):
        return _Split([], [], [], body, [], [], False)
    inputs: dict[str, set[str]] = {}
    parts: dict[str, list[str]] = {"": [], "mu_i": [], "mu_o": [], "rest": []}
    for line in body:
        target, expression = _ASSIGN.match(line).groups()
        refs: set[str] = set()
        for ref in _NAME.findall(expression):
            refs |= inputs.get(ref, {ref})
        inputs[target] = refs
        key = "".join(refs) if len(refs) <= 1 and target[0] == "t" else "rest"
        parts[key if key in parts else "rest"].append(line)
    i_part, o_part, rest = parts["mu_i"], parts["mu_o"], parts["rest"]
    read = {ref for line in rest for ref in _NAME.findall(_ASSIGN.match(line).group(2))}
    i_text, i_index = _canonical(i_part, "mu_i")
    o_text, o_index = _canonical(o_part, "mu_o")
    if i_text == o_text:  # hold the same positions of both
        at = sorted({i_index[n] for n in read & i_index.keys()}
                    | {o_index[n] for n in read & o_index.keys()})
        i_names, o_names = list(i_index), list(o_index)
        return _Split(parts[""], i_part, o_part, rest, [i_names[k] for k in at],
                      [o_names[k] for k in at], True)
    return _Split(parts[""], i_part, o_part, rest,
                  [n for n in i_index if n in read], [n for n in o_index if n in read], False)


def _held(names: list[str]) -> str:
    return "(" + (", ".join(names) + "," if names else "0.0,") + ")"


def _f_parts(unpack: list[str], body: list[str], channels: int) -> list[str]:
    """The printed ``base_f_o``, ``base_f_i``, ``base_f_i_as_o`` and ``base_f_io``
    (:func:`_split`)."""
    sp = _split(body)
    common = [*unpack, *("    " + line for line in sp.common)]
    as_o = "    return ho" if sp.symmetric else "    return base_f_i(mu, p)"
    return [
        _JIT,
        "def base_f_o(mu_o, p):",
        *common,
        *("    " + line for line in sp.o_part),
        f"    return {_held(sp.o_held)}",
        "",
        _JIT,
        "def base_f_i(mu_i, p):",
        *common,
        *("    " + line for line in sp.i_part),
        f"    return {_held(sp.i_held)}",
        "",
        _JIT,
        "def base_f_i_as_o(mu, ho, p):",
        as_o,
        "",
        _JIT,
        "def base_f_io(mu_i, mu_o, cos_io, hi, ho, out, p):",
        *common,
        *(f"    {name} = hi[{k}]" for k, name in enumerate(sp.i_held)),
        *(f"    {name} = ho[{k}]" for k, name in enumerate(sp.o_held)),
        *("    " + line for line in sp.rest),
        *(f"    out[{c}] = r{c}" for c in range(channels)),
        "",
    ]


def scalar_sources(model: Any) -> ScalarBase:
    """Trace ``model``'s ``brdf_cosines`` and its strategy's ``sample`` (float64).

    Parameters
    ----------
    model
        A closed-form model (``brdf_cosines``, ``channels``, ``channel(c)``,
        ``sampling_strategy()``, ``parameter_arrays(xp, dtype)``).

    Returns
    -------
    ScalarBase
    """
    g = Graph(np.dtype(np.float64))
    cosines = [g.input(name) for name in ("mu_i", "mu_o", "cos_io")]
    channels = max(int(model.channels), 1)
    outputs = [
        (model.channel(c) if model.channels else model).brdf_cosines(*cosines)
        for c in range(channels)
    ]
    consts_f, body_f = scalar_source(g, outputs, literal_name="_LF")
    s = Graph(np.dtype(np.float64))
    u1, u2 = s.input("u1"), s.input("u2")
    wo = SymVec(s, "wo")
    strategy = model.sampling_strategy()
    outs = strategy.sample(TraceNamespace(s), u1, u2, wo[0], wo[1], wo[2],
                           model.parameter_arrays(np, np.float64))
    consts_s, body_s = scalar_source(s, list(outs), literal_name="_LS")
    lines = [
        *consts_f,
        *consts_s,
        "",
        _JIT,
        "def base_f(mu_i, mu_o, cos_io, out, p):",
        *_unpack(g),
        *("    " + line for line in body_f),
        *(f"    out[{c}] = r{c}" for c in range(channels)),
        "",
        *_f_parts(_unpack(g), body_f, channels),
        _JIT,
        "def base_sample(u1, u2, wo0, wo1, wo2, p):",
        *_unpack(s),
        *("    " + line for line in body_s),
        "    return r0, r1, r2, r3",
        "",
    ]
    return ScalarBase("\n".join(lines), _params(g), _params(s), channels)
