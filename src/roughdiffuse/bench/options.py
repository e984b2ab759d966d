"""The benchmark suite's options (:mod:`.run`; also ``roughdiffuse bench``'s), in a module that
imports nothing but argparse, so that building the CLI's parser stays cheap."""

from __future__ import annotations

import argparse
from pathlib import Path

__all__ = ["parser"]


def parser(add_help: bool = True) -> argparse.ArgumentParser:
    """The benchmark's options (also the options of ``roughdiffuse bench``)."""
    p = argparse.ArgumentParser(
        prog="python -m roughdiffuse.bench",
        description="Throughput of every model: fast path vs C (compiled now) vs NumPy.",
        add_help=add_help,
    )
    p.add_argument(
        "--sizes",
        default="22,24",
        help="log2 of the numbers of geometries, comma-separated (default: 22,24)",
    )
    p.add_argument("--repeat", type=int, default=7, help="timed runs per variant (>= 1)")
    p.add_argument(
        "--models", default="", help="only models whose label or registry id contains this text"
    )
    p.add_argument("--no-numpy", action="store_true", help="skip the NumPy reference path")
    p.add_argument("--no-c", action="store_true", help="skip the C reference")
    p.add_argument(
        "--memory-log2", type=int, default=26, help="log2 rows of the memory test (0: skip)"
    )
    p.add_argument("--no-first-call", action="store_true", help="skip the first-call test")
    p.add_argument(
        "--brdf-sizes",
        default="22",
        help="log2 sizes of the default-call brdf benchmark, comma-separated ('' : skip)",
    )
    p.add_argument(
        "--startup-repeat", type=int, default=9, help="runs of each start-up command (0: skip)"
    )
    p.add_argument("--no-render", action="store_true", help="skip the renderer benchmark")
    p.add_argument("--no-fit", action="store_true", help="skip the fit benchmark")
    p.add_argument("--fit-size", type=int, default=1200, help="fit image side (default 1200)")
    p.add_argument("--fit-repeat", type=int, default=5, help="timed runs of each fit (default 5)")
    p.add_argument("--no-simulate", action="store_true", help="skip the V-cavity solver")
    p.add_argument("--simulate-repeat", type=int, default=3, help="timed solver runs (default 3)")
    p.add_argument(
        "--simulate-cavities",
        type=int,
        default=200_000,
        help="cavities of the solver's cavity cases (default 200000)",
    )
    p.add_argument(
        "--simulate-geometries",
        type=int,
        default=48,
        help="geometries of the solver's surface BRDF cases (default 48)",
    )
    p.add_argument(
        "--simulate-cases",
        default="",
        help="only solver cases whose name contains one of these comma-separated texts",
    )
    p.add_argument(
        "--output-dir",
        type=Path,
        default=Path("."),
        help="where RESULTS.md and results.json go (default: the current directory)",
    )
    return p
