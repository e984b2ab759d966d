"""A model's BRDF and its sampler as scalar functions of one direction pair, for Numba loops.

The fast path (:mod:`.fastpath`) compiles a loop over rows of a model's traced code; a Monte
Carlo walk that meets the model once per path vertex needs the same code as a *function* it
can call from its own compiled loop. :func:`scalar_sources` traces (:mod:`.trace`) the model's
``brdf_cosines`` (each colour channel, as :mod:`.fastpath` does) and its sampling strategy's
``sample`` (:mod:`roughdiffuse.models.sampling`: branch-free code on vector components) and
prints them as two functions:

* ``base_f(mu_i, mu_o, cos_io, out, p)``: writes f into ``out[0 .. C−1]``;
* ``base_sample(u1, u2, wox, woy, woz, p)``: returns ``(x, y, z, pdf)``, the sampled direction
  towards the light and its density per solid angle;
* ``base_f_o(mu_o, p)`` and ``base_f_at(mu_i, mu_o, cos_io, h, out, p)``: ``base_f`` in two
  parts, for a caller that evaluates f many times at one ωo (a walk's next events towards
  the view): ``h = base_f_o(mu_o, p)`` holds the values that depend on μo alone (a tuple),
  ``base_f_at`` the rest; ``base_f_at(mu_i, mu_o, cos_io, base_f_o(mu_o, p), out, p)``
  writes what ``base_f`` writes.

``p`` is a tuple of float64 values, the parameters met while tracing (:func:`scalar_sources`
returns them): a new albedo or roughness needs no new code. The code is float64, without
``fastmath``. A model or strategy the trace cannot express raises :class:`.trace.TraceError`.
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
    "from roughdiffuse.engine.numba_math import exp2i, exp2i_f64",
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
    return [f"    p{k} = p[{k}]" for k in range(len(graph.params))]


def _params(graph: Graph) -> tuple[float, ...]:
    return tuple(float(v) for v in graph.params)


_ASSIGN = re.compile(r"^([tr]\d+) = (.*)$")
_NAME = re.compile(r"\b(t\d+|mu_i|mu_o|cos_io)\b")


def _split_by_mu_o(body: list[str]) -> tuple[list[str], list[str], list[str]]:
    """``body`` (straight-line ``name = expression`` statements) split into the statements
    that depend on ``mu_o`` alone (and on constants), the others, and the names of the first
    part that the second reads. A body with a loop (a node sum) is not split."""
    if not all(_ASSIGN.match(line) for line in body):
        return [], body, []
    inputs: dict[str, set[str]] = {}
    first: list[str] = []
    rest: list[str] = []
    for line in body:
        target, expression = _ASSIGN.match(line).groups()
        refs: set[str] = set()
        for ref in _NAME.findall(expression):
            refs |= inputs.get(ref, {ref})
        inputs[target] = refs
        (first if refs == {"mu_o"} and target[0] == "t" else rest).append(line)
    hoisted = {_ASSIGN.match(line).group(1) for line in first}
    read = {ref for line in rest for ref in _NAME.findall(_ASSIGN.match(line).group(2))}
    return first, rest, sorted(hoisted & read, key=lambda n: int(n[1:]))


def _f_parts(unpack: list[str], body: list[str], channels: int) -> list[str]:
    """The printed ``base_f_o`` and ``base_f_at`` (:func:`_split_by_mu_o`)."""
    first, rest, shared = _split_by_mu_o(body)
    held = ", ".join(shared) + "," if shared else "0.0,"
    return [
        _JIT,
        "def base_f_o(mu_o, p):",
        *unpack,
        *("    " + line for line in first),
        f"    return ({held})",
        "",
        _JIT,
        "def base_f_at(mu_i, mu_o, cos_io, h, out, p):",
        *unpack,
        *(f"    {name} = h[{k}]" for k, name in enumerate(shared)),
        *("    " + line for line in rest),
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
