"""``roughdiffuse photometry correct``: normalise an I/F image to a reference geometry."""

from __future__ import annotations

import argparse
import math
import os
from typing import Any

from . import UsageError
from ._checks import output_file, reading

CORRECT_EXAMPLES = """\
examples:
  roughdiffuse photometry correct image.fits --incidence i.fits --emission e.fits \\
      --phase g.fits --model lunar-lambert --param L=0.6 -o corrected.fits
  roughdiffuse photometry correct moon.npy --subsolar 0,30 --subobserver 0,0 \\
      --model hapke --param Wh=0.25 --param B0=1.2 --param Hh=0.06 --param Theta=20 -o moon.fits
  roughdiffuse photometry correct image.cub --incidence i.cub --emission e.cub \\
      --phase g.cub --model hapke --param Wh=0.25 --chunk 2048 -o corrected.cub
  roughdiffuse photometry correct big.tif ... --scheduler tcp://10.0.0.5:8786 -o out.tif

Normalises I/F to ISIS's reference geometry: incidence = emission = phase = 0 (change with
--reference G,I,E), with the opposition-surge amplitudes (B0) set to 0 there, as ISIS's
ZeroB0Standard = TRUE. Methods (ISIS photomet's): albedo = I/F x P(ref)/P(g, i, e); mixed =
the model's topographic shading kept near the limb and terminator, the albedo normalised in
between (match geometry --match, default 45,45,0); topo = the topographic shading
normalised (ISIS's reference: --reference INCREF,INCREF,0); shade = a shaded relief from the
model alone, --albedo x P(g, i, e)/P(ref). Pixels with i or e beyond --max-incidence
/ --max-emission (default 90, as photomet; 85 leaves out grazing pixels) are NoData in the
output, and NoData stays NoData: NaN, the file's NoData value (FITS BLANK, GDAL nodata),
--nodata VALUE, and ISIS special pixels (Null, Lrs, Lis, His, Hrs; an output cube keeps each).
Backplanes come from files (--incidence/--emission/--phase, degrees, the image's size and
map projection) or from a sphere/ellipsoid (--subsolar, --subobserver LAT,LON in degrees,
--radii A,B,C). Files, by name or --format: ISIS3 .cub, PDS4 .xml, GeoTIFF .tif (through
GDAL), FITS, .npy, .exr; an output takes the input's map projection (an ISIS cube's
Dimensions, Pixels and Mapping groups). The image is read, corrected and written in chunks
of --chunk x --chunk pixels (never whole), on this machine's cores or a Dask cluster
(--scheduler; the workers must see the files). Parameters take roughdiffuse's names or
ISIS's (L, K, Wh, B0, Hh, Hg1, Hg2, Theta, Bh, Ch); angles in degrees.
"""


def _numbers(n: int, what: str):  # noqa: ANN202 - an argparse type
    def parse(text: str) -> tuple[float, ...]:
        try:
            vals = tuple(float(t) for t in text.replace(",", " ").split())
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {what} (got {text!r})") from None
        if len(vals) != n or not all(math.isfinite(v) for v in vals):
            raise argparse.ArgumentTypeError(f"expected {what} (got {text!r})")
        return vals

    return parse


def _param(text: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise argparse.ArgumentTypeError(f"--param takes NAME=VALUE (got {text!r})")
    return name.strip(), value.strip()


def _cost(chunk: int) -> str:
    from ..planetary.chunked import BYTES_PER_PIXEL

    return f"{chunk * chunk * BYTES_PER_PIXEL / 2**20:.0f} MiB per core"


def add_dem_arguments(c: argparse.ArgumentParser) -> None:
    """The geometry of angles from a DEM besides --subsolar/--subobserver (correct, fit of an
    image, angles)."""
    c.add_argument("--sun-vector", type=_numbers(3, "E,N,U"), metavar="E,N,U")
    c.add_argument("--observer-vector", type=_numbers(3, "E,N,U"), metavar="E,N,U")
    c.add_argument(
        "--sun-distance", type=float, metavar="M", help="from the map origin or body centre"
    )
    c.add_argument(
        "--observer-distance", type=float, metavar="M", help="default: far away (parallel rays)"
    )
    c.add_argument("--radius", type=float, default=0.0, metavar="M", help="the sphere's radius")
    c.add_argument(
        "--dem-holds",
        choices=("height", "radius"),
        default="height",
        help="the DEM's values: heights above the sphere, or radii (ISIS DEMs)",
    )


def add_geometry_arguments(c: argparse.ArgumentParser) -> None:
    """The options naming an image's band, its NoData, its backplanes and the chunk size
    (``photometry correct``, and ``photometry fit`` of an image)."""
    from ..planetary.chunked import BYTES_PER_PIXEL, CHUNK

    c.add_argument("--band", default="1", metavar="N|NAME", help="the image's band: number or name")
    c.add_argument(
        "--nodata",
        type=float,
        default=None,
        metavar="VALUE",
        help="a pixel value meaning NoData (besides NaN)",
    )
    for name in ("incidence", "emission", "phase"):
        c.add_argument(f"--{name}", metavar="FILE", help=f"{name} backplane (degrees)")
    c.add_argument("--subsolar", type=_numbers(2, "LAT,LON in degrees"), metavar="LAT,LON")
    c.add_argument("--subobserver", type=_numbers(2, "LAT,LON in degrees"), metavar="LAT,LON")
    c.add_argument("--radii", type=_numbers(3, "A,B,C"), default=(1.0, 1.0, 1.0), metavar="A,B,C")
    c.add_argument(
        "--dem",
        metavar="FILE",
        help="angles from a DEM (GeoTIFF, .cub; heights in metres) on the image's pixel grid, "
        "with --sun-vector/--observer-vector (map east, north, up) or --subsolar/--subobserver "
        "and --radius (a sphere)",
    )
    add_dem_arguments(c)
    c.add_argument(
        "--chunk",
        type=int,
        default=CHUNK,
        metavar="PIXELS",
        help=f"chunk side (default {CHUNK}); memory about {BYTES_PER_PIXEL} bytes per pixel of "
        f"a chunk, one chunk per core at work ({CHUNK}: {_cost(CHUNK)}; 2048: {_cost(2048)})",
    )


def register_correct(inner: argparse._SubParsersAction) -> None:
    from ..planetary.correct import METHODS
    from ..planetary.disk import PHOTOMETRIC_MODELS
    from ..planetary.rasters import FORMATS

    c = inner.add_parser(
        "correct",
        help="normalise an I/F image to a reference geometry (ISIS photomet's methods)",
        description="Photometric normalisation of an I/F image, as ISIS's photomet.",
        epilog=CORRECT_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    c.add_argument(
        "image", metavar="IMAGE", help="I/F image: .cub, .xml (PDS4), .tif, .fits, .npy, .exr"
    )
    c.add_argument("-o", "--output", required=True, metavar="OUT", help="the same formats")
    c.add_argument("--force", action="store_true", help="replace an existing OUT")
    c.add_argument(
        "--format",
        choices=tuple(FORMATS),
        metavar="FORMAT",
        help=f"the output's format (default: from its name): {', '.join(FORMATS)}",
    )
    c.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="a Dask scheduler (tcp://HOST:PORT) to run the chunks on; default this machine",
    )
    c.add_argument(
        "--model",
        default="lunar-lambert",
        metavar="NAME",
        help=f"one of: {', '.join(PHOTOMETRIC_MODELS)} (default: lunar-lambert)",
    )
    c.add_argument(
        "--param",
        type=_param,
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a model parameter (repeatable; ISIS names accepted)",
    )
    c.add_argument("--method", choices=METHODS, default="albedo")
    c.add_argument(
        "--albedo",
        type=float,
        default=1.0,
        metavar="A",
        help="mixed, topo, shade: ISIS's Albedo, the output's brightness scale (default 1)",
    )
    add_geometry_arguments(c)
    c.add_argument(
        "--reference",
        type=_numbers(3, "PHASE,INCIDENCE,EMISSION in degrees"),
        default=(0.0, 0.0, 0.0),
        metavar="G,I,E",
    )
    c.add_argument(
        "--match",
        type=_numbers(3, "PHASE,INCIDENCE,EMISSION in degrees"),
        default=(45.0, 45.0, 0.0),
        metavar="G,I,E",
    )
    c.add_argument(
        "--param-map",
        metavar="FILE",
        help="a cube (GDAL) with one band per model parameter, on the image's grid, the bands "
        "named (band descriptions or an ISIS BandBin Name) or named by --bands; angles in degrees",
    )
    c.add_argument(
        "--bands",
        metavar="NAME,NAME,...",
        help="the parameter each band of --param-map holds, in order (ISIS names accepted)",
    )
    c.add_argument("--max-incidence", type=float, default=90.0, metavar="DEG")
    c.add_argument("--max-emission", type=float, default=90.0, metavar="DEG")
    c.set_defaults(func=run_correct)


def _model(model_id: str, pairs: list[tuple[str, str]]) -> Any:
    from .. import registry
    from ..planetary.isis import parameter_name
    from ._common import current_name, parse_value

    entry = registry.get(model_id)
    declared = {p.name: p for p in entry.parameters}
    kwargs: dict[str, Any] = {}
    for name, text in pairs:
        ours = current_name(entry.cls, parameter_name(model_id, name), f"--param {name}")
        if ours not in declared:
            raise UsageError(
                f"--param: {model_id} has no parameter {name!r} (it has: {', '.join(declared)})"
            )
        kwargs[ours] = parse_value(declared[ours], text, f"--param {name}")
    return entry.create(**kwargs)


_DEFAULTS = {
    "radii": (1.0, 1.0, 1.0),
    "radius": 0.0,
    "dem_holds": "height",
    "albedo": 1.0,
    "match": (45.0, 45.0, 0.0),
    "band": "1",
    "samples": 20000,
}


def refuse_unused(
    args: argparse.Namespace, flags: tuple[str, ...], applies: bool, what: str
) -> None:
    """Nothing the user typed is silently ignored: ``flags`` set away from their defaults
    when they do not apply (``applies`` false) are refused, naming the flag and ``what``
    they need."""
    if applies:
        return
    from ..planetary.chunked import CHUNK

    for flag in flags:
        dest = flag.lstrip("-").replace("-", "_")
        value = getattr(args, dest, None)
        default = _DEFAULTS.get(dest, CHUNK if dest == "chunk" else None)
        if value is not None and value is not False and value != default:
            raise UsageError(f"{flag} applies only to {what}")


def check_geometry_options(args: argparse.Namespace) -> None:
    """The backplane options that apply only with others (correct, and fit of an image)."""
    refuse_unused(
        args,
        ("--sun-vector", "--observer-vector", "--sun-distance", "--observer-distance",
         "--radius", "--dem-holds"),
        bool(args.dem),
        "angles from a DEM (--dem)",
    )  # fmt: skip
    refuse_unused(
        args, ("--radii",), bool(args.subsolar) and not args.dem, "an ellipsoid's backplanes"
    )


def _plane(path: str, what: str, band: str = "1", nodata: float | None = None) -> Any:
    from ..planetary.rasters import open_plane

    with reading(path, what):
        return open_plane(path, band=int(band) if band.isdigit() else band, nodata=nodata)


def _geometry(args: argparse.Namespace, image: Any) -> Any:
    from ..planetary.chunked import EllipsoidGeometry, FileGeometry

    files = [args.incidence, args.emission, args.phase]
    if args.dem:
        if any(files):
            raise UsageError("give backplane files or --dem, not both")
        return _dem_geometry(args, image)
    if any(files):
        if not all(files):
            raise UsageError("give all three of --incidence, --emission and --phase")
        if args.subsolar or args.subobserver:
            raise UsageError("give backplane files or --subsolar/--subobserver, not both")
        planes = []
        for name, path in zip(("incidence", "emission", "phase"), files, strict=True):
            plane = _plane(path, f"{name} backplane")
            if plane.shape != image.shape:
                raise UsageError(
                    f"--{name} {path!r} is {plane.shape[1]} x {plane.shape[0]} "
                    f"pixels; the image is {image.shape[1]} x {image.shape[0]}"
                )
            if plane.georef and image.georef and plane.georef != image.georef:
                raise UsageError(
                    f"--{name} {path!r}: its map projection or pixel grid is not the image's"
                )
            planes.append(plane)
        return FileGeometry(*planes)
    if not (args.subsolar and args.subobserver):
        raise UsageError(
            "give backplanes (--incidence, --emission, --phase) or a shape "
            "(--subsolar and --subobserver)"
        )
    return EllipsoidGeometry(image.shape, args.subsolar, args.subobserver, args.radii)


def _dem_geometry(args: argparse.Namespace, image: Any) -> Any:
    from ..planetary.dem import dem_geometry, unit_from_lat_lon

    dem = _plane(args.dem, "DEM")
    if args.sun_vector and args.observer_vector:
        frame, sun, observer = "plane", args.sun_vector, args.observer_vector
    elif args.subsolar and args.subobserver:
        frame = "body"
        sun, observer = (tuple(unit_from_lat_lon(*p)) for p in (args.subsolar, args.subobserver))
    else:
        raise UsageError(
            "--dem needs --sun-vector and --observer-vector (map east, north, up), or "
            "--subsolar, --subobserver and --radius"
        )
    for flag, v in (
        ("--sun-distance", args.sun_distance),
        ("--observer-distance", args.observer_distance),
    ):
        if v is not None and not (math.isfinite(v) and v > 0):
            raise UsageError(f"{flag} must be a positive number of metres (got {v:g})")
    try:
        return dem_geometry(
            dem,
            image,
            sun=sun,
            observer=observer,
            frame=frame,
            sun_distance=args.sun_distance,
            observer_distance=args.observer_distance,
            radius=args.radius,
            holds_radius=args.dem_holds == "radius",
        )
    except ValueError as exc:
        raise UsageError(f"--dem: {exc}") from None


def _parameter_maps(args: argparse.Namespace, image: Any) -> Any:
    """The --param-map's bands as parameter maps of --model, each band matched by name."""
    from .. import registry
    from ..planetary.chunked import ParameterMaps
    from ..planetary.isis import parameter_name

    first = _plane(args.param_map, "parameter map")
    name = os.path.basename(args.param_map)
    count = len(first.band_names) or 1
    if args.bands:
        names = [b.strip() for b in args.bands.split(",") if b.strip()]
        if len(names) != count:
            raise UsageError(f"--bands names {len(names)} bands; {name} has {count}")
    else:
        names = list(first.band_names)
        if not all(names):
            raise UsageError(
                f"{name}: its bands have no names; name them with --bands (e.g. --bands Wh,B0)"
            )
    declared = {p.name: p for p in registry.get(args.model).parameters}
    planes = []
    for k, band in enumerate(names, start=1):
        ours = parameter_name(args.model, band)
        if ours not in declared:
            raise UsageError(
                f"{name}: band {k} ({band!r}) is no parameter of {args.model} "
                f"(it has: {', '.join(declared)})"
            )
        plane = _plane(args.param_map, "parameter map", str(k)) if k > 1 else first
        if plane.shape != image.shape:
            raise UsageError(
                f"--param-map {name!r} is {plane.shape[1]} x {plane.shape[0]} pixels; the "
                f"image is {image.shape[1]} x {image.shape[0]}"
            )
        if plane.georef and image.georef and plane.georef != image.georef:
            raise UsageError(f"--param-map {name!r}: its map projection or grid is not the image's")
        planes.append((ours, plane, declared[ours].unit == "radians"))
    return ParameterMaps(tuple(planes))


def run_correct(args: argparse.Namespace) -> int:
    from ..planetary.chunked import Correction, check_chunk, check_not_an_input, correct_file
    from ..planetary.disk import PHOTOMETRIC_MODELS
    from ..planetary.rasters import format_of
    from ..progress import progress_enabled
    from ._checks import available_memory

    if args.model not in PHOTOMETRIC_MODELS:
        raise UsageError(
            f"--model {args.model!r} has no radiance factor of (i, e, g) here; "
            f"choose one of: {', '.join(PHOTOMETRIC_MODELS)}"
        )
    try:
        out_fmt = format_of(args.output, args.format)
    except ValueError as exc:
        raise UsageError(f"-o: {exc}") from None
    for flag, value, hi in (
        ("--max-incidence", args.max_incidence, 90.0),
        ("--max-emission", args.max_emission, 90.0),
    ):
        if not 0.0 <= value <= hi:
            raise UsageError(f"{flag} must be in [0, {hi:g}] degrees (got {value:g})")
    for flag, (g, i, e) in (("--reference", args.reference), ("--match", args.match)):
        if not (0 <= g <= 180 and 0 <= i < 90 and 0 <= e < 90 and abs(i - e) <= g <= i + e):
            raise UsageError(
                f"{flag} must be a geometry G,I,E with I, E in [0, 90), "
                f"|I − E| <= G <= I + E (got {g:g},{i:g},{e:g})"
            )
    check_geometry_options(args)
    refuse_unused(args, ("--bands",), bool(args.param_map), "--param-map")
    refuse_unused(args, ("--albedo",), args.method != "albedo", "--method mixed, topo or shade")
    refuse_unused(args, ("--match",), args.method == "mixed", "--method mixed")
    model = _model(args.model, args.param)
    if not os.path.isfile(args.image):
        raise UsageError(f"image {args.image!r} does not exist")
    image = _plane(args.image, "image", args.band, args.nodata)
    geometry = _geometry(args, image)
    inputs = [args.image, args.incidence, args.emission, args.phase, args.dem, args.param_map]
    try:
        check_not_an_input(args.output, inputs)
    except ValueError as exc:
        raise UsageError(f"-o: {exc}") from None
    workers = os.cpu_count() or 1
    try:
        check_chunk(args.chunk, workers, available_memory())
    except ValueError as exc:
        raise UsageError(f"--chunk: {exc}") from None
    output_file(args.output, option="-o", force=args.force)
    correction = Correction(
        model,
        method=args.method,
        albedo=args.albedo,
        reference=tuple(math.radians(v) for v in args.reference),
        match=tuple(math.radians(v) for v in args.match),
        max_incidence=math.radians(args.max_incidence),
        max_emission=math.radians(args.max_emission),
        maps=_parameter_maps(args, image) if args.param_map else None,
    )
    _, n = correct_file(
        image,
        geometry,
        correction,
        args.output,
        out_fmt=out_fmt,
        chunk=args.chunk,
        scheduler=args.scheduler,
        progress=progress_enabled(),
    )
    total = image.shape[0] * image.shape[1]
    print(
        f"wrote {args.output}: {n} of {total} pixels normalised ({args.method}, "
        f"{args.model}); the rest NoData"
    )
    return 0
