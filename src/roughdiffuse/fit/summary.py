"""How a fit's numbers are shown: one rule for Python, the command line and the explorer.

A fitted value is *at its bound* when it lies within :data:`BOUND_TOL` of the width of its
box from either end; its linearised standard error then means nothing (the optimum is not a
stationary point), so none is shown. A standard error that is not finite, or wider than the
whole box the parameter may take (e.g. Hapke's ``h`` at ± 3e28), is *not determined*.
:func:`error_notes` gives that verdict per parameter, :func:`result_json` the JSON that
``roughdiffuse fit --json`` prints and the explorer's ``/api/fit`` and ``/api/rank`` send.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .least_squares import FitResult

__all__ = [
    "AT_BOUND",
    "BOUND_TOL",
    "NOT_DETERMINED",
    "at_bound",
    "error_notes",
    "result_json",
    "row_name",
    "shown_errors",
]

BOUND_TOL = 1e-6
"""A value within this fraction of its box's width from an end is on that bound."""

AT_BOUND = "at bound"
NOT_DETERMINED = "not determined"


def at_bound(values: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Boolean mask: which of ``values`` (P,) sit on an end of ``box`` (P, 2)."""
    values = np.asarray(values, dtype=np.float64)
    box = np.asarray(box, dtype=np.float64)
    tol = BOUND_TOL * (box[:, 1] - box[:, 0])
    return (values <= box[:, 0] + tol) | (values >= box[:, 1] - tol)


def error_notes(result: FitResult) -> list[str]:
    """Per fitted parameter: ``""`` (the standard error is usable), :data:`AT_BOUND` or
    :data:`NOT_DETERMINED` (not finite, or wider than the parameter's whole box)."""
    out = []
    for k in range(len(result.names)):
        err = float(result.errors[k])
        lo, hi = (float(b) for b in result.bounds[k])
        width = hi - lo if math.isfinite(hi - lo) else math.inf
        if result.on_bound[k]:
            out.append(AT_BOUND)
        elif not math.isfinite(err) or err > width:
            out.append(NOT_DETERMINED)
        else:
            out.append("")
    return out


def shown_errors(result: FitResult) -> list[float | None]:
    """The standard errors to show: ``None`` where :func:`error_notes` gives a note."""
    return [
        None if note else float(e)
        for e, note in zip(result.errors, error_notes(result), strict=True)
    ]


def _finite(v: float) -> float | None:
    return float(v) if math.isfinite(v) else None


def row_name(model_id: str, choices: Mapping[str, str] | None = None) -> str:
    """The name of a fit's row in a ranking: the registry id, then each choice it was fitted
    with, as ``--model coated --param base=eon`` fits it alone (``"coated base=eon"``)."""
    return " ".join([model_id, *(f"{k}={v}" for k, v in (choices or {}).items())])


def result_json(
    model_id: str, result: FitResult, choices: Mapping[str, str] | None = None
) -> dict[str, Any]:
    """A fit as JSON-safe values (``None`` for non-finite numbers): the registry id, the
    choices it was fitted with (``{"base": "eon"}`` for one row of ``coated``; ``{}`` when
    none was fixed) and the row's name (:func:`row_name`), the parameters, their shown
    standard errors and notes (:func:`error_notes`), RMS, AIC, BIC and the noise model."""
    return {
        "model": model_id,
        "choices": dict(choices or {}),
        "label": row_name(model_id, choices),
        "names": list(result.names),
        "values": [_finite(v) for v in result.values],
        "errors": shown_errors(result),
        "error_notes": error_notes(result),
        "on_bound": [bool(b) for b in result.on_bound],
        "rms": _finite(result.rms),
        "rms_relative": _finite(result.rms_relative),
        "residuals": int(result.n_samples),
        "aic": _finite(result.aic),
        "bic": _finite(result.bic),
        "noise": result.noise,
        "warnings": list(result.warnings),
    }
