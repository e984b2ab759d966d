"""The benchmark suite: every model's fast path and default call against C and NumPy, the
renderer, the fit, the V-cavity solver and start-up times, each against a baseline timed in
the same run.

Run it as ``roughdiffuse bench``, ``python -m roughdiffuse.bench`` or, from a checkout,
``python bench/run.py`` (which writes ``bench/RESULTS.md``). See :mod:`.run` for the parts and
options; the C reference, ``c/kernels.c``, ships with the package. The separate benchmarks
(:mod:`.smith_bench`, :mod:`.layered_bench`, :mod:`.stereo_bench`, :mod:`.table_time`) run as
``python -m roughdiffuse.bench.<name>``; a checkout's ``bench/`` has a thin script for each.
"""
