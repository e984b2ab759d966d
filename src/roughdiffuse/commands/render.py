"""``roughdiffuse render``: one image of a shape under distant light(s), written to a file."""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from . import UsageError
from ._checks import finite_float, fits_in_memory, output_file, require_finite
from ._common import add_model_arguments, model_from_args
from ._inputs import angle, input_file

EXAMPLES = """\
examples:
  roughdiffuse render --model oren-nayar --sigma 17 --albedo 0.8 --shape sphere \\
      --light-theta 30 --light-phi 0 --view-theta 0 --size 512 -o sphere.png
  roughdiffuse render --model lambert --shape vase --light-theta 50 --light-phi 90 -o vase.png
  roughdiffuse render --model lommel-seeliger --shape moon -o moon.exr
  roughdiffuse render --model eon --roughness 1 --albedo 0.8,0.5,0.3 --light 40,0 \\
      --light 70,180,0.5 --bits 16 -o two-lights.png
  roughdiffuse render --model oren-nayar-full --sigma 0.4rad --size 96 \\
      --lights data:lights.json -o stack/

--lights FILE renders one image per light of a lights.json file (the format `stereo`
reads) in one process, into the folder -o names (light-00.npy, light-01.npy, ... and
lights.json beside them; --format png or exr for other files).

Angles in degrees, or with a unit (0.5rad). θ is measured from the axis pointing at the
default viewer (+z), φ from the image's right (+x) towards its top (+y): --light-theta 0 puts
the light behind the viewer.
The file type follows the suffix: .png (exposure and the sRGB curve), .npy or .exr (linear
float32 radiance). An existing file is kept unless --force is given.
"""

SHAPES = ("sphere", "cylinder", "vase", "plane", "moon")


def _size(text: str) -> int | tuple[int, int]:
    try:
        if "x" in text.lower():
            w, h = (int(v) for v in text.lower().split("x"))
            return (h, w)
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"size must be N or WIDTHxHEIGHT in pixels (got {text!r})"
        ) from None


def _light(text: str) -> tuple[float, float, float]:
    parts = [p for p in text.split(",") if p.strip()]
    try:
        vals = [angle(p) for p in parts[:2]] + [float(p) for p in parts[2:]]
    except (ValueError, argparse.ArgumentTypeError):
        vals = []
    if len(vals) not in (2, 3):
        raise argparse.ArgumentTypeError(f"--light takes THETA,PHI[,E0] in degrees (got {text!r})")
    return (vals[0], vals[1], vals[2] if len(vals) == 3 else 1.0)


MAX_EXPOSURE = 64.0
"""Largest |--exposure| in stops (2^64 brightens the faintest float32 radiance to white)."""

BYTES_PER_SAMPLE = 9
"""Renderer memory per pixel sample besides the radiance: two float32 ray coordinates and a
hit flag (``render/renderer.py``); the radiance adds 4 bytes per colour channel."""


def _exposure(text: str) -> float | str:
    if text == "auto":
        return text
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not -MAX_EXPOSURE <= value <= MAX_EXPOSURE:
        raise argparse.ArgumentTypeError(
            f"exposure must be a number of stops in [-{MAX_EXPOSURE:g}, {MAX_EXPOSURE:g}] "
            f"or 'auto' (got {text!r})"
        )
    return value


def add_scene_arguments(p: argparse.ArgumentParser, shape: bool = True) -> None:
    """--shape, lights, view, --size, --spp, --no-shadows (shared with ``plot``)."""
    g = p.add_argument_group("scene")
    if shape:
        g.add_argument(
            "--shape", default="sphere", metavar="NAME", help=f"one of: {', '.join(SHAPES)}"
        )
    g.add_argument(
        "--light-theta", type=angle, default=0.0, help="light θ, degrees [0, 180] (default 0)"
    )
    g.add_argument("--light-phi", type=angle, default=0.0, help="light φ, degrees (default 0)")
    g.add_argument(
        "--irradiance", type=finite_float, default=1.0, help="E0 of the light (default 1)"
    )
    g.add_argument(
        "--light",
        type=_light,
        action="append",
        metavar="THETA,PHI[,E0]",
        help="a light (repeatable; replaces --light-theta/--light-phi); lights add",
    )
    g.add_argument(
        "--view-theta", type=angle, default=0.0, help="view θ, degrees [0, 180] (default 0)"
    )
    g.add_argument("--view-phi", type=angle, default=0.0, help="view φ, degrees (default 0)")
    g.add_argument("--size", type=_size, default=512, help="N or WxH pixels (default 512)")
    g.add_argument(
        "--spp", type=int, default=4, help="samples per pixel, a square: 1, 4, 9, ... (default 4)"
    )
    g.add_argument("--no-shadows", action="store_true", help="no cast shadows")


def add_output_arguments(p: argparse.ArgumentParser, suffixes: tuple[str, ...]) -> None:
    p.add_argument(
        "-o", "--output", required=True, metavar="FILE", help=f"output file ({', '.join(suffixes)})"
    )
    p.add_argument("--force", action="store_true", help="overwrite an existing output file")


def check_output(path: str, suffixes: tuple[str, ...], force: bool) -> Path:
    """The -o path, checked before any work (:func:`~roughdiffuse.commands._checks.
    output_file`): suffix, a folder that exists and can be written, no folder or existing
    file in the way unless --force."""
    return output_file(path, suffixes, force=force, option="-o")


def check_render_memory(args: argparse.Namespace, channels: int = 1, images: int = 1) -> None:
    """Refuse a --size/--spp whose rays cannot fit in memory (:data:`BYTES_PER_SAMPLE`)."""
    from ..render.renderer import MAX_SIZE

    size = args.size
    h, w = (size, size) if isinstance(size, int) else size
    if not (1 <= h <= MAX_SIZE and 1 <= w <= MAX_SIZE):
        raise UsageError(f"--size must be N or WxH with sides in [1, {MAX_SIZE}] (got {w}x{h})")
    if not (1 <= args.spp <= 256 and math.isqrt(args.spp) ** 2 == args.spp):
        raise UsageError(f"--spp must be a square number in [1, 256]: 1, 4, 9, … (got {args.spp})")
    per_sample = BYTES_PER_SAMPLE + 4 * channels
    fits_in_memory(
        float(h) * w * args.spp * per_sample * images,
        f"--size {w}x{h} --spp {args.spp} (about {per_sample} bytes per sample)",
    )


def make_shape(name: str):  # noqa: ANN201 - a Shape
    """The shape a --shape name stands for."""
    from ..render import Cylinder, Moon, Plane, Sphere, SurfaceOfRevolution

    shapes = {
        "sphere": Sphere,
        "cylinder": Cylinder,
        "vase": SurfaceOfRevolution,
        "plane": Plane,
        "moon": Moon,
    }
    if name not in shapes:
        raise UsageError(f"unknown shape {name!r}; choose one of: {', '.join(SHAPES)}")
    return shapes[name]()


def _angle(name: str, deg: float, hi: float = 180.0) -> float:
    if not (math.isfinite(deg) and 0.0 <= deg <= hi):
        raise UsageError(f"--{name} must be in [0, {hi:g}] degrees (got {deg:g})")
    return math.radians(deg)


def _finite(name: str, deg: float) -> float:
    if not math.isfinite(deg):
        raise UsageError(f"--{name} must be a finite number of degrees (got {deg:g})")
    return math.radians(deg)


FLOAT32_MAX = 3.4028234663852886e38
"""The renderer works in float32: a larger irradiance is infinite there."""


def _irradiance(name: str, e0: float) -> float:
    if not 0.0 <= e0 <= FLOAT32_MAX:
        raise UsageError(f"--{name} must be in [0, {FLOAT32_MAX:.4g}] (float32; got {e0:g})")
    return e0


def scene_from_args(args: argparse.Namespace):  # noqa: ANN201
    """(lights, camera) from the scene arguments."""
    from ..render import DistantLight, OrthographicCamera

    for *_, e in args.light or ():
        _irradiance("light E0", e)
    if not args.light:
        _irradiance("irradiance", args.irradiance)
    if args.light:
        lights = [
            DistantLight(_angle("light", t), _finite("light", p), e) for t, p, e in args.light
        ]
    else:
        lights = [
            DistantLight(
                _angle("light-theta", args.light_theta),
                _finite("light-phi", args.light_phi),
                args.irradiance,
            )
        ]
    camera = OrthographicCamera(
        _angle("view-theta", args.view_theta), _finite("view-phi", args.view_phi)
    )
    return lights, camera


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "render",
        help="render a sphere, cylinder, vase, plane or the moon to an image file",
        description="Render a shape made of a reflectance model under distant light, seen by "
        "an orthographic camera; write linear radiance (.npy, .exr) or an sRGB PNG.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_arguments(p, skip=("alpha",))  # --alpha: the PNG's coverage channel here
    add_scene_arguments(p)
    g = p.add_argument_group("output")
    add_output_arguments(g, (".png", ".npy", ".exr"))
    g.add_argument(
        "--exposure",
        type=_exposure,
        default="auto",
        help="PNG exposure in stops, or 'auto' (99.9th percentile -> white; default)",
    )
    g.add_argument("--bits", type=int, default=8, choices=(8, 16), help="PNG bit depth")
    g.add_argument("--alpha", action="store_true", help="PNG: write the coverage as alpha")
    g = p.add_argument_group("a light stack (for photometric stereo)")
    g.add_argument(
        "--lights",
        dest="lights_file",
        type=input_file,
        metavar="JSON",
        help="render one image per light of this lights.json into the folder -o names",
    )
    g.add_argument(
        "--format",
        choices=("npy", "exr", "png"),
        default="npy",
        help="--lights: the images' file type (default npy, linear float32)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..io.images import write_image
    from ..progress import progress_enabled
    from ..render import render

    if args.lights_file is not None:
        from ._render_stack import render_stack

        return render_stack(
            args,
            make_shape(args.shape),
            lambda channels: check_render_memory(args, channels=channels),
        )
    out = check_output(args.output, (".png", ".npy", ".exr"), args.force)
    model = model_from_args(args)
    shape = make_shape(args.shape)
    lights, camera = scene_from_args(args)
    rgb = model.channels > 1 or any(isinstance(x.irradiance, tuple) for x in lights)
    check_render_memory(args, channels=3 if rgb else 1)
    t0 = time.perf_counter()
    image, mask = render(
        model,
        shape,
        lights,
        camera,
        args.size,
        samples_per_pixel=args.spp,
        shadows=not args.no_shadows,
        progress=progress_enabled(),  # bands of rows, on a terminal (render.renderer)
    )
    elapsed = time.perf_counter() - t0
    require_finite(
        image,
        "the image",
        "this --irradiance / --light E0 (float32 radiance overflows above about 3.4e38) and model",
    )
    meta = {
        "roughdiffuse:model": repr(model),
        "roughdiffuse:shape": args.shape,
        "roughdiffuse:lights": "; ".join(
            f"theta={math.degrees(x.theta):g} phi={math.degrees(x.phi):g} E0={x.irradiance}"
            for x in lights
        ),
        "roughdiffuse:view": f"theta={args.view_theta:g} phi={args.view_phi:g}",
    }
    write_image(
        out,
        image,
        mask=mask if args.alpha else None,
        exposure=args.exposure,
        bits=args.bits,
        metadata=meta,
    )
    h, w = image.shape[:2]
    print(
        f"wrote {out} ({w}x{h}, max radiance {float(np.max(image)):.4g}, "
        f"rendered in {elapsed:.2f} s)"
    )
    return 0
