"""Thin wrapper, from a checkout: ``python bench/coat_furnace.py [options] [--write]`` runs
:mod:`roughdiffuse.bench.coat_furnace` (the white furnace of the layered walk's rough
coat); ``--write`` replaces its section of ``bench/RESULTS.md`` next to this file."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.coat_furnace import main
from roughdiffuse.bench.timing import with_write_target

if __name__ == "__main__":
    argv = with_write_target(sys.argv[1:], Path(__file__).resolve().parent / "RESULTS.md")
    main(argv, prog="python bench/coat_furnace.py")
