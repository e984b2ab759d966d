"""``python -m roughdiffuse.bench``: the benchmark suite (see :mod:`roughdiffuse.bench.run`)."""

import sys

from .run import main

sys.exit(main())
