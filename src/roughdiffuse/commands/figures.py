"""``roughdiffuse figures``: the lecture's eight figures and an index.html, in one command."""

from __future__ import annotations

import argparse

EXAMPLES = """\
examples:
  roughdiffuse figures                 # writes figures/*.png and figures/index.html
  roughdiffuse figures -o out/ --force # redraw every figure
  roughdiffuse figures --only 2 3      # the full moon and the vase

Figures already on disk are kept (an interrupted run resumes); --force redraws them.
"""


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "figures",
        help="write the lecture's figures (PNG) and an index.html into a folder",
        description="Render and plot the eight figures of the lecture on rough diffuse "
        "reflection (Lambert sphere, full moon, vase, roughness series, view dependence, "
        "blurred highlights, diffuse + specular, the Oren-Nayar family).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "-o", "--output", default="figures", metavar="DIR", help="folder (default: figures/)"
    )
    p.add_argument("--force", action="store_true", help="redraw figures that exist")
    p.add_argument("--only", nargs="+", metavar="NAME", help="figure names or numbers")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from . import UsageError

    # checked before the folder is created or anything drawn (or imported)
    if args.only is not None and not all(o.strip() for o in args.only):
        raise UsageError("--only needs figure names or numbers (got an empty name)")
    from ..figures import FIGURES, figure_matches, kept_figures, make_figures
    from ..progress import progress_enabled
    from ._checks import output_folder
    if args.only:
        unknown = [o for o in args.only if not any(figure_matches(f.name, o) for f in FIGURES)]
        if unknown:
            raise UsageError(
                f"--only: no figure matches {', '.join(unknown)}; names: "
                f"{', '.join(f.name for f in FIGURES)}"
            )
    output_folder(args.output, option="-o")
    kept = [] if args.force else kept_figures(args.output, args.only)
    paths = make_figures(
        args.output,
        force=args.force,
        progress=progress_enabled() and not args.no_progress,
        only=args.only,
    )
    drawn = len(paths) - 1 - len(kept)
    note = f" (kept {len(kept)} already there: {', '.join(kept)}; --force redraws them)"
    print(f"wrote {drawn} figures and {paths[-1]}" + (note if kept else ""))
    return 0
