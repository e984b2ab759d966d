"""``roughdiffuse stereo``: normals, albedo, roughness and depth of a rough object from images."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

from . import UsageError

EXAMPLES = """\
examples:
  roughdiffuse stereo img0.npy img1.npy img2.npy img3.npy --lights lights.json -o out/
  roughdiffuse stereo *.png --exposure 0 --lights lights.json --mask mask.png \\
      --model oren-nayar-full -o out/
  roughdiffuse stereo --diligent DiLiGenT/pmsData/potPNG --model oren-nayar -o pot/
  roughdiffuse stereo --demo -o demo/          # a rendered sphere with known truth

lights.json: {"directions": [[x, y, z], ...], "intensities": [E0 or [R, G, B], ...]}, one entry
per image in image order; directions point towards the lights in the camera frame (x right,
y up, z towards the camera) and need not be normalised. The camera is orthographic.
Writes normals.npy, albedo.npy, depth.npy/.ply, params.json, PNG and EXR maps and report.html.
"""

DEMO_SIGMA = 0.5
"""σ (radians) of the full Oren–Nayar sphere that ``--demo`` renders (albedo 0.7, 8 lights on
a 35° ring, 128 × 128 pixels, 1% noise)."""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "stereo",
        help="photometric stereo with a rough-diffuse model (normals, albedo, σ, depth)",
        description="Photometric stereo for rough matte objects: Lambertian least squares as "
        "the baseline and start, then a per-pixel fit of a rough-diffuse model with one "
        "roughness for the object (or one per pixel).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("images", nargs="*", metavar="IMAGE", help=".npy, .exr or .png images (K >= 3)")
    p.add_argument("--lights", metavar="JSON", help="light directions and intensities")
    p.add_argument("--mask", metavar="FILE", help="object mask (PNG or .npy; default: lit pixels)")
    p.add_argument("--exposure", type=float, help="PNG exposure in stops (linear = value / 2^E)")
    p.add_argument("--diligent", metavar="DIR", help="read a DiLiGenT object folder instead")
    p.add_argument(
        "--demo", action="store_true", help="run on a rendered sphere of known shape (no input)"
    )
    p.add_argument(
        "--model",
        default="oren-nayar-full",
        metavar="ID",
        help="model id (default: oren-nayar-full)",
    )
    p.add_argument("--per-pixel", action="store_true", help="one roughness per pixel")
    p.add_argument(
        "--shadow",
        type=float,
        default=0.02,
        help="leave out observations darker than this fraction of the pixel's brightest "
        "(default: 0.02)",
    )
    p.add_argument(
        "--depth",
        choices=("poisson", "frankot-chellappa"),
        default="poisson",
        help="normal integration (default: poisson)",
    )
    p.add_argument("-o", "--output", required=True, metavar="DIR", help="output folder")
    p.add_argument("--force", action="store_true", help="write into a folder that holds results")
    p.set_defaults(func=run)


def _model(model_id: str):  # noqa: ANN202
    from ..registry import create, ids

    if model_id not in ids():
        raise UsageError(f"unknown model {model_id!r}; choose one of: {', '.join(ids())}")
    return create(model_id)


def _prepare_output(folder: str, force: bool) -> Path:
    out = Path(folder)
    if out.exists() and not out.is_dir():
        raise UsageError(f"--output {folder!r} exists and is not a folder")
    if (out / "params.json").exists() and not force:
        raise UsageError(f"--output {folder!r} already holds results; add --force to replace them")
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(
            f"--output {folder!r}: cannot create the folder ({exc.strerror})"
        ) from None
    if not os.access(out, os.W_OK):
        raise UsageError(f"--output {folder!r} is not writable")
    return out


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import stereo

    sources = sum(bool(x) for x in (args.images, args.diligent, args.demo))
    if sources != 1:
        raise UsageError("give IMAGE files with --lights, or --diligent DIR, or --demo")
    if not 0.0 <= args.shadow < 1.0:
        raise UsageError(f"--shadow must be in [0, 1) (got {args.shadow:g})")
    model = _model(args.model)
    out = _prepare_output(args.output, args.force)
    truth = None
    if args.diligent:
        data = stereo.read_diligent(args.diligent)
    elif args.demo:
        from ..models import OrenNayar
        from ..render import Sphere

        truth_model = OrenNayar(0.7, DEMO_SIGMA, "full")
        data, truth = stereo.render_stereo(
            truth_model, Sphere(), stereo.default_lights(8), 128, noise=0.01
        )
    else:
        if not args.lights:
            raise UsageError("--lights JSON is required with IMAGE files")
        if len(args.images) < 3:
            raise UsageError(f"photometric stereo needs at least 3 images (got {len(args.images)})")
        images, valid = stereo.load_images(args.images, exposure=args.exposure)
        dirs, ints = stereo.read_lights(args.lights)
        if dirs.shape[0] != images.shape[0]:
            raise UsageError(
                f"{len(args.images)} images but {dirs.shape[0]} lights in {args.lights}"
            )
        mask = stereo.read_mask(args.mask) if args.mask else None
        data = stereo.StereoInput.from_arrays(images, dirs, ints, mask=mask, valid=valid)
    lam = stereo.lambertian(data, shadow=args.shadow)
    res = stereo.rough(
        data, model, per_pixel=args.per_pixel, start=lam, shadow=args.shadow, progress=True
    )
    normals = np.full(data.mask.shape + (3,), np.nan)
    normals[data.mask] = res.normals
    depth = stereo.integrate(normals, data.mask & np.all(np.isfinite(normals), axis=-1), args.depth)
    extra = None
    if args.demo:  # the report states the truth beside the fit
        extra = {"truth": {"model": "oren-nayar-full", "albedo": 0.7, "sigma": DEMO_SIGMA}}
    params = stereo.write_outputs(
        out, data, res, lam, depth, model_id=args.model, truth_normals=truth, extra=extra
    )
    r = params["roughness"]
    if r["per_pixel"]:
        line = f"{r['name']}: per pixel, median {r['median']:.4g}"
    else:
        line = f"{r['name']} = {r['value']:.4g} ± {r['standard_error']:.2g}"
    print(f"{args.model}: {line}; {params['pixels']} pixels; results in {out}/ (report.html)")
    return 0
