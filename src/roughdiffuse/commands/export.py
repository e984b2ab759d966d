"""``roughdiffuse export``: write a model or a fit result as a Mitsuba, MaterialX or Blender
material, a glTF sphere, or a GLSL function for the user's own shader."""

from __future__ import annotations

import argparse

from . import UsageError
from ._checks import output_file
from ._common import add_model_arguments, model_from_args
from ._export_targets import (
    add_blender_python,
    export_errors,
    quiet_backend_warnings,
    use_blender_python_flag,
)
from ._inputs import suggest

EXAMPLES = """\
examples:
  roughdiffuse export --model oren-nayar-full --param sigma=20 --to blender -o mat.py
  roughdiffuse export --model eon --roughness 0.5 --to materialx -o mat.mtlx --openpbr
  roughdiffuse export --model eon --roughness 0.5 --to mitsuba -o scene.xml
  roughdiffuse export --model oren-nayar-full --param sigma=20 --to glsl -o brdf.glsl
  roughdiffuse export --model hapke-2012 --to glsl --uniforms -o hapke.glsl
  roughdiffuse export --model eon --roughness 0.5 --albedo 0.8,0.5,0.2 --to gltf -o sphere.glb

glTF: a sphere whose material is EON (KHR_materials_diffuse_roughness, the specular lobe
off); FILE.gltf is JSON with its buffer embedded, FILE.glb binary. Other rough-diffuse
models are converted to EON; planetary and glossy models are refused (as by materialx and
blender): export them with --to glsl or mitsuba.

GLSL (WebGL 2, three.js, Godot): `vec3 rd_brdf(vec3 wi, vec3 wo)`, the BRDF in 1/sr
printed from the model's own code, wi and wo in the surface's frame (z the normal); paste it
above your shader's main and shade with rd_brdf(wi, wo) * E0 * max(wi.z, 0.0). --uniforms
declares the parameters as uniforms (named as in `roughdiffuse models`, angles in radians)
instead of baking their values in.

A fit result instead of a model: `roughdiffuse fit DATA --json > fit.json`, then
`--from fit.json` (also a stereo run's `params.json`, or `{"model": ID, "params": {...}}`).
Where the target has no exact counterpart the parameters are converted (roughdiffuse convert)
and the conversion error is printed and written in the file's comments.
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "export",
        help="write a model or a fit result as a Mitsuba, MaterialX or Blender material, a "
        "glTF sphere, or a GLSL function",
        description="Write a Mitsuba 3 scene (XML + dict), a MaterialX .mtlx, a Blender .py, "
        "a glTF sphere (.gltf or .glb) or a GLSL ES 3.00 function for a model (--model, "
        "--param) or a fit result (--from fit JSON or stereo params.json).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    add_model_arguments(p)
    p.add_argument("--from", dest="source", metavar="FILE.json", help="a fit result instead")
    p.add_argument(
        "--to", required=True, metavar="TARGET", help="mitsuba, materialx, blender, glsl or gltf"
    )
    p.add_argument(
        "-o",
        "--output",
        required=True,
        metavar="FILE",
        help="the file to write: mitsuba FILE.xml and FILE.py beside it (and FILE_builtin.xml "
        "for lambert and burley-2015), materialx FILE.mtlx, blender FILE.py and FILE.blend "
        "beside it (unless --no-blend or no Blender is found), glsl FILE.glsl, gltf FILE.gltf or "
        "FILE.glb; none is replaced "
        "without --force",
    )
    p.add_argument("--force", action="store_true", help="replace files that exist")
    p.add_argument(
        "--openpbr",
        action="store_true",
        help="MaterialX: an open_pbr_surface (base_diffuse_roughness)",
    )
    p.add_argument(
        "--principled", action="store_true", help="Blender: a Principled BSDF (Diffuse Roughness)"
    )
    p.add_argument(
        "--no-blend",
        action="store_true",
        help="Blender: the .py only (by default a .blend is also written beside it where "
        "Blender's Python is found: see --blender-python)",
    )
    add_blender_python(p)
    p.add_argument(
        "--uniforms",
        action="store_true",
        help="GLSL: the parameters as uniforms set by your program (default: values baked in)",
    )
    p.add_argument(
        "--name",
        default="rd_brdf",
        metavar="NAME",
        help="GLSL: the function's name (default: rd_brdf)",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..exporters import TARGETS, export, load_result, planned_files, suffixes
    from ..exporters.blender import write as write_blender
    from ..exporters.scope import check_model

    if args.to not in TARGETS:
        raise UsageError(
            f"--to: unknown target {args.to!r}{suggest(args.to, TARGETS)}; choose one of: "
            f"{', '.join(TARGETS)}"
        )
    use_blender_python_flag(args)
    out = output_file(args.output, suffixes(args.to), force=args.force)
    if args.source:
        try:
            model = load_result(args.source)
        except ValueError as exc:
            raise UsageError(f"--from: {exc}") from None
    else:
        model = model_from_args(args)
    blend = False if args.no_blend else None
    with export_errors(out, "--to", args.to, "--output"), quiet_backend_warnings():
        check_model(model, args.to)  # before a conversion (and Blender's own path)
        for path in planned_files(model, args.to, out, blend=blend)[1:]:
            output_file(path, force=args.force)  # each file it writes, kept unless --force
        if args.to == "blender":
            result = write_blender(model, out, principled=args.principled, blend=blend)
        else:
            result = export(
                model,
                args.to,
                out,
                openpbr=args.openpbr,
                uniforms=args.uniforms,
                name=args.name,
            )
    print(result.summary())
    return 0
