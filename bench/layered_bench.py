"""Thin wrapper, from a checkout: ``python bench/layered_bench.py [options] [--write]`` runs
:mod:`roughdiffuse.bench.layered_bench` (the layered walk's and ``Coated``'s speed);
``--write`` replaces its sections of ``bench/RESULTS.md`` next to this file (run it after
``bench/run.py``, which rewrites that file whole)."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.layered_bench import main
from roughdiffuse.bench.timing import with_write_target

if __name__ == "__main__":
    argv = with_write_target(sys.argv[1:], Path(__file__).resolve().parent / "RESULTS.md")
    main(argv, prog="python bench/layered_bench.py")
