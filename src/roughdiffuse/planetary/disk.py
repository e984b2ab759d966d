"""Fit a photometric model to disk-resolved I/F measured at many (i, e, g).

The measurements are radiance factors I/F (or bidirectional reflectances r = I/F/π) with the
photometric angles of each; they become :class:`roughdiffuse.fit.Measurements` of kind
``"radiance"`` with value = f × π μ0 (:mod:`.conventions`), and
:func:`roughdiffuse.fit.fit` — the engine of ``roughdiffuse fit`` — fits them (relative
noise by default: a constant fraction of the I/F). Each parameter comes with its standard
error and its correlations; :func:`constraint_notes` names the parameters the coverage cannot
constrain (an opposition surge with no data near opposition, an error bar as wide as a
quarter of the parameter's range, a correlation beyond 0.98, a direction the data cannot see).
"""

from __future__ import annotations

import base64
import csv
import html
import io
import math
import os
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._figure import displayable, literal
from .._validate import ParameterError
from .conventions import photometric_to_local

__all__ = [
    "PHOTOMETRIC_MODELS",
    "SURGE_PARAMETERS",
    "DiskFit",
    "DiskData",
    "constraint_notes",
    "fit_disk",
    "read_photometry_csv",
    "write_disk_report",
]

PHOTOMETRIC_MODELS: tuple[str, ...] = (
    "hapke",
    "hapke-legendre",
    "hapke-2012",
    "lunar-lambert",
    "minnaert",
    "lommel-seeliger",
    "lambert",
)
"""The registry ids written as radiance factors of (i, e, g) (the planetary functions, ISIS's
photometric models); ``photometry fit`` and ``photometry correct`` take these."""

SURGE_PARAMETERS: dict[str, float] = {
    "b0": 10.0,
    "h": 10.0,
    "bs0": 10.0,
    "h_s": 10.0,
    "bc0": 2.0,
    "h_c": 2.0,
}
"""Opposition-surge parameters and the phase angle (degrees) below which the data must reach
to constrain them: the shadow-hiding surge is some degrees wide, the coherent-backscatter one
about a degree."""

CORRELATION_LIMIT = 0.98
WIDE_ERROR = 0.25  # an error bar wider than this fraction of the fit box: unconstrained


@dataclass(frozen=True)
class DiskData:
    """Disk-resolved photometry: I/F with incidence, emission and phase (radians)."""

    iof: np.ndarray
    incidence: np.ndarray
    emission: np.ndarray
    phase: np.ndarray
    source: str = ""
    band: str | None = None

    def __post_init__(self) -> None:
        arrs = [
            np.asarray(a, dtype=np.float64).ravel()
            for a in (self.iof, self.incidence, self.emission, self.phase)
        ]
        n = arrs[0].size
        if any(a.size != n for a in arrs):
            raise ParameterError(
                "iof, incidence, emission and phase must have one value per sample"
            )
        if not np.all(np.isfinite(arrs[0])):
            raise ParameterError("iof must be finite")
        photometric_to_local(arrs[1], arrs[2], arrs[3])  # refuses impossible geometry
        for name, a in zip(("iof", "incidence", "emission", "phase"), arrs, strict=True):
            object.__setattr__(self, name, a)

    @property
    def size(self) -> int:
        return int(self.iof.size)

    def measurements(self) -> Any:
        """The samples as :class:`roughdiffuse.fit.Measurements` (value = f π μ0)."""
        from ..fit import Measurements

        mu0 = np.cos(self.incidence)
        return Measurements(
            mu0,
            np.cos(self.emission),
            np.cos(self.phase),
            self.iof,
            math.pi * mu0,
            kind="radiance",
            source=self.source + (f" [{self.band}]" if self.band else ""),
        )


@dataclass(frozen=True)
class DiskFit:
    """A photometric fit: the engine's result, correlations and the coverage notes."""

    data: DiskData
    result: Any  # roughdiffuse.fit.FitResult
    correlation: np.ndarray
    notes: dict[str, str] = field(default_factory=dict)

    @property
    def model_iof(self) -> np.ndarray:
        from ..models.photometry import radiance_factor

        d = self.data
        return np.asarray(radiance_factor(self.result.model, d.incidence, d.emission, d.phase))

    def table(self) -> str:
        """The engine's table, the correlations beyond 0.5 and the coverage notes."""
        lines = [self.result.table()]
        names = self.result.names
        for a in range(len(names)):
            for b in range(a + 1, len(names)):
                c = self.correlation[a, b]
                if np.isfinite(c) and abs(c) > 0.5:
                    lines.append(f"  correlation {names[a]}–{names[b]}: {c:+.2f}")
        lines.extend(f"  unconstrained: {k}: {v}" for k, v in self.notes.items())
        return "\n".join(lines)


def constraint_notes(data: DiskData, result: Any, correlation: np.ndarray) -> dict[str, str]:
    """Parameters the data cannot constrain, each with the reason (see the module)."""
    notes: dict[str, str] = {}
    min_g = math.degrees(float(np.min(data.phase)))
    for k, name in enumerate(result.names):
        base = name.split("[")[0]
        err = float(result.errors[k])
        lo, hi = result.bounds[k]
        if not math.isfinite(err):
            notes[name] = "the data cannot identify it (infinite error)"
        elif base in SURGE_PARAMETERS and min_g > SURGE_PARAMETERS[base]:
            notes[name] = (
                f"no data below g = {SURGE_PARAMETERS[base]:g}° (smallest phase "
                f"{min_g:.1f}°): the opposition surge is not observed"
            )
        elif err > WIDE_ERROR * (hi - lo):
            notes[name] = f"its error bar ({err:.3g}) spans over a quarter of its range"
        else:
            others = [
                (abs(correlation[k, j]), result.names[j])
                for j in range(len(result.names))
                if j != k and np.isfinite(correlation[k, j])
            ]
            if others:
                c, other = max(others)
                if c > CORRELATION_LIMIT:
                    notes[name] = f"correlated with {other} (|ρ| = {c:.3f})"
    return notes


def _correlation(cov: np.ndarray) -> np.ndarray:
    cov = np.asarray(cov, dtype=np.float64)
    sd = np.sqrt(np.abs(np.diag(cov)))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(sd, sd)
    corr[~np.isfinite(corr)] = np.nan
    np.fill_diagonal(corr, 1.0)
    return corr


def fit_disk(
    model: str,
    data: DiskData,
    *,
    params: Sequence[str] | None = None,
    fixed: Mapping[str, Any] | None = None,
    noise: str = "relative",
    seed: int = 0,
) -> DiskFit:
    """Fit the photometric model ``model`` (a registry id) to disk-resolved I/F.

    Parameters
    ----------
    model : str
        One of :data:`PHOTOMETRIC_MODELS`.
    data : DiskData
        The measurements.
    params : sequence of str, optional
        The parameters to fit (default: every numeric one not in ``fixed``).
    fixed : mapping, optional
        Parameters held at given values (radians for angles), e.g. ``{"hg2": 0.0}``.
    noise : {"relative", "absolute"}
        The noise model of :func:`roughdiffuse.fit.fit`.
    seed : int
        Seed of the engine's starting points.

    Returns
    -------
    DiskFit
    """
    from .. import registry
    from ..deprecation import rename_keywords
    from ..fit import DegenerateDataWarning, fit
    from ..fit.compare import candidate

    if model not in PHOTOMETRIC_MODELS:
        raise ParameterError(
            f"model {model!r} has no radiance factor of (i, e, g) here; choose one of: "
            f"{', '.join(PHOTOMETRIC_MODELS)}"
        )
    c = candidate(model)
    fixed = rename_keywords(registry.get(model).cls, fixed or {}, "fit_disk(fixed=...)")
    unknown = set(fixed) - set(c.params)
    if unknown:
        raise ParameterError(
            f"{model} has no parameter {sorted(unknown)[0]!r} (it has: {', '.join(c.params)})"
        )
    names = [p for p in (params or c.params) if p not in fixed]
    if data.size < len(names) + 1:
        raise ParameterError(
            f"{len(names)} parameters need more than {len(names)} samples (got {data.size})"
        )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DegenerateDataWarning)  # reported in the notes
        result = fit(
            c.model,
            data.measurements(),
            names,
            fixed={**(c.fixed or {}), **fixed},
            noise=noise,
            seed=seed,
        )
    corr = _correlation(result.covariance)
    return DiskFit(data, result, corr, constraint_notes(data, result, corr))


# ------------------------------------------------------------------------- CSV
_COLUMNS = {
    "iof": ("iof", "i/f", "radf", "radiance_factor"),
    "r": ("r", "reflectance", "bidirectional_reflectance"),
    "i": ("i", "inc", "incidence", "incidence_deg", "i_deg"),
    "e": ("e", "ema", "emission", "emission_deg", "e_deg"),
    "g": ("g", "pha", "phase", "phase_deg", "g_deg", "alpha"),
    "band": ("band", "filter", "wavelength"),
}


def _header(row: Sequence[str], path: str) -> dict[str, int]:
    found: dict[str, int] = {}
    for k, name in enumerate(row):
        key = name.strip().lower()
        for col, aliases in _COLUMNS.items():
            if key in aliases:
                found[col] = k
    missing = [c for c in ("i", "e", "g") if c not in found]
    if missing or ("iof" in found) == ("r" in found):
        raise ParameterError(
            f"{path}: the header must name the columns i, e, g (degrees) and one of I/F or r "
            f"(optional: band); got {', '.join(row)}"
        )
    return found


def read_photometry_csv(path: str | os.PathLike[str]) -> dict[str | None, DiskData]:
    """Read disk-resolved photometry: columns I/F (or r), i, e, g in degrees, optional band.

    Returns one :class:`DiskData` per band (key ``None`` without a band column). Angles
    outside [0°, 180°], i or e beyond 90° (unlit or unseen), and a band with a single row are
    refused with a ``ValueError`` naming the row or band.
    """
    path = os.fspath(path)
    with open(path, newline="", encoding="utf-8") as fh:
        rows = [r for r in csv.reader(fh) if r and not r[0].lstrip().startswith("#")]
    if len(rows) < 2:
        raise ParameterError(f"{path}: no data rows under the header")
    cols = _header(rows[0], path)
    value_col = "iof" if "iof" in cols else "r"
    groups: dict[str | None, list[tuple[float, float, float, float]]] = {}
    for n, row in enumerate(rows[1:], start=2):
        try:
            v, i, e, g = (float(row[cols[c]]) for c in (value_col, "i", "e", "g"))
        except (ValueError, IndexError):
            raise ParameterError(f"{path}, line {n}: expected numbers in every column") from None
        if not (math.isfinite(v) and v > 0.0):  # relative residuals divide by it
            raise ParameterError(
                f"{path}, line {n}: {value_col} must be a positive finite number (got {v:g}); "
                "drop unlit or missing pixels"
            )
        for name, a in (("i", i), ("e", e), ("g", g)):
            if not 0.0 <= a <= 180.0:
                raise ParameterError(
                    f"{path}, line {n}: {name} must be in [0, 180] degrees (got {a:g})"
                )
        for name, a in (("i", i), ("e", e)):
            if a > 90.0:
                raise ParameterError(
                    f"{path}, line {n}: {name} = {a:g}° is beyond 90° (the point is "
                    f"{'unlit' if name == 'i' else 'not seen'}); drop such rows"
                )
        band = row[cols["band"]].strip() if "band" in cols else None
        groups.setdefault(band, []).append((v * math.pi if value_col == "r" else v, i, e, g))
    out: dict[str | None, DiskData] = {}
    for band, vals in groups.items():
        if len(vals) < 2:
            raise ParameterError(f"{path}: band {band!r} has a single row; a fit needs more")
        a = np.radians(np.array(vals)[:, 1:])
        out[band] = DiskData(
            np.array(vals)[:, 0],
            a[:, 0],
            a[:, 1],
            a[:, 2],
            source=os.path.basename(path),
            band=band,
        )
    return out


# ------------------------------------------------------------------------- report
def plot_disk_fit(fit: DiskFit) -> Any:
    """I/F against g with the model, and the relative residuals against i, e and g."""
    from .._figure import subplots

    d = fit.data
    model = fit.model_iof
    fig, axes = subplots(1, 4, figsize=(16, 3.8), layout="constrained")
    deg = np.degrees
    ax = axes[0]
    ax.scatter(deg(d.phase), d.iof, s=10, c="0.55", label="data")
    ax.scatter(deg(d.phase), model, s=2, c="tab:red", label=fit.result.model_name)
    ax.set_xlabel("phase g (°)")
    ax.set_ylabel("I/F")
    ax.legend(fontsize=8)
    rel = (d.iof - model) / np.where(model != 0, model, np.nan)
    for ax, a, name in zip(axes[1:], (d.incidence, d.emission, d.phase), "ieg", strict=True):
        ax.scatter(deg(a), 100 * rel, s=4, c="0.3")
        ax.axhline(0.0, c="tab:red", lw=1)
        ax.set_xlabel(f"{name} (°)")
        ax.set_ylabel("(data − model)/model (%)")
    title = f"{d.source}{' [' + d.band + ']' if d.band else ''}: {fit.result.model_name}"
    fig.suptitle(literal(title))  # a band or file name is text, never mathtext
    return fig


def write_disk_report(path: str | os.PathLike[str], fits: Sequence[DiskFit]) -> None:
    """An HTML report (atomically written): per band the table, correlations, notes, plots."""
    from ..io.atomic import check_output_path, write_text

    path = check_output_path(path, "report")
    parts = [
        "<!doctype html><html><head><meta charset='utf-8'><title>roughdiffuse photometry fit"
        "</title><style>body{font-family:sans-serif;max-width:1300px;margin:2em auto}"
        "pre{background:#f6f6f6;padding:8px}.warn{color:#a40}</style></head><body>",
        "<h1>Disk-resolved photometric fit</h1>",
    ]
    for f in fits:
        buf = io.BytesIO()
        plot_disk_fit(f).savefig(buf, format="png", dpi=100)
        png = base64.b64encode(buf.getvalue()).decode("ascii")
        title = f.data.band or f.data.source
        parts.append(f"<h2>{html.escape(displayable(title))}: {f.data.size} samples</h2>")
        parts.append("<pre>" + html.escape(f.table()) + "</pre>")
        parts.append(f"<img alt='I/F against phase, residuals' src='data:image/png;base64,{png}'>")
    parts.append("</body></html>")
    write_text(path, "\n".join(parts))
