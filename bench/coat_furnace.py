"""Thin wrapper, from a checkout: ``python bench/coat_furnace.py [options]`` runs
:mod:`roughdiffuse.bench.coat_furnace` (the white furnace of the layered walk's rough coat) and
rewrites its section of ``bench/RESULTS.md`` next to this file (``--no-write``: print only)."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.coat_furnace import main

if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--no-write" in argv:
        argv.remove("--no-write")
    elif "--write" not in argv:
        argv += ["--write", str(Path(__file__).resolve().parent / "RESULTS.md")]
    main(argv, prog="python bench/coat_furnace.py")
