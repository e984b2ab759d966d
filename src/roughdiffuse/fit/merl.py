"""The MERL measured-BRDF binary format: read, write, look up, turn into samples.

Format (Matusik, Pfister, Brand, McMillan, "A data-driven reflectance model", SIGGRAPH 2003;
the database's reader ``BRDFRead.cpp``): a header of three little-endian int32 dimensions
(90, 90, 180), then three blocks of 90·90·180 little-endian float64, red, green and blue,
which multiplied by 1/1500, 1.15/1500 and 1.66/1500 give the BRDF in 1/sr. The cells are
indexed in Rusinkiewicz's half/difference angles (θh, θd, φd) — flat index
``iφ + 180 iθd + 180·90 iθh`` with

* iθh = ⌊√(θh/(π/2)) · 90⌋ (dense near the specular peak),
* iθd = ⌊θd/(π/2) · 90⌋,
* iφ = ⌊φd/π · 180⌋ with φd folded into [0, π) by reciprocity (φd → φd + π),

each clamped to its range. Negative entries mark missing samples.

A file written here from a model holds, in each cell, the model at the cell's centre in index
space (θh = ((i + ½)/90)² π/2, θd = (j + ½)/90 · π/2, φd = (k + ½)/180 · π), and −1 where a
direction of that centre is below the horizon; :meth:`MERLBRDF.to_measurements` returns
the samples at those same centres, so a model written and read back fits exactly.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import ParameterError
from ..io.atomic import atomic_open
from ..models import Model
from .measurements import Measurements

__all__ = [
    "MERL_FILE_SIZE",
    "MERL_SCALE",
    "MERL_SHAPE",
    "MERLBRDF",
    "directions_from_half_diff",
    "half_diff_from_directions",
    "merl_cell_index",
    "merl_from_bytes",
    "read_merl",
    "write_merl",
]

MERL_SHAPE = (90, 90, 180)
"""Cells along θh, θd and φd."""

MERL_SCALE = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])
"""Factors from the stored numbers to the BRDF (1/sr), red, green, blue."""

_HEADER = 3 * 4
_N = MERL_SHAPE[0] * MERL_SHAPE[1] * MERL_SHAPE[2]

MERL_FILE_SIZE = _HEADER + 3 * _N * 8
"""Bytes of a MERL file: the 12-byte header and three blocks of float64 (34 992 012)."""


def _rot_y(x: np.ndarray, y: np.ndarray, z: np.ndarray, a: Any) -> tuple[np.ndarray, ...]:
    c, s = np.cos(a), np.sin(a)
    return x * c + z * s, y, z * c - x * s


def _rot_z(x: np.ndarray, y: np.ndarray, z: np.ndarray, a: Any) -> tuple[np.ndarray, ...]:
    c, s = np.cos(a), np.sin(a)
    return x * c - y * s, x * s + y * c, z


def half_diff_from_directions(wi: Any, wo: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(θh, θd, φd) of local-frame directions (Rusinkiewicz 1998; MERL's
    ``std_coords_to_half_diff_coords``); φd in (−π, π], not yet folded."""
    wi = np.asarray(wi, dtype=np.float64)
    wo = np.asarray(wo, dtype=np.float64)
    wi = wi / np.linalg.norm(wi, axis=-1, keepdims=True)
    wo = wo / np.linalg.norm(wo, axis=-1, keepdims=True)
    h = wi + wo
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    theta_h = np.arccos(np.clip(h[..., 2], -1.0, 1.0))
    phi_h = np.arctan2(h[..., 1], h[..., 0])
    d = _rot_z(wi[..., 0], wi[..., 1], wi[..., 2], -phi_h)
    d = _rot_y(*d, -theta_h)
    theta_d = np.arccos(np.clip(d[2], -1.0, 1.0))
    phi_d = np.arctan2(d[1], d[0])
    return theta_h, theta_d, phi_d


def directions_from_half_diff(
    theta_h: Any, theta_d: Any, phi_d: Any, phi_h: Any = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Local-frame ``wi`` (to the light) and ``wo`` (to the viewer), shape (..., 3), from the
    half/difference angles: wi = R_z(φh) R_y(θh) d, wo = 2 (wi·h) h − wi."""
    th, td, pd, ph = np.broadcast_arrays(
        *(np.asarray(a, dtype=np.float64) for a in (theta_h, theta_d, phi_d, phi_h))
    )
    d = (np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td))
    wi = np.stack(_rot_z(*_rot_y(*d, th), ph), axis=-1)
    h = np.stack(_rot_z(np.sin(th), np.zeros_like(th), np.cos(th), ph), axis=-1)
    wo = 2.0 * np.sum(wi * h, axis=-1, keepdims=True) * h - wi
    return wi, wo


def merl_cell_index(theta_h: Any, theta_d: Any, phi_d: Any) -> tuple[np.ndarray, ...]:
    """(iθh, iθd, iφ) cell indices of MERL's ``BRDFRead.cpp`` (φd folded by reciprocity)."""
    th = np.asarray(theta_h, dtype=np.float64)
    td = np.asarray(theta_d, dtype=np.float64)
    pd = np.asarray(phi_d, dtype=np.float64)
    nh, nd, npd = MERL_SHAPE
    ih = np.where(th <= 0, 0.0, np.sqrt(np.maximum(th, 0.0) / (math.pi / 2) * nh * nh))
    ih = np.clip(ih.astype(np.int64), 0, nh - 1)
    idd = np.clip((td / (math.pi / 2) * nd).astype(np.int64), 0, nd - 1)
    pd = np.where(pd < 0, pd + math.pi, pd)
    ip = np.clip((pd / math.pi * npd).astype(np.int64), 0, npd - 1)
    return ih, idd, ip


def _cell_centres() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    nh, nd, npd = MERL_SHAPE
    th = ((np.arange(nh) + 0.5) / nh) ** 2 * (math.pi / 2)
    td = (np.arange(nd) + 0.5) / nd * (math.pi / 2)
    pd = (np.arange(npd) + 0.5) / npd * math.pi
    return np.meshgrid(th, td, pd, indexing="ij")


@dataclass(frozen=True)
class MERLBRDF:
    """A MERL-format measured BRDF.

    Parameters
    ----------
    raw : array (3, 90, 90, 180) float64
        The stored numbers (red, green, blue; θh, θd, φd), negative where missing.
    source : str
        File name, for reports.
    """

    raw: np.ndarray = field(repr=False)
    source: str = ""

    def __post_init__(self) -> None:
        raw = np.asarray(self.raw, dtype=np.float64)
        if raw.shape != (3, *MERL_SHAPE):
            raise ParameterError(f"raw must have shape (3, 90, 90, 180) (got {raw.shape})")
        _check_finite(raw, self.source or "raw")
        object.__setattr__(self, "raw", raw)

    @property
    def valid(self) -> np.ndarray:
        """(3, 90, 90, 180) bool: True where the sample is present (stored value ≥ 0)."""
        return self.raw >= 0

    @property
    def brdf(self) -> np.ndarray:
        """(3, 90, 90, 180) BRDF in 1/sr (stored × scale), NaN where missing."""
        return np.where(self.valid, self.raw * MERL_SCALE[:, None, None, None], np.nan)

    @classmethod
    def from_brdf(cls, brdf: Any, source: str = "") -> MERLBRDF:
        """From BRDF values (3, 90, 90, 180) in 1/sr; NaN or negative entries are missing."""
        b = np.asarray(brdf, dtype=np.float64)
        if b.shape != (3, *MERL_SHAPE):
            raise ParameterError(f"brdf must have shape (3, 90, 90, 180) (got {b.shape})")
        if np.any(np.isinf(b)):
            raise ParameterError("brdf must not contain infinite values")
        missing = np.isnan(b) | (b < 0)
        raw = np.where(missing, -1.0, np.where(missing, 0.0, b) / MERL_SCALE[:, None, None, None])
        return cls(raw, source)

    @classmethod
    def from_model(cls, model: Model) -> MERLBRDF:
        """Tabulate a model at the cell centres (−1 where a direction is below the horizon).

        A one-channel model gives the same BRDF in the three channels.
        """
        wi, wo = directions_from_half_diff(*_cell_centres())
        above = (wi[..., 2] > 0) & (wo[..., 2] > 0)
        f = np.asarray(model.brdf(wi[above], wo[above]), dtype=np.float64)
        if f.ndim == 1:
            f = np.stack([f, f, f], axis=-1)
        if f.shape[-1] != 3:
            raise ParameterError(f"model must have 1 or 3 channels (got {f.shape[-1]})")
        out = np.full((3, *MERL_SHAPE), np.nan)
        for c in range(3):
            out[c][above] = f[:, c]
        return cls.from_brdf(out, source=f"{type(model).__name__} tabulated")

    def lookup(self, wi: Any, wo: Any) -> np.ndarray:
        """BRDF (1/sr) at local-frame directions, shape (..., 3) (nearest cell, as MERL's
        ``lookup_brdf_val``); NaN where the file marks the sample missing."""
        ih, idd, ip = merl_cell_index(*half_diff_from_directions(wi, wo))
        return np.moveaxis(self.brdf[:, ih, idd, ip], 0, -1)

    def to_measurements(self, max_samples: int | None = None, seed: int = 0) -> Measurements:
        """The present samples at their cell centres (both directions above the horizon).

        Parameters
        ----------
        max_samples : int, optional
            Keep a random subset of at most this many cells (all when None).
        seed : int
            Seed of that subset.
        """
        wi, wo = directions_from_half_diff(*_cell_centres())
        use = (wi[..., 2] > 1e-9) & (wo[..., 2] > 1e-9) & np.all(self.valid, axis=0)
        idx = np.flatnonzero(use)
        if idx.size == 0:
            raise ParameterError(
                f"{self.source or 'MERL data'}: no sample present above the horizon"
            )
        if max_samples is not None and idx.size > max_samples:
            idx = np.sort(np.random.default_rng(seed).choice(idx, max_samples, replace=False))
        value = self.brdf.reshape(3, -1)[:, idx].T
        return Measurements.from_directions(
            wi.reshape(-1, 3)[idx],
            wo.reshape(-1, 3)[idx],
            value,
            source=self.source or "MERL data",
        )


def _check_finite(raw: np.ndarray, name: str) -> None:
    bad = ~np.isfinite(raw)
    if np.any(bad):
        c, ih, idd, ip = (int(v[0]) for v in np.nonzero(bad))
        raise ParameterError(
            f"{name}: {int(bad.sum())} entries are NaN or infinite (first: channel "
            f"{'RGB'[c]}, θh index {ih}, θd index {idd}, φd index {ip}); a MERL file marks "
            "missing samples with negative values"
        )


def read_merl(path: str | os.PathLike[str]) -> MERLBRDF:
    """Read a MERL ``.binary`` file.

    Raises
    ------
    ValueError
        If the file is shorter or longer than its header says (truncated), the dimensions
        are not 90 × 90 × 180, or an entry is NaN or infinite.
    """
    from ..io.reading import read_bytes

    path = os.fspath(path)
    # up to 4 MERL files' size is read, so a file of other dimensions or with extra bytes
    # gets the format's own message (merl_from_bytes), not only a size
    blob = read_bytes(path, 4 * MERL_FILE_SIZE, "MERL file")
    return merl_from_bytes(blob, os.path.basename(path))


def merl_from_bytes(blob: bytes, name: str = "MERL data") -> MERLBRDF:
    """A MERL ``.binary`` file's content (e.g. an upload), checked as :func:`read_merl` checks
    a file; ``name`` is used in messages and as the source.

    Raises
    ------
    ValueError
        If the content is shorter or longer than its header says, the dimensions are not
        90 × 90 × 180, or an entry is NaN or infinite.
    """
    if len(blob) < _HEADER:
        raise ParameterError(f"{name}: truncated MERL file ({len(blob)} bytes, no 12-byte header)")
    dims = tuple(int(d) for d in np.frombuffer(blob[:_HEADER], dtype="<i4"))
    if dims != MERL_SHAPE:
        raise ParameterError(
            f"{name}: MERL dimensions must be 90 x 90 x 180 (θh, θd, φd); the header says "
            f"{dims[0]} x {dims[1]} x {dims[2]}"
        )
    expected = MERL_FILE_SIZE
    if len(blob) != expected:
        what = "truncated" if len(blob) < expected else "too long"
        raise ParameterError(
            f"{name}: {what} MERL file: {len(blob)} bytes, expected {expected} "
            "(12-byte header + 3 x 90 x 90 x 180 float64)"
        )
    raw = np.frombuffer(blob, dtype="<f8", offset=_HEADER).reshape(3, *MERL_SHAPE)
    raw = raw.astype(np.float64)
    _check_finite(raw, name)
    return MERLBRDF(raw, source=name)


def write_merl(path: str | os.PathLike[str], brdf: MERLBRDF) -> None:
    """Write a MERL ``.binary`` file (atomically: temporary file, then rename)."""
    if not isinstance(brdf, MERLBRDF):
        raise ParameterError(f"brdf must be a MERLBRDF (got {type(brdf).__name__})")
    with atomic_open(path, "wb") as fh:
        fh.write(np.asarray(MERL_SHAPE, dtype="<i4").tobytes())
        fh.write(np.ascontiguousarray(brdf.raw, dtype="<f8").tobytes())
