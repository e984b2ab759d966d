"""Thin wrapper, from a checkout: ``python bench/stereo_renders.py [--write]`` runs
:mod:`roughdiffuse.bench.stereo_renders` (where a Mitsuba render's time goes, for the coated
plugin); ``--write`` replaces its section of ``bench/RESULTS.md`` next to this file."""

from __future__ import annotations

import sys
from pathlib import Path

from roughdiffuse.bench.stereo_renders import main
from roughdiffuse.bench.timing import with_write_target

if __name__ == "__main__":
    argv = with_write_target(sys.argv[1:], Path(__file__).resolve().parent / "RESULTS.md")
    main(argv, prog="python bench/stereo_renders.py")
