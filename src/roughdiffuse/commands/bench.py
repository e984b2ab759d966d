"""``roughdiffuse bench``: the benchmark suite of ``bench/run.py`` (needs a source checkout):
every model's fast path, the renderer, the fit and the V-cavity solver, each against a
baseline timed in the same run."""

from __future__ import annotations

import argparse
import importlib.util
import shlex
import sys
from pathlib import Path
from types import ModuleType

from . import UsageError

EXAMPLES = """\
examples:
  roughdiffuse bench                     # every model at 2^22 and 2^24, 7 runs each
  roughdiffuse bench --sizes 22 --repeat 9 --memory-log2 0
  roughdiffuse bench --models oren       # only the Oren-Nayar variants
  roughdiffuse bench --no-render --no-fit --no-simulate   # only the models' fast path
  roughdiffuse bench --sizes 20 --no-render --no-simulate --fit-size 400 --fit-repeat 2

Writes bench/RESULTS.md and bench/results.json (see the README's "Benchmarks" section).
"""


def find_run_script() -> Path | None:
    """bench/run.py of the current directory's checkout, else of this package's checkout."""
    candidates = [
        Path.cwd() / "bench" / "run.py",
        Path(__file__).resolve().parents[3] / "bench" / "run.py",
    ]
    return next((p for p in candidates if p.is_file()), None)


def _load(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location("roughdiffuse_bench_run", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def register(sub: argparse._SubParsersAction) -> None:
    script = find_run_script()
    parents = [_load(script).parser(add_help=False)] if script else []
    p = sub.add_parser(
        "bench",
        parents=parents,
        help="benchmarks: models' fast path vs C and NumPy, renderer, fit, V-cavity solver",
        description="Benchmarks of bench/run.py: every model's fast path against a C "
        "reference compiled in this run (gcc) and against plain NumPy; the renderer against "
        "NumPy shading; the fit of (ρ, σ) to an image against scipy.optimize.least_squares; "
        "the V-cavity solver's NumPy and JAX paths. Needs a source checkout (bench/ is not "
        "installed with the package).",
        epilog=EXAMPLES,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.set_defaults(func=run, bench_script=script)


def run(args: argparse.Namespace) -> int:
    if args.bench_script is None:
        raise UsageError("bench/run.py not found: run from a source checkout of roughdiffuse")
    module = sys.modules.get("roughdiffuse_bench_run") or _load(args.bench_script)
    words = sys.argv[2:] if len(sys.argv) > 1 and sys.argv[1] == "bench" else []
    command = " ".join(["roughdiffuse bench", *(shlex.quote(w) for w in words)])
    return int(module.run(args, command))
