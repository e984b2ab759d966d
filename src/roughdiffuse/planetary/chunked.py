"""Photometric correction of image files of any size, chunk by chunk, through ``dask.array``.

The image and its backplanes are never read whole: each chunk (a window of lines × samples)
is read from the files (:class:`~roughdiffuse.planetary.rasters.RasterPlane`), corrected by
:func:`~roughdiffuse.planetary.correct.normalize` and written to its window of the output,
which is written whole or not at all. Peak memory is a chunk per worker thread (about
:data:`BYTES_PER_PIXEL` bytes per pixel of a chunk) and the float32 results of two chunks per
thread, not the image.

The chunks run on Dask's threaded scheduler on this machine, or on a Dask cluster
(``scheduler``: a :class:`dask.distributed.Client` or its address). Each chunk's pixels are
computed by the same NumPy code from the same inputs wherever it runs, so the output is the
same bit for bit; the workers must see the files at the same paths.
"""

from __future__ import annotations

import dataclasses
import math
import os
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError
from .correct import MATCH, REFERENCE, THRESH, normalize
from .rasters import NULL, VALID, RasterPlane, blocks_of, encode, is_data, write_blocks

__all__ = [
    "BYTES_PER_PIXEL",
    "CHUNK",
    "Correction",
    "EllipsoidGeometry",
    "FileGeometry",
    "ParameterMaps",
    "check_not_an_input",
    "correct_file",
    "corrected_array",
    "input_paths",
    "sample_pixels",
]

CHUNK = 512
"""Default chunk side, pixels (a chunk of 512 × 512 pixels: about 100 MiB at work)."""
MIN_CHUNK, MAX_CHUNK = 16, 16384
FLOAT32_ANGLE = 4.0 * float(np.finfo(np.float32).eps) * math.pi
"""Rounding of an angle stored in float32 degrees, radians (four units in the last place of
180°)."""
BYTES_PER_PIXEL = 400
"""Memory one pixel of a chunk at work costs at its peak: the image, three backplanes and the
model's intermediate arrays in float64 (the peak of Python's allocations, tracemalloc, for
Hapke and Hapke 2012 with the mixed method: 394–400 bytes; the albedo method 290–335)."""


@dataclass(frozen=True)
class FileGeometry:
    """Backplanes from three files of the image's size, in degrees."""

    incidence: RasterPlane
    emission: RasterPlane
    phase: RasterPlane

    def describe(self) -> str:
        names = (os.path.basename(p.path) for p in (self.incidence, self.emission, self.phase))
        return "backplanes " + ", ".join(names)

    def read(self, rows: slice, cols: slice) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(i, e, g) of the window in radians, NaN where not data."""
        out = []
        for name, plane in (
            ("incidence", self.incidence),
            ("emission", self.emission),
            ("phase", self.phase),
        ):
            deg = plane.read(rows, cols)[0]
            bad = np.isfinite(deg) & ((deg < 0.0) | (deg > 180.0))
            if bad.any():
                r, c = (int(k[0]) for k in np.nonzero(bad))
                raise ParameterError(
                    f"{os.path.basename(plane.path)}: {name} must be in [0, 180] degrees (got "
                    f"{deg[r, c]:g} at line {rows.start + r + 1}, sample {cols.start + c + 1})"
                )
            out.append(np.radians(deg))
        i, e, g = out
        # backplanes are stored in float32: a phase outside [|i − e|, i + e] by no more than
        # that rounding is on the bound; beyond it, normalize's geometry check refuses it
        lo, hi = np.abs(i - e), i + e
        near = (np.abs(g - lo) <= FLOAT32_ANGLE) | (np.abs(g - hi) <= FLOAT32_ANGLE)
        g = np.where(near, np.clip(g, lo, hi), g)
        return i, e, g


@dataclass(frozen=True)
class EllipsoidGeometry:
    """Backplanes of a sphere or ellipsoid (:func:`.backplanes.ellipsoid_backplanes`)."""

    shape: tuple[int, int]
    subsolar: tuple[float, float]
    subobserver: tuple[float, float]
    radii: tuple[float, float, float] = (1.0, 1.0, 1.0)

    def describe(self) -> str:
        return "the ellipsoid's backplanes"

    def read(self, rows: slice, cols: slice) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        from .backplanes import ellipsoid_backplanes

        bp = ellipsoid_backplanes(
            self.shape, self.subsolar, self.subobserver, self.radii, window=(rows, cols)
        )
        return bp.incidence, bp.emission, bp.phase


@dataclass(frozen=True)
class ParameterMaps:
    """Parameter maps: one plane (a band of a cube) per model parameter, on the image's grid.

    Attributes
    ----------
    planes : tuple of (parameter, RasterPlane, in degrees)
        The parameter's name, its band, and whether the band holds degrees (an angle
        parameter; the model takes radians).
    """

    planes: tuple[tuple[str, RasterPlane, bool], ...]

    def read(self, rows: slice, cols: slice) -> dict[str, np.ndarray]:
        out = {}
        for name, plane, degrees in self.planes:
            values = plane.read(rows, cols)[0]
            out[name] = np.radians(values) if degrees else values
        return out


@dataclass(frozen=True)
class Correction:
    """The settings of :func:`~roughdiffuse.planetary.correct.normalize` (radians)."""

    model: Any
    method: str = "albedo"
    reference: tuple[float, float, float] = REFERENCE
    match: tuple[float, float, float] = MATCH
    albedo: float = 1.0
    max_incidence: float = math.radians(90.0)
    max_emission: float = math.radians(90.0)
    thresh: float = THRESH
    maps: ParameterMaps | None = None

    def __call__(self, iof: Any, i: Any, e: Any, g: Any, params: Any = None) -> np.ndarray:
        return normalize(
            iof,
            i,
            e,
            g,
            self.model,
            method=self.method,
            reference=self.reference,
            match=self.match,
            albedo=self.albedo,
            max_incidence=self.max_incidence,
            max_emission=self.max_emission,
            thresh=self.thresh,
            params=params,
        )


@dataclass(frozen=True)
class _Windows:
    """The corrected image as an array-like whose item ``[rows, cols]`` computes that window
    (``dask.array.from_array`` calls it once per chunk, on whichever worker runs the chunk)."""

    image: RasterPlane
    geometry: Any
    correction: Correction
    out_fmt: str

    @property
    def shape(self) -> tuple[int, int]:
        return self.image.shape

    dtype = np.dtype(np.float32)
    ndim = 2

    def __getitem__(self, key: tuple[slice, slice]) -> np.ndarray:
        rows, cols = (slice(*k.indices(n)[:2]) for k, n in zip(key, self.image.shape, strict=True))
        values, kind = self.image.read(rows, cols)
        i, e, g = self.geometry.read(rows, cols)
        maps = self.correction.maps
        params = maps.read(rows, cols) if maps is not None else None
        try:
            out = self.correction(values, i, e, g, params)
        except ParameterError as exc:
            raise ParameterError(
                f"{self.geometry.describe()}, lines {rows.start + 1}–{rows.stop}, samples "
                f"{cols.start + 1}–{cols.stop}: {exc}"
            ) from None
        # a pixel the correction masks (beyond the limits, the threshold, no geometry) is Null
        kind = np.where((kind == VALID) & ~np.isfinite(out), NULL, kind).astype(np.uint8)
        return encode(out, kind, self.out_fmt)


def corrected_array(
    image: RasterPlane,
    geometry: Any,
    correction: Correction,
    chunk: int = CHUNK,
    out_fmt: str = "npy",
) -> Any:
    """The corrected image as a lazy ``dask.array`` of float32 in ``chunk``² windows, each
    pixel encoded for ``out_fmt`` (:func:`.rasters.encode`)."""
    import dask.array as da

    src = _Windows(image, geometry, correction, out_fmt)
    return da.from_array(
        src,
        chunks=(chunk, chunk),
        asarray=False,
        lock=False,
        name=False,
        fancy=False,
        meta=np.empty((0, 0), np.float32),
    )


def check_chunk(chunk: int, workers: int, available: int | None) -> None:
    """Refuse a chunk side outside [MIN_CHUNK, MAX_CHUNK], or one whose chunks at work (one
    per worker thread) would not fit in ``available`` bytes."""
    if not MIN_CHUNK <= chunk <= MAX_CHUNK:
        raise ParameterError(
            f"chunk must be in [{MIN_CHUNK}, {MAX_CHUNK}] pixels (got {chunk}): smaller chunks "
            "cost more in overhead than in work, larger ones more memory than a machine has"
        )
    need = workers * chunk * chunk * BYTES_PER_PIXEL
    if available is not None and need > available:
        raise ParameterError(
            f"chunk {chunk} needs about {need / 2**30:.1f} GiB ({workers} chunks of "
            f"{chunk}² pixels × {BYTES_PER_PIXEL} bytes at work); {available / 2**30:.1f} GiB "
            "is available: give a smaller chunk"
        )


def _client(scheduler: Any) -> tuple[Any, bool]:
    """(client or None, whether it was made here and must be closed)."""
    if scheduler is None:
        return None, False
    if isinstance(scheduler, str):
        from distributed import Client

        try:
            return Client(scheduler, timeout=10), True
        except OSError as exc:
            raise ParameterError(
                f"scheduler {scheduler!r}: no Dask scheduler answers there ({exc})"
            ) from None
    return scheduler, False


def computed_blocks(
    array: Any,
    chunk: int,
    *,
    scheduler: Any = None,
    progress: bool | None = None,
) -> Iterator[tuple[slice, slice, np.ndarray]]:
    """Compute ``array``'s chunks, two per worker thread at a time (one at work on each, the
    results of the batch held until written), and yield each (rows, cols, pixels) in
    row-major order; a progress bar counts the chunks, the time spent and the time left."""
    import dask

    from ..progress import progress as bar_of

    client, own = _client(scheduler)
    try:
        if client is not None:
            workers = max(1, sum(client.nthreads().values()))
            run: dict[str, Any] = {"scheduler": client.get}
        else:
            workers = max(1, min(os.cpu_count() or 1, 8))
            run = {"scheduler": "threads", "num_workers": workers}
        windows = blocks_of(array.shape, (chunk, chunk))
        step = 2 * workers
        with bar_of(len(windows), "photometry correct", unit="chunk", enabled=progress) as bar:
            for k in range(0, len(windows), step):
                batch = windows[k : k + step]
                results = dask.compute(*(array[r, c] for r, c in batch), **run)
                for (r, c), pixels in zip(batch, results, strict=True):
                    yield r, c, np.asarray(pixels, dtype=np.float32)
                    bar.update(1)
    finally:
        if own:
            client.close()


def correct_file(
    image: RasterPlane,
    geometry: Any,
    correction: Correction,
    output: str | os.PathLike[str],
    *,
    out_fmt: str | None = None,
    chunk: int = CHUNK,
    scheduler: Any = None,
    progress: bool | None = None,
) -> tuple[Path, int]:
    """Correct ``image`` chunk by chunk and write ``output`` whole or not at all; return the
    path and the number of pixels corrected (the others are NoData or special).

    Parameters
    ----------
    image : RasterPlane
        The I/F image (:func:`.rasters.open_plane`).
    geometry : FileGeometry or EllipsoidGeometry
        Its backplanes.
    correction : Correction
    output : path
        Its format from the name unless ``out_fmt``; it takes ``image``'s label.
    chunk : int
        Chunk side in pixels.
    scheduler : dask.distributed.Client or str, optional
        A Dask cluster (a client, or the scheduler's address); default this machine's threads.
    progress : bool or None
        A progress bar on standard error (None: when it is a terminal).
    """
    from .rasters import format_of

    check_not_an_input(output, input_paths(image, geometry, correction))
    fmt = format_of(output, out_fmt)
    arr = corrected_array(image, geometry, correction, chunk, fmt)
    count = [0]

    def counted() -> Iterator[tuple[slice, slice, np.ndarray]]:
        for rows, cols, pixels in computed_blocks(
            arr, chunk, scheduler=scheduler, progress=progress
        ):
            count[0] += int(is_data(pixels).sum())
            yield rows, cols, pixels

    path = write_blocks(output, image.shape, counted(), fmt=fmt, like=image)
    return path, count[0]


def same_file(a: str | os.PathLike[str], b: str | os.PathLike[str]) -> bool:
    """Whether two paths name the same file (the output may not be an input)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.abspath(a) == os.path.abspath(b)


def input_paths(image: RasterPlane, geometry: Any, correction: Correction) -> list[str]:
    """The files a correction reads: the image, the backplanes or the DEM, the parameter
    maps (every field of the geometry that is a file's plane)."""
    paths = [image.path]
    if dataclasses.is_dataclass(geometry):
        for f in dataclasses.fields(geometry):
            path = getattr(getattr(geometry, f.name), "path", None)
            if isinstance(path, str | os.PathLike):
                paths.append(os.fspath(path))
    if correction.maps is not None:
        paths += [plane.path for _, plane, _ in correction.maps.planes]
    return paths


def check_not_an_input(
    output: str | os.PathLike[str], inputs: Iterable[str | os.PathLike[str] | None]
) -> None:
    """Refuse an ``output`` that is one of the ``inputs`` (it would be overwritten while it
    is read): the one check of ``photometry correct`` and :func:`correct_file`.

    Raises
    ------
    ParameterError
        Naming the output.
    """
    for path in filter(None, inputs):
        if same_file(path, output):
            raise ParameterError(
                f"the output {os.fspath(output)!r} is one of the inputs; name another file"
            )


def sample_pixels(
    image: RasterPlane,
    geometry: Any,
    samples: int,
    *,
    chunk: int = CHUNK,
    max_incidence: float = math.radians(90.0),
    max_emission: float = math.radians(90.0),
    seed: int = 0,
    progress: bool | None = None,
) -> Any:
    """Disk-resolved photometry from an image of any size: up to ``samples`` of its pixels
    (I/F and their (i, e, g)), read chunk by chunk, as a :class:`.disk.DiskData`.

    A first pass counts the image's data pixels N; then each one lit and seen within the
    limits is kept with probability ``samples``/N, from a generator seeded by ``seed`` and
    the chunk's position (so the sample does not depend on the order the chunks are read
    in); if more than ``samples`` are kept, an evenly spaced subset of them is. Peak memory:
    a chunk and the sample.
    """
    from ..progress import progress as bar_of
    from .disk import DiskData

    if samples < 2:
        raise ParameterError(f"samples must be at least 2 (got {samples})")
    windows = blocks_of(image.shape, (chunk, chunk))
    parts: list[np.ndarray] = []
    with bar_of(
        2 * len(windows), "photometry fit: sampling", unit="chunk", enabled=progress
    ) as bar:
        n_data = 0
        for rows, cols in windows:  # first pass: the image's data pixels, to set the rate
            n_data += int(np.isfinite(image.read(rows, cols)[0]).sum())
            bar.update(1)
        rate = min(1.0, samples / max(n_data, 1))
        for rows, cols in windows:
            values, _ = image.read(rows, cols)
            i, e, g = geometry.read(rows, cols)
            ok = np.isfinite(values) & np.isfinite(i) & np.isfinite(e) & np.isfinite(g)
            ok &= (i <= max_incidence) & (e <= max_emission) & (i < math.pi / 2)
            rng = np.random.default_rng([seed, rows.start, cols.start])
            ok &= rng.random(ok.shape) < rate
            parts.append(np.stack([values[ok], i[ok], e[ok], g[ok]]))
            bar.update(1)
    data = np.concatenate(parts, axis=1) if parts else np.empty((4, 0))
    if data.shape[1] > samples:
        data = data[:, np.linspace(0, data.shape[1] - 1, samples).astype(np.intp)]
    if data.shape[1] < 2:
        raise ParameterError(
            f"{os.path.basename(image.path)}: fewer than 2 lit, seen data pixels to fit"
        )
    return DiskData(*data, source=os.path.basename(image.path))
