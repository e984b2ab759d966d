"""Thin wrapper, from a checkout: ``python bench/table_time.py -- COMMAND...`` runs
:mod:`roughdiffuse.bench.table_time` (wall and total CPU time of one command's process tree)."""

from __future__ import annotations

import sys

from roughdiffuse.bench.table_time import main

if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
