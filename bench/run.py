"""Thin wrapper, from a checkout: ``python bench/run.py [options]`` runs the packaged benchmark
suite (:mod:`roughdiffuse.bench`) and writes ``bench/RESULTS.md`` and ``bench/results.json``
next to this file unless ``--output-dir`` says otherwise. ``python -m roughdiffuse.bench
--help`` lists the options."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.run import main

if __name__ == "__main__":
    argv = shown = sys.argv[1:]
    if not any(a == "--output-dir" or a.startswith("--output-dir=") for a in argv):
        argv = [*argv, "--output-dir", str(Path(__file__).resolve().parent)]
    sys.exit(main(argv, prog="python bench/run.py", shown=shown))
