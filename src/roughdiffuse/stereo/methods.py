"""The photometric-stereo methods by name: what ``--method`` and ``--benchmark`` run.

Each entry of :data:`METHODS` is a callable ``(data, *, progress=False) -> result`` whose
result has ``normals`` (P, 3) and ``weights`` (K, P) (1 = observation used, 0 = left out or
rejected as a shadow or an outlier), for the P object pixels of ``data``. ``coated`` is
:func:`.coated.coated` (η 1.5, one σ and one α for the object) from its own Lambertian start
(the rough fit of every pixel only for a matte object); its result also holds σ and α with
their standard errors.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .inputs import StereoInput
from .lambertian import lambertian
from .robust import robust

__all__ = ["DEFAULT_ROUGH_MODEL", "METHODS", "METHOD_LABELS", "run_method"]

DEFAULT_ROUGH_MODEL = "oren-nayar-full"
"""The model of the ``rough`` method (the stereo command's default model)."""


def _lambertian(data: StereoInput, *, progress: bool = False) -> Any:
    return lambertian(data)


def _rough(data: StereoInput, *, progress: bool = False) -> Any:
    from ..registry import create
    from .rough import rough

    return rough(data, create(DEFAULT_ROUGH_MODEL), start=lambertian(data), progress=progress)


def _coated(data: StereoInput, *, progress: bool = False) -> Any:
    from .coated import coated

    return coated(data, progress=progress)


def _robust(method: str) -> Callable[..., Any]:
    def run(data: StereoInput, *, progress: bool = False) -> Any:
        return robust(data, method, progress=progress)

    run.__name__ = f"robust_{method}"
    run.__doc__ = f"Robust Lambertian photometric stereo, :func:`.robust` with {method!r}."
    return run


METHODS: dict[str, Callable[..., Any]] = {
    "lambertian": _lambertian,
    "rough": _rough,
    "l1": _robust("l1"),
    "sparse": _robust("sparse"),
    "rpca": _robust("rpca"),
    "coated": _coated,
}
"""Method name -> callable(StereoInput, progress=False) -> result (normals, weights)."""

METHOD_LABELS = {
    "lambertian": "Lambertian least squares (Woodham 1980)",
    "rough": f"rough fit ({DEFAULT_ROUGH_MODEL})",
    "l1": "L1 residual (Ikehata et al. 2012)",
    "sparse": "sparse Bayesian (Ikehata et al. 2014)",
    "rpca": "RPCA (Wu et al. 2010)",
    "coated": f"coated fit (a coat of η 1.5 over {DEFAULT_ROUGH_MODEL})",
}
"""What each method is, for tables and reports."""


def run_method(name: str, data: StereoInput, *, progress: bool = False) -> Any:
    """Run the method ``name`` of :data:`METHODS` on ``data``."""
    from .._validate import ParameterError

    if name not in METHODS:
        raise ParameterError(f"method must be one of {', '.join(METHODS)} (got {name!r})")
    return METHODS[name](data, progress=progress)
