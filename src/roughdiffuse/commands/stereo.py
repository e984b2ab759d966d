"""``roughdiffuse stereo``: normals, albedo, roughness and depth of a rough object from images."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from ..progress import progress_enabled
from . import UsageError
from ._checks import bounded_float
from ._conflicts import given
from ._inputs import input_file, known_id
from .render import MAX_EXPOSURE

EXAMPLES = """\
examples:
  roughdiffuse render --model oren-nayar-full --sigma 0.4rad --size 96 \\
      --lights data:lights.json -o stack/
  roughdiffuse stereo stack/*.npy --lights stack/lights.json -o out/
  roughdiffuse stereo stack/*.npy --lights stack/lights.json --model lambert -o out-lambert/
  roughdiffuse render --model coated --roughness 0.3 --size 24 --lights data:lights.json \\
      -o gloss/                                 # a glossy sphere: a coat over Oren–Nayar
  roughdiffuse stereo gloss/*.npy --lights gloss/lights.json --model coated -o out-coated/
  roughdiffuse stereo --demo -o demo/          # a rendered sphere with known truth
  roughdiffuse stereo --demo --method l1 -o demo-l1/

PNG images: --exposure E (linear = value / 2^E), --mask mask.png. A DiLiGenT object:
--diligent DiLiGenT/pmsData/potPNG. --model lambert is Woodham's Lambertian photometric
stereo alone (least squares per pixel): the same outputs, no roughness (as --method lambertian).
--method l1, sparse or rpca: robust Lambertian photometric stereo (L1 residual, sparse Bayesian
learning, low-rank RPCA), which rejects highlights and shadows as outliers; --shadow, if given,
leaves dark observations out before their fit. --benchmark DIR runs every method on every
object of a DiLiGenT-format folder (pmsData/<object>PNG/ with Normal_gt.mat) and writes the
mean angular error table (benchmark.md, .csv, .json) and report.html.
--model coated fits a dielectric coat (index --eta, fitted roughness α) over a full Oren–Nayar
base: highlights are modelled, shadows found from the fitted shape; it needs at least 5 lights
(--method coated is the same).

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
    p.add_argument(
        "images",
        nargs="*",
        type=input_file,
        metavar="IMAGE",
        help=".npy, .exr or .png images (K >= 3)",
    )
    p.add_argument(
        "--lights", type=input_file, metavar="JSON", help="light directions and intensities"
    )
    p.add_argument(
        "--mask",
        type=input_file,
        metavar="FILE",
        help="object mask (PNG or .npy; default: lit pixels)",
    )
    p.add_argument(
        "--exposure",
        type=bounded_float(-MAX_EXPOSURE, MAX_EXPOSURE),
        help="PNG exposure in stops (linear = value / 2^E)",
    )
    p.add_argument("--diligent", metavar="DIR", help="read a DiLiGenT object folder instead")
    p.add_argument(
        "--demo", action="store_true", help="run on a rendered sphere of known shape (no input)"
    )
    p.add_argument(
        "--benchmark",
        metavar="DIR",
        help="run every method on a DiLiGenT-format folder and write the error table",
    )
    p.add_argument(
        "--method",
        choices=tuple(METHOD_CHOICES),
        help="lambertian, rough (default: the rough fit of --model), a robust Lambertian "
        "solver: l1, sparse, rpca, or coated (as --model coated)",
    )
    p.add_argument(
        "--model",
        metavar="ID",
        help=f"model id of the rough fit (default: {DEFAULT_MODEL})",
    )
    p.add_argument("--per-pixel", action="store_true", help="one roughness per pixel")
    p.add_argument(
        "--eta",
        type=bounded_float(1.05, 3.0),
        default=1.5,
        help="--model coated: the coat's refractive index, kept fixed (default: 1.5)",
    )
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


DEFAULT_MODEL = "oren-nayar-full"
"""The model of the rough fit when --model is not given."""

METHOD_CHOICES = ("lambertian", "rough", "l1", "sparse", "rpca", "coated")
"""``--method``: the names of :data:`roughdiffuse.stereo.methods.METHODS`."""

ROBUST = ("l1", "sparse", "rpca")
"""The robust Lambertian solvers of :func:`roughdiffuse.stereo.robust.robust`."""

LAMBERT = "lambert"
"""``--model lambert``: Woodham's Lambertian photometric stereo alone (least squares per
pixel), the same outputs with no roughness."""


def _model(model_id: str):  # noqa: ANN202
    from ..registry import create, ids

    known_id(model_id, ids())
    return None if model_id == LAMBERT else create(model_id)


RESULT_MARKER = "params.json"
"""The file every stereo result folder holds: only such a folder is replaced by --force."""

BENCHMARK_MARKER = "benchmark.json"
"""The file every --benchmark result folder holds (replaced by --force only if so)."""


def _prepare_output(folder: str, force: bool, marker: str = RESULT_MARKER) -> Path:
    """The -o folder, checked before any work (it is written whole at the end:
    :func:`roughdiffuse.io.atomic_folder`)."""
    from ..io import check_output_folder

    try:
        return check_output_folder(folder, replace=force, marker=marker)
    except ValueError as exc:
        raise UsageError(f"--output: {exc}") from None


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from .. import stereo

    sources = sum(bool(x) for x in (args.images, args.diligent, args.demo, args.benchmark))
    if sources != 1:
        raise UsageError(
            "give IMAGE files with --lights, or --diligent DIR, or --demo, or --benchmark DIR"
        )
    if not 0.0 <= args.shadow < 1.0:
        raise UsageError(f"--shadow must be in [0, 1) (got {args.shadow:g})")
    method = _method(args)
    model = _model(args.model or DEFAULT_MODEL) if method == "rough" else None
    out = _prepare_output(
        args.output, args.force, BENCHMARK_MARKER if args.benchmark else RESULT_MARKER
    )
    if args.benchmark:
        return _benchmark(args, out)
    data, truth = _read_input(args)
    if args.model == COATED:
        _check_coated_lights(data)
    lam = stereo.lambertian(data, shadow=args.shadow)
    shadow = args.shadow if "shadow" in given(args) else None  # robust: given, or none
    methods = _compared(data, truth, shadow)
    if method in ROBUST:
        from ..stereo.robust import robust

        res = methods.get(method) or robust(data, method, shadow=shadow,
                                            progress=progress_enabled())
        methods = {"lambertian": lam, **methods, method: res}
        return _lambert_only(args, data, res, out, truth, method, methods)
    if model is None:
        return _lambert_only(args, data, lam, out, truth, LAMBERT, {"lambertian": lam, **methods})
    res = _fit(args, data, lam, model)
    from ..fit.sanity import fit_problem

    problem = fit_problem(float(np.nanmedian(res.residual)), (), f"the {args.model} fit")
    if problem is not None:  # never a quiet result
        raise UsageError(problem)
    normals = np.full(data.mask.shape + (3,), np.nan)
    normals[data.mask] = res.normals
    depth = stereo.integrate(normals, data.mask & np.all(np.isfinite(normals), axis=-1), args.depth)
    extra = {}  # a coated result's coat: write_outputs adds it (params["coat"])
    if args.demo:  # the report states the truth beside the fit
        extra["truth"] = {"model": "oren-nayar-full", "albedo": 0.7, "sigma": DEMO_SIGMA}
    from ..io import atomic_folder

    model_id = args.model or DEFAULT_MODEL
    key = {DEFAULT_MODEL: "rough", COATED: "coated"}.get(model_id, f"rough ({model_id})")
    methods = {"lambertian": lam, key: res, **methods}
    with atomic_folder(out, replace=args.force, marker=RESULT_MARKER) as tmp:
        params = stereo.write_outputs(
            tmp, data, res, lam, depth, model_id=model_id, truth_normals=truth, extra=extra,
            methods=methods,
        )
    r = params["roughness"]
    if r["per_pixel"]:
        line = f"{r['name']}: per pixel, median {r['median']:.4g}"
    else:
        se = r["standard_error"]
        line = f"{r['name']} = {r['value']:.4g} ± {se:.2g}"
        if not math.isfinite(se):
            print(
                f"warning: the images cannot determine {r['name']} (its standard error is "
                "infinite, e.g. every image lit alike): the value is not a measurement",
                file=sys.stderr,
            )
    if args.model == COATED:
        line += _coat_line(res)
    print(f"{model_id}: {line}; {params['pixels']} pixels; results in {out}/ (report.html)")
    return 0


def _read_input(args: argparse.Namespace):  # noqa: ANN202
    """The StereoInput of IMAGE files, --diligent or --demo, and the true normals (--demo)."""
    from .. import stereo

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
    return data, truth


def _method(args: argparse.Namespace) -> str:
    """The method to run: --method, or the one --model implies (lambert: lambertian);
    --method coated is --model coated (``args.model`` set so), the rough fit's branch."""
    if args.method == COATED:
        if args.model not in (None, COATED):
            raise UsageError(f"--method coated fits the coated model, not --model {args.model}")
        args.model = COATED
        return "rough"
    if args.model == LAMBERT:
        if args.method not in (None, "lambertian"):
            raise UsageError(f"--model lambert is --method lambertian, not {args.method}")
        return "lambertian"
    if args.model is not None and args.method not in (None, "rough"):
        raise UsageError(f"--model applies only to --method rough (got --method {args.method})")
    return args.method or "rough"


def _compared(data, truth, shadow: float | None) -> dict:  # noqa: ANN001
    """With the truth known (--demo): every robust method, for the report's comparison."""
    if truth is None:
        return {}
    from ..stereo.robust import robust

    return {m: robust(data, m, shadow=shadow, progress=progress_enabled()) for m in ROBUST}


def _benchmark(args: argparse.Namespace, out: Path) -> int:
    """--benchmark DIR: every method on every object; the error table and report."""
    from ..io import atomic_folder
    from ..stereo.benchmark import run_benchmark, write_benchmark

    result = run_benchmark(args.benchmark, progress=progress_enabled())
    with atomic_folder(out, replace=args.force, marker=BENCHMARK_MARKER) as tmp:
        write_benchmark(tmp, result)
    print(result.markdown(), end="")
    print(f"{len(result.objects)} objects; table and report in {out}/ (benchmark.md, report.html)")
    return 0


COATED = "coated"
"""``--model coated``: :func:`roughdiffuse.stereo.coated`, a coat of index ``--eta`` over a
full Oren–Nayar base."""


def _check_coated_lights(data) -> None:  # noqa: ANN001
    """Refuse, before any work, fewer lights than the coated model's parameters per pixel."""
    from ..stereo.coated import parameter_count

    need = parameter_count(data.channels)
    if data.count < need:
        raise UsageError(
            f"--model coated fits {need} parameters per pixel (normal 2, albedo, σ, coat α): "
            f"it needs at least {need} lights (got {data.count})"
        )


def _fit(args: argparse.Namespace, data, lam, model):  # noqa: ANN001, ANN202
    """The rough fit of ``model`` from the Lambertian start; for ``--model coated`` the
    coated fit from the Lambertian start (its table solver fits σ and α on a subsample; the
    rough fit of every pixel runs only for a matte object, or for the direct solver of
    ``--per-pixel``)."""
    from .. import stereo

    show = progress_enabled()
    if args.model != COATED:
        return stereo.rough(data, model, per_pixel=args.per_pixel, start=lam,
                            shadow=args.shadow, progress=show)
    return stereo.coated(data, eta=args.eta, per_pixel=args.per_pixel, start=lam,
                         shadow=args.shadow, progress=show)


def _coat_line(res) -> str:  # noqa: ANN001
    """The coat's part of the summary line: α with its standard error (or its median per
    pixel), or that no coat fits better than the bare base."""
    import numpy as np

    if not res.coat:
        return " (no coat: a coat does not fit these images better than the bare base)"
    if np.ndim(res.alpha):
        alpha = f"per pixel, median {float(np.nanmedian(res.alpha)):.4g}"
    else:
        alpha = f"{float(res.alpha):.4g} ± {float(res.alpha_se):.2g}"
    return f", coat α = {alpha} (η = {res.eta:g})"


def _lambert_only(  # noqa: PLR0913
    args: argparse.Namespace, data, lam, out: Path, truth, label: str, methods: dict  # noqa: ANN001
) -> int:
    """Lambertian photometric stereo alone (Woodham's least squares, or a robust solver):
    normals, albedo, depth; no roughness."""
    import numpy as np

    from .. import stereo

    normals = np.full(data.mask.shape + (3,), np.nan)
    normals[data.mask] = lam.normals
    depth = stereo.integrate(normals, data.mask & np.all(np.isfinite(normals), axis=-1), args.depth)
    from ..io import atomic_folder

    with atomic_folder(out, replace=args.force, marker=RESULT_MARKER) as tmp:
        params = stereo.write_outputs(
            tmp, data, None, lam, depth, model_id=label, truth_normals=truth, methods=methods
        )
    res = params["lambertian"]["relative_rms_residual"]["median"]
    name = "lambert (Woodham)" if label == LAMBERT else label
    print(
        f"{name}: no roughness; median relative residual {res:.3g}; "
        f"{params['pixels']} pixels; results in {out}/ (report.html)"
    )
    return 0
