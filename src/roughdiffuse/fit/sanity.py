"""Whether a fit's result can be reported: never silently the starting guess.

A least-squares fit can end where it started, stop without converging, or end with a
residual as large as the data (a model that describes none of it, often data on the wrong
scale: an image scaled by 1e18, a PNG read with the wrong exposure). Its parameters are then
not a result. :func:`fit_problem` names the problem; the ``fit`` command refuses such a
result (exit status 2) and ``stereo`` refuses its roughness the same way.
"""

from __future__ import annotations

import math

__all__ = ["RESIDUAL_OF_DATA_SIZE", "fit_problem"]

RESIDUAL_OF_DATA_SIZE = 0.9
"""Relative RMS residual (RMS of (model − data) / data) from which a fit explains nothing of
the data: a model at zero has 1.0. Real data fitted by a reasonable model stay well below
(measured BRDFs and images: 0.01–0.3)."""


def fit_problem(
    rms_relative: float, notes: tuple[str, ...] = (), what: str = "the fit"
) -> str | None:
    """The reason a fit's result must not be reported, or None.

    Parameters
    ----------
    rms_relative : float
        RMS of the relative residuals.
    notes : tuple of str
        The fit's notes; one starting with ``"optimizer:"`` says it did not converge.
    what : str
        The fit, for the message.
    """
    if not math.isfinite(rms_relative):
        return f"{what} has no finite residual: it did not converge"
    if rms_relative >= RESIDUAL_OF_DATA_SIZE:
        return (
            f"{what} ends with a relative RMS residual of {100 * rms_relative:.0f}%, the size "
            "of the data itself: the model describes none of it and its parameters are not "
            "a result (is the data on the right scale? check --exposure or --irradiance)"
        )
    stopped = [n for n in notes if n.startswith("optimizer:")]
    if stopped:
        return f"{what} did not converge ({stopped[0]})"
    return None
