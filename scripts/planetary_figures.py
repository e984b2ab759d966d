"""Make the pictures of docs/planetary.md (the full moon, a disk-resolved fit, two corrected
images and their mosaic, angles from a DEM) into docs/images/. Run:
python scripts/planetary_figures.py"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import roughdiffuse as rd
from roughdiffuse._figure import colormap, subplots
from roughdiffuse.models.photometry import radiance_factor
from roughdiffuse.planetary.backplanes import ellipsoid_backplanes
from roughdiffuse.planetary.correct import normalize
from roughdiffuse.planetary.disk import DiskData, fit_disk, plot_disk_fit

OUT = Path(__file__).resolve().parent.parent / "docs" / "images"
GREY = colormap("gray").with_extremes(bad="black")  # off the body: black sky
HAPKE = {"b0": 1.2, "h": 0.06, "g": -0.3, "theta_bar": math.radians(20.0)}


def disk_iof(model, bp):
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    out = np.full(bp.emission.shape, np.nan)
    out[lit] = radiance_factor(model, bp.incidence[lit], bp.emission[lit], bp.phase[lit])
    return out


def full_moon() -> None:
    bp = ellipsoid_backplanes((201, 201), (0.0, 0.0), (0.0, 0.0))
    models = [
        ("Lambert", rd.Lambert(1.0)),
        ("Lommel–Seeliger", rd.LommelSeeliger(1.0)),
        ("Lunar-Lambert L = 1", rd.LunarLambert(1.0, 1.0)),
        ("Hapke (lunar)", rd.Hapke(0.25, **HAPKE)),
    ]
    fig, axes = subplots(1, 5, figsize=(17, 3.6), layout="constrained")
    x = np.linspace(-1, 1, 201) / 1.05
    for ax, (name, m) in zip(axes[:4], models, strict=True):
        img = disk_iof(m, bp)
        img /= np.nanmax(img)
        ax.imshow(img, cmap=GREY, vmin=0, vmax=1.15)
        ax.set_title(name, fontsize=10)
        ax.set_axis_off()
        axes[4].plot(x, img[100], label=name)
    axes[4].set_xlabel("position across the disk (radius 1)")
    axes[4].set_ylabel("I/F, relative to the brightest point")
    axes[4].set_ylim(0, 1.05)
    axes[4].legend(fontsize=8, loc="lower center")
    fig.suptitle("The full moon (phase 0°): only the Lambertian sphere darkens to its limb")
    fig.savefig(OUT / "planetary-full-moon.png", dpi=90)


def flyby(rng, phases_deg, per_image=60):
    out, v = [], np.array([0.0, 0.0, 1.0])
    for gdeg in phases_deg:
        g = math.radians(gdeg)
        s = np.array([math.sin(g), 0.0, math.cos(g)])
        n = rng.normal(size=(30 * per_image, 3))
        n /= np.linalg.norm(n, axis=1)[:, None]
        lim = math.cos(math.radians(80.0))
        n = n[(n @ s > lim) & (n @ v > lim)][:per_image]
        out.append(np.stack([np.arccos(n @ s), np.arccos(n @ v), np.full(len(n), g)]))
    return np.concatenate(out, axis=1)


def disk_fit() -> None:
    rng = np.random.default_rng(3)
    i, e, g = flyby(rng, [5, 8, 12, 20, 30, 45, 60, 75, 90])
    truth = rd.Hapke(0.3, 1.6, 0.06, -0.3, math.radians(20.0))
    iof = radiance_factor(truth, i, e, g) * (1.0 + 0.01 * rng.normal(size=i.size))
    f = fit_disk("hapke", DiskData(iof, i, e, g, source="synthetic flyby"), fixed={"hg2": 0.0})
    print(f.table())
    plot_disk_fit(f).savefig(OUT / "planetary-disk-fit.png", dpi=80)


def albedo_map(lat, lon):
    return 0.25 * (1.0 + 0.15 * np.sin(3.0 * lon) * np.cos(lat) + 0.1 * np.cos(5.0 * lat))


def hapke_image(bp):
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    w = albedo_map(bp.latitude[lit], bp.longitude[lit])
    mu0, mu = np.cos(bp.incidence[lit]), np.cos(bp.emission[lit])
    p = {k: np.full(w.shape, v) for k, v in HAPKE.items()}
    f = rd.Hapke(0.25, **HAPKE).kernel(
        np, mu0, mu, np.cos(bp.phase[lit]), albedo=w, hg2=np.zeros(w.shape), **p
    )
    out = np.full(bp.emission.shape, np.nan)
    out[lit] = math.pi * mu0 * f
    return out


def mosaic() -> None:
    model = rd.Hapke(0.25, **HAPKE)
    shots = []
    for sun in ((0.0, 25.0), (5.0, -60.0)):
        bp = ellipsoid_backplanes((240, 240), sun, (0.0, 0.0))
        raw = hapke_image(bp)
        shots.append((bp, raw, normalize(raw, bp.incidence, bp.emission, bp.phase, model)))
    (bpa, ra, ca), (bpb, rb, cb) = shots
    half = np.zeros(ra.shape, bool)
    half[:, :120] = True  # each image where it is well lit: B on the left, A on the right
    raw_mosaic = np.where(half, rb, ra)
    cor_mosaic = np.where(half, cb, ca)
    fig, axes = subplots(2, 3, figsize=(11, 8), layout="constrained")
    axes = axes.ravel()
    panels = [
        (ra, f"image A, g = {math.degrees(np.nanmax(bpa.phase)):.0f}° (I/F)"),
        (rb, f"image B, g = {math.degrees(np.nanmax(bpb.phase)):.0f}° (I/F)"),
        (raw_mosaic, "mosaic B | A as taken"),
        (ca, "A corrected (albedo method)"),
        (cb, "B corrected"),
        (cor_mosaic, "mosaic of the corrected B | A"),
    ]
    top = {0: np.nanpercentile(np.concatenate([ra.ravel(), rb.ravel()]), 99.5)}
    top[1] = np.nanpercentile(np.concatenate([ca.ravel(), cb.ravel()]), 99.5)
    for k, (ax, (img, title)) in enumerate(zip(axes, panels, strict=True)):
        vmax = top[k // 3]  # one scale for the images as taken, one for the corrected
        ax.imshow(img, cmap=GREY, vmin=0, vmax=vmax)
        ax.axvline(119.5, color="tab:red", lw=0.6, ls=":")
        ax.set_title(title, fontsize=9)
        ax.set_axis_off()
    fig.suptitle(
        "Two images of one moon at different phase, normalised to i = e = g = 0 and "
        "joined at the dotted line"
    )
    fig.savefig(OUT / "planetary-mosaic.png", dpi=80)


def dem_terrain(n: int = 240) -> tuple[np.ndarray, tuple[float, ...]]:
    """Heights (m) of a 1 m-pixel terrain: a slope, a crater with a raised rim, a hill."""
    rr, cc = np.mgrid[0:n, 0:n].astype(np.float64)
    z = 0.08 * cc
    r = np.hypot(rr - 0.45 * n, cc - 0.38 * n) / (0.18 * n)
    z += np.where(r < 1.0, 14.0 * (r**2 - 1.0), 0.0) + 6.0 * np.exp(-(((r - 1.0) / 0.25) ** 2))
    z += 18.0 * np.exp(-((rr - 0.72 * n) ** 2 + (cc - 0.75 * n) ** 2) / (0.08 * n) ** 2)
    return z, (1.0, 0.0, 0.0, 0.0, -1.0, float(n))


def dem_correction() -> None:
    """Local angles from a DEM and an image corrected with them, through the files."""
    import tempfile

    import rasterio
    from rasterio.transform import Affine

    from roughdiffuse.planetary.chunked import Correction, correct_file
    from roughdiffuse.planetary.dem import dem_geometry, local_angles, plane_points
    from roughdiffuse.planetary.rasters import open_plane

    z, transform = dem_terrain()
    sun = (math.sin(math.radians(60)), 0.0, math.cos(math.radians(60)))  # i = 60° from the east
    view = (0.0, 0.0, 1.0)
    points, up, north = plane_points(z.astype(np.float32), transform)
    a = local_angles(points, up, north, sun, view)
    rr, cc = np.mgrid[0 : z.shape[0], 0 : z.shape[1]]
    albedo = 0.12 * (1.0 + 0.25 * (np.sin(cc / 9.0) * np.sin(rr / 13.0) > 0.3))
    lit = a.incidence < math.pi / 2
    model = rd.LunarLambert(1.0, 0.6)
    iof = np.full(z.shape, np.nan)
    iof[lit] = albedo[lit] * radiance_factor(model, a.incidence[lit], a.emission[lit], a.phase[lit])
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        prof = {"driver": "GTiff", "width": z.shape[1], "height": z.shape[0], "count": 1}
        prof.update(dtype="float32", transform=Affine(*transform))
        for name, data in (("dem", z), ("img", iof)):
            with rasterio.open(folder / f"{name}.tif", "w", **prof) as d:
                d.write(data.astype(np.float32), 1)
        image = open_plane(folder / "img.tif")
        geo = dem_geometry(open_plane(folder / "dem.tif"), image, sun=sun, observer=view)
        correct_file(image, geo, Correction(model), folder / "out.tif", chunk=64)
        corrected = open_plane(folder / "out.tif").read_all()
    flat = normalize(
        iof,
        np.full(z.shape, math.radians(60)),
        np.zeros(z.shape),
        np.full(z.shape, math.radians(60)),
        model,
    )  # the DEM ignored
    fig, axes = subplots(2, 4, figsize=(14, 7.4), layout="constrained")
    deg = np.degrees
    panels = [
        (z, "DEM height (m)", "terrain", None),
        (deg(a.incidence), "local incidence i (°)", "viridis", None),
        (deg(a.slope), "slope (°)", "magma", None),
        (deg(a.azimuth), "azimuth the slope faces (° from north)", "twilight", (0, 360)),
        (albedo, "albedo (the truth)", GREY, (0, 0.17)),
        (iof, "I/F: Lunar-Lambert, sun from the east at 60°", GREY, None),
        (flat, "corrected without the DEM (flat: i = 60°)", GREY, (0, 0.17)),
        (corrected, "corrected with the DEM (--dem)", GREY, (0, 0.17)),
    ]
    for ax, (img, title, cmap, lims) in zip(axes.ravel(), panels, strict=True):
        vmin, vmax = lims if lims else (np.nanmin(img), np.nanmax(img))
        im = ax.imshow(img, cmap=cmap, vmin=vmin, vmax=vmax)
        ax.set_title(title, fontsize=9)
        ax.set_axis_off()
        fig.colorbar(im, ax=ax, shrink=0.7)
    fig.suptitle(
        "Angles from a DEM (1 m pixels) and an image normalised with them: the albedo "
        "pattern comes back, the relief goes"
    )
    fig.savefig(OUT / "planetary-dem.png", dpi=80)


def cube_on_a_cluster(n: int = 512, chunk: int = 128) -> None:
    """A moon written as ISIS cubes, corrected in chunks on a local Dask cluster of two
    workers, against the in-memory path."""
    import tempfile

    import distributed

    from roughdiffuse.planetary.chunked import Correction, FileGeometry, correct_file
    from roughdiffuse.planetary.correct import write_plane
    from roughdiffuse.planetary.rasters import open_plane

    bp = ellipsoid_backplanes((n, n), (5.0, -50.0), (0.0, 0.0))
    raw = hapke_image(bp)
    model = rd.Hapke(0.25, **HAPKE)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        write_plane(folder / "img.cub", raw)
        for name, a in (("i", bp.incidence), ("e", bp.emission), ("g", bp.phase)):
            write_plane(folder / f"{name}.cub", np.degrees(a))
        planes = [open_plane(folder / f"{k}.cub") for k in ("img", "i", "e", "g")]
        with (
            distributed.LocalCluster(
                n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
            ) as cluster,
            distributed.Client(cluster) as client,
        ):
            correct_file(planes[0], FileGeometry(*planes[1:]), Correction(model),
                         folder / "out.cub", chunk=chunk, scheduler=client)  # fmt: skip
        out = open_plane(folder / "out.cub").read_all()
        img, i, e, g = (p.read_all() for p in planes)
    i, e, g = (np.radians(a) for a in (i, e, g))
    g = np.clip(g, np.abs(i - e), i + e)
    ref = normalize(img, i, e, g, model).astype(np.float32)
    diff = np.where(np.isfinite(ref), np.abs(out.astype(np.float32) - ref), np.nan)
    fig, axes = subplots(1, 3, figsize=(13, 4.8), layout="constrained")
    top = np.nanpercentile(out, 99.5)
    panels = [
        (raw, "I/F, an ISIS cube (phase 50°)", GREY, 0, np.nanpercentile(raw, 99.5)),
        (out, f"corrected on 2 Dask workers, {chunk}² chunks", GREY, 0, top),
        (diff, f"|cluster − in-memory| (max {np.nanmax(diff):g})", "viridis", 0, 1e-7),
    ]
    for k, (ax, (data, title, cmap, lo, hi)) in enumerate(zip(axes, panels, strict=True)):
        im = ax.imshow(data, cmap=cmap, vmin=lo, vmax=hi)
        if k == 1:
            for x in range(chunk, n, chunk):
                ax.axvline(x - 0.5, color="tab:red", lw=0.5, ls=":")
                ax.axhline(x - 0.5, color="tab:red", lw=0.5, ls=":")
        ax.set_title(title, fontsize=9)
        ax.set_axis_off()
        fig.colorbar(im, ax=ax, shrink=0.75)
    fig.suptitle("A cube corrected chunk by chunk on a local cluster: the same pixels as in memory")
    fig.savefig(OUT / "planetary-cluster.png", dpi=80)


if __name__ == "__main__":
    full_moon()
    mosaic()
    disk_fit()
    dem_correction()
    cube_on_a_cluster()
