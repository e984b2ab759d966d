"""Image files of any size for ``photometry correct``: ISIS3 cubes, PDS4, GeoTIFF, FITS, .npy
and .exr read and written by window (roughdiffuse.planetary.rasters), and the correction
chunk by chunk through dask.array (roughdiffuse.planetary.chunked).

References: the in-memory path (:func:`normalize` on whole arrays) for the chunked one; the
ISIS special-pixel values of ``isis/src/base/objs/SpecialPixel/SpecialPixel.h`` (USGS ISIS3),
typed in here as their bit patterns; an ISIS cube's label parsed by ``pvl`` (an independent
PVL reader) for its groups.
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

import roughdiffuse as rd
from roughdiffuse import cli
from roughdiffuse.models.photometry import radiance_factor
from roughdiffuse.planetary.backplanes import ellipsoid_backplanes
from roughdiffuse.planetary.chunked import (
    Correction,
    EllipsoidGeometry,
    FileGeometry,
    correct_file,
)
from roughdiffuse.planetary.correct import normalize, read_plane, write_plane
from roughdiffuse.planetary.rasters import HIS, HRS, LIS, LRS, NULL, VALID, open_plane
from test_photometry_cli import error_line  # one line on stderr, exit status 2

rasterio = pytest.importorskip("rasterio")
pytest.importorskip("astropy")
pytestmark = [
    pytest.mark.filterwarnings("ignore::rasterio.errors.NotGeoreferencedWarning"),
    pytest.mark.filterwarnings("ignore:Use `@` matmul:PendingDeprecationWarning"),  # rasterio's
]

# ISIS 4-byte special pixels, SpecialPixel.h: INULL4, ILOW_REPR_SAT4, ILOW_INSTR_SAT4,
# IHIGH_INSTR_SAT4, IHIGH_REPR_SAT4
ISIS_SPECIAL = np.array([0xFF7FFFFB, 0xFF7FFFFC, 0xFF7FFFFD, 0xFF7FFFFE, 0xFF7FFFFF], np.uint32)
MOON_CRS = "+proj=eqc +lat_ts=0 +lat_0=0 +lon_0=0 +x_0=0 +y_0=0 +R=1737400 +units=m +no_defs"
HAPKE = rd.Hapke(0.25, b0=1.2, h=0.06, theta_bar=math.radians(20.0))
SHAPE = (70, 90)


def scene(shape=SHAPE):
    """A Hapke moon's I/F (float32 values) and its backplanes (float32 degrees)."""
    bp = ellipsoid_backplanes(shape, (5.0, -40.0), (0.0, 0.0))
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    iof = np.full(shape, np.nan)
    iof[lit] = radiance_factor(HAPKE, bp.incidence[lit], bp.emission[lit], bp.phase[lit])
    deg = [np.degrees(a).astype(np.float32) for a in (bp.incidence, bp.emission, bp.phase)]
    return iof.astype(np.float32), deg


def write_gdal(path, data, driver, georef=True, corner=(-4500.0, 3500.0), **extra):
    """A plane (H, W) or bands (B, H, W) written by GDAL, on a lunar equirectangular grid of
    100 m pixels whose upper-left corner is ``corner`` (or without a map projection)."""
    from rasterio.transform import from_origin

    bands = data[None] if data.ndim == 2 else data
    kw = {"crs": MOON_CRS, "transform": from_origin(*corner, 100.0, 100.0)}
    with rasterio.open(
        path,
        "w",
        driver=driver,
        width=bands.shape[2],
        height=bands.shape[1],
        count=bands.shape[0],
        dtype=bands.dtype.name,
        **(kw if georef else {}),
        **extra,
    ) as d:
        d.write(bands)
    return path


def in_memory(iof, deg, method="albedo"):
    """The in-memory path, on the values the files hold (float32), to float32."""
    i, e, g = (np.radians(d.astype(np.float64)) for d in deg)
    lo, hi = np.abs(i - e), i + e
    g = np.clip(g, lo, hi)  # the stored float32 angles' rounding, as FileGeometry snaps it
    out = normalize(iof.astype(np.float64), i, e, g, HAPKE, method=method)
    return out.astype(np.float32)


@pytest.mark.parametrize("ext", ["cub", "xml", "tif", "fits", "npy", "exr"])
def test_plane_round_trip(tmp_path, ext):
    data = np.linspace(0.0, 1.0, 35 * 24).reshape(35, 24)
    data[3, 4] = np.nan
    write_plane(tmp_path / f"p.{ext}", data)
    got = read_plane(tmp_path / f"p.{ext}")
    np.testing.assert_array_equal(got, data.astype(np.float32).astype(np.float64))
    # a window is the same pixels
    plane = open_plane(tmp_path / f"p.{ext}")
    values, kind = plane.read(slice(2, 9), slice(3, 20))
    np.testing.assert_array_equal(values, got[2:9, 3:20])
    assert kind[1, 1] == NULL and (kind == VALID).sum() == kind.size - 1
    left = {p.name for p in tmp_path.iterdir()}
    assert left <= {f"p.{ext}", "p.img"}, left  # PDS4: the label and its data file


def test_isis_special_pixels_classified_and_kept(tmp_path, capsys):
    iof, deg = scene()
    raw = iof.copy()
    raw[np.isnan(raw)] = ISIS_SPECIAL[:1].view(np.float32)[0]
    spots = [(35, 45), (36, 45), (37, 45), (38, 45), (39, 45)]  # on the lit disk
    for (r, c), bits in zip(spots, ISIS_SPECIAL, strict=True):
        raw[r, c] = np.array([bits], np.uint32).view(np.float32)[0]
    write_gdal(tmp_path / "img.cub", raw, "ISIS3")
    for name, d in zip("ieg", deg, strict=True):
        write_gdal(tmp_path / f"{name}.cub", d, "ISIS3")
    _, kind = open_plane(tmp_path / "img.cub").read(slice(35, 40), slice(45, 46))
    assert kind.ravel().tolist() == [NULL, LRS, LIS, HIS, HRS]
    argv = ["photometry", "correct", str(tmp_path / "img.cub"), "--model", "hapke"]
    argv += [f"--{n}={tmp_path / (n[0] + '.cub')}" for n in ("incidence", "emission")]
    argv += [f"--phase={tmp_path / 'g.cub'}", "--param", "Wh=0.25", "--param", "B0=1.2"]
    argv += ["--param", "Hh=0.06", "--param", "Theta=20", "--chunk", "32"]
    assert cli.main([*argv, "-o", str(tmp_path / "out.cub")]) == 0
    with rasterio.open(tmp_path / "out.cub") as ds:
        out = ds.read(1)
    bits = out.view(np.uint32)
    for (r, c), special in zip(spots, ISIS_SPECIAL, strict=True):
        assert bits[r, c] == special  # each special pixel stays the same special pixel
    off = np.isnan(iof)
    assert np.all(bits[off] == ISIS_SPECIAL[0])  # off the body and unlit: Null
    # every other pixel is corrected, and equals the in-memory path
    ref = in_memory(iof, deg)
    keep = ~off
    for r, c in spots:
        keep[r, c] = False
    keep &= np.isfinite(ref)
    assert keep.sum() > 2000
    np.testing.assert_array_equal(out[keep], ref[keep])
    # to a GeoTIFF the special pixels are NaN
    assert cli.main([*argv, "-o", str(tmp_path / "out.tif")]) == 0
    tif = read_plane(tmp_path / "out.tif")
    assert all(np.isnan(tif[r, c]) for r, c in spots)


def test_isis_16_bit_special_pixels(tmp_path):
    """SpecialPixel.h: NULL2 … HIGH_REPR_SAT2 are −32768 … −32764; the rest is data."""
    raw = np.array([[-32768, -32767, -32766, -32765, -32764, -32763, 7]], np.int16)
    write_gdal(tmp_path / "s.cub", raw, "ISIS3", georef=False)
    values, kind = open_plane(tmp_path / "s.cub").read(slice(0, 1), slice(0, 7))
    assert kind.ravel().tolist() == [NULL, LRS, LIS, HIS, HRS, VALID, VALID]
    assert values[0, 5:].tolist() == [-32763.0, 7.0]


def test_fits_blank_and_scaling(tmp_path):
    from astropy.io import fits

    raw = np.array([[0, 5, -1], [7, -1, 2]], np.int16)
    hdu = fits.PrimaryHDU(raw)
    hdu.header["BSCALE"] = 0.5
    hdu.header["BZERO"] = 1.0
    hdu.header["BLANK"] = -1
    hdu.writeto(tmp_path / "b.fits")
    values, kind = open_plane(tmp_path / "b.fits").read(slice(0, 2), slice(0, 3))
    np.testing.assert_array_equal(values, [[1.0, 3.5, np.nan], [4.5, np.nan, 2.0]])
    assert kind.tolist() == [[VALID, VALID, NULL], [VALID, NULL, VALID]]


def test_cube_label_groups_carried(tmp_path):
    pvl = pytest.importorskip("pvl")
    iof, deg = scene()
    write_gdal(tmp_path / "img.cub", np.nan_to_num(iof, nan=0.0), "ISIS3")
    out = tmp_path / "out.cub"

    def correct() -> None:
        geometry = EllipsoidGeometry(SHAPE, (5.0, -40.0), (0.0, 0.0))
        correct_file(open_plane(tmp_path / "img.cub"), geometry, Correction(HAPKE), out, chunk=40)

    correct()
    a, b = pvl.load(str(tmp_path / "img.cub")), pvl.load(str(out))
    for group in ("Dimensions", "Pixels"):
        assert a["IsisCube"]["Core"][group] == b["IsisCube"]["Core"][group]
    assert a["IsisCube"]["Mapping"] == b["IsisCube"]["Mapping"]
    assert b["IsisCube"]["Mapping"]["ProjectionName"] == "Equirectangular"
    with rasterio.open(out) as d:
        first = d.read(1)
    # the rest of the label too: an Instrument group comes through
    body = "    SpacecraftName = MARS_RECONNAISSANCE_ORBITER\n    InstrumentId = HIRISE\n"
    set_label_group(tmp_path / "img.cub", "Instrument", body)
    correct()
    b = pvl.load(str(out))
    assert b["IsisCube"]["Instrument"]["InstrumentId"] == "HIRISE"
    assert a["IsisCube"]["Mapping"] == b["IsisCube"]["Mapping"]
    with rasterio.open(out) as d:
        got = d.read(1)
    np.testing.assert_array_equal(got, first)  # the corrected pixels, not the input's
    # a GeoTIFF output takes the map projection and pixel grid too
    correct_file(
        open_plane(tmp_path / "img.cub"),
        EllipsoidGeometry(SHAPE, (5.0, -40.0), (0.0, 0.0)),
        Correction(HAPKE),
        tmp_path / "out.tif",
    )
    with rasterio.open(tmp_path / "img.cub") as s, rasterio.open(tmp_path / "out.tif") as t:
        assert s.crs == t.crs and s.transform == t.transform


@pytest.mark.parametrize("chunk", [16, 37, 128])
@pytest.mark.parametrize("method", ["albedo", "mixed"])
def test_chunked_equals_in_memory(tmp_path, chunk, method):
    iof, deg = scene()
    np.save(tmp_path / "img.npy", iof)
    for name, d in zip("ieg", deg, strict=True):
        np.save(tmp_path / f"{name}.npy", d)
    geo = FileGeometry(*(open_plane(tmp_path / f"{n}.npy") for n in "ieg"))
    _, n = correct_file(
        open_plane(tmp_path / "img.npy"),
        geo,
        Correction(HAPKE, method=method),
        tmp_path / "out.npy",
        chunk=chunk,
    )
    ref = in_memory(iof, deg, method)
    got = np.load(tmp_path / "out.npy")
    np.testing.assert_array_equal(got, ref)
    assert n == np.isfinite(ref).sum() > 2000


def test_ellipsoid_window_is_the_whole_image_there():
    whole = ellipsoid_backplanes((50, 60), (10.0, 30.0), (-5.0, 0.0), (1.0, 0.9, 0.8))
    part = ellipsoid_backplanes(
        (50, 60), (10.0, 30.0), (-5.0, 0.0), (1.0, 0.9, 0.8), window=(slice(7, 31), slice(40, 60))
    )
    for name in ("incidence", "emission", "phase"):
        np.testing.assert_array_equal(getattr(part, name), getattr(whole, name)[7:31, 40:60])


def test_interrupted_run_writes_nothing(tmp_path):
    iof, _ = scene()
    np.save(tmp_path / "img.npy", iof)

    class Failing(EllipsoidGeometry):
        def read(self, rows, cols):
            if rows.start > 30:
                raise KeyboardInterrupt
            return super().read(rows, cols)

    before = sorted(os.listdir(tmp_path))
    for ext in ("npy", "cub", "xml", "tif", "fits"):
        with pytest.raises(KeyboardInterrupt):
            correct_file(
                open_plane(tmp_path / "img.npy"),
                Failing(SHAPE, (5.0, -40.0), (0.0, 0.0)),
                Correction(HAPKE),
                tmp_path / f"out.{ext}",
                chunk=16,
            )
        assert sorted(os.listdir(tmp_path)) == before


def test_progress_bar_counts_chunks(tmp_path, capsys):
    iof, _ = scene()
    np.save(tmp_path / "img.npy", iof)
    correct_file(
        open_plane(tmp_path / "img.npy"),
        EllipsoidGeometry(SHAPE, (5.0, -40.0), (0.0, 0.0)),
        Correction(HAPKE),
        tmp_path / "out.npy",
        chunk=32,
        progress=True,
    )
    err = capsys.readouterr().err
    assert "photometry correct" in err and "9/9" in err and "chunk" in err  # 3 × 3 chunks


def test_dask_cluster_output_identical(tmp_path):
    distributed = pytest.importorskip("distributed")
    iof, deg = scene()
    np.save(tmp_path / "img.npy", iof)
    for name, d in zip("ieg", deg, strict=True):
        np.save(tmp_path / f"{name}.npy", d)
    args = (
        open_plane(tmp_path / "img.npy"),
        FileGeometry(*(open_plane(tmp_path / f"{n}.npy") for n in "ieg")),
        Correction(HAPKE, method="mixed"),
    )
    correct_file(*args, tmp_path / "one.cub", chunk=24)
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        correct_file(*args, tmp_path / "two.cub", chunk=24, scheduler=client)
    with rasterio.open(tmp_path / "one.cub") as a, rasterio.open(tmp_path / "two.cub") as b:
        one, two = a.read(1), b.read(1)
    assert one.tobytes() == two.tobytes()  # bit for bit (the labels differ in their history)
    assert np.isfinite(one).sum() > 2000


# ------------------------------------------------------------------------- bad input
def test_bad_input_one_line_nothing_written(tmp_path, capsys):
    iof, deg = scene()
    write_gdal(tmp_path / "img.tif", iof, "GTiff")
    for name, d in zip("ieg", deg, strict=True):
        write_gdal(tmp_path / f"{name}.tif", d, "GTiff")
    base = ["photometry", "correct", str(tmp_path / "img.tif")]
    planes = [f"--incidence={tmp_path / 'i.tif'}", f"--emission={tmp_path / 'e.tif'}"]
    out = tmp_path / "out.cub"
    good = [*base, *planes, f"--phase={tmp_path / 'g.tif'}", "-o", str(out)]
    before = sorted(os.listdir(tmp_path))
    # the output is an input
    error_line(
        capsys,
        [*base, *planes, f"--phase={tmp_path / 'g.tif'}", "-o", str(tmp_path / "i.tif")],
        "one of the inputs",
    )
    # a backplane on another pixel grid
    write_gdal(tmp_path / "shifted.tif", deg[2], "GTiff", corner=(0.0, 0.0))
    error_line(
        capsys,
        [*base, *planes, f"--phase={tmp_path / 'shifted.tif'}", "-o", str(out)],
        "--phase",
        "map projection or pixel grid",
    )
    # chunks too small and too large for the memory
    error_line(capsys, [*good, "--chunk", "4"], "--chunk", "[16, 16384]")
    error_line(capsys, [*good, "--chunk", "16384"], "--chunk")
    # a label GDAL cannot read
    (tmp_path / "bad.cub").write_bytes(b"Object = IsisCube\n  garbage\n")
    error_line(capsys, [*good[:2], str(tmp_path / "bad.cub"), *good[3:]], "bad.cub", "GDAL")
    # a band the image does not have
    error_line(capsys, [*good, "--band", "Phase Angle"], "img.tif", "no band named")
    # an impossible geometry: phase beyond i + e
    bad_g = deg[2].copy()
    bad_g[35, 45] = 179.0
    write_gdal(tmp_path / "badg.tif", bad_g, "GTiff")
    error_line(
        capsys,
        [*base, *planes, f"--phase={tmp_path / 'badg.tif'}", "-o", str(out)],
        "backplanes i.tif, e.tif, badg.tif",
        "phase must be in",
    )
    assert not out.exists()
    assert sorted(os.listdir(tmp_path)) == sorted([*before, "shifted.tif", "bad.cub", "badg.tif"])
    # an unknown output format
    error_line(capsys, [*good[:-1], str(tmp_path / "out.png")], "-o", "unknown format")


@pytest.mark.slow  # the fit's starting points: about 4 s
def test_fit_samples_an_image(tmp_path, capsys):
    """Lunar-Lambert is fitted from the pixels of a cube of its own I/F: ρ and L come back."""
    shape = (80, 80)
    bp = ellipsoid_backplanes(shape, (0.0, 35.0), (0.0, 0.0))
    lit = bp.on_body & (bp.incidence < math.radians(85)) & (bp.emission < math.radians(85))
    iof = np.full(shape, np.nan)
    iof[lit] = radiance_factor(
        rd.LunarLambert(0.12, 0.6), bp.incidence[lit], bp.emission[lit], bp.phase[lit]
    )
    write_gdal(tmp_path / "img.cub", iof.astype(np.float32), "ISIS3")
    argv = ["photometry", "fit", str(tmp_path / "img.cub"), "--model", "lunar-lambert"]
    argv += ["--subsolar", "0,35", "--subobserver", "0,0", "--samples", "400", "--chunk", "32"]
    assert cli.main(argv) == 0
    out = capsys.readouterr().out
    n = int(out.split(" samples")[0].split()[-1])
    assert 340 <= n <= 400, out  # each data pixel kept with probability 400/N
    vals = {
        line.split()[0]: float(line.split()[1])
        for line in out.splitlines()
        if line.strip().startswith(("albedo", "limb_darkening"))
    }
    assert vals["albedo"] == pytest.approx(0.12, rel=1e-4)
    assert vals["limb_darkening"] == pytest.approx(0.6, rel=1e-3)


def set_label_group(path, group, body=""):
    """Put a group (``body``: its keyword lines) into an ISIS cube's attached label after
    the Core object, replacing one of that name, or take it out (no body). The cube is
    GDAL's: its label is padded to 65536 bytes, so there is room."""
    data = bytearray(path.read_bytes())
    label = data[:65536].decode("latin-1")
    start = label.find(f"  Group = {group}\n")
    if start >= 0:
        end = label.index("  End_Group\n", start) + len("  End_Group\n")
        label = label[:start] + label[end:]
    if body:
        at = label.index("  End_Object\n") + len("  End_Object\n")
        label = label[:at] + f"  Group = {group}\n{body}  End_Group\n" + label[at:]
    data[:65536] = label.encode("latin-1").ljust(65536, b"\0")[:65536]
    path.write_bytes(bytes(data))


def with_band_bin(path, *names):
    """Name a cube's bands in a BandBin group (no names: take it out)."""
    body = f"    Name = ({', '.join(names)})\n" if any(names) else ""
    set_label_group(path, "BandBin", body)


def test_parameter_map_cube(tmp_path, capsys):
    """A cube of w and θ̄ (degrees) per pixel, bands named by --bands: the corrected image is
    the in-memory path with those maps; a band no parameter of the model is refused."""
    iof, deg = scene()
    w = np.full(SHAPE, 0.25, np.float32)
    w[:, 45:] = 0.3
    theta = np.full(SHAPE, 20.0, np.float32)
    theta[30:, :] = 25.0
    write_gdal(tmp_path / "maps.cub", np.stack([w, theta]), "ISIS3", georef=False)
    for name, d in zip("ieg", deg, strict=True):
        np.save(tmp_path / f"{name}.npy", d)
    np.save(tmp_path / "img.npy", iof)
    argv = ["photometry", "correct", str(tmp_path / "img.npy"), "--model", "hapke"]
    argv += [f"--{n}={tmp_path / (n[0] + '.npy')}" for n in ("incidence", "emission")]
    argv += [f"--phase={tmp_path / 'g.npy'}", "--param", "B0=1.2", "--param", "Hh=0.06"]
    argv += ["--param-map", str(tmp_path / "maps.cub"), "--chunk", "64"]
    assert cli.main([*argv, "--bands", "Wh,Theta", "-o", str(tmp_path / "o.npy")]) == 0
    i, e, g = (np.radians(d.astype(np.float64)) for d in deg)
    g = np.clip(g, np.abs(i - e), i + e)
    ref = normalize(
        iof.astype(np.float64),
        i,
        e,
        g,
        HAPKE,
        params={"albedo": w.astype(np.float64), "theta_bar": np.radians(theta.astype(np.float64))},
    ).astype(np.float32)
    np.testing.assert_array_equal(np.load(tmp_path / "o.npy"), ref)
    assert not np.array_equal(ref, in_memory(iof, deg), equal_nan=True)  # the maps matter
    # the same with the bands named in the cube's label (an ISIS BandBin group)
    with_band_bin(tmp_path / "maps.cub", "Wh", "Theta")
    assert cli.main([*argv, "-o", str(tmp_path / "o2.npy")]) == 0
    np.testing.assert_array_equal(np.load(tmp_path / "o2.npy"), ref)
    with_band_bin(tmp_path / "maps.cub", "", "")  # back to unnamed bands
    error_line(
        capsys,
        [*argv, "--bands", "Wh,K", "-o", str(tmp_path / "x.npy")],
        "maps.cub",
        "band 2 ('K') is no parameter of hapke",
    )
    error_line(capsys, [*argv, "-o", str(tmp_path / "x.npy")], "maps.cub", "--bands")
    error_line(capsys, [*argv, "--bands", "Wh", "-o", str(tmp_path / "x.npy")], "has 2")
    assert not (tmp_path / "x.npy").exists()


def test_options_that_do_not_apply_are_refused(tmp_path, capsys):
    iof, _ = scene()
    np.save(tmp_path / "img.npy", iof)
    base = ["photometry", "correct", str(tmp_path / "img.npy"), "-o", str(tmp_path / "o.npy")]
    sphere = ["--subsolar", "5,-40", "--subobserver", "0,0"]
    error_line(capsys, [*base, *sphere, "--bands", "Wh"], "--bands", "--param-map")
    error_line(capsys, [*base, *sphere, "--albedo", "0.2"], "--albedo", "--method")
    error_line(capsys, [*base, *sphere, "--sun-vector", "0,0,1"], "--sun-vector", "--dem")
    error_line(capsys, [*base, *sphere, "--method", "topo", "--match", "30,30,0"], "--match")
    csv = tmp_path / "d.csv"
    csv.write_text("I/F,i,e,g\n0.1,30,20,40\n0.1,40,20,50\n")
    error_line(
        capsys, ["photometry", "fit", str(csv), "--samples", "50"], "--samples", "image DATA"
    )
    assert not (tmp_path / "o.npy").exists()


def test_cloud_optimised_geotiff_output(tmp_path):
    iof, _ = scene((600, 700))
    write_gdal(tmp_path / "img.tif", iof, "GTiff")
    args = (
        open_plane(tmp_path / "img.tif"),
        EllipsoidGeometry((600, 700), (5.0, -40.0), (0.0, 0.0)),
        Correction(HAPKE),
    )
    correct_file(*args, tmp_path / "plain.tif", chunk=256)
    correct_file(*args, tmp_path / "cog.tif", out_fmt="cog", chunk=256)
    with rasterio.open(tmp_path / "cog.tif") as c, rasterio.open(tmp_path / "plain.tif") as p:
        assert c.tags(ns="IMAGE_STRUCTURE").get("LAYOUT") == "COG"
        assert c.overviews(1)  # overviews for viewers
        assert c.crs == p.crs and c.transform == p.transform
        np.testing.assert_array_equal(c.read(1), p.read(1))
    assert sorted(q.name for q in tmp_path.iterdir()) == ["cog.tif", "img.tif", "plain.tif"]


def test_tiled_cube_read_by_window(tmp_path):
    """A tiled ISIS cube (GDAL's ISIS3 driver, TILED=YES) reads the same as a BSQ one."""
    data = np.arange(100 * 130, dtype=np.float32).reshape(100, 130) / 1000.0
    write_gdal(tmp_path / "t.cub", data, "ISIS3", TILED="YES", BLOCKXSIZE=32, BLOCKYSIZE=32)
    plane = open_plane(tmp_path / "t.cub")
    assert plane.block == (32, 32)
    values, kind = plane.read(slice(17, 83), slice(40, 129))
    np.testing.assert_array_equal(values, data[17:83, 40:129])
    assert (kind == VALID).all()
