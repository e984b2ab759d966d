"""Which model explains the data best: fit several, rank by an information criterion.

Each candidate is fitted with :func:`~roughdiffuse.fit.least_squares.fit`; the ranking is by
the Bayesian information criterion BIC = M ln(RSS/M) + P ln M (Schwarz, Ann. Stat. 6, 1978),
which charges each extra parameter, so Oren–Nayar ranks above Lambert only when its σ buys a
real drop of the residual. The RMS and the AIC (Akaike 1974) are reported alongside.

A model whose choice decides which parameters it has (``coated``'s ``base``: Lambert,
Oren–Nayar, Fujii or EON under the coat, with σ, r or neither) is ranked once per choice, a
row named ``coated base=eon`` (:func:`rows`): which base is under the coat is part of what the
data should tell.
"""

from __future__ import annotations

import itertools
import math
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from .._validate import ParameterError
from .measurements import Measurements
from .summary import row_name

if TYPE_CHECKING:  # least_squares imports JAX and SciPy: only when fitting
    from ..models.base import Model
    from ..models.declaration import Param
    from ..registry import Entry
    from .least_squares import FitResult

__all__ = ["CANDIDATES", "Comparison", "compare_models", "fitted_row", "rows"]


@dataclass(frozen=True)
class Candidate:
    """A model to try: a name, the class (or factory), fitted params, fixed args, bounds."""

    name: str
    model: type | Callable[..., Any]
    params: tuple[str, ...]
    fixed: Mapping[str, Any] | None = None
    bounds: Mapping[str, tuple[float, float]] | None = None


def candidate(model_id: str, choices: Mapping[str, str] | None = None) -> Candidate:
    """The candidate of one registry id: its numeric parameters fitted, its fixed choices
    fixed, the boxes its declaration gives (see :mod:`roughdiffuse.registry`).

    ``choices`` fixes categorical parameters the id leaves free (``{"base": "eon"}`` for
    ``coated``; the others at their defaults); the numeric parameters fitted are those that
    exist for these values (:meth:`~roughdiffuse.registry.Entry.applicable`).
    """
    from .. import registry

    entry = registry.get(model_id)
    choices = dict(choices or {})
    for name, value in choices.items():
        p = entry.param(name)  # ValueError naming the id's parameters
        if not p.categorical:
            raise ParameterError(
                f"{name} is a number the fit estimates; only a choice can be fixed "
                f"({', '.join(q.name for q in entry.parameters if q.categorical) or 'none'})"
            )
        p.check(value)
    factory = getattr(entry.cls, "from_params", entry.cls)
    numeric = tuple(p.name for p in entry.applicable(choices) if not p.categorical)
    fixed = {**choices, **entry.fixed}
    return Candidate(entry.id, factory, numeric, fixed or None, None)


def rows(model_id: str) -> list[dict[str, str]]:
    """The choices one registry id is ranked under: one row per value of each categorical
    parameter that other parameters depend on (their ``when``; ``coated``'s ``base``), every
    combination if there are several; ``[{}]`` for an id without such a choice (its other
    choices stay at their defaults).

    >>> rows("lambert")
    [{}]
    >>> [r["base"] for r in rows("coated")]
    ['lambert', 'oren-nayar', 'oren-nayar-full', 'fujii', 'eon']
    """
    from .. import registry

    deciding = _deciding(registry.get(model_id))
    return [
        {p.name: v for p, v in zip(deciding, values, strict=True)}
        for values in itertools.product(*(p.choices or () for p in deciding))
    ]


def _deciding(entry: Entry) -> list[Param]:
    """The categorical parameters of ``entry`` that others depend on (their ``when``)."""
    return [
        p for p in entry.parameters
        if p.categorical and any(p.name in (q.when or {}) for q in entry.parameters)
    ]


def fitted_row(model: Model) -> tuple[str, dict[str, str]] | None:
    """The registry id of a fitted model and its :func:`rows` choices, read off the instance
    (a choice held as the model it names, as ``Coated.base``, by that model's id);
    ``None`` for a model the registry does not describe.

    >>> from roughdiffuse import EON, Coated
    >>> fitted_row(Coated(EON(0.5, 0.2)))
    ('coated', {'base': 'eon'})
    """
    from .. import registry
    from ..models.base import Model

    model_id = registry.id_of(model)
    if model_id is None:
        return None
    choices = {}
    for p in _deciding(registry.get(model_id)):
        value = getattr(model, p.name, None)
        if isinstance(value, Model):
            value = registry.id_of(value)
        if isinstance(value, str):
            choices[p.name] = value
    return model_id, choices


def _fittable_ids() -> list[str]:
    """Registry ids of the closed-form models that JAX can trace (a simulation or a table,
    ``closed_form = False``, has no parameters to differentiate; a model with ``traceable =
    False`` has no gradient from JAX)."""
    from .. import registry

    return [e.id for e in registry.entries() if e.cls.closed_form and e.cls.traceable]


class _Candidates(Mapping[str, Candidate]):
    """Every fittable registry id as a :class:`Candidate` (read when asked: plugins
    included)."""

    def __getitem__(self, name: str) -> Candidate:
        if name not in _fittable_ids():
            raise KeyError(name)
        return candidate(name)

    def __iter__(self) -> Iterator[str]:
        return iter(_fittable_ids())

    def __len__(self) -> int:
        return len(_fittable_ids())


CANDIDATES: Mapping[str, Candidate] = _Candidates()
"""The models :func:`compare_models` tries: every id of :mod:`roughdiffuse.registry` that is
a formula."""


@dataclass(frozen=True)
class Comparison:
    """Fits of several models, best (lowest BIC) first.

    Attributes
    ----------
    names : tuple of str
        Each row's name (:func:`~roughdiffuse.fit.summary.row_name`): the registry id,
        with the choice it was fitted with for a model ranked per choice
        (``"coated base=eon"``).
    results : tuple of FitResult
    ids : tuple of str
        Each row's registry id.
    choices : tuple of dict
        Each row's choices (:func:`rows`; ``{}`` for most models).
    """

    names: tuple[str, ...]
    results: tuple[FitResult, ...]
    ids: tuple[str, ...] = ()
    choices: tuple[Mapping[str, str], ...] = ()

    def __post_init__(self) -> None:  # rows built by hand: names are ids without choices
        if not self.ids:
            object.__setattr__(self, "ids", tuple(self.names))
        if not self.choices:
            object.__setattr__(self, "choices", tuple({} for _ in self.names))

    @property
    def best(self) -> str:
        """Name of the row with the lowest BIC (``"coated base=eon"`` for a coat)."""
        return self.names[0]

    def table(self) -> str:
        """Ranking table: model, parameters, RMS, ΔAIC, ΔBIC."""
        b0 = self.results[0].bic
        a0 = min(r.aic for r in self.results)
        w = max(18, *(len(n) + 2 for n in self.names))
        head = f"{'RMS':>11}{'RMS %':>8}{'ΔAIC':>11}{'ΔBIC':>11}  parameters"
        lines = [f"  {'rank':<5}{'model':<{w}}{head}"]
        for k, (n, r) in enumerate(zip(self.names, self.results, strict=True), start=1):
            params = ", ".join(
                f"{p}={v:.4g}±{e:.2g}" if math.isfinite(e) else f"{p}={v:.4g}±inf"
                for p, v, e in zip(r.names, r.values, r.errors, strict=True)
            )
            lines.append(
                f"  {k:<5}{n:<{w}}{r.rms:>11.4g} {100 * r.rms_relative:>7.3g}"
                f"{r.aic - a0:>11.1f}{r.bic - b0:>11.1f}  {params}"
            )
        return "\n".join(lines)


def compare_models(
    data: Measurements,
    models: Sequence[str] | None = None,
    *,
    progress: bool = False,
    **fit_options: Any,
) -> Comparison:
    """Fit each candidate model to ``data`` and rank them by BIC.

    Parameters
    ----------
    data : Measurements
    models : sequence of str, optional
        Names from :data:`CANDIDATES` (default: all of them). An id with a choice that
        decides its parameters is fitted once per choice (:func:`rows`: ``coated`` over
        each of its bases).
    progress : bool
        Show a progress bar, fit n of N (:func:`roughdiffuse.progress.progress`).
    **fit_options
        Passed to :func:`~roughdiffuse.fit.least_squares.fit` (``noise``, ``loss``, …). The
        noise model is relative unless ``noise="absolute"`` is given (the default of
        :func:`~roughdiffuse.fit.least_squares.fit`, of ``roughdiffuse fit --compare`` and of
        the explorer's ranking: one ranking for the same data everywhere).

    Returns
    -------
    Comparison
        The rows (``names``, ``ids``, ``choices``, ``results``) sorted by BIC, best first;
        ``table()`` prints them.
    """
    names = list(CANDIDATES) if models is None else list(models)
    unknown = [n for n in names if n not in CANDIDATES]
    if unknown or not names:
        raise ParameterError(
            f"models must be names from: {', '.join(CANDIDATES)} "
            f"(got {', '.join(unknown) or 'none'})"
        )
    from .least_squares import (
        DEFAULT_NOISE,
        DegenerateDataWarning,
        NoiseModelWarning,
        fit,
        noise_model,
    )

    _, note = noise_model(data, fit_options.get("noise", DEFAULT_NOISE))
    if note:  # once, not once per model
        warnings.warn(note, NoiseModelWarning, stacklevel=2)
    from ..progress import progress as progress_bar

    todo = [(n, choices) for n in names for choices in rows(n)]
    out = []
    bar = progress_bar(len(todo), "fitting models", unit="fit", enabled=progress)
    for n, choices in todo:
        bar.set_postfix_str(row_name(n, choices))
        c = candidate(n, choices)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", DegenerateDataWarning)
            warnings.simplefilter("ignore", NoiseModelWarning)
            r = fit(c.model, data, c.params, c.bounds, fixed=c.fixed, **fit_options)
        out.append((n, choices, r))
        bar.update(1)
    bar.close()
    out.sort(key=lambda t: t[2].bic)
    return Comparison(
        tuple(row_name(n, ch) for n, ch, _ in out),
        tuple(r for _, _, r in out),
        tuple(n for n, _, _ in out),
        tuple(ch for _, ch, _ in out),
    )
