"""Benchmark: ``photometry correct`` on image files of any size, chunk by chunk.

Two measurements; the section "Planetary images" of ``bench/RESULTS.md`` is rewritten::

    python bench/planetary_bench.py [--size 4096] [--scale 20000x50000] [--chunk 512] [--write]
                                    [--workdir DIR] [--no-write]

* **Correctness.** A ``--size`` × ``--size`` synthetic scene (a Hapke moon whose albedo
  varies by ±10 %, with its incidence, emission and phase backplanes) is written three ways:
  as ISIS3 cubes by GDAL's ISIS3 driver (with a lunar equirectangular map projection), as
  GeoTIFF and as FITS. Each is corrected (Hapke, albedo method). Checked: the three outputs
  are equal in float32; they equal the in-memory path (:func:`normalize` on the whole planes,
  as read from the files); the output cube's Dimensions, Pixels and Mapping groups (parsed
  by ``pvl``) equal the input's; the run on a local Dask cluster of two workers (one thread
  each, in this process) writes the same pixels, bit for bit, as the threaded run.
* **Scale.** A ``--scale`` LINES×SAMPLES float32 image and its three backplanes, tiled
  GeoTIFF written window by window (every pixel on the body: a zoom into a sphere), are
  corrected with Hapke by the command line in a child
  process: wall time, CPU time, and the child's own peak resident memory (``VmHWM``, which
  the child reports at exit; Linux only). Targets for 20000×50000 on 2 cores:
  at most 20 minutes and 2 GB. A crop of at most 4096 × 4096 of the output is checked against
  the in-memory path on the same crop.

The machine may be shared: the load average is noted. ``--size 1024 --scale 2000x5000`` is a
quick check.
"""

from __future__ import annotations

import argparse
import math
import os
import re
import resource
import tempfile
import time
from pathlib import Path

import numpy as np

import roughdiffuse as rd
from roughdiffuse.io.atomic import write_text
from roughdiffuse.models.photometry import radiance_factor
from roughdiffuse.planetary.backplanes import ellipsoid_backplanes
from roughdiffuse.planetary.chunked import Correction, FileGeometry, correct_file
from roughdiffuse.planetary.correct import normalize
from roughdiffuse.planetary.rasters import blocks_of, open_plane, write_blocks
from roughdiffuse.programs import PYTHON
from roughdiffuse.programs import run as run_program

HAPKE = {"b0": 1.2, "h": 0.06, "theta_bar": math.radians(20.0)}
PARAMS = ["Wh=0.25", "B0=1.2", "Hh=0.06", "Theta=20"]
SUN, VIEW = (5.0, -40.0), (0.0, 0.0)
_MEASURED = """\
import re, sys
from roughdiffuse.cli import main
report, sys.argv = sys.argv[1], ["roughdiffuse", *sys.argv[2:]]
try:
    code = main()
finally:
    status = open("/proc/self/status").read()
    open(report, "w").write(re.search(r"VmHWM:\\s*(\\d+) kB", status).group(1))
sys.exit(code)
"""
"""The command line run in a child that writes its own peak RSS (KiB; ``VmHWM`` of
``/proc/self/status``, the high-water mark of the program's own memory since it started) to
the file named by its first argument. Not ``ru_maxrss``: Linux carries the high-water mark of
the process image replaced by ``exec`` into it, so a child forked from a parent that holds
2 GB reports at least 2 GB."""

MOON_CRS = "+proj=eqc +lat_ts=0 +lat_0=0 +lon_0=0 +x_0=0 +y_0=0 +R=1737400 +units=m +no_defs"


def filling_margin(shape) -> float:
    """The margin (negative: a zoom) that puts the whole image on the body (corners at 0.95
    of its radius): a scene without empty pixels for the scale run."""
    m = min(shape)
    return 0.95 / math.hypot(shape[0] / m, shape[1] / m) - 1.0


def scene_window(shape, rows, cols, margin=0.05):
    """I/F and (i, e, g) in degrees of a window of the synthetic scene, float32."""
    bp = ellipsoid_backplanes(shape, SUN, VIEW, margin=margin, window=(rows, cols))
    lit = bp.on_body & (bp.incidence < math.pi / 2)
    iof = np.full(bp.incidence.shape, np.nan)
    pattern = 1.0 + 0.1 * np.sin(3.0 * bp.longitude[lit]) * np.cos(bp.latitude[lit])
    model = rd.Hapke(0.25, **HAPKE)
    iof[lit] = pattern * radiance_factor(model, bp.incidence[lit], bp.emission[lit], bp.phase[lit])
    planes = [iof] + [np.degrees(a) for a in (bp.incidence, bp.emission, bp.phase)]
    return [p.astype(np.float32) for p in planes]


def write_scene(folder: Path, shape, fmt: str, chunk: int, margin=0.05) -> list[Path]:
    """The scene's four planes (img, i, e, g) in ``fmt``, written window by window."""
    ext = {"isis3": "cub", "gtiff": "tif", "fits": "fits"}[fmt]
    paths = [folder / f"{n}.{ext}" for n in ("img", "i", "e", "g")]
    if fmt == "fits":
        for k, path in enumerate(paths):
            blocks = (
                (r, c, scene_window(shape, r, c, margin)[k])
                for r, c in blocks_of(shape, (chunk, chunk))
            )
            write_blocks(path, shape, blocks)
        return paths
    import rasterio
    from rasterio.transform import from_origin
    from rasterio.windows import Window

    h, w = shape
    profile = {
        "driver": {"isis3": "ISIS3", "gtiff": "GTiff"}[fmt],
        "width": w,
        "height": h,
        "count": 1,
        "dtype": "float32",
        "crs": MOON_CRS,
        "transform": from_origin(-w * 50.0, h * 50.0, 100.0, 100.0),
    }
    if fmt == "gtiff":
        profile.update(tiled=True, blockxsize=512, blockysize=512, nodata=float("nan"))
        profile["BIGTIFF"] = "YES"
    with rasterio.Env(GDAL_CACHEMAX=64):
        dsts = [rasterio.open(p, "w", **profile) for p in paths]
        try:
            for r, c in blocks_of(shape, (chunk, chunk)):
                win = Window(c.start, r.start, c.stop - c.start, r.stop - r.start)
                for dst, plane in zip(dsts, scene_window(shape, r, c, margin), strict=True):
                    if fmt == "isis3":
                        plane = np.where(np.isnan(plane), np.float32(dst.nodata), plane)
                    dst.write(plane, 1, window=win)
        finally:
            for d in dsts:
                d.close()
    return paths


def in_memory(paths, rows=None, cols=None):
    """The in-memory path on the planes as the files hold them (a window of them)."""
    planes = [open_plane(p) for p in paths]
    h, w = planes[0].shape
    rows, cols = rows or slice(0, h), cols or slice(0, w)
    img, i, e, g = (p.read(rows, cols)[0] for p in planes)
    i, e, g = (np.radians(a) for a in (i, e, g))
    g = np.clip(g, np.abs(i - e), i + e)  # float32 rounding of stored angles, as FileGeometry
    return normalize(img, i, e, g, rd.Hapke(0.25, **HAPKE)).astype(np.float32)


def as_nan(path) -> np.ndarray:
    return open_plane(path).read_all().astype(np.float32)


def correctness(folder: Path, size: int, chunk: int) -> list[str]:
    import distributed
    import pvl

    shape = (size, size)
    outs, times = {}, {}
    model = rd.Hapke(0.25, **HAPKE)
    for fmt in ("isis3", "gtiff", "fits"):
        sub = folder / fmt
        sub.mkdir(exist_ok=True)
        paths = write_scene(sub, shape, fmt, chunk)
        geo = FileGeometry(*(open_plane(p) for p in paths[1:]))
        out = sub / f"out{paths[0].suffix}"
        t = time.perf_counter()
        correct_file(open_plane(paths[0]), geo, Correction(model), out, chunk=chunk)
        times[fmt] = time.perf_counter() - t
        outs[fmt] = (paths, out)
    cube_in, cube_out = outs["isis3"][0][0], outs["isis3"][1]
    got = {fmt: as_nan(out) for fmt, (_, out) in outs.items()}
    ref = in_memory(outs["isis3"][0])
    equal_formats = all(
        np.array_equal(got["isis3"], got[f], equal_nan=True) for f in ("gtiff", "fits")
    )
    equal_memory = all(np.array_equal(got[f], ref, equal_nan=True) for f in got)
    a, b = pvl.load(str(cube_in)), pvl.load(str(cube_out))
    labels = all(
        a["IsisCube"]["Core"][g] == b["IsisCube"]["Core"][g] for g in ("Dimensions", "Pixels")
    ) and (a["IsisCube"]["Mapping"] == b["IsisCube"]["Mapping"])
    # the same on a local Dask cluster of two workers
    paths = outs["isis3"][0]
    geo = FileGeometry(*(open_plane(p) for p in paths[1:]))
    with (
        distributed.LocalCluster(
            n_workers=2, threads_per_worker=1, processes=False, dashboard_address=None
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        t = time.perf_counter()
        correct_file(
            open_plane(paths[0]),
            geo,
            Correction(model),
            folder / "cluster.cub",
            chunk=chunk,
            scheduler=client,
        )
        t_cluster = time.perf_counter() - t
    import rasterio

    with rasterio.open(cube_out) as x, rasterio.open(folder / "cluster.cub") as y:
        cluster_same = x.read(1).tobytes() == y.read(1).tobytes()
    n = int(np.isfinite(ref).sum())
    yes = {True: "yes", False: "**no**"}
    return [
        f"Correctness, a {size} × {size} scene ({n:,} pixels corrected, chunk {chunk}): "
        f"ISIS3 cube {times['isis3']:.1f} s, GeoTIFF {times['gtiff']:.1f} s, FITS "
        f"{times['fits']:.1f} s; a local Dask cluster of two workers {t_cluster:.1f} s.",
        "",
        "| check | result |",
        "| --- | --- |",
        f"| the three outputs (.cub, GeoTIFF, FITS) equal in float32 | {yes[equal_formats]} |",
        f"| each equals the in-memory path (`normalize` on whole planes) | {yes[equal_memory]} |",
        f"| output cube's Dimensions, Pixels, Mapping groups = input's (pvl) | {yes[labels]} |",
        f"| Dask cluster (2 workers) output = threaded output, bit for bit | {yes[cluster_same]} |",
        "",
    ]


def scale(folder: Path, lines: int, samples: int, chunk: int) -> list[str]:
    shape = (lines, samples)
    t = time.perf_counter()
    paths = write_scene(folder, shape, "gtiff", chunk, filling_margin(shape))
    t_write = time.perf_counter() - t
    out = folder / "out.tif"
    report = folder / "maxrss.txt"
    argv = [*PYTHON, "-c", _MEASURED, str(report), "photometry", "correct", str(paths[0])]
    argv += ["--incidence", str(paths[1]), "--emission", str(paths[2]), "--phase", str(paths[3])]
    argv += ["--model", "hapke", "--chunk", str(chunk), "-o", str(out)]
    for p in PARAMS:
        argv += ["--param", p]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    proc = run_program(argv, capture_output=True, text=True)
    wall = time.perf_counter() - t
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if proc.returncode:
        raise SystemExit(proc.stderr)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    peak_gb = int(report.read_text()) * 1024 / 1e9  # ru_maxrss: KiB on Linux
    crop = min(4096, lines), min(4096, samples)
    r0, c0 = (lines - crop[0]) // 2, (samples - crop[1]) // 2
    rows, cols = slice(r0, r0 + crop[0]), slice(c0, c0 + crop[1])
    ref = in_memory(paths, rows, cols)
    got = open_plane(out).read(rows, cols)[0].astype(np.float32)
    same = np.array_equal(got, ref, equal_nan=True)
    gpx = lines * samples / 1e9
    return [
        f"Scale: a {lines:,} × {samples:,} float32 image ({gpx:.2f} Gpx) and three backplanes, "
        f"tiled GeoTIFF (written in {t_write:.0f} s), corrected with Hapke by "
        f"`roughdiffuse photometry correct --chunk {chunk}` in a child process.",
        "",
        "| wall time | CPU time | peak RSS (child) | central crop = in-memory path |",
        "| ---: | ---: | ---: | --- |",
        f"| {wall:.0f} s ({wall / 60:.1f} min) | {cpu:.0f} s | {peak_gb:.2f} GB | "
        f"{crop[0]} × {crop[1]}: {'yes' if same else '**no**'} |",
        "",
    ]


def _replace_section(path: Path, heading: str, text: str) -> None:
    """Replace the section under ``heading`` (to the next ``## `` heading, or the ``<!-- ``
    marker of another benchmark's section) of ``path`` by ``text``, or add it at the end;
    written whole or not at all."""
    old = path.read_text(encoding="utf-8") if path.exists() else "# Benchmarks\n\n"
    pattern = re.compile(re.escape(heading) + r"\n.*?(?=\n## |\n<!-- |\Z)", re.S)
    new = (
        pattern.sub(lambda _: text.rstrip("\n") + "\n", old)
        if pattern.search(old)
        else old.rstrip("\n") + "\n\n" + text
    )
    write_text(path, new)


def main(argv: list[str] | None = None, prog: str | None = None) -> None:
    parser = argparse.ArgumentParser(prog=prog, description=__doc__.split("\n")[0])
    parser.add_argument("--size", type=int, default=4096, help="correctness scene side")
    parser.add_argument("--scale", default="20000x50000", help="LINESxSAMPLES of the scale run")
    parser.add_argument("--chunk", type=int, default=512)
    parser.add_argument("--workdir", help="where the images go (default: a temporary folder)")
    parser.add_argument("--write", metavar="FILE", help="replace its section of this RESULTS.md")
    args = parser.parse_args(argv)
    lines, samples = (int(v) for v in args.scale.lower().split("x"))
    cores = len(os.sched_getaffinity(0))
    load0 = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(dir=args.workdir) as tmp:
        folder = Path(tmp)
        (folder / "c").mkdir()
        (folder / "s").mkdir()
        part1 = correctness(folder / "c", args.size, args.chunk)
        part2 = scale(folder / "s", lines, samples, args.chunk)
    load1 = os.getloadavg()[0]
    full = (lines, samples) == (20000, 50000) and args.size == 4096
    text = "\n".join(
        [
            "## Planetary images",
            "",
            f"`python bench/planetary_bench.py --size {args.size} --scale {lines}x{samples} "
            f"--chunk {args.chunk} --write` ({cores} cores, load average {load0:.1f} at the "
            "start and "
            f"{load1:.1f} at the end, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}).",
            ""
            if full
            else "\nA reduced run: the full one (`--size 4096 --scale 20000x50000`, targets "
            "≤ 20 min and ≤ 2 GB peak RSS on 2 cores) waits for a quiet machine.\n",
            *part1,
            *part2,
        ]
    )
    print(text)
    if args.write:
        _replace_section(Path(args.write), "## Planetary images", text)


if __name__ == "__main__":
    main()
