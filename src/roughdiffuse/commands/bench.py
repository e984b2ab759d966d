"""``roughdiffuse bench``: the packaged benchmark suite, :mod:`roughdiffuse.bench` (every
model's fast path and default call against C and NumPy, the renderer, the fit, the V-cavity
solver, start-up). It runs only the package's own code: nothing from the current directory."""

from __future__ import annotations

import argparse
import shlex
import sys

EXAMPLES = """\
examples:
  roughdiffuse bench                     # every model at 2^22 and 2^24, 7 runs each
  roughdiffuse bench --sizes 22 --repeat 9 --memory-log2 0
  roughdiffuse bench --models oren       # only the Oren-Nayar variants
  roughdiffuse bench --no-render --no-fit --no-simulate   # only the models' fast path
  roughdiffuse bench --sizes 20 --no-render --no-simulate --fit-size 400 --fit-repeat 2

Writes RESULTS.md and results.json to --output-dir (default: the current directory); from a
checkout, `python bench/run.py` writes bench/RESULTS.md (see
docs/developer/speed-and-benchmarks.md).
"""


def register(sub: argparse._SubParsersAction) -> None:
    from ..bench.options import parser  # argparse only: no NumPy, no Numba

    p = sub.add_parser(
        "bench",
        parents=[parser(add_help=False)],
        help="benchmarks: models' fast path vs C and NumPy, renderer, fit, V-cavity solver",
        description="The benchmark suite (roughdiffuse.bench): every model's fast path and "
        "default call against a C reference compiled in this run (gcc) and against plain "
        "NumPy; the renderer against NumPy shading; the fit of (ρ, σ) to an image against "
        "scipy.optimize.least_squares; the V-cavity solver's NumPy and JAX paths; start-up "
        "times.",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from ..bench.run import run as run_bench

    words = sys.argv[2:] if len(sys.argv) > 1 and sys.argv[1] == "bench" else []
    command = " ".join(["roughdiffuse bench", *(shlex.quote(w) for w in words)])
    return int(run_bench(args, command))
