"""The accuracy report: every registry model against the exact ground truths.

Above the registry and the solvers: it reads models by registry id
(:mod:`roughdiffuse.registry`) and truths from :mod:`roughdiffuse.simulate` (V-cavity,
Smith, heightfields). ``roughdiffuse simulate --report -o DIR`` writes it
(:func:`.report.write_report`); :mod:`.model_scores` scores every registry model against the
three all-bounce truths, :mod:`.smith_checks` checks the Smith solver and the rendered
heightfields.
"""

from .report import write_report

__all__ = ["write_report"]
