"""``roughdiffuse photometry``: planetary photometry — fit disk-resolved I/F, correct images."""

from __future__ import annotations

import argparse
import os

from . import UsageError
from ._checks import output_file, reading

FIT_EXAMPLES = """\
examples:
  roughdiffuse photometry fit flyby.csv --model hapke --fix hg2=0 --report fit.html
  roughdiffuse photometry fit ceres.csv --model lunar-lambert
  roughdiffuse photometry fit image.cub --incidence i.cub --emission e.cub --phase g.cub \\
      --model hapke --fix hg2=0 --samples 20000

DATA is a CSV file with a header naming the columns: I/F (or iof, radf; or r, the
bidirectional reflectance I/F/π), i, e and g (incidence, emission, phase, in DEGREES), and
optionally band (each band is fitted separately). Angles stay within [0, 180]; rows with i
or e beyond 90 are refused (unlit or unseen points). Angle parameters given with --fix are
in degrees, as everywhere on the command line. DATA may instead be an I/F image (ISIS3
.cub, PDS4 .xml, GeoTIFF, FITS, .npy, .exr) with its backplanes (as `photometry correct`
takes them): up to --samples of its lit, seen data pixels are drawn, the image read chunk by
chunk (never whole).
"""


def _assignment(text: str) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep or not name.strip() or not value.strip():
        raise argparse.ArgumentTypeError(f"--fix takes NAME=VALUE (got {text!r})")
    return name.strip().replace("-", "_"), value.strip()


def register(sub: argparse._SubParsersAction) -> None:
    from ..planetary.disk import PHOTOMETRIC_MODELS

    p = sub.add_parser(
        "photometry",
        help="planetary photometry: fit disk-resolved I/F, correct images to a standard geometry",
        description="Planetary photometry in the units and angles of planetary science: "
        "I/F and the incidence, emission and phase angles (i, e, g).",
        epilog="examples:\n"
        "  roughdiffuse photometry fit --help       # fit disk-resolved I/F (CSV of i, e, g)\n"
        "  roughdiffuse photometry correct --help   # normalise an image to a standard geometry\n"
        "  roughdiffuse photometry angles --help    # local angles, slope and azimuth from a DEM\n",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    inner = p.add_subparsers(dest="action", metavar="ACTION", parser_class=type(p))
    inner.required = True
    f = inner.add_parser(
        "fit",
        help="fit a photometric model to disk-resolved I/F at many (i, e, g)",
        description="Fit a photometric model to disk-resolved I/F by nonlinear least squares "
        "(the engine of `roughdiffuse fit`) and print each parameter with its standard error, "
        "their correlations, and the parameters the coverage cannot constrain.",
        epilog=FIT_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    f.add_argument(
        "data",
        metavar="DATA",
        help="a CSV file of I/F (or r), i, e, g [, band] per row, or an I/F image",
    )
    f.add_argument(
        "--model",
        default="hapke",
        metavar="NAME",
        help=f"one of: {', '.join(PHOTOMETRIC_MODELS)} (default: hapke)",
    )
    f.add_argument(
        "--fix",
        type=_assignment,
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="hold a parameter at a value (repeatable), e.g. --fix hg2=0",
    )
    f.add_argument(
        "--noise",
        choices=("relative", "absolute"),
        default="relative",
        help="noise model: a constant fraction of I/F, or constant (default: relative)",
    )
    f.add_argument("--report", metavar="OUT.html", help="write an HTML report with plots")
    f.add_argument("--force", action="store_true", help="replace an existing --report file")
    f.add_argument(
        "--samples",
        type=int,
        default=20000,
        metavar="N",
        help="an image: the pixels to fit, at most (default 20000)",
    )
    from .photometry_correct import add_geometry_arguments, register_correct

    add_geometry_arguments(f)
    f.set_defaults(func=run_fit)
    from .photometry_angles import register_angles

    register_correct(inner)
    register_angles(inner)


def _fixed(model: str, pairs: list[tuple[str, str]]) -> dict[str, object]:
    from .. import registry
    from ..planetary.isis import parameter_name
    from ._common import current_name, parse_value

    declared = {p.name: p for p in registry.get(model).parameters}
    out: dict[str, object] = {}
    for isis_name, text in pairs:
        name = current_name(registry.get(model).cls, parameter_name(model, isis_name), "--fix")
        if name not in declared:
            raise UsageError(
                f"--fix: {model} has no parameter {name!r} (it has: {', '.join(declared)})"
            )
        out[name] = parse_value(declared[name], text, f"--fix {name}")
        declared[name].check(out[name])
    return out


def run_fit(args: argparse.Namespace) -> int:
    from ..fit.sanity import fit_problem
    from ..planetary.disk import (
        PHOTOMETRIC_MODELS,
        fit_disk,
        read_photometry_csv,
        write_disk_report,
    )

    if args.model not in PHOTOMETRIC_MODELS:
        raise UsageError(
            f"--model {args.model!r} has no radiance factor of (i, e, g) here; choose one of: "
            f"{', '.join(PHOTOMETRIC_MODELS)}"
        )
    if args.report:
        if not args.report.lower().endswith((".html", ".htm")):
            raise UsageError(f"--report must name an .html file (got {args.report!r})")
        output_file(args.report, option="--report", force=args.force)
    if not os.path.isfile(args.data):
        raise UsageError(f"data file {args.data!r} does not exist")
    from .photometry_correct import check_geometry_options, refuse_unused

    image_flags = (
        *("--incidence", "--emission", "--phase", "--subsolar", "--subobserver", "--radii"),
        *("--dem", "--band", "--nodata", "--samples", "--chunk"),
    )
    is_csv = args.data.lower().endswith(".csv")
    refuse_unused(args, image_flags, not is_csv, "an image DATA (not a .csv file)")
    check_geometry_options(args)
    fixed = _fixed(args.model, args.fix)
    if is_csv:
        with reading(args.data, "data file"):
            bands = read_photometry_csv(args.data)
    else:
        bands = {None: _image_samples(args)}
    fits = []
    for band, data in bands.items():
        label = f"band {band}: " if band is not None else ""
        print(f"{label}{data.size} samples, phase {_deg_range(data.phase)}")
        result = fit_disk(args.model, data, fixed=fixed, noise=args.noise)
        problem = fit_problem(  # the fit sanity rule of fit and stereo: never "RMS inf"
            result.result.rms_relative, result.result.warnings, f"{label}the {args.model} fit"
        )
        if problem is not None:
            raise UsageError(problem)
        print(result.table())
        fits.append(result)
    if args.report:
        write_disk_report(args.report, fits)
        print(f"wrote {args.report}")
    return 0


def _image_samples(args: argparse.Namespace) -> object:
    """Up to --samples pixels of the image DATA with their angles, read chunk by chunk."""
    from ..planetary.chunked import check_chunk, sample_pixels
    from ..progress import progress_enabled
    from ._checks import available_memory
    from .photometry_correct import _geometry, _plane

    if args.samples < 2:
        raise UsageError(f"--samples must be at least 2 (got {args.samples})")
    image = _plane(args.data, "image", args.band, args.nodata)
    geometry = _geometry(args, image)
    try:
        check_chunk(args.chunk, 1, available_memory())
    except ValueError as exc:
        raise UsageError(f"--chunk: {exc}") from None
    return sample_pixels(
        image, geometry, args.samples, chunk=args.chunk, progress=progress_enabled()
    )


def _deg_range(a: object) -> str:
    import numpy as np

    d = np.degrees(np.asarray(a))
    return f"{d.min():.1f}°–{d.max():.1f}°"
