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

Normalises I/F to ISIS's reference geometry: incidence = emission = phase = 0 (change with
--reference G,I,E), with the opposition-surge amplitudes (B0) set to 0 there, as ISIS's
ZeroB0Standard = TRUE. Methods (ISIS photomet's): albedo = I/F x P(ref)/P(g, i, e); mixed =
the model's topographic shading kept near the limb and terminator, the albedo normalised in
between (match geometry --match, default 45,45,0). Pixels with i or e beyond --max-incidence
/ --max-emission (default 85) and NoData pixels (NaN, FITS BLANK, or --nodata VALUE) are
NaN in the output. Backplanes come from files (--incidence/--emission/--phase, degrees, the
image's size) or from a sphere/ellipsoid (--subsolar, --subobserver LAT,LON in degrees,
--radii A,B,C). Files: FITS (astropy, extra `planetary`), .npy, .exr. Parameters take
roughdiffuse's names or ISIS's (L, K, Wh, B0, Hh, Hg1, Hg2, Theta, Bh, Ch); angles in degrees.
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


def register_correct(inner: argparse._SubParsersAction) -> None:
    from ..planetary.disk import PHOTOMETRIC_MODELS

    c = inner.add_parser(
        "correct",
        help="normalise an I/F image to a reference geometry (ISIS photomet's albedo, mixed)",
        description="Photometric normalisation of an I/F image, as ISIS's photomet.",
        epilog=CORRECT_EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    c.add_argument("image", metavar="IMAGE", help="I/F image: .fits, .npy or .exr")
    c.add_argument("-o", "--output", required=True, metavar="OUT", help=".fits, .npy or .exr")
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
    c.add_argument("--method", choices=("albedo", "mixed"), default="albedo")
    for name in ("incidence", "emission", "phase"):
        c.add_argument(f"--{name}", metavar="FILE", help=f"{name} backplane (degrees)")
    c.add_argument("--subsolar", type=_numbers(2, "LAT,LON in degrees"), metavar="LAT,LON")
    c.add_argument("--subobserver", type=_numbers(2, "LAT,LON in degrees"), metavar="LAT,LON")
    c.add_argument("--radii", type=_numbers(3, "A,B,C"), default=(1.0, 1.0, 1.0), metavar="A,B,C")
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
    c.add_argument("--max-incidence", type=float, default=85.0, metavar="DEG")
    c.add_argument("--max-emission", type=float, default=85.0, metavar="DEG")
    c.add_argument(
        "--nodata",
        type=float,
        default=None,
        metavar="VALUE",
        help="a pixel value meaning NoData (besides NaN)",
    )
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


def _backplanes(args: argparse.Namespace, shape: tuple[int, ...]) -> tuple[Any, Any, Any]:
    import numpy as np

    from ..planetary.backplanes import ellipsoid_backplanes
    from ..planetary.correct import read_plane

    files = [args.incidence, args.emission, args.phase]
    if any(files):
        if not all(files):
            raise UsageError("give all three of --incidence, --emission and --phase")
        if args.subsolar or args.subobserver:
            raise UsageError("give backplane files or --subsolar/--subobserver, not both")
        planes = []
        for name, path in zip(("incidence", "emission", "phase"), files, strict=True):
            with reading(path, f"{name} backplane"):
                plane = read_plane(path)
            if plane.shape != shape:
                raise UsageError(
                    f"--{name} {path!r} is {plane.shape[1]} x {plane.shape[0]} "
                    f"pixels; the image is {shape[1]} x {shape[0]}"
                )
            bad = np.isfinite(plane) & ((plane < 0) | (plane > 180))
            if bad.any():
                raise UsageError(
                    f"--{name} {path!r}: angles must be in [0, 180] degrees "
                    f"(got {plane[bad].flat[0]:g})"
                )
            planes.append(np.radians(plane))
        return planes[0], planes[1], planes[2]
    if not (args.subsolar and args.subobserver):
        raise UsageError(
            "give backplanes (--incidence, --emission, --phase) or a shape "
            "(--subsolar and --subobserver)"
        )
    bp = ellipsoid_backplanes(shape, args.subsolar, args.subobserver, args.radii)
    return bp.incidence, bp.emission, bp.phase


def run_correct(args: argparse.Namespace) -> int:
    import numpy as np

    from ..planetary.correct import PLANE_SUFFIXES, normalize, read_plane, write_plane
    from ..planetary.disk import PHOTOMETRIC_MODELS
    from ..progress import progress_enabled

    if args.model not in PHOTOMETRIC_MODELS:
        raise UsageError(
            f"--model {args.model!r} has no radiance factor of (i, e, g) here; "
            f"choose one of: {', '.join(PHOTOMETRIC_MODELS)}"
        )
    if not args.output.lower().endswith(PLANE_SUFFIXES):
        raise UsageError(f"-o must end in {', '.join(PLANE_SUFFIXES)} (got {args.output!r})")
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
    model = _model(args.model, args.param)
    output_file(args.output, option="-o", overwrite=True)
    if not os.path.isfile(args.image):
        raise UsageError(f"image {args.image!r} does not exist")
    with reading(args.image, "image"):
        image = read_plane(args.image, nodata=args.nodata)
    inc, ema, pha = _backplanes(args, image.shape)
    out = normalize(
        image,
        inc,
        ema,
        pha,
        model,
        method=args.method,
        reference=tuple(math.radians(v) for v in args.reference),
        match=tuple(math.radians(v) for v in args.match),
        max_incidence=math.radians(args.max_incidence),
        max_emission=math.radians(args.max_emission),
        progress=progress_enabled(),  # chunks of pixels, on a terminal
    )
    write_plane(args.output, out)
    n = int(np.isfinite(out).sum())
    print(
        f"wrote {args.output}: {n} of {out.size} pixels normalised ({args.method}, "
        f"{args.model}); the rest NoData"
    )
    return 0
