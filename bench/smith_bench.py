"""Thin wrapper, from a checkout: ``python bench/smith_bench.py [--write]`` runs
:mod:`roughdiffuse.bench.smith_bench` (the Smith random walk's speed); ``--write`` replaces its
section of ``bench/RESULTS.md`` next to this file (run it after ``bench/run.py``, which rewrites
that file whole)."""

from __future__ import annotations

import os
import sys
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # before NumPy is imported
os.environ.setdefault("OMP_NUM_THREADS", "1")

from roughdiffuse.bench.smith_bench import main  # noqa: E402
from roughdiffuse.bench.timing import with_write_target  # noqa: E402

if __name__ == "__main__":
    argv = with_write_target(sys.argv[1:], Path(__file__).resolve().parent / "RESULTS.md")
    main(argv, prog="python bench/smith_bench.py")
