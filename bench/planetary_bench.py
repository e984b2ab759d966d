"""Thin wrapper, from a checkout: ``python bench/planetary_bench.py [options]`` runs
:mod:`roughdiffuse.bench.planetary_bench` (planetary images: formats, chunks, scale) and
rewrites its section of ``bench/RESULTS.md`` next to this file (``--no-write``: print only)."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.planetary_bench import main

if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--no-write" in argv:
        argv.remove("--no-write")
    elif "--write" not in argv:
        argv += ["--write", str(Path(__file__).resolve().parent / "RESULTS.md")]
    main(argv, prog="python bench/planetary_bench.py")
