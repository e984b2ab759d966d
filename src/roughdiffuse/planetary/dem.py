"""Local photometric angles from a digital elevation model, as ISIS's ``ANGLESOURCE=DEM``.

Each DEM sample is a point X on the surface. Its normal is the cross product of the surface's
tangents along the grid, n ∝ ∂X/∂(sample) × ∂X/∂(line) (oriented away from the body), the
derivatives by fourth-order central differences (Fornberg 1988, the five-point stencil
(X[k−2] − 8 X[k−1] + 8 X[k+1] − X[k+2])/12; second order within two samples of the DEM's
edge). With s and o the unit vectors from X to the sun and to the observer (a direction when
the body is far away, else from X to its position):

    cos i = n·s,  cos e = n·o,  cos g = s·o

(each angle computed as atan2(|a × b|, a·b), accurate to the last digits near 0°; the local
incidence and emission angles; the phase angle does not depend on the slope).
The slope is the angle between n and the reference "up" u (the plane's z axis, or the
sphere's radial direction), and the azimuth is the direction, clockwise from north, that the
slope faces: atan2(n·east, n·north), in [0°, 360°).

Two ways to place the samples:

* :func:`plane_points` — a flat map (x east, y north, z up, metres), the DEM's heights on
  the grid of its geotransform: a small region, the sun and the observer as vectors in the
  same frame;
* :func:`body_points` — a sphere of radius R: each sample's latitude and longitude from its
  map projection (PROJ, through rasterio), X = (R + h)(cos φ cos λ, cos φ sin λ, sin φ) in
  the body-fixed frame, the sun and the observer from their sub-points and distances.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import ParameterError

__all__ = [
    "DemGeometry",
    "LocalAngles",
    "body_points",
    "dem_geometry",
    "local_angles",
    "plane_points",
    "unit_from_lat_lon",
]


@dataclass(frozen=True)
class LocalAngles:
    """Per-sample local geometry, radians (NaN where the DEM holds no data)."""

    incidence: np.ndarray
    emission: np.ndarray
    phase: np.ndarray
    slope: np.ndarray
    azimuth: np.ndarray


def _derivative(a: np.ndarray, axis: int) -> np.ndarray:
    """d a / d(index) along ``axis``: the five-point stencil inside, second order near edges
    (the central three-point stencil one sample in, one-sided three-point at the edge)."""
    a = np.moveaxis(np.asarray(a, dtype=np.float64), axis, 0)
    n = a.shape[0]
    if n < 3:
        raise ParameterError(f"a DEM needs at least 3 samples each way (got {n})")
    d = np.empty_like(a)
    d[0] = (-3.0 * a[0] + 4.0 * a[1] - a[2]) / 2.0
    d[-1] = (3.0 * a[-1] - 4.0 * a[-2] + a[-3]) / 2.0
    if n >= 5:
        d[1] = (a[2] - a[0]) / 2.0
        d[-2] = (a[-1] - a[-3]) / 2.0
        d[2:-2] = (a[:-4] - 8.0 * a[1:-3] + 8.0 * a[3:-1] - a[4:]) / 12.0
    else:
        d[1:-1] = (a[2:] - a[:-2]) / 2.0
    return np.moveaxis(d, 0, axis)


def unit_from_lat_lon(lat_deg: Any, lon_deg: Any) -> np.ndarray:
    """Unit vectors (..., 3) of planetocentric latitude and longitude in degrees."""
    la, lo = (
        np.radians(np.asarray(lat_deg, np.float64)),
        np.radians(np.asarray(lon_deg, np.float64)),
    )
    return np.stack([np.cos(la) * np.cos(lo), np.cos(la) * np.sin(lo), np.sin(la)], axis=-1)


def plane_points(
    heights: np.ndarray,
    transform: Sequence[float],
    rows: slice | None = None,
    cols: slice | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (H, W, 3), up, north) of a DEM on a flat map: x, y from the geotransform
    (a, b, c, d, e, f: x = a·col + b·row + c, y = d·col + e·row + f, at the pixel centres),
    z the height; ``rows``, ``cols`` place a window of the DEM."""
    h = np.asarray(heights, dtype=np.float64)
    a, b, c, d, e, f = (float(v) for v in transform[:6])
    r0 = rows.start if rows is not None else 0
    c0 = cols.start if cols is not None else 0
    rr, cc = np.meshgrid(
        np.arange(h.shape[0]) + r0 + 0.5, np.arange(h.shape[1]) + c0 + 0.5, indexing="ij"
    )
    x = a * cc + b * rr + c
    y = d * cc + e * rr + f
    return np.stack([x, y, h], axis=-1), np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])


def body_points(
    heights: np.ndarray, lat_deg: np.ndarray, lon_deg: np.ndarray, radius: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(points (H, W, 3), radial up (H, W, 3), north: the spin axis +z) of a DEM on a sphere
    of ``radius`` (metres): X = (R + h) û(φ, λ)."""
    up = unit_from_lat_lon(lat_deg, lon_deg)
    points = (radius + np.asarray(heights, np.float64))[..., None] * up
    return points, up, np.array([0.0, 0.0, 1.0])


def _toward(target: np.ndarray, distance: float | None, points: np.ndarray) -> np.ndarray:
    """Unit vectors from ``points`` to a body in direction ``target`` (a unit vector) at
    ``distance`` from the origin (None: infinitely far, the direction itself)."""
    t = np.asarray(target, dtype=np.float64)
    t = t / np.linalg.norm(t)
    if distance is None:
        return np.broadcast_to(t, points.shape)
    v = distance * t - points
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def local_angles(
    points: np.ndarray,
    up: np.ndarray,
    north: Sequence[float],
    sun: Sequence[float],
    observer: Sequence[float],
    *,
    sun_distance: float | None = None,
    observer_distance: float | None = None,
) -> LocalAngles:
    """Local incidence, emission, phase, slope and azimuth of DEM points (see the module).

    Parameters
    ----------
    points : array (H, W, 3)
        The samples' positions (:func:`plane_points` or :func:`body_points`); a window's
        outer two rows and columns only serve its derivatives when the caller crops them.
    up : array (3,) or (H, W, 3)
        The reference up direction(s).
    north : 3-vector
        The direction of north: on a flat map +y, on a body its spin axis +z.
    sun, observer : 3-vectors
        Directions from the frame's origin (normalised here).
    sun_distance, observer_distance : float, optional
        Their distances from the origin (same unit as the points); None: infinitely far.
    """
    p = np.asarray(points, dtype=np.float64)
    t_col = _derivative(p, 1)  # along a line: east on a north-up map
    t_row = _derivative(p, 0)  # down the lines: south on a north-up map
    n = np.cross(t_col, -t_row)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    u = np.broadcast_to(np.asarray(up, dtype=np.float64), p.shape)
    flip = np.einsum("...k,...k", n, u) < 0
    n[flip] *= -1.0  # away from the body whatever the grid's orientation
    s = _toward(np.asarray(sun), sun_distance, p)
    o = _toward(np.asarray(observer), observer_distance, p)

    def angle(a: np.ndarray, b: np.ndarray) -> np.ndarray:
        # atan2(|a × b|, a·b): accurate near 0 and π, where arccos loses half the digits
        cross = np.linalg.norm(np.cross(a, b), axis=-1)
        return np.arctan2(cross, np.einsum("...k,...k", a, b))

    # azimuth: n against local north (north less its part along up) and east = north × up
    spin = np.broadcast_to(np.asarray(north, dtype=np.float64), u.shape)
    nor = spin - np.einsum("...k,...k", spin, u)[..., None] * u
    nor_len = np.linalg.norm(nor, axis=-1, keepdims=True)
    nor = np.divide(nor, nor_len, out=np.zeros_like(nor), where=nor_len > 1e-15)
    east = np.cross(nor, u)
    az = np.arctan2(np.einsum("...k,...k", n, east), np.einsum("...k,...k", n, nor))
    return LocalAngles(angle(n, s), angle(n, o), angle(s, o), angle(n, u), np.mod(az, 2 * math.pi))


HALO = 2
"""Samples of margin a window of the DEM is read with: the five-point stencil's reach."""


@dataclass(frozen=True)
class DemGeometry:
    """The backplanes of an image from a DEM on its pixel grid (picklable, read by window).

    Attributes
    ----------
    dem : RasterPlane
        The DEM (heights in metres, or radii with ``holds_radius``).
    offset : (line, sample)
        The image's first pixel in the DEM's grid (the DEM covers the image).
    shape : (lines, samples)
        The image's size.
    frame : {"plane", "body"}
        :func:`plane_points` (vectors in the map's east, north, up) or :func:`body_points`.
    sun, observer : 3-vectors
        Directions (plane: east, north, up; body: body-fixed, from the sub-points).
    sun_distance, observer_distance : float or None
        From the map's origin (plane) or the body's centre (body), metres; None: far away.
    radius : float
        The sphere's radius, metres (body frame).
    holds_radius : bool
        The DEM holds radii (ISIS's DEMs), not heights above the sphere.
    """

    dem: Any
    offset: tuple[int, int]
    shape: tuple[int, int]
    transform: tuple[float, ...]
    crs: str
    frame: str
    sun: tuple[float, float, float]
    observer: tuple[float, float, float]
    sun_distance: float | None = None
    observer_distance: float | None = None
    radius: float = 0.0
    holds_radius: bool = False

    def angles(self, rows: slice, cols: slice) -> LocalAngles:
        """All five angles of an image window (radians)."""
        r0, c0 = self.offset
        dh, dw = self.dem.shape
        top, left = max(r0 + rows.start - HALO, 0), max(c0 + cols.start - HALO, 0)
        bottom, right = min(r0 + rows.stop + HALO, dh), min(c0 + cols.stop + HALO, dw)
        wr, wc = slice(top, bottom), slice(left, right)
        z = self.dem.read(wr, wc)[0]
        if self.holds_radius:
            z = z - self.radius
        if self.frame == "plane":
            points, up, north = plane_points(z, self.transform, wr, wc)
        else:
            lat, lon = self._lat_lon(wr, wc)
            points, up, north = body_points(z, lat, lon, self.radius)
        got = local_angles(
            points,
            up,
            north,
            self.sun,
            self.observer,
            sun_distance=self.sun_distance,
            observer_distance=self.observer_distance,
        )
        inner = (
            slice(r0 + rows.start - top, r0 + rows.stop - top),
            slice(c0 + cols.start - left, c0 + cols.stop - left),
        )
        return LocalAngles(*(getattr(got, k)[inner] for k in LocalAngles.__dataclass_fields__))

    def describe(self) -> str:
        return f"angles from the DEM {os.path.basename(self.dem.path)}"

    def read(self, rows: slice, cols: slice) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        a = self.angles(rows, cols)
        return a.incidence, a.emission, a.phase

    def _lat_lon(self, rows: slice, cols: slice) -> tuple[np.ndarray, np.ndarray]:
        """Planetocentric latitude and longitude (degrees) of the DEM samples of a window,
        from the map projection by PROJ (rasterio.warp)."""
        from rasterio.crs import CRS
        from rasterio.warp import transform

        x, y, _ = np.moveaxis(
            plane_points(
                np.zeros((rows.stop - rows.start, cols.stop - cols.start)),
                self.transform,
                rows,
                cols,
            )[0],
            -1,
            0,
        )
        geo = CRS.from_proj4(f"+proj=longlat +R={self.radius!r} +no_defs")
        lon, lat = transform(CRS.from_user_input(self.crs), geo, x.ravel(), y.ravel())
        return np.reshape(lat, x.shape), np.reshape(lon, x.shape)


def dem_geometry(
    dem: Any,
    image: Any,
    *,
    sun: Sequence[float],
    observer: Sequence[float],
    frame: str = "plane",
    sun_distance: float | None = None,
    observer_distance: float | None = None,
    radius: float = 0.0,
    holds_radius: bool = False,
) -> DemGeometry:
    """The :class:`DemGeometry` of ``image`` (a RasterPlane) from ``dem`` (a RasterPlane), checked.

    The DEM must be on the image's pixel grid: the same size without a map projection; with
    one, the same projection and pixel size, the image's pixels a whole-pixel window of the
    DEM's. The body frame needs a map projection and ``radius``.

    Raises
    ------
    ValueError
        Naming the DEM: not covering the image, another grid or projection, no projection.
    """
    import rasterio

    name = os.path.basename(dem.path)
    if frame not in ("plane", "body"):
        raise ParameterError(f"frame must be 'plane' or 'body' (got {frame!r})")
    with rasterio.open(dem.path) as ds:
        dt, dcrs = ds.transform, ds.crs
    if dt.is_identity:
        raise ParameterError(f"{name}: a DEM needs a geotransform (its pixel size in metres)")
    offset = (0, 0)
    if image.georef and dem.georef:
        with rasterio.open(image.path) as ds:
            it, icrs = ds.transform, ds.crs
        if icrs != dcrs:
            raise ParameterError(f"{name}: its map projection is not the image's")
        if not np.allclose(tuple(it)[:2] + tuple(it)[3:5], tuple(dt)[:2] + tuple(dt)[3:5]):
            raise ParameterError(f"{name}: its pixel size is not the image's; resample it first")
        # the image's corner in the DEM's pixels: solve x = a col + b row + c, y = d col + e row + f
        col, row = np.linalg.solve([[dt.a, dt.b], [dt.d, dt.e]], [it.c - dt.c, it.f - dt.f])
        if abs(col - round(col)) > 1e-6 or abs(row - round(row)) > 1e-6:
            raise ParameterError(f"{name}: its pixels are not aligned with the image's")
        offset = (int(round(row)), int(round(col)))
    elif dem.shape != image.shape:
        raise ParameterError(
            f"{name} is {dem.shape[1]} x {dem.shape[0]} pixels, the image "
            f"{image.shape[1]} x {image.shape[0]}; without map projections they must match"
        )
    r0, c0 = offset
    if r0 < 0 or c0 < 0 or r0 + image.shape[0] > dem.shape[0] or c0 + image.shape[1] > dem.shape[1]:
        raise ParameterError(f"{name} does not cover the image")
    if frame == "body":
        if dcrs is None:
            raise ParameterError(f"{name}: a DEM on a body needs a map projection")
        if not (math.isfinite(radius) and radius > 0):
            raise ParameterError(f"radius must be a positive number of metres (got {radius})")
    return DemGeometry(
        dem,
        offset,
        image.shape,
        tuple(float(v) for v in tuple(dt)[:6]),
        dcrs.to_wkt() if dcrs is not None else "",
        frame,
        tuple(float(v) for v in sun),
        tuple(float(v) for v in observer),
        sun_distance,
        observer_distance,
        float(radius),
        holds_radius,
    )
