"""What the exporters share: the result record, the conversion's comment lines, parameters."""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .. import registry
from .._validate import ParameterError
from ..fit.between_models import Conversion, convert
from ..io.atomic import write_text
from ..models.base import Model

__all__ = [
    "BackendWarning",
    "Export",
    "error_lines",
    "material_for",
    "model_record",
    "params_of",
    "warn_backends",
    "write_files",
]


class BackendWarning(UserWarning):
    """One of the target's backends renders the written material as another model (the
    message names the backend and the registry id of what it renders)."""


@dataclass(frozen=True)
class Export:
    """What :func:`export` wrote: the files, the target model, the conversion (or None) and
    notes (what was not written, and why)."""

    target: str
    paths: tuple[Path, ...]
    model_id: str
    params: dict[str, Any]
    conversion: Conversion | None
    notes: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()

    def summary(self) -> str:
        """The lines ``roughdiffuse export`` prints (a backend warning on one line each)."""
        lines = [f"{self.target}: {', '.join(str(p) for p in self.paths)}"]
        lines.append(f"  as {self.model_id}: " + _params_text(self.params))
        lines.extend("  " + line for line in error_lines(self.conversion))
        lines.extend("  " + line for line in self.notes)
        lines.extend("  warning: " + line for line in self.warnings)
        return "\n".join(lines)


def warn_backends(result: Export) -> Export:
    """Issue each of ``result.warnings`` as a :class:`BackendWarning` (for the caller of
    :func:`roughdiffuse.exporters.export`); returns ``result``. The command line prints them
    in its summary instead."""
    import warnings

    for text in result.warnings:
        warnings.warn(text, BackendWarning, stacklevel=4)
    return result


def _params_text(params: dict[str, Any]) -> str:
    return ", ".join(f"{k}={_num(v)}" for k, v in params.items())


def _num(v: Any) -> str:
    if isinstance(v, list | tuple):
        return "[" + ", ".join(f"{x:.6g}" for x in v) + "]"
    return f"{v:.6g}" if isinstance(v, float) else str(v)


def error_lines(conversion: Conversion | None) -> list[str]:
    """The conversion error as comment lines ('exact' when nothing was converted)."""
    if conversion is None:
        return ["exact: the target computes this model (no conversion)"]
    return [
        f"converted from {conversion.source} by least squares "
        "(roughdiffuse.fit.between_models):",
        f"f cos theta_i differs by {100 * conversion.rms_f:.3g} % RMS, "
        f"{100 * conversion.max_f:.3g} % at most (relative to the source's RMS);",
        f"directional albedo differs by {100 * conversion.rms_albedo:.3g} % RMS, "
        f"{100 * conversion.max_albedo:.3g} % at most",
    ]


_MISSING = object()


def xml_comment_text(text: str) -> str:
    """``text`` safe inside an XML comment (Mitsuba's scenes, MaterialX documents): XML
    forbids ``--`` there and a final ``-``, so a ``-`` before another gets a space.

    >>> xml_comment_text("a ---> b -")
    'a - - -> b'
    """
    return re.sub(r"-(?=-)", "- ", text).rstrip("- ")


def rgb_of(albedo: Any) -> list[float]:
    """An albedo as the three values of an RGB colour: one value (grey) or three channels;
    any other number of channels is a ``ValueError`` (a colour of 4 values would write a
    file its renderer cannot load)."""
    values = [float(x) for x in np.ravel(albedo)]
    if len(values) == 1:
        return values * 3
    if len(values) != 3:
        raise ParameterError(f"albedo has {len(values)} channels; an RGB colour takes 1 or 3")
    return values


def python_comment_lines(text: str) -> list[str]:
    """``text`` as Python comment lines: every line it holds (any line break Python or a
    reader might see) gets its own comment mark (``#`` and a space), so no part of it
    becomes code."""
    return ["# " + line for line in (text.splitlines() or [""])]


def params_of(model: Model, model_id: str) -> dict[str, Any]:
    entry = registry.get(model_id)
    out: dict[str, Any] = {}
    for p in entry.parameters:
        if p.categorical:
            continue
        value = getattr(model, p.name, _MISSING)
        if value is _MISSING:  # built by from_params (Coated, Mix): not kept as it was given
            raise ParameterError(
                f"{model_id} is built of other models (its parameter {p.name} belongs to one "
                "of them); this export writes one model's own parameters and cannot hold it"
            )
        if value is None:
            continue
        arr = [float(x) for x in np.ravel(value)]
        out[p.name] = arr if len(arr) > 1 else arr[0]
    return out


def model_record(model: Model) -> dict[str, Any]:
    """``{"model": id, "params": {...}}``, which :func:`load_result` reads (``ValueError``
    for a model the registry does not name)."""
    model_id = registry.id_of(model)
    if model_id is None:
        raise ParameterError(f"{type(model).__name__} is not a registry model")
    return {"model": model_id, "params": params_of(model, model_id)}


def material_for(model: Model, target_id: str) -> tuple[dict[str, Any], Conversion | None]:
    """The parameters of ``target_id`` for ``model``: its own if it is that model, else
    converted (``ValueError`` if the target cannot hold it)."""
    source_id = registry.id_of(model)
    if source_id == target_id or (
        source_id is not None and registry.get(source_id).cls is registry.get(target_id).cls
    ):
        return params_of(model, target_id), None
    base = getattr(model, "base_model", None)
    if base is not None and registry.id_of(base()) == target_id:  # an alias of the target
        return params_of(base(), target_id), None
    result = convert(model, target=target_id)
    return dict(result.params), result


def write_files(files: dict[Path, str]) -> tuple[Path, ...]:
    """Write each text file whole (:mod:`roughdiffuse.io.atomic`)."""
    for p, text in files.items():
        write_text(p, text)
    return tuple(files)
