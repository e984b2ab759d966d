"""A model's BRDF and its sampler as scalar functions of one direction pair, for Numba loops.

The fast path (:mod:`.fastpath`) compiles a loop over rows of a model's traced code; a Monte
Carlo walk that meets the model once per path vertex needs the same code as a *function* it
can call from its own compiled loop. :func:`scalar_sources` traces (:mod:`.trace`) the model's
``brdf_cosines`` (each colour channel, as :mod:`.fastpath` does) and its sampling strategy's
``sample`` (:mod:`roughdiffuse.models.sampling`: branch-free code on vector components) and
prints them as two functions:

* ``base_f(mu_i, mu_o, cos_io, out, p)``: writes f into ``out[0 .. C−1]``;
* ``base_sample(u1, u2, wox, woy, woz, p)``: returns ``(x, y, z, pdf)``, the sampled direction
  towards the light and its density per solid angle.

``p`` is a tuple of float64 values, the parameters met while tracing (:func:`scalar_sources`
returns them): a new albedo or roughness needs no new code. The code is float64, without
``fastmath``. A model or strategy the trace cannot express raises :class:`.trace.TraceError`.
"""

from __future__ import annotations

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
        _JIT,
        "def base_sample(u1, u2, wo0, wo1, wo2, p):",
        *_unpack(s),
        *("    " + line for line in body_s),
        "    return r0, r1, r2, r3",
        "",
    ]
    return ScalarBase("\n".join(lines), _params(g), _params(s), channels)
