"""Local photometric angles from a DEM (roughdiffuse.planetary.dem) against closed forms.

An inclined plane z = αx + βy + c has the normal (−α, −β, 1)/√(1 + α² + β²) everywhere; a
spherical cap z = √(R² − x² − y²) has the normal (x, y, z)/R at each point; a DEM of zero
heights on a sphere of radius R has the radial normal, and with the sun and the observer far
away its angles are those of :func:`ellipsoid_backplanes`' closed form cos i = û·s. The
incidence, emission and phase are checked to 1e-9 rad with the observer at a finite distance
(the direction to it changes from sample to sample), the slope and azimuth from the normal.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from roughdiffuse.planetary.dem import body_points, local_angles, plane_points, unit_from_lat_lon

SUN = np.array([0.3, -0.4, 0.866])
OBSERVER = np.array([-0.1, 0.2, 1.0])
DIST = 5.0e4  # metres: the observer 50 km from the origin


def angle(a, b):
    """The angle between vectors, as atan2(|a × b|, a·b) (arccos of the cosine loses 1e-8
    rad near 0)."""
    a, b = np.broadcast_arrays(a, b)
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("...k,...k", a, b))


def expected(points, normals):
    s = SUN / np.linalg.norm(SUN)
    o = DIST * OBSERVER / np.linalg.norm(OBSERVER) - points
    return (
        angle(normals, np.broadcast_to(s, points.shape)),
        angle(normals, o),
        angle(np.broadcast_to(s, points.shape), o),
    )


def check(got, points, normals, inner):
    inc, ema, pha = expected(points, normals)
    for a, b in ((got.incidence, inc), (got.emission, ema), (got.phase, pha)):
        np.testing.assert_allclose(a[inner], b[inner], rtol=0, atol=1e-9)


# a 60 × 80 grid, 2 m pixels, north up (geotransform a, b, c, d, e, f)
TRANSFORM = (2.0, 0.0, -80.0, 0.0, -2.0, 60.0)


def test_inclined_plane():
    alpha, beta = 0.35, -0.2
    x, y = np.meshgrid(np.arange(80) * 2.0 - 79.0, 59.0 - np.arange(60) * 2.0)
    z = alpha * x + beta * y + 3.0
    points, up, north = plane_points(z, TRANSFORM)
    np.testing.assert_allclose(points[..., 0], x)
    got = local_angles(points, up, north, SUN, OBSERVER, observer_distance=DIST)
    normal = np.array([-alpha, -beta, 1.0]) / math.sqrt(1 + alpha**2 + beta**2)
    every = np.ones(z.shape, bool)  # a plane: exact at the edges too
    check(got, points, np.broadcast_to(normal, points.shape), every)
    np.testing.assert_allclose(got.slope, math.atan(math.hypot(alpha, beta)), atol=1e-12)
    # the surface faces down-slope: east (−α > 0 is toward −x...) azimuth atan2(n_east, n_north)
    np.testing.assert_allclose(got.azimuth, math.atan2(-alpha, -beta) % (2 * math.pi), atol=1e-12)


def test_spherical_cap():
    radius = 400.0
    x, y = np.meshgrid(np.arange(80) * 2.0 - 79.0, 59.0 - np.arange(60) * 2.0)
    z = np.sqrt(radius**2 - x**2 - y**2)
    points, up, north = plane_points(z, TRANSFORM)
    got = local_angles(points, up, north, SUN, OBSERVER, observer_distance=DIST)
    normals = points / radius
    inner = np.zeros(z.shape, bool)
    inner[2:-2, 2:-2] = True  # the five-point stencil; second order at the edges
    check(got, points, normals, inner)
    np.testing.assert_allclose(got.slope[inner], np.arctan2(np.hypot(x, y), z)[inner], atol=1e-9)
    # edges: second order, still close
    np.testing.assert_allclose(got.incidence, expected(points, normals)[0], atol=1e-4)


def test_flat_dem_on_a_sphere_is_the_sphere():
    """Zero heights on a sphere: the normal is radial, the angles the sphere's closed form."""
    radius = 1737.4e3
    lat, lon = np.meshgrid(np.linspace(20.0, 10.0, 41), np.linspace(-5.0, 12.0, 57), indexing="ij")
    points, up, north = body_points(np.zeros(lat.shape), lat, lon, radius)
    sun = unit_from_lat_lon(5.0, 30.0)
    obs = unit_from_lat_lon(0.0, 0.0)
    got = local_angles(points, up, north, sun, obs, observer_distance=radius + 5.0e5)
    inner = np.zeros(lat.shape, bool)
    inner[2:-2, 2:-2] = True
    o = (radius + 5.0e5) * obs - points
    np.testing.assert_allclose(
        got.incidence[inner], angle(up, np.broadcast_to(sun, up.shape))[inner], atol=1e-9
    )
    np.testing.assert_allclose(got.emission[inner], angle(up, o)[inner], atol=1e-9)
    np.testing.assert_allclose(got.slope[inner], 0.0, atol=1e-9)


def test_window_with_halo_equals_whole():
    """A window computed with two samples of margin equals the whole DEM's values there."""
    rng = np.random.default_rng(3)
    z = rng.normal(0.0, 1.0, (30, 40)).cumsum(axis=0).cumsum(axis=1) * 0.1
    points, up, north = plane_points(z, TRANSFORM[:2] + (0.0,) + TRANSFORM[3:5] + (0.0,))
    whole = local_angles(points, up, north, SUN, OBSERVER, observer_distance=DIST)
    rows, cols = slice(5, 17), slice(9, 31)
    halo_r, halo_c = slice(3, 19), slice(7, 33)
    p, u, n = plane_points(
        z[halo_r, halo_c], TRANSFORM[:2] + (0.0,) + TRANSFORM[3:5] + (0.0,), halo_r, halo_c
    )
    part = local_angles(p, u, n, SUN, OBSERVER, observer_distance=DIST)
    for name in ("incidence", "emission", "phase", "slope", "azimuth"):
        np.testing.assert_array_equal(
            getattr(part, name)[2:-2, 2:-2], getattr(whole, name)[rows, cols]
        )


def test_too_small_dem_refused():
    with pytest.raises(ValueError, match="at least 3 samples"):
        points, up, north = plane_points(np.zeros((2, 5)), TRANSFORM)
        local_angles(points, up, north, SUN, OBSERVER)


# ------------------------------------------------------------------------- files, the command
rasterio = pytest.importorskip("rasterio")
MOON_CRS = "+proj=eqc +lat_ts=0 +lat_0=0 +lon_0=0 +x_0=0 +y_0=0 +R=1737400 +units=m +no_defs"


def write_tif(path, data, transform, crs=MOON_CRS):
    from rasterio.transform import Affine

    with rasterio.open(
        path,
        "w",
        driver="GTiff",
        width=data.shape[1],
        height=data.shape[0],
        count=1,
        dtype="float32",
        crs=crs,
        transform=Affine(*transform),
    ) as d:
        d.write(data.astype(np.float32), 1)
    return path


def hill_dem(tmp_path):
    """A 100 × 120 DEM, 2 m pixels: an inclined plane with a Gaussian hill."""
    transform = (2.0, 0.0, 1000.0, 0.0, -2.0, 5000.0)
    rr, cc = np.mgrid[0:100, 0:120]
    z = 0.1 * cc - 0.05 * rr + 8.0 * np.exp(-((rr - 50) ** 2 + (cc - 60) ** 2) / 200.0)
    return write_tif(tmp_path / "dem.tif", z, transform), z, transform


def test_dem_geometry_windows_of_a_covering_dem(tmp_path):
    from roughdiffuse.planetary.dem import dem_geometry
    from roughdiffuse.planetary.rasters import open_plane

    dem_path, z, transform = hill_dem(tmp_path)
    # the image: 60 × 80 pixels from line 10, sample 20 of the DEM's grid
    img_t = (2.0, 0.0, 1000.0 + 20 * 2.0, 0.0, -2.0, 5000.0 - 10 * 2.0)
    image = write_tif(tmp_path / "img.tif", np.full((60, 80), 0.1), img_t)
    geo = dem_geometry(
        open_plane(dem_path),
        open_plane(image),
        sun=SUN,
        observer=OBSERVER,
        observer_distance=DIST,
    )
    assert geo.offset == (10, 20)
    points, up, north = plane_points(z.astype(np.float32), transform)
    whole = local_angles(points, up, north, SUN, OBSERVER, observer_distance=DIST)
    for rows, cols in ((slice(0, 60), slice(0, 80)), (slice(13, 40), slice(50, 80))):
        got = geo.angles(rows, cols)
        want = (slice(rows.start + 10, rows.stop + 10), slice(cols.start + 20, cols.stop + 20))
        for name in ("incidence", "emission", "phase", "slope", "azimuth"):
            np.testing.assert_array_equal(getattr(got, name), getattr(whole, name)[want])


def test_correct_with_dem_flattens_lambert_shading(tmp_path, capsys):
    """I/F = ρ cos i_local over the hill; the albedo method with Lambert gives back ρ."""
    from roughdiffuse import cli

    dem_path, z, transform = hill_dem(tmp_path)
    points, up, north = plane_points(z.astype(np.float32), transform)
    a = local_angles(points, up, north, SUN, OBSERVER)
    iof = 0.3 * np.cos(a.incidence)
    write_tif(tmp_path / "img.tif", iof, transform)
    argv = ["photometry", "correct", str(tmp_path / "img.tif"), "--dem", str(dem_path)]
    argv += ["--sun-vector", "0.3,-0.4,0.866", "--observer-vector=-0.1,0.2,1"]
    argv += ["--model", "lambert", "--chunk", "64", "-o", str(tmp_path / "out.tif")]
    assert cli.main(argv) == 0, capsys.readouterr().err
    with rasterio.open(tmp_path / "out.tif") as d:
        out = d.read(1)
    np.testing.assert_allclose(out, 0.3, rtol=2e-6)  # float32 files
    # a DEM that does not cover the image: one line, exit 2, nothing written
    write_tif(tmp_path / "small.tif", z[:50, :60], transform)
    argv[4] = str(tmp_path / "small.tif")
    argv[-1] = str(tmp_path / "none.tif")
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "small.tif does not cover the image" in err[0]
    assert not (tmp_path / "none.tif").exists()


def test_flat_dem_on_the_moon_through_its_map_projection(tmp_path):
    """Zero heights in a lunar equirectangular DEM: the local angles are the sphere's."""
    from roughdiffuse.planetary.dem import dem_geometry
    from roughdiffuse.planetary.rasters import open_plane

    radius = 1737400.0
    step = 200.0  # metres
    transform = (step, 0.0, 1.0e5, 0.0, -step, 3.0e5)
    dem = write_tif(tmp_path / "dem.tif", np.zeros((50, 60)), transform)
    sun, obs = unit_from_lat_lon(5.0, 30.0), unit_from_lat_lon(2.0, 1.0)
    geo = dem_geometry(
        open_plane(dem),
        open_plane(dem),
        sun=sun,
        observer=obs,
        frame="body",
        radius=radius,
        observer_distance=radius + 4.0e5,
    )
    got = geo.angles(slice(0, 50), slice(0, 60))
    # the samples' latitude and longitude, inverted by hand: eqc with R, lat_ts = 0
    rr, cc = np.mgrid[0:50, 0:60] + 0.5
    lon = np.degrees((1.0e5 + step * cc) / radius)
    lat = np.degrees((3.0e5 - step * rr) / radius)
    u = unit_from_lat_lon(lat, lon)
    o = (radius + 4.0e5) * obs - radius * u
    inner = (slice(2, -2), slice(2, -2))
    np.testing.assert_allclose(got.incidence[inner], angle(u, sun)[inner], atol=1e-9)
    np.testing.assert_allclose(got.emission[inner], angle(u, o)[inner], atol=1e-9)
    np.testing.assert_allclose(got.slope[inner], 0.0, atol=1e-9)


def test_angles_command_writes_five_planes(tmp_path, capsys):
    from roughdiffuse import cli

    dem_path, z, transform = hill_dem(tmp_path)
    out = tmp_path / "ang.tif"
    argv = ["photometry", "angles", str(dem_path), "--sun-vector", "0.3,-0.4,0.866"]
    argv += ["--observer-vector=-0.1,0.2,1", "--observer-distance", str(DIST)]
    assert cli.main([*argv, "--chunk", "48", "-o", str(out)]) == 0, capsys.readouterr().err
    points, up, north = plane_points(z.astype(np.float32), transform)
    want = local_angles(points, up, north, SUN, OBSERVER, observer_distance=DIST)
    for name in ("incidence", "emission", "phase", "slope", "azimuth"):
        with rasterio.open(tmp_path / f"ang-{name}.tif") as d:
            got = d.read(1)
            assert d.transform == rasterio.open(dem_path).transform
        np.testing.assert_array_equal(got, np.degrees(getattr(want, name)).astype(np.float32))
    # geometry missing: one line, exit 2, none of the five written
    assert cli.main(["photometry", "angles", str(dem_path), "-o", str(tmp_path / "x.tif")]) == 2
    assert "--sun-vector" in capsys.readouterr().err
    assert not list(tmp_path.glob("x-*"))
