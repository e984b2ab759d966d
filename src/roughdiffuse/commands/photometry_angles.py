"""``roughdiffuse photometry angles``: local incidence, emission, phase, slope and azimuth from
a DEM, written as five planes (as ISIS's ``photomet`` takes them with ``ANGLESOURCE=DEM``)."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from . import UsageError
from ._checks import output_file

ANGLES_EXAMPLES = """\
examples:
  roughdiffuse photometry angles dem.tif --sun-vector 0.5,0,0.866 --observer-vector 0,0,1 \\
      -o angles.tif
  roughdiffuse photometry angles dem.cub --subsolar 2,40 --subobserver 0,0 \\
      --radius 1737400 --dem-holds radius -o angles.cub

Writes OUT-incidence, OUT-emission, OUT-phase, OUT-slope and OUT-azimuth (degrees; the
azimuth the slope faces, clockwise from north), in OUT's format, on the DEM's grid and map
projection, all five or none. The DEM is read chunk by chunk (--chunk); see
`photometry correct --help` for the geometry options.
"""

NAMES = ("incidence", "emission", "phase", "slope", "azimuth")


def register_angles(inner: argparse._SubParsersAction) -> None:
    from .photometry_correct import _numbers as numbers_type
    from .photometry_correct import add_dem_arguments

    a = inner.add_parser(
        "angles",
        help="local incidence, emission, phase, slope and azimuth from a DEM",
        description="Local photometric angles from a DEM, as ISIS's ANGLESOURCE=DEM.",
        epilog=ANGLES_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    a.add_argument("dem", metavar="DEM", help="heights in metres: .tif, .cub, .xml (PDS4)")
    a.add_argument("-o", "--output", required=True, metavar="OUT", help="e.g. angles.tif")
    a.add_argument("--force", action="store_true", help="replace existing OUT-* files")
    a.add_argument("--subsolar", type=numbers_type(2, "LAT,LON in degrees"), metavar="LAT,LON")
    a.add_argument("--subobserver", type=numbers_type(2, "LAT,LON in degrees"), metavar="LAT,LON")
    add_dem_arguments(a)
    a.add_argument("--chunk", type=int, default=512, metavar="PIXELS")
    a.set_defaults(func=run_angles)


def outputs(output: str) -> list[Path]:
    """The five files: OUT-incidence.EXT, ..."""
    p = Path(output)
    return [p.with_name(f"{p.stem}-{name}{p.suffix}") for name in NAMES]


def run_angles(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io.atomic import deferred
    from ..planetary.chunked import check_chunk
    from ..planetary.rasters import NULL, VALID, blocks_of, encode, format_of, write_blocks
    from ._checks import available_memory
    from .photometry_correct import _dem_geometry, _plane

    try:
        fmt = format_of(args.output)
    except ValueError as exc:
        raise UsageError(f"-o: {exc}") from None
    if not os.path.isfile(args.dem):
        raise UsageError(f"DEM {args.dem!r} does not exist")
    try:
        check_chunk(args.chunk, 1, available_memory())
    except ValueError as exc:
        raise UsageError(f"--chunk: {exc}") from None
    dem = _plane(args.dem, "DEM")
    geometry = _dem_geometry(args, dem)  # the DEM on its own grid
    paths = outputs(args.output)
    for path in paths:
        output_file(path, option="-o", force=args.force)
        if os.path.exists(path) and os.path.samefile(path, args.dem):
            raise UsageError(f"-o: {str(path)!r} is the DEM; name another file")
    windows = blocks_of(dem.shape, (args.chunk, args.chunk))

    def blocks(name: str):  # noqa: ANN202 - a generator of (rows, cols, pixels)
        for rows, cols in windows:
            value = np.degrees(getattr(geometry.angles(rows, cols), name))
            kind = np.where(np.isfinite(value), VALID, NULL).astype(np.uint8)
            yield rows, cols, encode(value, kind, fmt)

    folder = paths[0].parent if str(paths[0].parent) else Path(".")
    with deferred(folder):  # all five or none
        for name, path in zip(NAMES, paths, strict=True):
            write_blocks(path, dem.shape, blocks(name), fmt=fmt, like=dem, description=name)
    print(f"wrote {', '.join(str(p) for p in paths)} (degrees)")
    return 0
