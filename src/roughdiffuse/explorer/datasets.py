"""Measured data on the explorer's server: uploads, a bounded store, slices, fits.

The page uploads a MERL ``.binary`` file (Matusik, Pfister, Brand and McMillan, "A
data-driven reflectance model", SIGGRAPH 2003) or a CSV of BRDF samples; the server parses it
with :mod:`roughdiffuse.fit` (:func:`~roughdiffuse.fit.merl_from_bytes`,
:func:`~roughdiffuse.fit.csv_from_text`: the one reader of each format) and keeps it in
memory, in a store of at most :data:`DATASETS_KEPT` datasets (least recently used dropped
first; nothing is written to disk). The page then asks for slices (MERL: the nearest cell,
as MERL's ``lookup_brdf_val``) and for fits of one model (:func:`roughdiffuse.fit.fit`) or a
ranking by BIC (:func:`roughdiffuse.fit.compare_models`).

What a request may cost is bounded: an upload by :data:`MAX_MERL_BYTES` or
:data:`MAX_CSV_BYTES`, a fit by :data:`FIT_SAMPLES` samples (a fixed random subset of a
larger dataset, seed 0) and by one fit at a time (:data:`FIT_LOCK`: a second one is refused
at once, not queued).
"""

from __future__ import annotations

import itertools
import math
import threading
from collections import OrderedDict
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .._validate import ParameterError

__all__ = [
    "DATASETS_KEPT",
    "FIT_LOCK",
    "FIT_SAMPLES",
    "MAX_CSV_BYTES",
    "MAX_MERL_BYTES",
    "RANK_MODELS_AT_ONCE",
    "Busy",
    "Dataset",
    "DatasetStore",
    "STORE",
    "fit_model",
    "parse_upload",
    "rank_models",
    "slice_points",
]

MAX_MERL_BYTES = 36_000_000
"""Largest MERL upload accepted (bytes): a MERL file is 34 992 012 bytes
(:data:`roughdiffuse.fit.merl.MERL_FILE_SIZE`); anything larger is refused unread (413)."""

MAX_CSV_BYTES = 4_000_000
"""Largest CSV upload accepted (bytes): about 100 000 samples."""

DATASETS_KEPT = 4
"""Datasets kept in memory at once (a MERL dataset is about 35 MB); the least recently used
goes first."""

FIT_SAMPLES = 4000
"""Samples a fit uses at most: a larger dataset (a MERL file has about 1.3 million cells
with both directions above the horizon) is fitted on a random subset of this many (seed 0,
the same subset every time), with its three channels: 12 000 residuals. Model A's fit takes
a few seconds (the first one also compiles)."""

RANK_MODELS_AT_ONCE = 4
"""Models one ranking request may fit (the page asks for one at a time, to show progress; a
model ranked per choice, ``coated``, is fitted once over each of its bases in its request)."""

FIT_LOCK = threading.Lock()
"""One fit at a time (the machine may have 2 cores): a second request gets :class:`Busy`."""

SLICE_THETA_R = tuple(float(t) for t in range(-89, 90))
"""Viewing angles (degrees, signed: > 0 at Δφ, < 0 at Δφ + 180°) of a MERL slice."""


class Busy(Exception):
    """Another fit is running; the request is refused rather than queued."""


@dataclass
class Dataset:
    """One uploaded dataset.

    Attributes
    ----------
    id : str
        Key in the store (``d1``, ``d2``, …).
    name, kind : str
        File name and ``"merl"`` or ``"csv"``.
    data : Measurements
        What a fit uses (at most :data:`FIT_SAMPLES` samples).
    total : int
        Samples in the whole dataset.
    merl : MERLBRDF or None
        The MERL table (for slices), when ``kind == "merl"``.
    theta_i : list of float
        The incidence angles (degrees) the page's selector steps through.
    """

    id: str
    name: str
    kind: str
    data: Any
    total: int
    merl: Any = None
    theta_i: list[float] = field(default_factory=list)

    def summary(self) -> dict[str, Any]:
        """What the page is told about the dataset."""
        from ..fit.compare import CANDIDATES

        return {
            "id": self.id,
            "name": self.name,
            "kind": self.kind,
            "samples": self.total,
            "fit_samples": int(self.data.size),
            "channels": int(self.data.channels),
            "theta_i": self.theta_i,
            "candidates": list(CANDIDATES),
        }


class DatasetStore:
    """At most ``maxsize`` datasets in memory, least recently used dropped first."""

    def __init__(self, maxsize: int = DATASETS_KEPT) -> None:
        self.maxsize = maxsize
        self._items: OrderedDict[str, Dataset] = OrderedDict()
        self._lock = threading.Lock()
        self._ids = itertools.count(1)

    def __len__(self) -> int:
        return len(self._items)

    def new_id(self) -> str:
        """A fresh key."""
        return f"d{next(self._ids)}"

    def add(self, ds: Dataset) -> None:
        """Keep ``ds``, dropping the least recently used datasets beyond ``maxsize``."""
        with self._lock:
            self._items[ds.id] = ds
            self._items.move_to_end(ds.id)
            while len(self._items) > self.maxsize:
                self._items.popitem(last=False)

    def get(self, key: str) -> Dataset:
        """The dataset ``key``; ``KeyError`` when it was never uploaded or was dropped."""
        with self._lock:
            ds = self._items[key]
            self._items.move_to_end(key)
            return ds


STORE = DatasetStore()
"""The server's datasets."""


def _subset(data: Any, n: int) -> Any:
    if data.size <= n:
        return data
    idx = np.sort(np.random.default_rng(0).choice(data.size, n, replace=False))
    return data.subset(idx)


def parse_upload(kind: str, name: str, body: bytes, store: DatasetStore = STORE) -> Dataset:
    """Parse an upload and keep it in ``store``.

    Parameters
    ----------
    kind : {"merl", "csv"}
    name : str
        The file's name (for messages).
    body : bytes
        The file's content.

    Raises
    ------
    ValueError
        Naming what is wrong: the kind, the size, the MERL header, a NaN or infinite entry,
        the CSV line and column.
    """
    from ..fit.csv_samples import csv_from_text
    from ..fit.merl import MERL_FILE_SIZE, merl_from_bytes

    name = (name or "data")[:200]
    if kind == "merl":
        if len(body) != MERL_FILE_SIZE:
            raise ParameterError(
                f"{name}: not a MERL file: {len(body)} bytes, a MERL .binary file has "
                f"{MERL_FILE_SIZE} (12-byte header + 3 x 90 x 90 x 180 float64)"
            )
        merl = merl_from_bytes(body, name)
        data = merl.to_measurements(max_samples=FIT_SAMPLES)
        present = np.all(merl.valid, axis=0).sum()
        ds = Dataset(
            store.new_id(),
            name,
            "merl",
            data,
            int(present),
            merl,
            [float(t) for t in range(0, 90)],
        )
    elif kind == "csv":
        try:
            text = body.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise ParameterError(f"{name}: not a text (UTF-8) CSV file ({exc.reason})") from None
        full = csv_from_text(text, name=name)
        ti = np.degrees(np.arccos(np.clip(full.mu_i, -1.0, 1.0)))
        ds = Dataset(
            store.new_id(),
            name,
            "csv",
            _subset(full, FIT_SAMPLES),
            int(full.size),
            None,
            sorted({round(float(t), 1) for t in ti}),
        )
    else:
        raise ParameterError(f"format must be 'merl' or 'csv' (got {kind!r})")
    store.add(ds)
    return ds


def slice_points(ds: Dataset, theta_i_deg: float, delta_phi_deg: float) -> dict[str, Any]:
    """BRDF of a MERL dataset along a slice: θi fixed, the viewing direction at azimuth Δφ
    from the light (θr > 0) and at Δφ + 180° (θr < 0), θr = −89°, …, 89°; each value from
    the nearest cell (:func:`roughdiffuse.fit.merl_cell_index`), ``None`` where missing."""
    from ..fit.merl import MERL_SCALE, half_diff_from_directions, merl_cell_index

    if ds.merl is None:
        raise ParameterError(f"{ds.name}: slices are computed on the page for CSV data")
    if not (math.isfinite(theta_i_deg) and 0.0 <= theta_i_deg < 90.0):
        raise ParameterError(f"theta_i must be in [0, 90) degrees (got {theta_i_deg!r})")
    if not (math.isfinite(delta_phi_deg) and -360.0 <= delta_phi_deg <= 360.0):
        raise ParameterError(
            f"delta_phi must be in [-360, 360] degrees (got {delta_phi_deg!r})"
        )
    tr = np.asarray(SLICE_THETA_R)
    ti = math.radians(theta_i_deg)
    phi = np.where(tr >= 0, math.radians(delta_phi_deg), math.radians(delta_phi_deg) + math.pi)
    a = np.radians(np.abs(tr))
    wi = np.broadcast_to([math.sin(ti), 0.0, math.cos(ti)], (tr.size, 3))
    wo = np.stack([np.sin(a) * np.cos(phi), np.sin(a) * np.sin(phi), np.cos(a)], axis=-1)
    ih, idd, ip = merl_cell_index(*half_diff_from_directions(wi, wo))
    raw = ds.merl.raw[:, ih, idd, ip].T  # (N, 3)
    brdf = raw * MERL_SCALE
    values = [
        [float(v) for v in row] if np.all(r >= 0) else None
        for row, r in zip(brdf, raw, strict=True)
    ]
    return {
        "theta_r": list(SLICE_THETA_R),
        "brdf": values,
        "theta_i": theta_i_deg,
        "delta_phi": delta_phi_deg,
    }


def _model_id(model: Any) -> str:
    from ..fit.compare import CANDIDATES

    if not isinstance(model, str) or model not in CANDIDATES:
        raise ParameterError(f"model must be one of {', '.join(CANDIDATES)} (got {model!r})")
    return model


def fit_model(ds: Dataset, model: Any, choices: Any = None) -> dict[str, Any]:
    """Fit one registry model to the dataset (:func:`roughdiffuse.fit.fit` with its default,
    relative noise, as ``roughdiffuse fit``; the model's declared parameters and bounds, as
    :func:`roughdiffuse.fit.compare.candidate` gives them for ``choices``, the values of the
    slot's menus: Coated over the base chosen, as ``--param base=eon``). The result is
    :func:`roughdiffuse.fit.summary.result_json`: no standard error at a bound or where it is
    not determined. Raises :class:`Busy` when another fit runs."""
    import warnings

    from ..fit.compare import candidate
    from ..fit.least_squares import DegenerateDataWarning, NoiseModelWarning, fit
    from ..fit.summary import result_json

    model_id = _model_id(model)
    if choices is not None and not (
        isinstance(choices, dict)
        and all(isinstance(k, str) and isinstance(v, str) for k, v in choices.items())
    ):
        raise ParameterError(f"choices must map parameter names to choices (got {choices!r})")
    c = candidate(model_id, choices)  # a choice the model does not have: refused by name
    if not FIT_LOCK.acquire(blocking=False):
        raise Busy("a fit is already running; try again when it has finished")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegenerateDataWarning)
            warnings.simplefilter("ignore", NoiseModelWarning)  # said in r.warnings
            r = fit(c.model, ds.data, c.params, c.bounds, fixed=c.fixed)
    finally:
        FIT_LOCK.release()
    out = result_json(model_id, r, choices)
    out.update(dataset=ds.id, fit_samples=int(ds.data.size), samples=ds.total)
    return out


def rank_models(ds: Dataset, models: Any) -> dict[str, Any]:
    """Fit ``models`` (registry ids, at most :data:`RANK_MODELS_AT_ONCE`) and rank them by
    BIC with :func:`roughdiffuse.fit.compare_models` (relative noise, its default, as
    ``roughdiffuse fit --compare``): one row per fit, ``coated`` one per base (each row's
    ``choices`` and ``label`` say which). Raises :class:`Busy` when another fit runs."""
    from ..fit.compare import compare_models
    from ..fit.summary import result_json

    if not isinstance(models, list) or not 1 <= len(models) <= RANK_MODELS_AT_ONCE:
        raise ParameterError(
            f"models must be a list of 1 to {RANK_MODELS_AT_ONCE} model ids (got {models!r})"
        )
    ids = [_model_id(m) for m in models]
    if not FIT_LOCK.acquire(blocking=False):
        raise Busy("a fit is already running; try again when it has finished")
    try:
        cmp = compare_models(ds.data, ids)
    finally:
        FIT_LOCK.release()
    return {
        "dataset": ds.id,
        "fit_samples": int(ds.data.size),
        "ranking": [
            result_json(n, r, ch)
            for n, ch, r in zip(cmp.ids, cmp.choices, cmp.results, strict=True)
        ],
    }
