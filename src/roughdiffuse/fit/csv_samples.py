"""BRDF samples from a CSV file or a table (NumPy structured array, pandas DataFrame, dict).

The header names the columns and says the angle unit; one row per sample::

    # irradiance = 2.0          (optional; needed for radiance without an irradiance column)
    theta_i_deg, theta_r_deg, delta_phi_deg, brdf
    30, 45, 0, 0.2312
    ...

Angles: ``theta_i``, ``theta_r`` (``theta_o`` too) and either ``delta_phi`` (φr − φi) or
``phi_i`` and ``phi_r``; each with its unit as a suffix, ``_deg``/``_rad`` or ``[deg]``,
``(rad)``, ``degrees``, ``radians``. θ must be in [0, 90] degrees ([0, π/2] radians).
Values: ``brdf`` (1/sr) or ``radiance`` (with ``irradiance``, a column or the header line
``# irradiance = E0``); for colour, ``brdf_r, brdf_g, brdf_b`` (or ``radiance_r`` …). A unit
in brackets after a value column (``brdf [1/sr]``) is ignored. Lines starting with ``#`` are
comments. A bad cell raises ``ValueError`` naming the file, line and column.
"""

from __future__ import annotations

import csv
import math
import os
import re
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..io.atomic import atomic_open
from ..io.reading import MAX_CSV_BYTES, MAX_CSV_LINE, read_text, short
from .measurements import Measurements

__all__ = ["csv_from_text", "read_csv", "samples_from_table", "write_csv"]

_UNIT = re.compile(
    r"^\s*(?P<name>[a-z_]+?)\s*(?:_|\s|\[|\()\s*(?P<unit>deg|degs|degree|degrees|rad|rads|"
    r"radian|radians)\s*[\])]?\s*$",
    re.IGNORECASE,
)
_ANGLE_ALIASES = {
    "theta_i": "theta_i",
    "theta_r": "theta_r",
    "theta_o": "theta_r",
    "delta_phi": "delta_phi",
    "phi_d": "delta_phi",
    "dphi": "delta_phi",  # the explorer's old name
    "phi_i": "phi_i",
    "phi_r": "phi_r",
    "phi_o": "phi_r",
}
_CHANNELS = ("r", "g", "b")
_CHANNEL_ALIASES = {"r": "r", "red": "r", "g": "g", "green": "g", "b": "b", "blue": "b"}


class _Cell:
    """Where a value came from, for messages: 'file line 7, column "brdf"'."""

    def __init__(self, source: str, rows: Sequence[str]):
        self.source, self.rows = source, rows

    def at(self, k: int, column: str) -> str:
        return f"{self.source}{self.rows[k]}, column {column!r}"


def _classify(header: Sequence[str]) -> dict[str, tuple[str, str]]:
    """Map each raw column name to (role, unit): roles theta_i…, brdf, brdf_r…, irradiance."""
    roles: dict[str, tuple[str, str]] = {}
    for raw in header:
        name = raw.strip()
        low = name.lower()
        base = re.sub(r"\s*[\[(].*[\])]\s*$", "", low).strip()  # drop "[1/sr]"
        m = _UNIT.match(low)
        if m and m.group("name").rstrip("_") in _ANGLE_ALIASES:
            role = _ANGLE_ALIASES[m.group("name").rstrip("_")]
            roles[raw] = (role, "deg" if m.group("unit").lower().startswith("deg") else "rad")
            continue
        if base in _ANGLE_ALIASES:
            raise ParameterError(
                f"column {name!r} must state its unit: {base}_deg or {base}_rad (or '{base} [deg]')"
            )
        for kind in ("brdf", "radiance"):
            if base == kind:
                roles[raw] = (kind, "")
            elif base.startswith(kind + "_") and base[len(kind) + 1 :] in _CHANNEL_ALIASES:
                roles[raw] = (f"{kind}_{_CHANNEL_ALIASES[base[len(kind) + 1 :]]}", "")
        if base in ("irradiance", "e0"):
            roles[raw] = ("irradiance", "")
    seen: dict[str, str] = {}
    for raw, (role, _) in roles.items():
        if role in seen:
            raise ParameterError(f"columns {seen[role]!r} and {raw!r} both give {role}")
        seen[role] = raw
    return roles


def _to_float(text: Any, where: str) -> float:
    if text is None:
        raise ParameterError(f"{where}: missing value")
    if isinstance(text, str):
        if not text.strip():
            raise ParameterError(f"{where}: missing value")
        try:
            val = float(text)
        except ValueError:
            raise ParameterError(f"{where}: not a number ({text.strip()!r})") from None
    else:
        try:
            val = float(text)
        except (TypeError, ValueError):
            raise ParameterError(f"{where}: not a number ({text!r})") from None
    if not math.isfinite(val):
        raise ParameterError(f"{where}: missing or non-finite value ({val})")
    return val


class _Table:
    """A parsed table's columns by role (:func:`_classify`), read as numbers on demand."""

    def __init__(self, columns: Mapping[str, Sequence[Any]], cell: _Cell, source: str):
        roles = _classify(list(columns))
        self.by_role = {role: (raw, unit) for raw, (role, unit) in roles.items()}
        self.columns, self.cell, self.source = columns, cell, source

    def __contains__(self, role: str) -> bool:
        return role in self.by_role

    def column(self, role: str) -> tuple[np.ndarray, str, str]:
        """(values, the column's name, its unit)."""
        raw, unit = self.by_role[role]
        vals = self.columns[raw]
        n = len(self.cell.rows)
        return np.array([_to_float(vals[k], self.cell.at(k, raw)) for k in range(n)]), raw, unit


def _angles(t: _Table) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """θi, θr (in [0, π/2]) and Δφ in radians, from whichever columns the table has."""
    for need in ("theta_i", "theta_r"):
        if need not in t:
            raise ParameterError(
                f"{t.source}: no {need} column (e.g. '{need}_deg' or '{need}_rad')"
            )
    angles = {}
    for role in ("theta_i", "theta_r"):
        vals, raw, unit = t.column(role)
        top = 90.0 if unit == "deg" else math.pi / 2
        bad = np.flatnonzero((vals < 0) | (vals > top * (1 + 1e-12)))
        if bad.size:
            k = bad[0]
            rng = "[0, 90] degrees" if unit == "deg" else "[0, π/2] radians"
            raise ParameterError(f"{t.cell.at(k, raw)}: angle {vals[k]:g} out of range {rng}")
        angles[role] = np.minimum(np.radians(vals) if unit == "deg" else vals, math.pi / 2)
    delta_phi = None
    if "phi_i" in t and "phi_r" in t:
        pi_, _, ui = t.column("phi_i")
        pr, _, ur = t.column("phi_r")
        delta_phi = (np.radians(pr) if ur == "deg" else pr) - (
            np.radians(pi_) if ui == "deg" else pi_
        )
    if "delta_phi" in t:
        vals, raw, unit = t.column("delta_phi")
        given = np.radians(vals) if unit == "deg" else vals
        if delta_phi is not None:  # both ways of giving the azimuth: they must agree
            off = np.abs(np.angle(np.exp(1j * (given - delta_phi))))
            bad = np.flatnonzero(off > 1e-6)
            if bad.size:
                k = bad[0]
                raise ParameterError(
                    f"{t.cell.at(k, raw)}: contradicts phi_r - phi_i "
                    f"({math.degrees(delta_phi[k]):.6g}° against {math.degrees(given[k]):.6g}°); "
                    "give one of them"
                )
        delta_phi = given
    if delta_phi is None:
        raise ParameterError(
            f"{t.source}: no azimuth: give delta_phi, or phi_i and phi_r (with units)"
        )
    return angles["theta_i"], angles["theta_r"], delta_phi


def _values(t: _Table) -> tuple[np.ndarray, str]:
    """The values (N,) or (N, 3) and their kind, "brdf" or "radiance"; none negative."""
    kinds = [k for k in ("brdf", "radiance") if k in t or f"{k}_r" in t]
    if len(kinds) != 1:
        raise ParameterError(
            f"{t.source}: give exactly one kind of value column: 'brdf' (1/sr) or 'radiance' "
            "(or brdf_r, brdf_g, brdf_b …)"
        )
    kind = kinds[0]
    if kind in t:
        roles_v = [kind]
    else:
        roles_v = [f"{kind}_{c}" for c in _CHANNELS]
        missing = [r for r in roles_v if r not in t]
        if missing:
            raise ParameterError(f"{t.source}: colour columns {', '.join(missing)} missing")
    values = []
    for role in roles_v:
        vals, raw, _ = t.column(role)
        bad = np.flatnonzero(vals < 0)
        if bad.size:
            raise ParameterError(f"{t.cell.at(bad[0], raw)}: negative value {vals[bad[0]]:g}")
        values.append(vals)
    return (values[0] if len(values) == 1 else np.stack(values, axis=-1)), kind


def _irradiance(t: _Table, kind: str, irradiance: float | None) -> Any:
    """E0 of radiance values: a column, else the header's or the caller's value."""
    if kind != "radiance":
        if "irradiance" in t:
            raise ParameterError(
                f"{t.source}: an irradiance column only makes sense with radiance values"
            )
        return None
    if "irradiance" in t:
        e0, raw, _ = t.column("irradiance")
        bad = np.flatnonzero(e0 <= 0)
        if bad.size:
            raise ParameterError(
                f"{t.cell.at(bad[0], raw)}: irradiance must be > 0 (got {e0[bad[0]]:g})"
            )
        return e0
    if irradiance is not None:
        if not irradiance > 0:
            raise ParameterError(f"irradiance must be > 0 (got {irradiance})")
        return irradiance
    raise ParameterError(
        f"{t.source}: radiance values need the irradiance: an 'irradiance' column, "
        "a header line '# irradiance = E0', or irradiance=…"
    )


def _build(
    columns: Mapping[str, Sequence[Any]], cell: _Cell, irradiance: float | None, source: str
) -> Measurements:
    t = _Table(columns, cell, source)
    theta_i, theta_r, delta_phi = _angles(t)
    value, kind = _values(t)
    e0 = _irradiance(t, kind, irradiance)
    return Measurements.from_angles(
        theta_i, theta_r, delta_phi, value, irradiance=e0, source=source
    )


def read_csv(path: str | os.PathLike[str], *, irradiance: float | None = None) -> Measurements:
    """Read BRDF (or radiance) samples from a CSV file (format in the module docstring).

    Parameters
    ----------
    path : path-like
        The CSV file (comma, semicolon or tab separated).
    irradiance : float, optional
        E0 for radiance values when the file gives none.

    Returns
    -------
    Measurements

    Raises
    ------
    ValueError
        Naming the line and column of a missing value, an angle out of range, a negative
        value, or the missing column.
    """
    path = os.fspath(path)
    text = read_text(path, MAX_CSV_BYTES, "CSV file")
    return csv_from_text(text, name=os.path.basename(path), irradiance=irradiance)


def csv_from_text(
    text: str, *, name: str = "data.csv", irradiance: float | None = None
) -> Measurements:
    """BRDF samples from the text of a CSV file (e.g. an upload), as :func:`read_csv` reads
    a file; ``name`` is used in messages and as the source.

    Raises
    ------
    ValueError
        As :func:`read_csv`.
    """
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = text.splitlines()
    header: list[str] | None = None
    rows: list[list[str]] = []
    line_no: list[str] = []
    dialect: Any = None
    for k, line in enumerate(lines, start=1):
        stripped = line.strip()
        if not stripped:
            continue
        if stripped.startswith("#"):
            m = re.match(r"#\s*(irradiance|e0)\s*[=:]\s*(\S+)", stripped, re.IGNORECASE)
            if m and irradiance is None:
                irradiance = _to_float(m.group(2), f"{name} line {k}, header 'irradiance'")
            continue
        if dialect is None:
            delim = max((",", ";", "\t"), key=stripped.count)
            dialect = delim if stripped.count(delim) else ","
        if len(line) > MAX_CSV_LINE:
            raise ParameterError(
                f"{name} line {k}: {len(line)} characters; a line may have at most "
                f"{MAX_CSV_LINE}"
            )
        cells = next(csv.reader([line], delimiter=dialect))
        if header is None:
            header = [c.strip() for c in cells]
            continue
        if len(cells) != len(header):
            raise ParameterError(f"{name} line {k}: {len(cells)} values for {len(header)} columns")
        rows.append(cells)
        line_no.append(f" line {k}")
    if header is None:
        raise ParameterError(f"{name}: no header line (column names)")
    if not rows:
        raise ParameterError(f"{name}: no data rows")
    twice = sorted({h for h in header if header.count(h) > 1})
    if twice:
        raise ParameterError(
            f"{name}: column {short(twice[0])} appears more than once; each column once"
        )
    columns = {h: [r[j] for r in rows] for j, h in enumerate(header)}
    return _build(columns, _Cell(name, line_no), irradiance, name)


def samples_from_table(
    table: Any, *, irradiance: float | None = None, source: str = "table"
) -> Measurements:
    """Samples from a table with the CSV column names: a dict of columns, a NumPy structured
    array or a pandas DataFrame. Errors name the row (0-based) and column."""
    if hasattr(table, "dtype") and getattr(table.dtype, "names", None):
        columns = {nm: list(table[nm]) for nm in table.dtype.names}
    elif hasattr(table, "columns") and hasattr(table, "__getitem__"):
        columns = {str(nm): list(table[nm]) for nm in table.columns}
    elif isinstance(table, Mapping):
        columns = {str(k): list(np.atleast_1d(v)) for k, v in table.items()}
    else:
        raise ParameterError("table must be a dict of columns, a structured array or a DataFrame")
    lengths = {len(v) for v in columns.values()}
    if len(lengths) != 1:
        raise ParameterError(f"table columns have different lengths: {sorted(lengths)}")
    n = lengths.pop()
    if n == 0:
        raise ParameterError("table has no rows")
    return _build(columns, _Cell(source, [f" row {k}" for k in range(n)]), irradiance, source)


def write_csv(path: str | os.PathLike[str], data: Measurements) -> None:
    """Write samples as CSV (angles in degrees, BRDF values), atomically."""
    ti, tr, dp = data.angles()
    f = data.brdf_value
    cols = ["theta_i_deg", "theta_r_deg", "delta_phi_deg"]
    cols += ["brdf"] if f.ndim == 1 else [f"brdf_{c}" for c in _CHANNELS[: f.shape[1]]]
    table = np.column_stack([np.degrees(ti), np.degrees(tr), np.degrees(dp), f])
    with atomic_open(path, "w") as fh:
        np.savetxt(fh, table, delimiter=",", header=",".join(cols), comments="", fmt="%.10g")
