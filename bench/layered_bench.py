"""Thin wrapper, from a checkout: ``python bench/layered_bench.py [options] [--write]`` runs
:mod:`roughdiffuse.bench.layered_bench` (the layered walk's and ``Coated``'s speed);
``--write`` replaces its sections of ``bench/RESULTS.md`` next to this file (run it after
``bench/run.py``, which rewrites that file whole)."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.layered_bench import main

if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--write" in argv:
        k = argv.index("--write")
        if k + 1 >= len(argv) or argv[k + 1].startswith("-"):
            argv.insert(k + 1, str(Path(__file__).resolve().parent / "RESULTS.md"))
    main(argv, prog="python bench/layered_bench.py")
