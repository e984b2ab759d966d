"""``roughdiffuse plot``: the lecture's plots for models chosen on the command line."""

from __future__ import annotations

import argparse
import copy
import math
from typing import Any

from . import UsageError
from ._common import (
    add_model_arguments,
    model_from_args,
    model_ids,
    parameter_help,
)
from ._inputs import angle_list, known_id
from .render import (
    add_output_arguments,
    add_scene_arguments,
    check_output,
    check_render_memory,
    make_shape,
)

EXAMPLES = """\
examples:
  roughdiffuse plot plane --model lambert,oren-nayar,oren-nayar-full --sigma 15,30 \\
      --theta-i 30,60 -o plane.png
  roughdiffuse plot polar --model oren-nayar --sigma 30 --theta-i 60 -o polar.png
  roughdiffuse plot cross-section --model lambert,oren-nayar --sigma 17 --shape vase -o cs.png
  roughdiffuse plot roughness-series --model oren-nayar --sigma 0,6,11,17,29 -o series.png

--model and --sigma take comma-separated lists: every model is drawn for every σ (models
without σ once). σ and the angles are in degrees.
"""

KINDS = ("plane", "polar", "cross-section", "roughness-series", "albedo")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "plot",
        help="plots: plane of incidence (Cartesian, polar), cross-sections, roughness series",
        description="Draw one of the lecture's plots for the models given, as a PNG (or SVG, PDF).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("kind", metavar="KIND", help=f"one of: {', '.join(KINDS)}")
    add_model_arguments(p)
    for action in p._actions:  # --model and --sigma take lists here
        if action.dest == "model":
            action.help = f"comma-separated ids from: {', '.join(model_ids())}"
        if action.dest == "sigma":
            action.type = angle_list
            action.default = [20.0]
            action.help = f"{parameter_help('sigma')}; comma-separated (default: 20)"
    p.add_argument(
        "--theta-i",
        type=angle_list,
        default=[30.0, 60.0],
        help="plane/polar: incidence angles θi, degrees [0, 90], comma-separated (default 30,60)",
    )
    add_scene_arguments(p)
    g = p.add_argument_group("output")
    add_output_arguments(g, (".png", ".svg", ".pdf"))
    p.set_defaults(func=run)


def _models(args: argparse.Namespace, sigma_list: list[float] | None = None) -> dict:
    names = [n.strip() for n in args.model.split(",") if n.strip()]
    if not names:
        raise UsageError("--model must name at least one model")
    sigmas = sigma_list if sigma_list is not None else args.sigma
    from .. import registry

    models = {}
    for name in names:
        uses_sigma = "sigma" in registry.get(known_id(name, registry.ids())).defaults()
        for s in sigmas if uses_sigma else sigmas[:1]:
            a = copy.copy(args)
            a.model, a.sigma = name, s if uses_sigma else None
            label = f"{name}, σ = {s:g}°" if uses_sigma else name
            models[label] = model_from_args(a, strict=False)
    return models


def run(args: argparse.Namespace) -> int:
    from ..io.atomic import atomic_write
    from .render import scene_from_args

    if args.kind not in KINDS:
        raise UsageError(f"unknown plot {args.kind!r}; choose one of: {', '.join(KINDS)}")
    out = check_output(args.output, (".png", ".svg", ".pdf"), args.force)
    if args.kind == "albedo":  # white furnace at ρ = 1; `roughdiffuse albedo` has more options
        from .albedo import plot_kind

        return plot_kind(args, out)

    lights, camera = scene_from_args(args)
    if args.kind in ("plane", "polar"):
        fig = _plane(args)
    elif args.kind == "cross-section":
        fig = _cross_section(args, lights, camera)
    else:
        fig = _roughness_series(args, lights, camera)
    fig.tight_layout()
    atomic_write(out, lambda tmp: fig.savefig(tmp, dpi=110))
    print(f"wrote {out}")
    return 0


def _plane(args: argparse.Namespace) -> Any:
    """``plane`` and ``polar``: radiance in the plane of incidence, one panel per θi."""
    from .. import plots
    from .._figure import figure

    for t in args.theta_i:
        if not 0.0 <= t <= 90.0:
            raise UsageError(f"--theta-i must be in [0, 90] degrees (got {t:.15g})")
    models = _models(args)
    polar = args.kind == "polar"
    n = len(args.theta_i)
    fig = figure(figsize=(5.2 * n, 4.2))
    for i, t in enumerate(args.theta_i):
        ax = fig.add_subplot(1, n, i + 1, projection="polar" if polar else None)
        plots.plot_plane_of_incidence(models, math.radians(t), ax=ax, polar=polar)
    fig.suptitle("radiance in the plane of incidence (E0 = 1)")
    return fig


def _cross_section(args: argparse.Namespace, lights: Any, camera: Any) -> Any:
    """``cross-section``: brightness across the middle row of each model's image."""
    from .. import plots
    from .._figure import subplots
    from ..render import pixel_coordinates, render

    models = _models(args)
    shape = make_shape(args.shape)
    check_render_memory(args, channels=3, images=len(models))
    results = {
        k: render(
            m,
            shape,
            lights,
            camera,
            args.size,
            samples_per_pixel=args.spp,
            shadows=not args.no_shadows,
        )
        for k, m in models.items()
    }
    fig, ax = subplots(figsize=(6.5, 4.2))
    x = pixel_coordinates(shape, camera, args.size)[0]
    plots.plot_cross_section(
        {k: v[0] for k, v in results.items()},
        masks={k: v[1] for k, v in results.items()},
        ax=ax,
        x=x,
    )
    ax.set_title(f"{args.shape}: brightness across the middle row")
    return fig


def _roughness_series(args: argparse.Namespace, lights: Any, camera: Any) -> Any:
    """``roughness-series``: one model's images at each σ."""
    from .. import plots
    from ..render import DistantLight

    names = [n.strip() for n in args.model.split(",") if n.strip()]
    if len(names) != 1:
        raise UsageError("roughness-series takes one --model")
    for s in args.sigma:
        if not 0.0 <= s <= 90.0:
            raise UsageError(f"--sigma must be in [0, 90] degrees (got {s:.15g})")

    def make(sigma_rad: float):  # noqa: ANN202
        a = copy.copy(args)
        a.model, a.sigma = names[0], math.degrees(sigma_rad)
        return model_from_args(a, strict=False)

    size = args.size if isinstance(args.size, int) else min(args.size)
    fig = plots.plot_roughness_series(
        make,
        [math.radians(s) for s in args.sigma],
        shape=make_shape(args.shape),
        lights=[DistantLight(x.theta, x.phi, x.irradiance) for x in lights],
        camera=camera,
        size=min(size, 512),
        samples_per_pixel=args.spp,
    )
    for ax, s in zip(fig.axes, args.sigma, strict=False):
        ax.set_title(f"σ = {s:g}°", fontsize="medium")
    fig.suptitle(f"{names[0]}: increasing roughness")
    return fig
