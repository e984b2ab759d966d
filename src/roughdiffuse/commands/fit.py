"""``roughdiffuse fit``: fit a model (or rank several) to BRDF samples, a MERL file or an image."""

from __future__ import annotations

import argparse
import math
import os
import warnings
from typing import Any

from . import UsageError
from ._checks import bounded_float, finite_float, output_file, reading, require_finite
from ._common import _assignment
from ._export_targets import add_blender_python
from ._inputs import angle_pair, input_file, known_id
from .render import MAX_EXPOSURE

DATA_RANGE = (1e-100, 1e100)
"""Magnitudes of data values the fit accepts: their squares, and sums of a few million of
them, stay normal float64 numbers (about 2.2e-308 to 1.8e308), so RMS, AIC and BIC are
finite and meaningful."""

MAX_F_SCALE = 1e6
"""Largest --f-scale: a relative residual scale beyond any data's (the robust losses act as
the linear one long before), and far from overflowing when multiplied by the data."""

EXAMPLES = """\
examples:
  roughdiffuse fit data:samples.csv --model oren-nayar-full --report fit.html
  roughdiffuse fit data:samples.csv --compare --models lambert,oren-nayar,oren-nayar-full
  roughdiffuse fit data:samples.csv --model oren-nayar-full --noise absolute --json
  roughdiffuse fit data:samples.csv --model oren-nayar-full --export blender,materialx,mitsuba
  roughdiffuse fit data:oren-nayar.binary --model oren-nayar-full --max-samples 20000
  roughdiffuse fit data:sphere.npy --shape sphere --light 30,0 --model oren-nayar-full
  roughdiffuse fit data:sphere.npy --normals data:sphere_normals.npy --light 0.5236rad,0

Data by suffix: .csv/.txt (BRDF samples; header names the columns and the angle unit, e.g.
theta_i_deg, theta_r_deg, delta_phi_deg, brdf), .binary (MERL), .npy/.exr/.png (a linear
image; give --normals or --shape, and --light). data:NAME reads a file shipped with the
package (`roughdiffuse data` lists them). Angles on the command line are in DEGREES, or
with a unit (30deg, 0.52rad); the fitted σ is printed in radians and degrees. The noise model
is relative (errors proportional to the value), as in Python's fit() and the explorer.
--param fixes a choice the model leaves open and fits the numbers of that choice, e.g.
`--model coated --param base=eon` fits the coat over EON (albedo, base_roughness, eta, ...).
"""

SHAPES = ("sphere", "vase", "cylinder")


def register(sub: argparse._SubParsersAction) -> None:
    from ..fit.compare import CANDIDATES

    p = sub.add_parser(
        "fit",
        help="fit a model to BRDF samples, a MERL file or an image (albedo, roughness, errors)",
        description="Fit a reflectance model by nonlinear least squares and print the "
        "parameters with standard errors, or rank several models (--compare).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "data",
        metavar="DATA",
        type=input_file,
        help="a .csv, MERL .binary, or .npy/.exr/.png image; data:NAME is a file shipped with "
        "roughdiffuse (`roughdiffuse data` lists them)",
    )
    p.add_argument(
        "--model",
        default="oren-nayar",
        metavar="NAME",
        help=f"one of: {', '.join(CANDIDATES)} (default: oren-nayar)",
    )
    p.add_argument(
        "--param",
        type=_assignment,
        action="append",
        default=[],
        metavar="NAME=CHOICE",
        help="fix a choice the model leaves open, e.g. --model coated --param base=eon (its "
        "numeric parameters are fitted)",
    )
    p.add_argument(
        "--compare",
        action="store_true",
        help="fit every model and rank them (BIC); coated once over each of its bases",
    )
    p.add_argument(
        "--models",
        metavar="ID,ID,...",
        help="with --compare: rank only these registry ids (default: every fittable model)",
    )
    p.add_argument(
        "--noise",
        choices=("relative", "absolute"),
        default="relative",
        help="noise model: proportional to the value, or constant (default: relative, as "
        "roughdiffuse.fit.fit and the explorer; absolute when a value is <= 0)",
    )
    p.add_argument("--json", action="store_true", help="print the fit (or ranking) as JSON")
    p.add_argument(
        "--loss",
        default="linear",
        choices=("linear", "soft_l1", "huber", "cauchy", "arctan"),
        help="robust loss of scipy.optimize.least_squares (default: linear)",
    )
    p.add_argument(
        "--f-scale",
        type=bounded_float(0.0, MAX_F_SCALE),
        default=None,
        help="residual scale where a robust loss sets in: a fraction of the value "
        "(default 0.03, i.e. 3%%)",
    )
    _add_output_arguments(p)
    _add_input_arguments(p)
    p.set_defaults(func=run)


def _add_output_arguments(p: argparse.ArgumentParser) -> None:
    """The report and the exports of a fit: --report, --force, --export, --export-prefix and
    Blender's Python."""
    p.add_argument("--report", metavar="OUT.html", help="write an HTML report with plots")
    p.add_argument(
        "--force", action="store_true", help="replace an existing --report file or --export files"
    )
    p.add_argument(
        "--export",
        metavar="TARGET,...",
        help="after the fit, write the (best) fitted model for blender, materialx, mitsuba, "
        "glsl and/or gltf (see `roughdiffuse export`), converted where needed",
    )
    p.add_argument(
        "--export-prefix",
        default="material",
        metavar="PREFIX",
        help="--export's files: PREFIX_TARGET.py/.blend/.mtlx/.xml/.glsl/.gltf (default: material)",
    )
    add_blender_python(p)


def _models(args: argparse.Namespace) -> tuple[Any, list[str] | None]:
    """The candidate of ``--model`` (with the choices ``--param`` fixes) and the ids of
    ``--models``, checked before any data is read."""
    from ..fit import CANDIDATES
    from ..fit.compare import candidate

    known_id(args.model, CANDIDATES)
    if args.param and args.compare:
        raise UsageError("--param fixes a choice of --model; it does not apply with --compare")
    chosen = candidate(args.model, dict(args.param))  # a bad choice refused by name
    models = None
    if args.models is not None:
        if not args.compare:
            raise UsageError("--models needs --compare")
        models = [m.strip() for m in args.models.split(",") if m.strip()]
        for m in models:
            known_id(m, CANDIDATES, "--models")
    return chosen, models


def _add_input_arguments(p: argparse.ArgumentParser) -> None:
    """The options of the two kinds of input: samples/MERL files and images."""
    g = p.add_argument_group("samples and MERL files")
    g.add_argument("--irradiance", type=finite_float, default=None, help="E0 for radiance data")
    g.add_argument(
        "--max-samples",
        type=int,
        default=200_000,
        help="MERL: fit a random subset of this many cells (default: 200000)",
    )
    g = p.add_argument_group("images")
    g.add_argument(
        "--normals",
        type=input_file,
        metavar="NORMALS.npy",
        help="normal map (H, W, 3), world frame",
    )
    g.add_argument("--shape", choices=SHAPES, help="the renderer's shape the image shows")
    g.add_argument(
        "--light",
        type=angle_pair,
        metavar="THETA,PHI",
        help="direction to the light (degrees)",
    )
    g.add_argument(
        "--view",
        type=angle_pair,
        default=(0.0, 0.0),
        metavar="THETA,PHI",
        help="direction to the viewer (degrees, default 0,0)",
    )
    g.add_argument("--margin", type=finite_float, default=0.04, help="--shape: the render's margin")
    g.add_argument(
        "--erode",
        type=int,
        default=1,
        help="drop this many pixels along silhouettes and shadow edges (default 1)",
    )
    g.add_argument(
        "--exposure",
        type=bounded_float(-MAX_EXPOSURE, MAX_EXPOSURE),
        default=None,
        help=f"PNG: exposure in stops, in [-{MAX_EXPOSURE:g}, {MAX_EXPOSURE:g}]",
    )
    g.add_argument("--encoding", choices=("srgb", "linear"), default=None, help="PNG curve")


def _load(args: argparse.Namespace):  # noqa: ANN202 - returns Measurements
    from ..fit import read_csv, read_merl

    path = args.data
    ext = os.path.splitext(path)[1].lower()
    if ext in (".csv", ".txt", ".tsv"):
        with reading(path, "data file"):
            return read_csv(path, irradiance=args.irradiance)
    if ext == ".binary":
        if args.max_samples < 10:
            raise UsageError(f"--max-samples must be >= 10 (got {args.max_samples})")
        with reading(path, "MERL file"):
            merl = read_merl(path)
        return merl.to_measurements(max_samples=args.max_samples)
    if ext in (".npy", ".exr", ".png"):
        return _load_image(args, path)
    raise UsageError(f"DATA must end in .csv, .binary, .npy, .exr or .png (got {path!r})")


def _load_image(args: argparse.Namespace, path: str):  # noqa: ANN202
    import numpy as np

    from ..fit import image_measurements, read_image, read_normals, shape_normals
    from ..render import Cylinder, DistantLight, OrthographicCamera, Sphere, SurfaceOfRevolution

    if args.light is None:
        raise UsageError("an image needs --light THETA,PHI (degrees, direction to the light)")
    if (args.normals is None) == (args.shape is None):
        raise UsageError("an image needs exactly one of --normals FILE.npy and --shape NAME")
    for name, (theta, _) in (("--light", args.light), ("--view", args.view)):
        if not 0.0 <= theta <= 180.0:
            raise UsageError(f"{name} theta must be in [0, 180] degrees (got {theta:g})")
    e0 = 1.0 if args.irradiance is None else args.irradiance
    if not e0 > 0:
        raise UsageError(f"--irradiance must be > 0 (got {e0:g})")
    light = DistantLight(math.radians(args.light[0]), math.radians(args.light[1]), e0)
    camera = OrthographicCamera(
        math.radians(args.view[0]), math.radians(args.view[1]), margin=args.margin
    )
    with reading(path, "image"):
        image, mask = read_image(path, exposure=args.exposure, encoding=args.encoding)
    if args.normals is not None:
        with reading(args.normals, "normal map"):
            normals = read_normals(args.normals)
        if normals.shape[:2] != image.shape[:2]:
            raise UsageError(
                f"normal map {normals.shape[:2]} and image {image.shape[:2]} differ in size"
            )
    else:
        shape = {"sphere": Sphere(), "vase": SurfaceOfRevolution(), "cylinder": Cylinder()}[
            args.shape
        ]
        normals, on = shape_normals(shape, image.shape[:2], light, camera)
        mask = mask & on
    if args.erode < 0:
        raise UsageError(f"--erode must be >= 0 (got {args.erode})")
    return image_measurements(
        image,
        normals,
        light,
        camera,
        mask=np.asarray(mask),
        erode=args.erode,
        source=os.path.basename(path),
    )


def _check_values(value: object, path: str) -> None:
    """Refuse data the fit cannot handle: non-finite, all zero, or beyond :data:`DATA_RANGE`."""
    import numpy as np

    v = np.asarray(value, dtype=np.float64)
    if v.size == 0:
        raise UsageError(f"{path}: no data values")
    if not np.all(np.isfinite(v)):
        raise UsageError(f"{path}: {int(np.sum(~np.isfinite(v)))} values are NaN or infinite")
    mag = np.abs(v[v != 0])
    if mag.size == 0:
        raise UsageError(f"{path}: every value is 0; there is nothing to fit")
    lo, hi = DATA_RANGE
    if mag.max() > hi or mag.min() < lo:
        raise UsageError(
            f"{path}: values from {mag.min():.3g} to {mag.max():.3g} in magnitude; the fit takes "
            f"[{lo:g}, {hi:g}] (rescale the data, or give --irradiance for radiance)"
        )


def run(args: argparse.Namespace) -> int:
    from ..io.reading import check_regular

    try:  # before the fit's imports and any work
        check_regular(args.data, "data file")
    except ValueError as exc:
        raise UsageError(str(exc)) from None
    import numpy as np

    from ..fit import DegenerateDataWarning, compare_models, fit
    from ..fit.least_squares import noise_model
    from ..fit.report import write_report
    from ..progress import progress_enabled

    chosen, models = _models(args)
    if args.report:  # checked before the data is read or fitted; kept unless --force
        if not args.report.lower().endswith((".html", ".htm")):
            raise UsageError(f"--report must name an .html file (got {args.report!r})")
        output_file(args.report, force=args.force, option="--report")
    exports = _export_plan(args)  # targets and folder checked before the data is read
    data = _load(args)
    _check_values(data.value, args.data)
    say = (lambda *a: None) if args.json else print
    say(f"data: {data.source}: {data.size} samples ({data.kind})")
    noise, note = noise_model(data, args.noise)
    if note:
        say(f"note: {note}")
    options = {"noise": noise, "loss": args.loss}
    f_scale = 0.03 if args.f_scale is None else args.f_scale
    if not f_scale > 0:
        raise UsageError(f"--f-scale must be > 0 (got {f_scale:g})")
    if options["noise"] == "absolute":  # weighted residuals are in data units
        f_scale *= float(np.median(np.abs(data.value)))
    options["f_scale"] = f_scale
    comparison = None
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", DegenerateDataWarning)
        if args.compare:
            comparison = compare_models(data, models, progress=progress_enabled(), **options)
            results = list(comparison.results)
        else:
            c = chosen
            results = [fit(c.model, data, c.params, c.bounds, fixed=c.fixed, **options)]
    for r in results:
        require_finite(
            [r.rms, r.aic, r.bic, *np.ravel(r.values)],
            f"the fit of {r.model_name} (RMS, AIC, BIC, parameters)",
            args.data,
        )
    from ..fit.sanity import fit_problem

    problem = fit_problem(
        results[0].rms_relative, results[0].warnings, f"the fit of {results[0].model_name}"
    )
    if problem is not None:  # never a quiet result: refused before anything is printed
        raise UsageError(problem)
    if args.json:
        _print_json(data, results, comparison, args.model, dict(args.param))
    else:
        if comparison is not None:
            print("models ranked by BIC (lower is better):")
            print(comparison.table())
            print()
        print(results[0].table())
    degenerate = any(issubclass(w.category, DegenerateDataWarning) for w in caught)
    if degenerate and not args.compare and not args.json:
        print("warning: the data cannot identify every parameter (see the table)")
    if args.report:
        write_report(args.report, data, results, comparison)
        say(f"wrote {args.report}")
    if exports:
        _export(results[0].model, exports, args.json)
    return 0


def _export_plan(args: argparse.Namespace) -> dict | None:
    """``--export``'s files by target (``None`` without it), checked before any work."""
    if args.export is None:
        return None
    from ._export_targets import export_paths, parse_targets, use_blender_python_flag

    use_blender_python_flag(args)
    return export_paths(args.export_prefix, parse_targets(args.export), force=args.force)


def _export(model: object, exports: dict, json_out: bool) -> None:
    """Write the fitted model for each target; the summaries go to stderr with --json (whose
    stdout is the JSON)."""
    import sys

    from ._export_targets import export_model

    say = print if not json_out else (lambda *a: print(*a, file=sys.stderr))
    export_model(model, exports, say)


def _print_json(data, results, comparison, model_id: str, choices: dict) -> None:  # noqa: ANN001
    """The fit (or the ranking, best first) as :func:`roughdiffuse.fit.summary.result_json`;
    ``choices``: those ``--param`` fixed for ``--model``."""
    import json

    from ..fit.summary import result_json

    if comparison is not None:
        rows = zip(comparison.ids, comparison.choices, results, strict=True)
    else:
        rows = zip((model_id,), (choices,), results, strict=True)
    out = {
        "data": data.source,
        "samples": int(data.size),
        "fits": [result_json(n, r, ch) for n, ch, r in rows],
    }
    print(json.dumps(out, indent=2, ensure_ascii=False, allow_nan=False))
