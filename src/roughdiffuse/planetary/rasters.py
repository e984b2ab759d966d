"""Image planes of any size, read and written one window at a time.

Formats, chosen from the file name or named (``--format``):

==========  ===================  =============================================================
format      file name            through
==========  ===================  =============================================================
``isis3``   ``.cub``             GDAL's ISIS3 driver (rasterio): BSQ and tiled cubes
``pds4``    ``.xml``             GDAL's PDS4 driver (the label; the data in ``.img`` beside it)
``gtiff``   ``.tif``, ``.tiff``  GDAL's GTiff driver: GeoTIFF, cloud-optimised ones too
``cog``     (``--format cog``)   GDAL's COG driver: written tiled, then copied with overviews
``fits``    ``.fits`` ...        astropy (sections on read; a memory-mapped data unit on write)
``npy``     ``.npy``             NumPy (memory-mapped both ways)
``exr``     ``.exr``             OpenEXR (read and written whole: a format for small images)
==========  ===================  =============================================================

NoData. A pixel is data only if it is finite and is none of: the file's NoData value (GDAL's
``nodata``, FITS ``BLANK``), the value given by the user, and an ISIS special pixel.
ISIS special pixels (``isis/src/base/objs/SpecialPixel/SpecialPixel.h``): for 4-byte reals
the bit patterns 0xFF7FFFFB (Null), …FC (Lrs), …FD (Lis), …FE (His), …FF (Hrs), and every
value below VALID_MIN4 (0xFF7FFFFA); for 2-byte signed integers −32768 … −32764; for unsigned
2-byte 0, 1, 2, 65534, 65535; for bytes 0 (Null) and 255 (Hrs). :meth:`RasterPlane.read` returns
each pixel's class (:data:`VALID`, :data:`NULL`, :data:`LRS`, :data:`LIS`, :data:`HIS`,
:data:`HRS`) beside its value (NaN unless valid), so that a writer keeps the class: an ISIS
cube written gets the same special pixel back, any other format NaN.

Labels. A cube written from a cube of one band of 4-byte reals is a copy of it (GDAL's
ISIS3 driver keeps the whole label: Dimensions, Pixels, Mapping, Instrument, BandBin, ...)
whose pixels are then replaced window by window: the image is written twice, the label
kept whole. Otherwise a GDAL output takes the input's map projection and geotransform (and
the band description), from which GDAL writes an ISIS cube's Dimensions, Pixels (Real) and
Mapping groups. A FITS output takes the input FITS header's cards (not the structural
ones).

Every file is written whole or not at all (:func:`roughdiffuse.io.atomic.atomic_write`).
"""

from __future__ import annotations

import contextlib
import functools
import math
import os
import re
import warnings
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .._validate import ParameterError

__all__ = [
    "FORMATS",
    "HIS",
    "HRS",
    "LIS",
    "LRS",
    "NULL",
    "VALID",
    "RasterPlane",
    "format_of",
    "is_data",
    "open_plane",
    "write_blocks",
]

FORMATS: dict[str, tuple[str, ...]] = {
    "isis3": (".cub",),
    "pds4": (".xml",),
    "gtiff": (".tif", ".tiff"),
    "cog": (),  # by name only (--format cog): a GeoTIFF whose name says nothing more
    "fits": (".fits", ".fit", ".fts"),
    "npy": (".npy",),
    "exr": (".exr",),
}
"""Format name -> the file name endings that choose it."""
_GDAL = {"isis3": "ISIS3", "pds4": "PDS4", "gtiff": "GTiff", "cog": "GTiff"}
_GDAL_ENV = {"GDAL_PAM_ENABLED": "NO", "GDAL_CACHEMAX": 64}  # no .aux.xml; a bounded cache

VALID, NULL, LRS, LIS, HIS, HRS = range(6)
SPECIAL_NAMES = ("valid", "Null", "Lrs", "Lis", "His", "Hrs")
_SPECIAL4 = np.array([0xFF7FFFFB, 0xFF7FFFFC, 0xFF7FFFFD, 0xFF7FFFFE, 0xFF7FFFFF], np.uint32)
SPECIAL_REAL = _SPECIAL4.view(np.float32)
"""ISIS's 4-byte special pixels Null, Lrs, Lis, His, Hrs (SpecialPixel.h)."""
_VALID_MIN4 = np.array([0xFF7FFFFA], np.uint32).view(np.float32)[0]
_SPECIAL_INT: dict[str, tuple[int, ...]] = {  # Null, Lrs, Lis, His, Hrs
    "int16": (-32768, -32767, -32766, -32765, -32764),
    "uint16": (0, 1, 2, 65534, 65535),
    "uint8": (0, -1, -1, -1, 255),  # 0 is Null (= Lrs = Lis), 255 Hrs (= His)
}


def format_of(path: str | os.PathLike[str], fmt: str | None = None) -> str:
    """The format ``fmt`` (checked), or the one the file name's ending chooses."""
    if fmt is not None:
        key = fmt.lower()
        if key not in FORMATS:
            raise ParameterError(f"format must be one of {', '.join(FORMATS)} (got {fmt!r})")
        return key
    name = os.fspath(path).lower()
    for key, suffixes in FORMATS.items():
        if name.endswith(suffixes):
            return key
    endings = ", ".join(s for v in FORMATS.values() for s in v)
    raise ParameterError(
        f"{os.path.basename(os.fspath(path))}: unknown format; the name must end in "
        f"{endings} (or give the format)"
    )


@contextlib.contextmanager
def _gdal() -> Iterator[None]:
    """GDAL's settings for these files, and no warning for a plane without a map projection
    (a plain image is one)."""
    rasterio = _rasterio()
    from rasterio.errors import NotGeoreferencedWarning

    with rasterio.Env(**_GDAL_ENV), warnings.catch_warnings():
        warnings.simplefilter("ignore", NotGeoreferencedWarning)
        yield


def _rasterio() -> Any:
    try:
        import rasterio
    except ImportError:
        raise ParameterError(
            "ISIS cubes, PDS4 and GeoTIFF need rasterio: pip install 'roughdiffuse[planetary]'"
        ) from None
    return rasterio


def _fits() -> Any:
    try:
        from astropy.io import fits
    except ImportError:
        raise ParameterError(
            "FITS files need astropy: pip install 'roughdiffuse[planetary]' (or use .npy/.exr)"
        ) from None
    return fits


def classify(raw: np.ndarray, isis: bool, nodata: Iterable[float]) -> tuple[np.ndarray, np.ndarray]:
    """(values float64 with NaN where not data, class per pixel uint8) of raw pixels."""
    kind = np.zeros(raw.shape, np.uint8)
    if isis and raw.dtype == np.float32:
        bits = raw.view(np.uint32)
        low = raw < _VALID_MIN4
        kind[low] = LRS  # ISIS TestPixel: any other value below VALID_MIN4 is Lrs
        for k, code in enumerate(_SPECIAL4):
            kind[bits == code] = NULL + k
    elif isis and raw.dtype.name in _SPECIAL_INT:
        for k, code in enumerate(_SPECIAL_INT[raw.dtype.name]):
            if code >= 0 or raw.dtype.kind == "i":
                kind[(raw == code) & (kind == VALID)] = NULL + k
    values = raw.astype(np.float64)
    for v in nodata:
        if v is not None and math.isfinite(v):
            kind[(raw == v) & (kind == VALID)] = NULL
    kind[~np.isfinite(values) & (kind == VALID)] = NULL
    values[kind != VALID] = np.nan
    return values, kind


@dataclass(frozen=True)
class RasterPlane:
    """One image plane of a file, read by windows (picklable: it holds the path, not an open
    file, so a Dask worker opens it itself).

    Attributes
    ----------
    path : str
    fmt : str
        A key of :data:`FORMATS`.
    shape : (lines, samples)
    band : int
        1-based band of a GDAL file, or of a FITS or .npy cube (bands first or last, by the
        shape rule of :func:`~roughdiffuse.io.reading.image_array`); .exr: the first plane.
    nodata : float or None
        A value meaning NoData besides the file's own.
    file_nodata : float or None
        The file's own NoData value (GDAL's nodata, FITS BLANK), compared with raw pixels.
    scale : float
        Raw pixels to values: value = raw × scale + offset (GDAL's scale and offset, an ISIS
        cube's Multiplier and Base; FITS BSCALE and BZERO).
    offset : float
        See ``scale``.
    band_names : tuple of str
        Every band's name (GDAL files).
    block : (lines, samples)
        The file's block size (GDAL files).
    georef : str
        The map projection and pixel grid ("" without): two planes on one grid have equal
        texts.
    """

    path: str
    fmt: str
    shape: tuple[int, int]
    band: int = 1
    nodata: float | None = None
    file_nodata: float | None = None
    scale: float = 1.0
    offset: float = 0.0
    band_names: tuple[str, ...] = ()
    block: tuple[int, int] = (0, 0)
    georef: str = ""

    @property
    def isis(self) -> bool:
        return self.fmt == "isis3"

    def read(self, rows: slice, cols: slice) -> tuple[np.ndarray, np.ndarray]:
        """(values float64, NaN where not data; class per pixel) of the window."""
        if self.fmt in _GDAL:
            rasterio = _rasterio()
            from rasterio.windows import Window

            win = Window(cols.start, rows.start, cols.stop - cols.start, rows.stop - rows.start)
            with _gdal(), rasterio.open(self.path) as ds:
                raw = ds.read(self.band, window=win)
        elif self.fmt == "fits":
            fits = _fits()
            with fits.open(self.path, memmap=True, do_not_scale_image_data=True) as hdul:
                section = _fits_hdu(hdul, self.path).section
                raw = np.array(section[_window(section.shape, rows, cols, self.band, self.path)])
        elif self.fmt == "npy":
            arr = np.load(self.path, mmap_mode="r", allow_pickle=False)
            raw = np.array(arr[_window(arr.shape, rows, cols, self.band, self.path)])
        else:
            raw = _exr_plane(self.path, os.stat(self.path).st_mtime_ns)[rows, cols]
        raw = raw.astype(raw.dtype.newbyteorder("="))
        values, kind = classify(raw, self.isis, (self.nodata, self.file_nodata))
        if self.scale != 1.0 or self.offset != 0.0:
            values = values * self.scale + self.offset
        return values, kind

    def read_all(self) -> np.ndarray:
        """The whole plane (values, NaN where not data): for small images and tests."""
        return self.read(slice(0, self.shape[0]), slice(0, self.shape[1]))[0]


@functools.lru_cache(maxsize=2)
def _exr_plane(path: str, mtime_ns: int) -> np.ndarray:
    """An OpenEXR file's first channel, NaN where not finite, read once per process and file
    version (OpenEXR is read whole: a format for images that fit in memory)."""
    from ..fit import read_image

    img, finite = read_image(path)  # NaN and infinity: not finite, read as 0
    if img.ndim == 3:
        img = img[..., 0]
    out = np.where(finite, img, np.nan)
    out.setflags(write=False)
    return out


def _layout(shape: tuple[int, ...], dtype: Any, path: str) -> tuple[int, int, int, str]:
    """(lines, samples, bands, where the band axis is: "", "first" or "last") of an array
    file (.npy, FITS), by the one shape and value rule of every image reader
    (:func:`~roughdiffuse.io.reading.image_array`, :func:`~roughdiffuse.io.reading.check_real`):
    (H, W); (H, W, C) bands last; (C, H, W) bands first (FITS order), C in {1, 3}."""
    from ..io.reading import check_real, image_array

    name = os.path.basename(path)
    check_real(np.empty(0, dtype=dtype), name)
    stand_in = np.broadcast_to(np.zeros((), dtype=np.uint8), shape)  # the shape, no memory
    plane = image_array(stand_in, name)
    lines, samples = (int(n) for n in plane.shape[:2])
    if len(shape) == 2:
        return lines, samples, 1, ""
    bands = int(shape[0] if shape[1:] == (lines, samples) else shape[2])
    return lines, samples, bands, "first" if shape[1:] == (lines, samples) else "last"


def _window(shape: tuple[int, ...], rows: slice, cols: slice, band: int, path: str) -> Any:
    """The index of band ``band`` (1-based) of a window in an array of ``shape``."""
    *_, where = _layout(shape, np.float32, path)
    if where == "first":
        return (band - 1, rows, cols)
    if where == "last":
        return (rows, cols, band - 1)
    return (rows, cols)


def _array_plane(
    path: str, fmt: str, shape: tuple[int, ...], dtype: Any, band: int | str
) -> tuple[int, int, int]:
    """(lines, samples, band) of band ``band`` of an array file, checked (see :func:`_layout`)."""
    name = os.path.basename(path)
    lines, samples, bands, _ = _layout(shape, dtype, path)
    index = int(band) if isinstance(band, int) or str(band).isdigit() else None
    if index is None or not 1 <= index <= bands:
        held = "one band" if bands == 1 else f"{bands} bands (1 to {bands})"
        raise ParameterError(f"{name}: a {fmt} file of {held}; no band {band!r}")
    return lines, samples, index


def _fits_hdu(hdul: Any, path: str) -> Any:
    for h in hdul:
        if h.header.get("NAXIS", 0) >= 2 and h.is_image:
            return h
    raise ParameterError(f"{os.path.basename(path)}: no image in the FITS file")


def open_plane(
    path: str | os.PathLike[str],
    fmt: str | None = None,
    *,
    band: int | str = 1,
    nodata: float | None = None,
) -> RasterPlane:
    """Open one plane of an image file (the header only; pixels are read by window).

    Parameters
    ----------
    path : path
    fmt : str, optional
        A key of :data:`FORMATS` (default: from the name).
    band : int or str
        1-based band number, or a band's name (GDAL files: the band description, or an ISIS
        cube's BandBin ``Name``).
    nodata : float, optional
        A value meaning NoData besides the file's own.

    Raises
    ------
    ValueError
        Naming the file: unknown format, unreadable file or label, a missing band, or not a
        single plane.
    """
    path = os.fspath(path)
    name = os.path.basename(path)
    fmt = format_of(path, fmt)
    if not os.path.isfile(path):
        raise ParameterError(f"{name}: no such file")
    if fmt in _GDAL:
        rasterio = _rasterio()
        try:
            with _gdal(), rasterio.open(path) as ds:
                names = _band_names(ds)
                index = _band_index(band, names, ds.count, name)
                scale = float(ds.scales[index - 1] or 1.0)
                offset = float(ds.offsets[index - 1] or 0.0)
                return RasterPlane(
                    path,
                    fmt,
                    (int(ds.height), int(ds.width)),
                    index,
                    nodata,
                    None if ds.nodata is None else float(ds.nodata),
                    scale,
                    offset,
                    names,
                    tuple(int(n) for n in ds.block_shapes[index - 1]),
                    _georef(ds),
                )
        except rasterio.errors.RasterioIOError as exc:
            raise ParameterError(f"{name}: GDAL cannot read it ({_gdal_reason(exc)})") from None
    if fmt == "exr" and band not in (1, "1"):
        raise ParameterError(f"{name}: an exr file holds one plane (asked for band {band!r})")
    if fmt == "fits":
        fits = _fits()
        try:
            with fits.open(path, memmap=True, do_not_scale_image_data=True) as hdul:
                hdu = _fits_hdu(hdul, path)
                hdr = hdu.header
                shape = tuple(int(hdr[f"NAXIS{k}"]) for k in range(hdr["NAXIS"], 0, -1))
                blank = hdr.get("BLANK") if hdr.get("BITPIX", -32) > 0 else None
                scale, offset = float(hdr.get("BSCALE", 1.0)), float(hdr.get("BZERO", 0.0))
                dtype = np.float64 if hdr.get("BITPIX", -32) < 0 else np.int64
        except OSError as exc:
            raise ParameterError(f"{name}: not a FITS file ({exc})") from None
        lines, samples, index = _array_plane(path, fmt, shape, dtype, band)
        return RasterPlane(path, fmt, (lines, samples), index, nodata, blank, scale, offset)
    if fmt == "npy":
        try:
            arr = np.load(path, mmap_mode="r", allow_pickle=False)
        except ValueError as exc:
            raise ParameterError(f"{name}: not a .npy array ({exc})") from None
        lines, samples, index = _array_plane(path, fmt, arr.shape, arr.dtype, band)
        return RasterPlane(path, fmt, (lines, samples), index, nodata)
    img = _exr_plane(path, os.stat(path).st_mtime_ns)
    return RasterPlane(path, fmt, (int(img.shape[0]), int(img.shape[1])), 1, nodata)


def _georef(ds: Any) -> str:
    """The map projection and geotransform of a GDAL dataset as text ("" without either)."""
    if ds.crs is None and ds.transform.is_identity:
        return ""
    crs = ds.crs.to_wkt() if ds.crs is not None else "no map projection"
    return f"{crs}; pixel grid {tuple(round(v, 9) for v in ds.transform[:6])}"


def is_data(pixels: np.ndarray) -> np.ndarray:
    """Where encoded pixels (:func:`encode`) hold data: finite and no ISIS special pixel."""
    return np.isfinite(pixels) & (pixels >= _VALID_MIN4)


def _gdal_reason(exc: BaseException) -> str:
    text = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
    return text


def _band_names(ds: Any) -> tuple[str, ...]:
    """Band names: GDAL's band descriptions, else an ISIS cube's BandBin Name (or Center)."""
    names = [d or "" for d in ds.descriptions]
    if all(names):
        return tuple(names)
    import json

    for key, value in (
        ds.tags(ns="json:ISIS3").items() if "json:ISIS3" in (ds.tag_namespaces() or []) else ()
    ):
        try:
            doc = json.loads(f"{key}:{value}")
        except ValueError:
            break
        band_bin = doc.get("IsisCube", {}).get("BandBin", {})
        got = band_bin.get("Name") or band_bin.get("FilterName")
        if isinstance(got, list) and len(got) == ds.count:
            return tuple(str(g) for g in got)
        if isinstance(got, str) and ds.count == 1:
            return (got,)
    return tuple(names)


def _band_index(band: int | str, names: tuple[str, ...], count: int, file: str) -> int:
    if isinstance(band, int) or str(band).isdigit():
        k = int(band)
        if not 1 <= k <= count:
            raise ParameterError(f"{file}: no band {k} (it has {count})")
        return k
    want = str(band).strip().lower()
    for k, n in enumerate(names, start=1):
        if n.strip().lower() == want:
            return k
    raise ParameterError(
        f"{file}: no band named {band!r} (its bands: {', '.join(n or '?' for n in names)})"
    )


# ------------------------------------------------------------------------- writing
Block = tuple[slice, slice, np.ndarray]
"""(rows, cols, float32 pixels already in the output's encoding: :func:`encode`)."""


def encode(values: np.ndarray, kind: np.ndarray, fmt: str) -> np.ndarray:
    """float32 pixels for ``fmt``: an ISIS cube gets each special class's special pixel (NaN
    values that are valid, i.e. masked by the correction, become Null); others NaN."""
    out = np.asarray(values, dtype=np.float32).copy()
    if fmt == "isis3":
        special = kind != VALID
        out[special] = SPECIAL_REAL[kind[special].astype(np.intp) - 1]
        out[~special & ~np.isfinite(out)] = SPECIAL_REAL[0]
    else:
        out[kind != VALID] = np.nan
    return out


def write_blocks(
    path: str | os.PathLike[str],
    shape: tuple[int, int],
    blocks: Iterable[Block],
    *,
    fmt: str | None = None,
    like: RasterPlane | None = None,
    description: str = "",
) -> Path:
    """Write a float32 plane from its blocks, whole or not at all.

    Parameters
    ----------
    path : path
        The output file (its format from the name unless ``fmt``).
    shape : (lines, samples)
    blocks : iterable of (rows, cols, pixels)
        Covering the plane once (any order), pixels float32 as :func:`encode` gives them for
        the output's format; consumed while the file is being written.
    like : RasterPlane, optional
        The input whose label (map projection, geotransform; FITS header) the output takes.
    description : str
        The band's description (GDAL formats).
    """
    from ..io.atomic import atomic_write

    target = Path(path)
    fmt = format_of(target, fmt)
    h, w = (int(n) for n in shape)
    if fmt in _GDAL:
        return _write_gdal(target, fmt, (h, w), blocks, like, description)

    def write(tmp: Path) -> None:
        if fmt == "npy":
            arr = np.lib.format.open_memmap(tmp, mode="w+", dtype=np.float32, shape=(h, w))
            for rows, cols, pixels in blocks:
                arr[rows, cols] = pixels
            arr.flush()
            del arr
        elif fmt == "fits":
            _write_fits(tmp, (h, w), blocks, like)
        else:
            from ..io.images import write_exr

            img = np.full((h, w), np.nan, np.float32)
            for rows, cols, pixels in blocks:
                img[rows, cols] = pixels
            write_exr(tmp, img)

    return atomic_write(target, write)


_STRUCTURAL = re.compile(r"^(SIMPLE|BITPIX|NAXIS\d*|EXTEND|BSCALE|BZERO|BLANK|PCOUNT|GCOUNT|END)$")


def _write_fits(tmp: Path, shape: tuple[int, int], blocks: Iterable[Block], like: Any) -> None:
    """A FITS primary HDU of float32 written through a memory map of its data unit."""
    fits = _fits()
    h, w = shape
    hdr = fits.Header()
    hdr["SIMPLE"] = True
    hdr["BITPIX"] = -32
    hdr["NAXIS"] = 2
    hdr["NAXIS1"] = w
    hdr["NAXIS2"] = h
    if like is not None and like.fmt == "fits":
        with fits.open(like.path, memmap=True, do_not_scale_image_data=True) as hdul:
            for card in _fits_hdu(hdul, like.path).header.cards:
                if not _STRUCTURAL.match(card.keyword) and card.keyword not in ("", "COMMENT"):
                    hdr.append(card)
    head = hdr.tostring().encode("ascii")
    data_bytes = h * w * 4
    pad = (-data_bytes) % 2880
    with open(tmp, "wb") as fh:
        fh.write(head)
        fh.truncate(len(head) + data_bytes + pad)
    arr = np.memmap(tmp, dtype=">f4", mode="r+", offset=len(head), shape=(h, w))
    for rows, cols, pixels in blocks:
        arr[rows, cols] = pixels
    arr.flush()
    del arr


def _gdal_profile(fmt: str, shape: tuple[int, int], like: RasterPlane | None) -> dict[str, Any]:
    """The rasterio profile of a one-band float32 output of ``fmt``: the grid and map
    projection of ``like`` (a GDAL input), tiles for GeoTIFF, the format's NoData."""
    rasterio = _rasterio()
    h, w = shape
    profile: dict[str, Any] = {
        "driver": _GDAL[fmt],
        "width": w,
        "height": h,
        "count": 1,
        "dtype": "float32",
    }
    if like is not None and like.fmt in _GDAL:
        with _gdal(), rasterio.open(like.path) as src:
            if src.crs is not None:
                profile["crs"] = src.crs
            if not src.transform.is_identity:
                profile["transform"] = src.transform
    if fmt in ("gtiff", "cog"):
        profile.update(tiled=True, blockxsize=512, blockysize=512, nodata=float("nan"))
        profile.update(BIGTIFF="IF_SAFER")
    elif fmt == "isis3":
        profile["nodata"] = float(SPECIAL_REAL[0])
    else:
        profile["nodata"] = float("nan")
    return profile


def _write_gdal(
    target: Path,
    fmt: str,
    shape: tuple[int, int],
    blocks: Iterable[Block],
    like: RasterPlane | None,
    description: str,
) -> Path:
    from ..io.atomic import atomic_write

    rasterio = _rasterio()
    from rasterio.windows import Window

    profile = _gdal_profile(fmt, shape, like)
    image_tmp: list[Path] = []
    whole_label = fmt == "isis3" and _single_real_cube(like)

    def write(tmp: Path) -> None:
        if whole_label:  # the input cube's whole label: a copy of it, its pixels then replaced
            from rasterio.shutil import copy

            with _gdal():
                copy(like.path, tmp, driver="ISIS3")
            with _gdal(), rasterio.open(tmp, "r+") as dst:
                for rows, cols, pixels in blocks:
                    win = Window(
                        cols.start, rows.start, cols.stop - cols.start, rows.stop - rows.start
                    )
                    dst.write(pixels, 1, window=win)
            return
        opts = dict(profile)
        if fmt == "pds4":
            img = tmp.with_suffix(".img")
            image_tmp.append(img)
            opts["IMAGE_FILENAME"] = str(img)
        # a cloud-optimised GeoTIFF cannot be written by windows: a tiled GeoTIFF first, then
        # GDAL's COG driver copies it (with overviews) into the target's temporary file
        first = tmp.with_name(tmp.name + ".tiled.tif") if fmt == "cog" else tmp
        if fmt == "cog":
            image_tmp.append(first)
        with _gdal(), rasterio.open(first, "w", **opts) as dst:
            if description:
                dst.set_band_description(1, description)
            for rows, cols, pixels in blocks:
                win = Window(cols.start, rows.start, cols.stop - cols.start, rows.stop - rows.start)
                dst.write(pixels, 1, window=win)
        if fmt == "cog":
            from rasterio.shutil import copy

            with _gdal():
                copy(first, tmp, driver="COG", BIGTIFF="IF_SAFER", OVERVIEWS="AUTO")
            first.unlink()
        if fmt == "pds4":
            _pds4_finish(tmp, img, target)

    try:
        return atomic_write(target, write)
    finally:
        for img in image_tmp:
            if img.exists():
                img.unlink()


def _single_real_cube(like: RasterPlane | None) -> bool:
    """Whether ``like`` is an ISIS cube of one band of 4-byte reals: an output cube is then
    a copy of it (GDAL's ISIS3 driver keeps the source's whole label: Instrument, BandBin,
    Kernels, ... besides Dimensions, Pixels and Mapping) with its pixels replaced."""
    if like is None or like.fmt != "isis3":
        return False
    with _gdal(), _rasterio().open(like.path) as src:
        return src.count == 1 and src.dtypes[0] == "float32"


def _pds4_finish(label_tmp: Path, image_tmp: Path, target: Path) -> None:
    """Move a PDS4 product's data file beside the target and point the label at it; the
    label (the product's entry point) is committed after, by the caller."""
    from ..io.atomic import place

    final_image = target.with_suffix(".img")
    text = label_tmp.read_text(encoding="utf-8")
    text = text.replace(
        f"<file_name>{image_tmp.name}</file_name>", f"<file_name>{final_image.name}</file_name>"
    )
    label_tmp.write_text(text, encoding="utf-8")
    place(image_tmp, final_image)


def blocks_of(shape: tuple[int, int], chunk: tuple[int, int]) -> list[tuple[slice, slice]]:
    """The windows of ``chunk`` (lines, samples) tiling ``shape``, row-major."""
    h, w = shape
    ch, cw = chunk
    return [
        (slice(r, min(r + ch, h)), slice(c, min(c + cw, w)))
        for r in range(0, h, ch)
        for c in range(0, w, cw)
    ]
