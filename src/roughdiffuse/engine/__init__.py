"""The compiled engine: models' own code traced and compiled by Numba, on every core.

* :mod:`.dispatch` — the automatic choice, in the models' methods, between the array-API
  reference path and compiled code (``roughdiffuse.use_fastpath``, ``fastpath_enabled``);
* :mod:`.fastpath` — the compiled ``radiance``, ``brdf`` and ``brdf_cosines`` (also
  ``roughdiffuse.fastpath``);
* :mod:`.trace` — the symbolic array namespace a model's method runs on once, and the
  scalar source printed from it;
* :mod:`.numba_math`, :mod:`.numba_random` — the Numba helpers the kernels and the compiled
  Smith walk call;
* :mod:`.protocol` — what the engine needs of a model; :mod:`.cache` — the private cache
  folder.

Below the models: nothing here imports :mod:`roughdiffuse.models` (see
docs/developer/index.md).
"""
